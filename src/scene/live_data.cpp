// Reading the live Data of a built scene (live_data.hpp): which Data a component or node has, and
// the current value of each with SOFA's type. Writes are in live_writes.cpp.
#include "penalty/scene/scene.hpp"

#include "penalty/mechanics/mass.hpp"
#include "penalty/scene/components.hpp"
#include "scene/builder/scene_builder.hpp"
#include "scene/live_edits.hpp"
#include "scene/live_policy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace penalty::scene {

namespace {

/// The catalog type of a component type: SofaPython3's class for penalty's Python components.
std::string_view catalog_type(std::string_view type) {
    if (type == "PythonForceField") return "ForceFieldVec3d";
    if (type == "PythonMapping") return "Mapping_Vec3d_Vec3d";
    return type;
}

/// True when the component works on Rigid3d DOFs: its template, else its node's state's.
bool is_rigid(const io::SceneComponent& c) {
    const auto rigid_name = [](std::string_view t) { return t.substr(0, 5) == "Rigid"; };
    if (!c.template_name.empty()) return rigid_name(c.template_name);
    for (const auto& other : c.node->components)
        if (other->type == "MechanicalObject") return rigid_name(other->template_name);
    return false;
}

/// How SofaPython3 would present an attribute SOFA's catalog lacks, from the registry's kind.
std::pair<std::string, std::string> form_of_kind(AttributeKind kind) {
    switch (kind) {
        case AttributeKind::boolean:
            return {"bool", "int"};
        case AttributeKind::integer:
            return {"i", "int"};
        case AttributeKind::real:
            return {"d", "float"};
        case AttributeKind::vector3:
            return {"Vec3d", "ndarray:float64:1"};
        case AttributeKind::numbers:
            return {"vector<d>", "ndarray:float64:1"};
        case AttributeKind::indices:
            return {"vector<I>", "ndarray:int32:1"};
        case AttributeKind::points:
            return {"vector<Vec3d>", "ndarray:float64:2"};
        case AttributeKind::frames:
            return {"vector<RigidCoord3d>", "ndarray:float64:2"};
        case AttributeKind::elements:
            return {"vector<I>", "ndarray:int32:2"};
        case AttributeKind::text:
            return {"string", "str"};
        case AttributeKind::link:
            return {"link", "link"};
        case AttributeKind::links:
            return {"link", "list"};
    }
    return {"string", "str"};
}

/// A number as SOFA writes it (std::ostream's default: 6 significant digits).
std::string sofa_number(double v, bool integral) {
    std::ostringstream out;
    if (integral && std::abs(v) < 9.2e18) out << static_cast<long long>(v);
    else out << v;
    return out.str();
}

/// SOFA's index ranges of a vector of integers ("0-255", "10-0-2": first-last[-step]), else
/// nullopt (io::get_indices reads them so in scenes).
std::optional<std::vector<double>> parse_index_ranges(std::string_view text) {
    io::SceneComponent probe;
    probe.type = "Data";
    probe.attributes.push_back({"value", std::string(text), 0});
    try {
        const std::vector<PointId> indices = io::get_indices(probe, "value");
        return std::vector<double>(indices.begin(), indices.end());
    } catch (const io::SceneError&) {
        return std::nullopt;
    }
}

/// The numbers of a text; words that are not numbers (`true`, `false`) count as 1 and 0.
std::vector<double> parse_numbers(std::string_view text) {
    std::vector<double> out;
    std::istringstream in{std::string(text)};
    std::string word;
    while (in >> word) {
        if (word == "true" || word == "True") {
            out.push_back(1.0);
            continue;
        }
        if (word == "false" || word == "False") {
            out.push_back(0.0);
            continue;
        }
        char* end = nullptr;
        const double v = std::strtod(word.c_str(), &end);
        if (end == word.c_str() || *end != '\0') return {};  // not a list of numbers (a link, a word)
        out.push_back(v);
    }
    return out;
}

/// Values per row of a 2-D form: SOFA's type, else the registry's kind.
std::size_t columns_of(const DataField& f) {
    if (const std::size_t c = sofa_type_columns(f.sofa_type)) return c;
    if (f.spec != nullptr && f.spec->kind == AttributeKind::frames) return 7;
    if (f.spec != nullptr && f.spec->kind == AttributeKind::points) return 3;
    return 0;
}

bool integral_form(std::string_view form) { return form == "int" || form.find("int32") != std::string_view::npos; }

/// Numbers as SOFA writes a vector of them: blank-separated.
std::string numbers_text(const std::vector<double>& numbers, bool integral) {
    std::string text;
    for (std::size_t i = 0; i < numbers.size(); ++i) {
        if (i > 0) text += ' ';
        text += sofa_number(numbers[i], integral);
    }
    return text;
}

/// A value made of numbers (a live value: states, context, outputs).
DataValue numeric_value(const DataField& f, std::vector<double> numbers, std::size_t columns) {
    DataValue v;
    v.python_form = f.python_form;
    v.columns = columns;
    v.text = numbers_text(numbers, integral_form(f.python_form));
    v.numbers = std::move(numbers);
    return v;
}

const io::SceneNode* find_node_at(const io::SceneNode& root, std::string_view path) {
    if (path.empty() || path == "/") return &root;
    if (path.front() == '/') path.remove_prefix(1);
    const io::SceneNode* n = &root;
    while (!path.empty() && n != nullptr) {
        const std::size_t slash = path.find('/');
        n = n->child(path.substr(0, slash));
        path = slash == std::string_view::npos ? std::string_view{} : path.substr(slash + 1);
    }
    return n;
}

}  // namespace

std::vector<DataField> make_data_fields(std::string_view type, bool node, bool rigid);

DataValue make_data_value(const DataField& f, std::string_view text) {
    DataValue v;
    v.python_form = f.python_form;
    const std::string_view form = f.python_form;
    if (form == "str" || form == "link" || form == "none") {
        v.text = std::string(text);
        return v;
    }
    if (form == "list") {
        std::istringstream in{std::string(text)};
        for (std::string w; in >> w;) v.items.push_back(w);
        v.text = std::string(text);
        return v;
    }
    v.numbers = parse_numbers(text);
    const bool integral = integral_form(form);
    if (v.numbers.empty() && integral && text.find('-', 1) != std::string_view::npos)
        if (auto ranges = parse_index_ranges(text)) v.numbers = std::move(*ranges);
    if (form == "float" || form == "int") {
        if (v.numbers.empty()) v.numbers.push_back(0.0);
        v.numbers.resize(1);
    } else if (form.size() > 2 && form.substr(form.size() - 2) == ":2") {
        v.columns = columns_of(f);
        if (v.columns == 0) v.columns = std::max<std::size_t>(1, v.numbers.size());
        v.numbers.resize(v.numbers.size() - v.numbers.size() % v.columns);
    }
    v.text = numbers_text(v.numbers, integral);
    return v;
}

std::string Scene::component_path(const io::SceneComponent& c) {
    const std::string node = c.node->path();
    return (node == "/" ? std::string() : node) + "/" + (c.name.empty() ? sofa_default_name(c) : c.name);
}

const io::SceneElement* Scene::find_element(const DataOwner& owner) const {
    if (!file_.root) return nullptr;
    if (owner.node) return find_node_at(*file_.root, owner.path);
    const std::size_t slash = owner.path.rfind('/');
    if (slash == std::string::npos) return nullptr;
    const io::SceneNode* node = find_node_at(*file_.root, std::string_view(owner.path).substr(0, slash));
    if (node == nullptr) return nullptr;
    const std::string_view name = std::string_view(owner.path).substr(slash + 1);
    for (const auto& c : node->components)
        if ((c->name.empty() ? sofa_default_name(*c) : c->name) == name && !live_->removed.count(c.get()))
            return c.get();
    return nullptr;
}

const io::MeshData* Scene::loader_mesh(const io::SceneComponent& loader) const {
    const auto it = loader_meshes_.find(&loader);
    return it == loader_meshes_.end() ? nullptr : &it->second;
}

const std::vector<PointId>* Scene::engine_indices(const io::SceneComponent& engine, const std::string& data) const {
    if (LiveEngine* live = live_->engine(engine)) {  // over moving positions: run on read (live_engines.cpp)
        live->update_if_dirty();
        if (const auto out = live->indices.find(data); out != live->indices.end()) return &out->second;
    }
    const auto it = engine_indices_.find({&engine, data});
    return it == engine_indices_.end() ? nullptr : &it->second;
}

const io::MeshData* Scene::engine_mesh(const io::SceneComponent& engine, const std::string& data) const {
    if (LiveEngine* live = live_->engine(engine)) {
        live->update_if_dirty();
        if (const auto out = live->meshes.find(data); out != live->meshes.end()) return &out->second;
    }
    const auto it = engine_meshes_.find({&engine, data});
    return it == engine_meshes_.end() ? nullptr : &it->second;
}

const std::vector<DataField>& data_fields_of_type(std::string_view type, bool node, bool rigid) {
    // Built once per (type, template): the registry and the catalog do not change.
    static std::mutex mutex;
    static std::map<std::tuple<std::string, bool, bool>, std::vector<DataField>> cache;
    const std::lock_guard<std::mutex> lock(mutex);
    auto [it, inserted] = cache.try_emplace({std::string(type), node, rigid});
    if (inserted) it->second = make_data_fields(type, node, rigid);
    return it->second;
}

std::vector<DataField> make_data_fields(std::string_view type, bool node, bool rigid) {
    const ComponentSpec* spec = node ? nullptr : find_component(type);
    const std::vector<CatalogEntry>& sofa = sofa_data_catalog(node ? "Node" : catalog_type(type), rigid);
    std::vector<DataField> out;
    const auto add = [&](const CatalogEntry* entry, const AttributeSpec* attribute, std::string_view name) {
        DataField f;
        f.name = std::string(name);
        f.spec = attribute;
        if (entry != nullptr) {
            f.sofa_type = entry->sofa_type;
            f.python_form = entry->python_form;
            f.default_text = entry->default_text;
        } else {
            std::tie(f.sofa_type, f.python_form) = form_of_kind(attribute->kind);
            if (!attribute->default_value.empty() && attribute->default_value.front() != '(')
                f.default_text = std::string(attribute->default_value);
        }
        f.live = live_policy(type, node, f.name, f.spec, entry, f.refusal);
        if (f.live == LiveWrite::read_only && f.refusal.empty()) f.refusal = "SOFA computes it";
        out.push_back(std::move(f));
    };
    const std::span<const AttributeSpec> node_attrs = node_attributes();
    const auto attribute_of = [&](std::string_view name) -> const AttributeSpec* {
        if (spec != nullptr) return find_attribute(*spec, name);
        if (node)
            for (const AttributeSpec& a : node_attrs)
                if (a.name == name) return &a;
        return nullptr;
    };
    for (const CatalogEntry& entry : sofa) add(&entry, attribute_of(entry.name), entry.name);
    const auto known = [&](std::string_view name) {
        return std::any_of(out.begin(), out.end(), [&](const DataField& f) { return f.name == name; });
    };
    const auto add_registry = [&](std::span<const AttributeSpec> attributes) {
        for (const AttributeSpec& a : attributes)
            if (!known(a.name)) add(nullptr, &a, a.name);
    };
    if (spec != nullptr) {
        add_registry(spec->attributes);
        add_registry(spec->shared_attributes);
    } else if (node) {
        add_registry(node_attrs);
    }
    return out;
}

std::size_t data_field_columns(const DataField& f) { return columns_of(f); }

std::vector<DataField> Scene::data_fields(const DataOwner& owner) const { return fields_of(owner); }

const std::vector<DataField>& Scene::fields_of(const DataOwner& owner) const {
    const io::SceneElement* e = find_element(owner);
    if (e == nullptr)
        throw std::invalid_argument(std::string(owner.node ? "no node '" : "no component '") + owner.path + "'");
    if (owner.node) return data_fields_of_type("Node", true, false);
    const auto& c = *static_cast<const io::SceneComponent*>(e);
    return data_fields_of_type(c.type, false, is_rigid(c));
}

DataValue Scene::data(const DataOwner& owner, std::string_view name) {
    const std::vector<DataField>& fields = fields_of(owner);
    const auto it = std::find_if(fields.begin(), fields.end(), [&](const DataField& f) { return f.name == name; });
    const io::SceneElement* e = find_element(owner);
    if (it == fields.end()) throw std::invalid_argument(e->describe() + " has no data '" + std::string(name) + "'");
    const DataField& f = *it;
    // A write waiting for the component's reinit(): SOFA's Data holds it already.
    const auto pending = live_->at_reinit.find({owner.path, owner.node});
    if (pending != live_->at_reinit.end())
        if (const auto w = pending->second.find(name); w != pending->second.end()) return make_data_value(f, w->second);
    // Outputs read after a write that changes them: built again first (SOFA's engines update
    // when read).
    if (live_->rebuild) apply_pending_writes();
    e = find_element(owner);
    const auto numbers_value = [&](std::vector<double> numbers, std::size_t columns) {
        return numeric_value(f, std::move(numbers), columns);
    };
    if (owner.node) {
        const auto* sn = static_cast<const io::SceneNode*>(e);
        const Node* built = node_of(*sn);
        if (name == "time") return numbers_value({simulation_->time()}, 0);
        if (built != nullptr && name == "dt") return numbers_value({built->dt()}, 0);
        if (built != nullptr && name == "gravity") {
            const Vec3 g = built->gravity();
            return numbers_value({g.x(), g.y(), g.z()}, 0);
        }
        if (name == "name") return make_data_value(f, sn->parent == nullptr && sn->name.empty() ? "root" : sn->name);
    } else {
        const auto& c = *static_cast<const io::SceneComponent*>(e);
        if (name == "name") return make_data_value(f, c.name.empty() ? sofa_default_name(c) : c.name);
        if (auto live = live_value(c, f)) return *live;
    }
    if (const io::SceneAttribute* a = e->find(name)) {
        // A Data linked to another (`indices="@box.indices"`) reads the other's value.
        if (io::is_link(a->value) && f.python_form != "link" && !owner.node) {
            const io::LinkTarget t = io::resolve_link(*static_cast<const io::SceneComponent*>(e), a->name);
            if (t.component != nullptr && !t.data.empty()) {
                DataValue v = data(DataOwner{component_path(*t.component), false}, t.data);
                v.python_form = f.python_form;
                return v;
            }
        }
        return make_data_value(f, a->value);
    }
    return make_data_value(f, f.default_text);
}

std::optional<DataValue> Scene::live_value(const io::SceneComponent& c, const DataField& f) const {
    const auto numbers_value = [&](std::vector<double> numbers, std::size_t columns) {
        return numeric_value(f, std::move(numbers), columns);
    };
    if (auto quirk = quirk_value(c, f)) return quirk;  // live_quirks.cpp
    const Node* node = node_of(*c.node);
    const std::string& name = f.name;
    if (c.type == "MechanicalObject" && node != nullptr && node->state() != nullptr) {
        BaseState* s = node->state();
        static const std::pair<std::string_view, StateVector> vectors[] = {
            {"position", StateVector::position},
            {"velocity", StateVector::velocity},
            {"force", StateVector::force},
            {"rest_position", StateVector::rest_position},
            {"externalForce", StateVector::external_force}};
        for (const auto& [data_name, which] : vectors) {
            if (name != data_name) continue;
            DataValue v = numbers_value(state_vector_numbers(*s, which), 0);
            v.columns = (which == StateVector::position || which == StateVector::rest_position) &&
                                dynamic_cast<Rigid3Object*>(s)
                            ? 7
                            : std::size_t(s->deriv_size());
            v.state = s;
            v.state_vector = which;
            return v;
        }
        if (name == "size") return numbers_value({double(s->num_dofs())}, 0);
    }
    if (c.type == "BoxROI" && name == "box")
        if (LiveEngine* live = live_->engine(c))
            for (const FollowedInput& in : live->followed_inputs()) {
                if (in.name != "box") continue;
                // a list of points read as boxes: SOFA's BaseData::genericCopyValueFrom copies each
                // point's three numbers into a box and leaves the three others 0
                std::vector<double> numbers;
                for (const Vec3& p : in.source.current()) numbers.insert(numbers.end(), {p.x(), p.y(), p.z(), 0, 0, 0});
                return numbers_value(std::move(numbers), 6);
            }
    if (const auto refused = live_->refused_reals.find(&c); refused != live_->refused_reals.end() &&
                                                            f.python_form == "ndarray:float64:1" &&
                                                            live_->engine_reals.count({&c, name}) != 0)
        throw std::invalid_argument(refused->second);
    if (LiveEngine* live = live_->engine(c)) {
        live->update_if_dirty();
        if (const auto out = live->reals.find(name); out != live->reals.end()) return numbers_value(out->second, 0);
    }
    if (const auto reals = live_->engine_reals.find({&c, name}); reals != live_->engine_reals.end())
        return numbers_value(reals->second, 0);
    if (const std::vector<PointId>* indices = engine_indices(c, name)) {
        std::vector<double> numbers(indices->begin(), indices->end());
        return numbers_value(std::move(numbers), 0);
    }
    const io::MeshData* mesh = engine_mesh(c, name);
    if (mesh == nullptr && component_category(c.type) == ComponentCategory::loader) mesh = loader_mesh(c);
    if (mesh != nullptr) {
        std::vector<double> numbers;
        const auto flatten = [&](const auto& list, std::size_t width) {
            for (const auto& row : list)
                for (std::size_t k = 0; k < width; ++k) numbers.push_back(double(row[k]));
            return numbers_value(std::move(numbers), width);
        };
        // points: a loader's `position`, an engine's `output_position`, `outputPoints`, `pointsInROI`
        const bool point_list = f.python_form == "ndarray:float64:2";
        // (ValuesFromPositions' `pointVectors`, `edgeVectors`, ...: a vector per point or element)
        if (point_list && (name.find("osition") != std::string::npos || name.find("oints") != std::string::npos ||
                           name.find("Vectors") != std::string::npos))
            return flatten(mesh->positions, 3);
        if (name.find("dge") != std::string::npos) return flatten(mesh->edges, 2);
        if (name.find("riangle") != std::string::npos) return flatten(mesh->triangles, 3);
        if (name.find("uad") != std::string::npos) return flatten(mesh->quads, 4);
        if (name.find("etra") != std::string::npos) return flatten(mesh->tetrahedra, 4);
        if (name.find("exa") != std::string::npos) return flatten(mesh->hexahedra, 8);
        if (name == "listRadius") return numbers_value(mesh->radii, 0);
    }
    if (auto topology = topology_value(c, f)) return topology;
    if (c.type == "UniformMass" && node != nullptr && node->mass() != nullptr &&
        (name == "vertexMass" || name == "totalMass")) {
        const BaseMass& m = *node->mass();
        const double n = m.state() != nullptr ? double(m.state()->num_dofs()) : 0.0;
        const double total = m.total_mass();
        const double vertex = n > 0 ? total / n : 0.0;
        if (f.python_form == "float") return numbers_value({name == "vertexMass" ? vertex : total}, 0);
    }
    return std::nullopt;
}

std::optional<DataValue> Scene::topology_value(const io::SceneComponent& c, const DataField& f) const {
    const ComponentSpec* spec = find_component(c.type);
    if (spec == nullptr || spec->family != ComponentFamily::topology) return std::nullopt;
    const std::string node_path = c.node->path();
    const output::StateRecord* record = nullptr;
    for (const output::StateRecord& r : states_)
        if (r.node_path == node_path) record = &r;
    if (record == nullptr) return std::nullopt;
    // the node's topology is its last one (SOFA's node keeps the last)
    const io::SceneComponent* last = nullptr;
    for (const auto& other : c.node->components) {
        const ComponentSpec* o = find_component(other->type);
        if (o != nullptr && o->family == ComponentFamily::topology) last = other.get();
    }
    const std::string& name = f.name;
    std::vector<double> numbers;
    const auto flatten = [&](const auto& list, std::size_t width) {
        for (const auto& row : list)
            for (std::size_t k = 0; k < width; ++k) numbers.push_back(double(row[k]));
        return numeric_value(f, std::move(numbers), width);
    };
    if (last == &c && record->topology != nullptr && !c.has(name)) {
        const MeshTopology& t = *record->topology;
        if (name == "edges") return flatten(t.edges(), 2);
        if (name == "triangles") return flatten(t.triangles(), 3);
        if (name == "quads") return flatten(t.quads(), 4);
        if (name == "tetrahedra" || name == "tetras") return flatten(t.tetrahedra(), 4);
        if (name == "hexahedra" || name == "hexas") return flatten(t.hexahedra(), 8);
    }
    if (name == "position" && !c.has("position")) {
        if (c.has("src")) {
            const io::LinkTarget t = io::resolve_link(c, "src");
            if (t.component != nullptr)
                if (const io::MeshData* mesh = loader_mesh(*t.component)) return flatten(mesh->positions, 3);
        }
        if (const auto* v = dynamic_cast<const Vec3Object*>(record->state); v != nullptr && last == &c)
            return flatten(v->rest_position, 3);  // a grid's points: its state's rest positions
    }
    return std::nullopt;
}

std::vector<double> Scene::state_vector_numbers(const BaseState& s, StateVector which) {
    std::vector<double> out;
    if (const auto* v = dynamic_cast<const Vec3Object*>(&s)) {
        const std::vector<Vec3>* list = which == StateVector::position        ? &v->position
                                        : which == StateVector::velocity      ? &v->velocity
                                        : which == StateVector::force         ? &v->force
                                        : which == StateVector::rest_position ? &v->rest_position
                                                                              : &v->external_force;
        for (const Vec3& p : *list) out.insert(out.end(), {p.x(), p.y(), p.z()});
    } else if (const auto* w = dynamic_cast<const Vec1Object*>(&s)) {
        const std::vector<double>& list = which == StateVector::position        ? w->position
                                          : which == StateVector::velocity      ? w->velocity
                                          : which == StateVector::force         ? w->force
                                          : which == StateVector::rest_position ? w->rest_position
                                                                                : w->external_force;
        out = list;
    } else if (const auto* r = dynamic_cast<const Rigid3Object*>(&s)) {
        if (which == StateVector::position || which == StateVector::rest_position) {
            for (const RigidFrame& f : which == StateVector::position ? r->position : r->rest_position) {
                const auto q = f.orientation.coeffs();  // x y z w
                out.insert(out.end(), {f.center.x(), f.center.y(), f.center.z(), q[0], q[1], q[2], q[3]});
            }
        } else {
            for (const RigidDeriv& d : which == StateVector::velocity ? r->velocity
                                       : which == StateVector::force  ? r->force
                                                                      : r->external_force)
                out.insert(out.end(),
                           {d.linear.x(), d.linear.y(), d.linear.z(), d.angular.x(), d.angular.y(), d.angular.z()});
        }
    }
    return out;
}

}  // namespace penalty::scene
