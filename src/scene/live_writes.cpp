// Writing the live Data of a built scene after init (live_data.hpp): a state in place; any other
// Data into the scene's text, the scene then built again from it before the next step while every
// state keeps its values and its memory (Scene::apply_pending_writes).
#include "penalty/scene/scene.hpp"

#include "io/text.hpp"
#include "penalty/scene/components.hpp"
#include "scene/builder/scene_builder.hpp"
#include "scene/live_edits.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <typeinfo>

namespace penalty::scene {

std::vector<double> written_numbers(std::string_view text, const std::string& what, bool nonnegative) {
    // each word a finite number as a scene's attribute reads it (io::detail::parse_double)
    std::vector<double> out;
    for (const std::string_view word : io::detail::split_blanks(text)) {
        const std::optional<double> v = io::detail::parse_double(word);
        if (!v || (nonnegative && *v < 0))
            throw std::invalid_argument(
                std::string(what)
                    .append(nonnegative ? ": expected numbers >= 0, found '" : ": expected finite numbers, found '")
                    .append(word)
                    .append("'"));
        out.push_back(*v);
    }
    if (nonnegative && out.empty()) throw std::invalid_argument(what + ": expected at least one number");
    return out;
}

namespace {

void copy_element(const io::SceneElement& from, io::SceneElement& to) {
    to.type = from.type;
    to.name = from.name;
    to.attributes = from.attributes;
    to.line = from.line;
    to.file = from.file;
    to.included_from = from.included_from;
}

/// A deep copy of a node and what is below it, leaving out the elements in `skip`.
std::unique_ptr<io::SceneNode> clone_node(const io::SceneNode& from, const io::SceneNode* parent,
                                          const std::set<const io::SceneElement*>& skip) {
    auto n = std::make_unique<io::SceneNode>();
    copy_element(from, *n);
    n->parent = parent;
    for (const auto& c : from.components) {
        if (skip.count(c.get())) continue;
        auto copy = std::make_unique<io::SceneComponent>();
        copy_element(*c, *copy);
        copy->template_name = c->template_name;
        copy->node = n.get();
        copy->index = n->components.size();
        n->components.push_back(std::move(copy));
    }
    for (const auto& child : from.children)
        if (!skip.count(child.get())) n->children.push_back(clone_node(*child, n.get(), skip));
    return n;
}

/// The numbers of a state write (SOFA's text form).
std::vector<double> numbers_of(std::string_view text, const std::string& what) {
    return written_numbers(text, what, false);
}

/// Swaps (or copies) the vectors of two states when both are MechanicalObject<Types>.
template <class Types>
bool move_state_vectors(BaseState& a, BaseState& b, bool copy) {
    auto* ta = dynamic_cast<MechanicalObject<Types>*>(&a);
    auto* tb = dynamic_cast<MechanicalObject<Types>*>(&b);
    if (ta == nullptr || tb == nullptr) return false;
    const auto move = [copy](auto& x, auto& y) {
        if (copy) y = x;
        else x.swap(y);
    };
    move(ta->position, tb->position);
    move(ta->velocity, tb->velocity);
    move(ta->force, tb->force);
    move(ta->rest_position, tb->rest_position);
    move(ta->external_force, tb->external_force);
    return true;
}

/// Swaps the vectors of two states of the same type and size (the new scene takes the old one's
/// values and memory). False when the types differ.
bool swap_state_vectors(BaseState& a, BaseState& b) {
    return move_state_vectors<Vec3Types>(a, b, false) || move_state_vectors<Rigid3Types>(a, b, false) ||
           move_state_vectors<Vec1Types>(a, b, false);
}

/// b's vectors take a's values (same types and sizes: the buffers stay).
void copy_state_values(BaseState& a, BaseState& b) {
    const bool copied = move_state_vectors<Vec3Types>(a, b, true) || move_state_vectors<Rigid3Types>(a, b, true) ||
                        move_state_vectors<Vec1Types>(a, b, true);
    PENALTY_DEMAND(copied);
}

}  // namespace

std::optional<std::string> Scene::write_attribute(io::SceneElement& element, std::string_view name,
                                                  std::string_view text) {
    for (io::SceneAttribute& a : element.attributes) {
        if (a.name != name) continue;
        std::optional<std::string> old = a.value;
        a.value = std::string(text);
        return old;
    }
    element.attributes.push_back({std::string(name), std::string(text), element.line});
    return std::nullopt;
}

std::uint64_t Scene::generation() const { return live_->generation; }

void Scene::set_event_listener(std::function<void(std::string_view)> listener) {
    event_listener_ = std::move(listener);
    install_contact_stage();
}

void Scene::ContactPhase::detect() {
    if (scene_.event_listener_) scene_.event_listener_("CollisionBeginEvent");
    for (ScenePipeline& p : scene_.pipelines_) {
        p.pipeline->detect();
        scene_.timings_.detection_seconds += p.pipeline->last_timings().detection_seconds;
    }
}

void Scene::ContactPhase::respond() {
    for (ScenePipeline& p : scene_.pipelines_) {
        p.pipeline->respond();
        scene_.timings_.response_seconds += p.pipeline->last_timings().response_seconds;
    }
    if (scene_.event_listener_) {
        scene_.event_listener_("CollisionEndEvent");
        scene_.event_listener_("IntegrateBeginEvent");
    }
}

void Scene::install_contact_stage() {
    // the simulation is this scene's alone: whatever stage it holds (a rebuilt scene's) goes
    const std::vector<ContactStage*> registered = simulation_->contact_stages();
    for (ContactStage* stage : registered) simulation_->remove_contact_stage(*stage);
    if (pipelines_.empty() && !event_listener_) return;
    if (!contact_phase_) contact_phase_ = std::make_unique<ContactPhase>(*this);
    simulation_->add_contact_stage(*contact_phase_);
}

namespace {

/// Checks `text` as the builder reads attribute `name` of `element` (its kind and ValueCheck), so
/// that a bad value is refused when written, with the builder's message.
void check_write(const io::SceneElement& element, bool node, const DataField& f, std::string_view text) {
    if (f.spec == nullptr || (!text.empty() && text.front() == '@')) return;
    io::SceneComponent probe;
    probe.type = node ? std::string("Node") : element.type;
    probe.name = element.name;
    probe.file = element.file;
    probe.line = element.line;
    probe.included_from = element.included_from;
    probe.attributes.push_back({f.name, std::string(text), element.line});
    if (node) {
        if (f.name == "dt") {
            const auto dt = io::get_double(probe, "dt");
            if (!dt || !(*dt > 0)) io::throw_attribute_error(probe, "dt", "must be > 0");
        }
        if (f.name == "gravity") (void)io::get_vec3(probe, "gravity");
        return;
    }
    const Attributes a(probe);
    switch (f.spec->kind) {
        case AttributeKind::boolean:
            (void)a.boolean_or(f.name, false);
            break;
        case AttributeKind::integer:
            (void)a.integer_or(f.name, 0);
            break;
        case AttributeKind::real:
            (void)a.real_or(f.name, 0.0);
            break;
        case AttributeKind::vector3:
            (void)a.vector3_or(f.name, Vec3::Zero());
            break;
        case AttributeKind::numbers:
            (void)a.numbers(f.name);
            break;
        case AttributeKind::indices:
            (void)a.indices(f.name);
            break;
        case AttributeKind::points:
            (void)a.points(f.name);
            break;
        case AttributeKind::frames:
            (void)a.frames(f.name);
            break;
        default:
            break;
    }
}

/// TetrahedronFEMForceField with updateStiffness: SOFA recomputes each element's material
/// stiffness at every AnimateBeginEvent (TetrahedronFEMForceField::handleEvent →
/// computeMaterialStiffness), so its Young's modulus, Poisson ratio and localStiffnessFactor act
/// at the next step, not at reinit().
bool recomputed_each_step(const io::SceneElement& e, std::string_view name) {
    if (e.type != "TetrahedronFEMForceField") return false;
    if (name != "youngModulus" && name != "poissonRatio" && name != "localStiffnessFactor") return false;
    const io::SceneAttribute* update = e.find("updateStiffness");
    return update != nullptr && (update->value == "1" || update->value == "true");
}

}  // namespace

void Scene::set_data(const DataOwner& owner, std::string_view name, std::string_view text) {
    auto* e = const_cast<io::SceneElement*>(find_element(owner));
    if (e == nullptr)
        throw std::invalid_argument(std::string(owner.node ? "no node '" : "no component '") + owner.path + "'");
    const std::vector<DataField>& fields = fields_of(owner);
    const auto it = std::find_if(fields.begin(), fields.end(), [&](const DataField& f) { return f.name == name; });
    if (it == fields.end()) throw std::invalid_argument(e->describe() + " has no data '" + std::string(name) + "'");
    const DataField& f = *it;
    const std::string what = e->describe() + ": data '" + f.name + "'";
    switch (f.live) {
        case LiveWrite::refused:
        case LiveWrite::read_only:
            throw std::invalid_argument(what + " cannot be written after init: " + f.refusal);
        case LiveWrite::no_effect:
            write_attribute(*e, name, text);
            return;
        case LiveWrite::state: {
            if (owner.node) {  // the node's time
                const std::vector<double> t = numbers_of(text, what);
                if (t.size() != 1) throw std::invalid_argument(what + ": expected one number");
                simulation_->set_time(t[0]);
                return;
            }
            const Node* node = node_of(*static_cast<io::SceneComponent*>(e)->node);
            if (node == nullptr || node->state() == nullptr)
                throw std::invalid_argument(what + ": the state is not built");
            write_state(*node->state(), f.name, numbers_of(text, what), what);
            return;
        }
        case LiveWrite::next_step:
        case LiveWrite::reinit:
            break;
    }
    if (write_spring_list_quirk(*e, owner, name, text, what)) return;  // a list: checked there
    check_write(*e, owner.node, f, text);
    if (write_uniform_mass_quirk(*e, owner, name, text, what)) return;
    note_box_roi_write(*e, owner, name);
    if (owner.node) {
        auto* sn = static_cast<io::SceneNode*>(e);
        if (sn->parent != nullptr)
            throw std::invalid_argument(what + " cannot be written after init: SOFA copies the root's " + f.name +
                                        " over a child node's at each step");
        Node& root = simulation_->root();
        if (name == "dt") {
            root.set_dt(numbers_of(text, what).at(0));
            options_.dt.reset();  // the script's write wins over a --dt given at load
        } else {
            const std::vector<double> g = numbers_of(text, what);
            if (live_->gravity_write_delay) hold_gravity_of_children();
            root.set_gravity(Vec3(g.at(0), g.at(1), g.at(2)));
        }
        write_attribute(*e, name, text);
        return;
    }
    if (f.live == LiveWrite::reinit && !recomputed_each_step(*e, name)) {
        live_->at_reinit[{owner.path, owner.node}][std::string(name)] = std::string(text);
        return;
    }
    live_->applied.push_back({owner, std::string(name), write_attribute(*e, name, text)});
    live_->rebuild = true;
}

/// SOFA's root gravity reaches the other nodes at the end of a step (DefaultAnimationLoop's
/// UpdateSimulationContextVisitor copies the context down after the solve): a gravity written
/// between two steps acts on the root's own masses at the next step, on the others one step
/// later. The root's child nodes (but those with a Gravity component, which set their own) keep
/// their gravity until the end of the next step.
void Scene::hold_gravity_of_children() {
    for (const auto& child : file_.root->children) {
        const std::string path = child->path();
        if (live_->delayed_gravity.count(path)) continue;
        const bool own = std::any_of(child->components.begin(), child->components.end(),
                                     [](const auto& c) { return c->type == "Gravity"; });
        if (own) continue;
        if (Node* n = const_cast<Node*>(node_of(*child))) {
            live_->delayed_gravity[path] = n->gravity();
            n->set_gravity(n->gravity());
        }
    }
}

void Scene::release_held_gravity() {
    if (live_->delayed_gravity.empty()) return;
    const Vec3 g = simulation_->root().gravity();
    for (const auto& child : file_.root->children)
        if (live_->delayed_gravity.count(child->path()))
            if (Node* n = const_cast<Node*>(node_of(*child))) n->set_gravity(g);
    live_->delayed_gravity.clear();
}

void Scene::set_gravity_write_delay(bool delay) { live_->gravity_write_delay = delay; }

void Scene::write_state(BaseState& s, std::string_view name, const std::vector<double>& values,
                        const std::string& what) const {
    const std::size_t n = s.num_dofs();
    if (auto* v = dynamic_cast<Vec3Object*>(&s)) {
        std::vector<Vec3>& list = name == "position"        ? v->position
                                  : name == "velocity"      ? v->velocity
                                  : name == "force"         ? v->force
                                  : name == "rest_position" ? v->rest_position
                                                            : v->external_force;
        if (values.size() != 3 * list.size())
            throw std::invalid_argument(what + ": expected " + std::to_string(list.size()) +
                                        " points (3 numbers each), found " + std::to_string(values.size()) +
                                        " numbers (penalty keeps a state's size after init)");
        for (std::size_t i = 0; i < list.size(); ++i)
            list[i] = Vec3(values[3 * i], values[3 * i + 1], values[3 * i + 2]);
        return;
    }
    if (auto* w = dynamic_cast<Vec1Object*>(&s)) {
        std::vector<double>& list = name == "position"        ? w->position
                                    : name == "velocity"      ? w->velocity
                                    : name == "force"         ? w->force
                                    : name == "rest_position" ? w->rest_position
                                                              : w->external_force;
        if (values.size() != list.size())
            throw std::invalid_argument(what + ": expected " + std::to_string(list.size()) + " values, found " +
                                        std::to_string(values.size()) + " (penalty keeps a state's size after init)");
        std::copy(values.begin(), values.end(), list.begin());
        return;
    }
    auto& r = dynamic_cast<Rigid3Object&>(s);
    if (name == "position" || name == "rest_position") {
        std::vector<RigidFrame>& list = name == "position" ? r.position : r.rest_position;
        if (values.size() != 7 * list.size())
            throw std::invalid_argument(what + ": expected " + std::to_string(list.size()) +
                                        " frames (x y z qx qy qz qw), found " + std::to_string(values.size()) +
                                        " numbers");
        for (std::size_t i = 0; i < list.size(); ++i) {
            const double* x = values.data() + 7 * i;
            list[i].center = Vec3(x[0], x[1], x[2]);
            list[i].orientation = Quat(x[6], x[3], x[4], x[5]);  // as written (SOFA), unless fixed:
            if (options_.sofa_quirk_fixes.fix_rigid_orientation_as_written) list[i].orientation.normalize();
        }
        return;
    }
    std::vector<RigidDeriv>& list = name == "velocity" ? r.velocity : name == "force" ? r.force : r.external_force;
    if (values.size() != 6 * n)
        throw std::invalid_argument(what + ": expected " + std::to_string(n) + " rows of 6 numbers, found " +
                                    std::to_string(values.size()) + " numbers");
    for (std::size_t i = 0; i < list.size(); ++i) {
        const double* x = values.data() + 6 * i;
        list[i].linear = Vec3(x[0], x[1], x[2]);
        list[i].angular = Vec3(x[3], x[4], x[5]);
    }
}

void Scene::reinit(const DataOwner& owner) {
    if (find_element(owner) == nullptr)
        throw std::invalid_argument(std::string(owner.node ? "no node '" : "no component '") + owner.path + "'");
    // The component's writes waiting for it; a node's init(): those of every component below.
    const std::string prefix = owner.path == "/" ? "/" : owner.path + "/";
    for (auto it = live_->at_reinit.begin(); it != live_->at_reinit.end();) {
        const auto& [key, writes] = *it;
        const bool below = owner.node ? key.first.compare(0, prefix.size(), prefix) == 0 || key.first == owner.path
                                      : key == std::make_pair(owner.path, owner.node);
        if (!below) {
            ++it;
            continue;
        }
        const DataOwner target{key.first, key.second};
        auto* e = const_cast<io::SceneElement*>(find_element(target));
        if (e != nullptr)
            for (const auto& [name, text] : writes)
                live_->applied.push_back({target, name, write_attribute(*e, name, text)});
        it = live_->at_reinit.erase(it);
        live_->rebuild = true;
    }
    apply_pending_writes();
}

std::string Scene::add_to_node(std::string_view node_path, std::unique_ptr<io::SceneComponent> component,
                               std::string_view node_name) {
    auto* node =
        const_cast<io::SceneNode*>(static_cast<const io::SceneNode*>(find_element({std::string(node_path), true})));
    if (node == nullptr) throw std::invalid_argument("no node '" + std::string(node_path) + "'");
    std::string path;
    if (component) {
        component->node = node;
        component->index = node->components.size();
        node->components.push_back(std::move(component));
        live_->added.emplace_back(node, node->components.back().get());
        path = component_path(*node->components.back());
    } else {
        auto child = std::make_unique<io::SceneNode>();
        child->type = "Node";
        child->name = std::string(node_name);
        child->parent = node;
        child->file = node->file;
        child->line = node->line;
        node->children.push_back(std::move(child));
        live_->added.emplace_back(node, node->children.back().get());
        path = node->children.back()->path();
    }
    live_->structure_changed = true;
    live_->rebuild = true;
    return path;
}

void Scene::remove(const DataOwner& owner) {
    const io::SceneElement* e = find_element(owner);
    if (e == nullptr)
        throw std::invalid_argument(std::string(owner.node ? "no node '" : "no component '") + owner.path + "'");
    if (owner.node && static_cast<const io::SceneNode*>(e)->parent == nullptr)
        throw std::invalid_argument("the root node cannot be removed");
    live_->removed.insert(e);
    live_->structure_changed = true;
    live_->rebuild = true;
}

void Scene::apply_pending_writes() {
    if (!live_->rebuild || live_->stepping) return;
    rebuild(/*reset=*/false);
}

void Scene::reset() {
    if (live_->stepping) throw std::logic_error("Scene::reset: not during a step (a handler of the collision phase)");
    rebuild(/*reset=*/true);
}

void Scene::rebuild(bool reset) {
    live_->rebuild = false;
    const auto undo = [&] {
        for (auto w = live_->applied.rbegin(); w != live_->applied.rend(); ++w) {
            auto* e = const_cast<io::SceneElement*>(find_element(w->owner));
            if (e == nullptr) continue;
            if (w->old) write_attribute(*e, w->name, *w->old);
            else std::erase_if(e->attributes, [&](const io::SceneAttribute& a) { return a.name == w->name; });
        }
        for (auto a = live_->added.rbegin(); a != live_->added.rend(); ++a) {
            auto* node = const_cast<io::SceneNode*>(a->first);
            std::erase_if(node->components, [&](const auto& c) { return c.get() == a->second; });
            std::erase_if(node->children, [&](const auto& c) { return c.get() == a->second; });
        }
        live_->applied.clear();
        live_->added.clear();
        live_->removed.clear();
    };
    std::unique_ptr<Scene> fresh;
    try {
        // the scene's text holds the topologies as built: a rebuild would undo the changes
        // (docs/topological-changes.md, "Limits")
        if (topology_revision() != 0)
            throw io::SceneError(
                std::string(reset
                                ? "reset"
                                : "a write of a Data that takes effect at reinit, or an added or removed component,") +
                " builds the scene again from its text, which would undo the topological changes made since init "
                "(elements removed or added): refused once a topology changed");
        io::SceneFile copy;
        copy.path = file_.path;
        copy.root = clone_node(*file_.root, nullptr, live_->removed);
        fresh = build_from(std::move(copy), options_, live_.get());
        carry_states(*fresh, reset);
        carry_live_quirks(*fresh);  // live_quirks.cpp
    } catch (...) {
        undo();
        throw;
    }
    if (!reset) fresh->simulation_->set_time(simulation_->time());
    const TunnellingOptions tunnelling = tunnelling_options();  // set at run time, maybe
    // The fresh scene's internals come here; the old ones leave with `fresh`.
    std::swap(file_, fresh->file_);
    std::swap(simulation_, fresh->simulation_);
    std::swap(topologies_, fresh->topologies_);
    std::swap(models_, fresh->models_);
    std::swap(pipelines_, fresh->pipelines_);
    std::swap(guard_, fresh->guard_);  // each guard with its simulation and pipelines
    std::swap(build_warnings_, fresh->build_warnings_);
    std::swap(masses_, fresh->masses_);
    std::swap(mass_nodes_, fresh->mass_nodes_);
    std::swap(roles_, fresh->roles_);
    std::swap(nodes_, fresh->nodes_);
    std::swap(built_from_, fresh->built_from_);
    std::swap(implicit_solvers_, fresh->implicit_solvers_);
    std::swap(implicit_solver_paths_, fresh->implicit_solver_paths_);
    std::swap(contacts_, fresh->contacts_);
    std::swap(engine_indices_, fresh->engine_indices_);
    std::swap(engine_meshes_, fresh->engine_meshes_);
    std::swap(loader_meshes_, fresh->loader_meshes_);
    std::swap(live_->engines, fresh->live_->engines);  // their readers are the fresh components
    std::swap(live_->engine_reals, fresh->live_->engine_reals);
    std::swap(live_->refused_reals, fresh->live_->refused_reals);
    std::swap(topology_runtime_, fresh->topology_runtime_);  // its handlers refer to the fresh components
    // States: the records keep their addresses when the list has the same states (the usual
    // case: a Data written), so that what points to them stays valid.
    const bool same_list =
        states_.size() == fresh->states_.size() &&
        std::equal(states_.begin(), states_.end(), fresh->states_.begin(),
                   [](const auto& a, const auto& b) { return a.node_path == b.node_path && a.name == b.name; });
    if (same_list) {
        for (std::size_t i = 0; i < states_.size(); ++i) std::swap(states_[i], fresh->states_[i]);
    } else {
        std::swap(states_, fresh->states_);
    }
    fresh->install_contact_stage();  // its simulation held this scene's stage
    install_contact_stage();
    set_tunnelling(tunnelling);
    for (const auto& child : file_.root->children)  // gravity held until the end of the step
        if (const auto held = live_->delayed_gravity.find(child->path()); held != live_->delayed_gravity.end())
            if (Node* n = const_cast<Node*>(node_of(*child))) n->set_gravity(held->second);
    refresh_contacts();
    live_->applied.clear();
    live_->added.clear();
    live_->removed.clear();
    live_->structure_changed = false;
    ++live_->generation;
    if (!same_list) live_->retired.push_back(std::move(fresh));
}

void Scene::carry_states(Scene& fresh, bool reset) const {
    // First check every size (nothing is swapped when one differs), then swap.
    std::vector<std::pair<BaseState*, BaseState*>> pairs;
    for (const output::StateRecord& n : fresh.states_) {
        const auto old = std::find_if(states_.begin(), states_.end(), [&](const output::StateRecord& o) {
            return o.node_path == n.node_path && o.name == n.name;
        });
        if (old == states_.end()) continue;        // added after init: its own values
        const BaseState& old_state = *old->state;  // (typeid of a plain reference: nothing evaluated twice)
        const BaseState& new_state = *n.state;
        if (typeid(old_state) != typeid(new_state))
            throw io::SceneError(output::state_label(n) +
                                 ": a write changes the template of the state (penalty keeps it after init)");
        if (old->state->num_dofs() != n.state->num_dofs())
            throw io::SceneError(output::state_label(n) + ": the write changes its number of DOFs from " +
                                 std::to_string(old->state->num_dofs()) + " to " + std::to_string(n.state->num_dofs()) +
                                 " (penalty keeps a state's size after init)");
        pairs.emplace_back(old->state, n.state);
    }
    // the vectors linked to a Data the writes made dirty take the rebuilt values (live_links.cpp)
    std::vector<std::pair<const BaseState*, StateVector>> linked;
    if (!reset) linked = states_linked_to_writes(fresh);
    for (auto [old, n] : pairs) {
        (void)swap_state_vectors(*old, *n);
        // reset: the values of the new build in the memory of the old one (an assignment of
        // equal size keeps the buffer)
        if (reset) copy_state_values(*old, *n);
        for (const auto& [state, which] : linked)
            if (state == n) take_linked_vectors(*old, *n, which);
    }
}

}  // namespace penalty::scene
