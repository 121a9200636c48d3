// SOFA's Data links followed after a write (docs/python.md, "Data linked to an engine output"):
// a Data whose text is a link to another Data (`position="@engine.output_position"`) has that
// Data as its parent (BaseData::setParent). A write marks the written Data's children dirty
// (DDGNode::setDirtyOutputs), an engine whose input is dirty marks all its outputs dirty
// (DataEngine: every output depends on every input), and a dirty Data takes its parent's value
// again at its next read (Data::getValue / beginEdit → DDGNode::updateIfDirty → BaseData::update,
// which runs DataEngine::update first).
//
// A rebuilt scene (Scene::rebuild) computes every component and engine from the text again, so
// components other than states follow their links by themselves; a state keeps its values across
// the rebuild (Scene::carry_states), except the vectors linked to a Data the writes made dirty:
// those take the rebuilt values, the engine's new output. The rebuild runs before the next step,
// or at the next read of a Data (Scene::data), which is where SOFA's lazy evaluation reads them
// (the step's first read of a state's position comes after the AnimateBeginEvent, in the
// collision or the solve; a read from Python pulls the engine at once).
#include "penalty/scene/scene.hpp"

#include "penalty/scene/components.hpp"
#include "scene/live_edits.hpp"

#include <array>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace penalty::scene {

namespace {

/// A Data of a component: its SOFA path and the Data's name.
using DataKey = std::pair<std::string, std::string>;

bool is_engine(const io::SceneComponent& c) {
    const ComponentSpec* spec = find_component(c.type);
    return spec != nullptr && (spec->family == ComponentFamily::engine || spec->family == ComponentFamily::data_engine);
}

/// The Data targets of the links in attribute `a` of `c` (none for object links and broken ones:
/// the builder has reported those).
std::vector<io::LinkTarget> data_links(const io::SceneComponent& c, const io::SceneAttribute& a) {
    if (!io::is_link(a.value)) return {};
    try {
        std::vector<io::LinkTarget> out;
        for (io::LinkTarget& t : io::resolve_links(c, a.name))
            if (t.component != nullptr && !t.data.empty()) out.push_back(std::move(t));
        return out;
    } catch (const io::SceneError&) {
        return {};
    }
}

/// The Data dirty after writing `written`: the written ones, every Data linked to a dirty one, and
/// every Data of an engine one of whose Data is dirty (its outputs), to the fixed point.
class DirtyData {
public:
    DirtyData(const io::SceneNode& root, std::set<DataKey> written) : dirty_(std::move(written)) {
        for (bool changed = true; changed;) {
            changed = false;
            io::for_each_component(root, [&](const io::SceneComponent& c) { changed = visit(c) || changed; });
        }
    }
    [[nodiscard]] bool contains(const DataKey& key) const {
        return dirty_.count(key) != 0 || engines_.count(key.first) != 0;
    }

private:
    bool visit(const io::SceneComponent& c) {
        bool changed = false;
        const std::string path = Scene::component_path(c);
        for (const io::SceneAttribute& a : c.attributes) {
            if (dirty_.count({path, a.name})) continue;
            for (const io::LinkTarget& t : data_links(c, a))
                if (contains({Scene::component_path(*t.component), t.data})) {
                    dirty_.insert({path, a.name});
                    changed = true;
                    break;
                }
        }
        if (!engines_.count(path) && is_engine(c)) {
            const auto first = dirty_.lower_bound({path, std::string()});
            if (first != dirty_.end() && first->first == path) {
                engines_.insert(path);
                changed = true;
            }
        }
        return changed;
    }
    std::set<DataKey> dirty_;
    std::set<std::string> engines_;  ///< engines with a dirty input: every Data of theirs is dirty
};

/// b's vector `which` takes a's values (same sizes: the buffer stays).
template <class Types>
bool copy_state_vector(const BaseState& a, BaseState& b, StateVector which) {
    const auto* from = dynamic_cast<const MechanicalObject<Types>*>(&a);
    auto* to = dynamic_cast<MechanicalObject<Types>*>(&b);
    if (from == nullptr || to == nullptr) return false;
    switch (which) {
        case StateVector::position:
            to->position = from->position;
            break;
        case StateVector::velocity:
            to->velocity = from->velocity;
            break;
        case StateVector::force:
            to->force = from->force;
            break;
        case StateVector::rest_position:
            to->rest_position = from->rest_position;
            break;
        case StateVector::external_force:
            to->external_force = from->external_force;
            break;
        case StateVector::none:
            break;
    }
    return true;
}

}  // namespace

std::vector<std::pair<const BaseState*, StateVector>> Scene::states_linked_to_writes(const Scene& fresh) const {
    std::set<DataKey> written;
    for (const LiveEdits::Applied& w : live_->applied)
        if (!w.owner.node) written.insert({w.owner.path, w.name});
    std::vector<std::pair<const BaseState*, StateVector>> out;
    if (written.empty() || !fresh.file_.root) return out;
    const DirtyData dirty(*fresh.file_.root, std::move(written));
    static constexpr std::array<std::pair<const char*, StateVector>, 5> vectors{
        {{"position", StateVector::position},
         {"velocity", StateVector::velocity},
         {"force", StateVector::force},
         {"rest_position", StateVector::rest_position},
         {"externalForce", StateVector::external_force}}};
    io::for_each_component(*fresh.file_.root, [&](const io::SceneComponent& c) {
        if (c.type != "MechanicalObject") return;
        const Node* node = fresh.node_of(*c.node);
        if (node == nullptr || node->state() == nullptr) return;
        const std::string path = component_path(c);
        for (const auto& [name, which] : vectors)
            if (c.find(name) != nullptr && dirty.contains({path, name})) out.emplace_back(node->state(), which);
    });
    return out;
}

void Scene::take_linked_vectors(const BaseState& rebuilt, BaseState& carried, StateVector which) {
    const bool copied = copy_state_vector<Vec3Types>(rebuilt, carried, which) ||
                        copy_state_vector<Rigid3Types>(rebuilt, carried, which) ||
                        copy_state_vector<Vec1Types>(rebuilt, carried, which);
    PENALTY_DEMAND(copied);
}

}  // namespace penalty::scene
