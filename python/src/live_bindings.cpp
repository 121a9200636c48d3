// The live scene from Python (SofaPython3's object model, penalty/sofa_api): Data of any component
// or node by path and name (Scene::data_fields, data, set_data, reinit), components added or
// removed after init, SOFA's events of the collision phase, steps with a given dt, the assembled
// matrices of a force field or mass, and the build of a script's tree with its Python components.
#include "py_scene.hpp"
#include "python_components.hpp"

#include "penalty/io/error.hpp"
#include "penalty/scene/components.hpp"

#include <pybind11/functional.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <cstring>

namespace penalty::python {

namespace {

using scene::DataOwner;
using scene::DataValue;
using scene::Scene;

/// numpy dtype of a python_form "ndarray:<dtype>:<ndim>".
py::dtype dtype_of(std::string_view form) {
    if (form.find("int32") != std::string_view::npos) return py::dtype::of<std::int32_t>();
    if (form.find("float32") != std::string_view::npos) return py::dtype::of<float>();
    return py::dtype::of<double>();
}

/// A state vector's memory as a numpy array (no copy) owned by `owner`; Rigid3d frames (padded)
/// are copied.
py::object state_array(const DataValue& v, py::handle owner, bool writeable) {
    BaseState* s = v.state;
    const auto view_of = [&](auto& list) -> py::object {
        using T = typename std::decay_t<decltype(list)>::value_type;
        constexpr py::ssize_t width = sizeof(T) / sizeof(double);
        py::array a = view(list.empty() ? nullptr : reinterpret_cast<double*>(list.data()), py::ssize_t(list.size()),
                           width, sizeof(T), owner);
        if (!writeable) a.attr("flags").attr("writeable") = false;
        return a;
    };
    using scene::StateVector;
    // a Vec3 or Vec1 state's vectors ((n, 1) for Vec1, as SofaPython3's Vec1d)
    const auto vector_of = [&](auto& x) -> py::object {
        switch (v.state_vector) {
            case StateVector::position:
                return view_of(x.position);
            case StateVector::velocity:
                return view_of(x.velocity);
            case StateVector::force:
                return view_of(x.force);
            case StateVector::rest_position:
                return view_of(x.rest_position);
            default:
                return view_of(x.external_force);
        }
    };
    if (auto* x = dynamic_cast<Vec3Object*>(s)) return vector_of(*x);
    if (auto* x = dynamic_cast<Vec1Object*>(s)) return vector_of(*x);
    auto* r = dynamic_cast<Rigid3Object*>(s);
    switch (v.state_vector) {
        case StateVector::velocity:
            return view_of(r->velocity);
        case StateVector::force:
            return view_of(r->force);
        case StateVector::external_force:
            return view_of(r->external_force);
        default:
            break;
    }
    py::array_t<double> a({py::ssize_t(v.numbers.size() / 7), py::ssize_t(7)});
    std::memcpy(a.mutable_data(), v.numbers.data(), v.numbers.size() * sizeof(double));
    return a;
}

/// A Data's value as SofaPython3 presents it.
py::object to_python(const DataValue& v, py::handle owner, bool writeable) {
    const std::string_view form = v.python_form;
    if (v.state != nullptr) return state_array(v, owner, writeable);
    if (form == "float") return py::float_(v.numbers.empty() ? 0.0 : v.numbers[0]);
    if (form == "int") return py::int_(static_cast<long long>(v.numbers.empty() ? 0.0 : v.numbers[0]));
    if (form == "list") return py::cast(v.items);
    if (form.substr(0, 8) != "ndarray:") return py::str(v.text);
    const py::dtype dtype = dtype_of(form);
    py::array out;
    if (form.find("int32") != std::string_view::npos) {
        // SOFA's unsigned values in SofaPython3's int32 (4294967295 reads -1), wrapped as C++ does
        py::array_t<std::int32_t> ints(py::ssize_t(v.numbers.size()));
        std::transform(v.numbers.begin(), v.numbers.end(), ints.mutable_data(), [](double x) {
            return static_cast<std::int32_t>(static_cast<std::uint32_t>(static_cast<std::int64_t>(x)));
        });
        out = ints;
    } else {
        py::array_t<double> flat(py::ssize_t(v.numbers.size()));
        std::copy(v.numbers.begin(), v.numbers.end(), flat.mutable_data());
        out = flat.attr("astype")(dtype);
    }
    if (v.columns > 0)
        out = out.attr("reshape")(py::make_tuple(py::ssize_t(v.numbers.size() / v.columns), py::ssize_t(v.columns)));
    return out;
}

py::dict field_dict(const scene::DataField& f) {
    py::dict d;
    d["name"] = f.name;
    d["sofa_type"] = f.sofa_type;
    d["python_form"] = f.python_form;
    d["default"] = f.default_text;
    d["live"] = std::string(scene::live_write_name(f.live));
    d["refusal"] = f.refusal;
    d["read_by_penalty"] = f.spec != nullptr;
    d["link"] = f.python_form == "link";
    d["columns"] = scene::data_field_columns(f);
    return d;
}

/// A component of a script's tree: {"type", "name", "template", "file", "line", "attributes"}.
std::unique_ptr<io::SceneComponent> read_component(const py::dict& d) {
    auto c = std::make_unique<io::SceneComponent>();
    c->type = d["type"].cast<std::string>();
    c->name = d.contains("name") ? d["name"].cast<std::string>() : std::string();
    c->file = d["file"].cast<std::string>();
    c->line = d["line"].cast<int>();
    c->template_name = d.contains("template") ? d["template"].cast<std::string>() : std::string();
    for (const py::handle a : d["attributes"]) {
        auto t = a.cast<py::tuple>();
        c->attributes.push_back(
            io::SceneAttribute{t[0].cast<std::string>(), t[1].cast<std::string>(), t[2].cast<int>()});
    }
    return c;
}

bool has_python_components(const py::dict& node) {
    for (const py::handle o : node["objects"]) {
        const auto type = o.cast<py::dict>()["type"].cast<std::string>();
        if (type == "PythonForceField" || type == "PythonMapping") return true;
    }
    for (const py::handle child : node["children"])
        if (has_python_components(child.cast<py::dict>())) return true;
    return false;
}

void read_node(const py::dict& d, io::SceneNode& node, int depth) {
    if (depth > 256) throw py::value_error("scene tree: nodes nested more than 256 levels deep");
    node.type = "Node";
    node.name = d.contains("name") ? d["name"].cast<std::string>() : std::string();
    node.file = d["file"].cast<std::string>();
    node.line = d["line"].cast<int>();
    for (const py::handle a : d["attributes"]) {
        auto t = a.cast<py::tuple>();
        node.attributes.push_back(
            io::SceneAttribute{t[0].cast<std::string>(), t[1].cast<std::string>(), t[2].cast<int>()});
    }
    for (const py::handle o : d["objects"]) {
        auto c = read_component(o.cast<py::dict>());
        c->node = &node;
        c->index = node.components.size();
        node.components.push_back(std::move(c));
    }
    for (const py::handle ch : d["children"]) {
        auto child = std::make_unique<io::SceneNode>();
        child->parent = &node;
        read_node(ch.cast<py::dict>(), *child, depth + 1);
        node.children.push_back(std::move(child));
    }
}

/// A parsed scene's node as the dict the Python tree reads (Sofa.Simulation.load).
py::dict tree_dict(const io::SceneNode& n) {
    const auto attributes = [](const io::SceneElement& e) {
        py::list out;
        for (const io::SceneAttribute& a : e.attributes) out.append(py::make_tuple(a.name, a.value, a.line));
        return out;
    };
    py::dict d;
    d["name"] = n.name;
    d["file"] = n.file;
    d["line"] = n.line;
    d["attributes"] = attributes(n);
    py::list objects, children;
    for (const auto& c : n.components) {
        py::dict o;
        o["type"] = c->type;
        o["name"] = c->name;
        o["template"] = c->template_name;
        o["file"] = c->file;
        o["line"] = c->line;
        o["attributes"] = attributes(*c);
        objects.append(o);
    }
    for (const auto& child : n.children) children.append(tree_dict(*child));
    d["objects"] = objects;
    d["children"] = children;
    return d;
}

py::object triplets_to_csr(const TripletList& t, Index size) {
    SparseMatrix m(size, size);
    m.setFromTriplets(t.begin(), t.end());
    m.makeCompressed();
    const auto nnz = py::ssize_t(m.nonZeros());
    py::array_t<double> data(nnz);
    py::array_t<std::int64_t> indices(nnz), indptr(py::ssize_t(m.rows() + 1));
    std::copy(m.valuePtr(), m.valuePtr() + nnz, data.mutable_data());
    std::copy(m.innerIndexPtr(), m.innerIndexPtr() + nnz, indices.mutable_data());
    std::copy(m.outerIndexPtr(), m.outerIndexPtr() + m.rows() + 1, indptr.mutable_data());
    py::object csr = py::module_::import("scipy.sparse").attr("csr_matrix");
    return csr(py::make_tuple(data, indices, indptr), py::arg("shape") = py::make_tuple(size, size));
}

/// K (factor 1) of the force field built from the component at `path`: SofaPython3's
/// ForceField.assembleKMatrix (a matrix of the state's size; both states for an interaction).
py::object stiffness_matrix(Scene& s, const std::string& path) {
    const auto* c = static_cast<const io::SceneComponent*>(s.find_element({path, false}));
    if (c == nullptr) throw py::key_error("no component '" + path + "'");
    const Node* node = s.node_of(*c->node);
    if (node != nullptr)
        for (const auto& ff : node->force_fields()) {
            if (s.component_of(ff.get()) != c) continue;
            const ForceFieldStates states = ff->states();
            Index size = 0;
            std::vector<std::pair<const BaseState*, Index>> offsets;
            for (BaseState* st : states) {
                offsets.emplace_back(st, size);
                size += Index(st->num_dofs()) * st->deriv_size();
            }
            TripletList t;
            ff->add_stiffness(
                t,
                [&](const BaseState* st) {
                    for (const auto& [state, offset] : offsets)
                        if (state == st) return offset;
                    return size;
                },
                1.0);
            std::erase_if(t, [&](const Triplet& x) { return x.row() >= size || x.col() >= size; });
            return triplets_to_csr(t, size);
        }
    throw py::value_error(c->describe() + ": not a force field of the built scene");
}

/// The force field built from the component at `path`, with its one Vec3d state.
std::pair<BaseForceField*, Vec3Object*> vec3_force_field(Scene& s, const std::string& path) {
    const auto* c = static_cast<const io::SceneComponent*>(s.find_element({path, false}));
    if (c == nullptr) throw py::key_error("no component '" + path + "'");
    const Node* node = s.node_of(*c->node);
    if (node != nullptr)
        for (const auto& ff : node->force_fields()) {
            if (s.component_of(ff.get()) != c) continue;
            auto* state = ff->states().size() == 1 ? dynamic_cast<Vec3Object*>(ff->states()[0]) : nullptr;
            if (state == nullptr)
                throw py::value_error(c->describe() + ": the probe takes force fields on one Vec3d state");
            return {ff.get(), state};
        }
    throw py::value_error(c->describe() + ": not a force field of the built scene");
}

/// Copies an (n, 3) array into points (shape checked).
void assign_points(std::vector<Vec3>& to, const py::handle& from, const char* what) {
    auto a = as_points(from, what);
    if (std::size_t(a.shape(0)) != to.size())
        throw py::value_error(std::string(what) + ": expected " + std::to_string(to.size()) + " points");
    for (std::size_t i = 0; i < to.size(); ++i)
        to[i] = Vec3(a.at(py::ssize_t(i), 0), a.at(py::ssize_t(i), 1), a.at(py::ssize_t(i), 2));
}

py::array_t<double> points_copy(const std::vector<Vec3>& p) {
    py::array_t<double> out({py::ssize_t(p.size()), py::ssize_t(3)});
    auto w = out.mutable_unchecked<2>();
    for (std::size_t i = 0; i < p.size(); ++i)
        for (int k = 0; k < 3; ++k) w(py::ssize_t(i), k) = p[i][k];
    return out;
}

/// f(x, v) of one force field alone (the state's vectors are restored after): the probe the
/// finite-difference checks of tests/python use for C++ and Python force fields alike.
py::array_t<double> probe_force(Scene& s, const std::string& path, const py::handle& x, const py::handle& v) {
    auto [ff, state] = vec3_force_field(s, path);
    const std::vector<Vec3> position = state->position, velocity = state->velocity, force = state->force;
    assign_points(state->position, x, "x");
    assign_points(state->velocity, v, "v");
    std::fill(state->force.begin(), state->force.end(), Vec3::Zero());
    py::array_t<double> out;
    try {
        ff->accumulate_force();
        out = points_copy(state->force);
    } catch (...) {
        state->position = position, state->velocity = velocity, state->force = force;
        throw;
    }
    state->position = position, state->velocity = velocity, state->force = force;
    return out;
}

/// k·K·dx + b·B·dx of one force field, linearised at its last probe_force (or step).
py::array_t<double> probe_dforce(Scene& s, const std::string& path, const py::handle& dx, double k, double b) {
    auto [ff, state] = vec3_force_field(s, path);
    const std::vector<Vec3> saved_dx = state->dx, saved_df = state->df;
    state->dx.resize(state->num_dofs());
    state->df.assign(state->num_dofs(), Vec3::Zero());
    assign_points(state->dx, dx, "dx");
    py::array_t<double> out;
    try {
        ff->accumulate_dforce(k, b);
        out = points_copy(state->df);
    } catch (...) {
        state->dx = saved_dx, state->df = saved_df;
        throw;
    }
    state->dx = saved_dx, state->df = saved_df;
    return out;
}

/// M of the mass built from the component at `path` (SofaPython3's Mass.assembleMMatrix).
py::object mass_matrix(Scene& s, const std::string& path) {
    const auto* c = static_cast<const io::SceneComponent*>(s.find_element({path, false}));
    if (c == nullptr) throw py::key_error("no component '" + path + "'");
    const Node* node = s.node_of(*c->node);
    if (node == nullptr || node->mass() == nullptr || s.component_of(node->mass()) != c)
        throw py::value_error(c->describe() + ": not a mass of the built scene");
    const BaseState* st = node->mass()->state();
    const Index size = Index(st->num_dofs()) * st->deriv_size();
    TripletList t;
    node->mass()->add_mass_triplets(t, 0, 1.0);
    return triplets_to_csr(t, size);
}

/// The live Data, structure changes, events, steps with a dt, matrices and probes of a scene.
void add_live_methods(py::class_<PyScene>& cls) {
    cls.def("_data_fields",
            [](PyScene& s, const std::string& path, bool node) {
                py::list out;
                for (const scene::DataField& f : s.scene->data_fields({path, node})) out.append(field_dict(f));
                return out;
            })
        .def(
            "_data",
            [](py::object self, const std::string& path, bool node, const std::string& name, bool writeable) {
                PyScene& s = self.cast<PyScene&>();
                return to_python(s.scene->data({path, node}, name), self, writeable);
            },
            py::arg("path"), py::arg("node"), py::arg("name"), py::arg("writeable") = false)
        .def("_data_text",
             [](PyScene& s, const std::string& path, bool node, const std::string& name) {
                 return s.scene->data({path, node}, name).text;
             })
        .def("_set_data",
             [](PyScene& s, const std::string& path, bool node, const std::string& name, const std::string& text) {
                 s.scene->set_data({path, node}, name, text);
             })
        .def("_set_state",
             [](PyScene& s, const std::string& path, const std::string& name, const py::handle& value) {
                 const auto* c = static_cast<const io::SceneComponent*>(s.scene->find_element({path, false}));
                 const Node* node = c != nullptr ? s.scene->node_of(*c->node) : nullptr;
                 if (node == nullptr || node->state() == nullptr) throw py::key_error("no built state '" + path + "'");
                 auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
                 if (!a) throw py::type_error(path + "." + name + ": expected an array of numbers");
                 const std::vector<double> values(a.data(), a.data() + a.size());
                 s.scene->write_state(*node->state(), name, values, c->describe() + ": data '" + name + "'");
             })
        .def("_reinit",
             [](PyScene& s, const std::string& path, bool node) {
                 s.scene->reinit({path, node});
             })
        .def("_add_component",
             [](PyScene& s, const std::string& node_path, const py::dict& component) {
                 return s.scene->add_to_node(node_path, read_component(component));
             })
        .def("_add_node", [](PyScene& s, const std::string& node_path,
                             const std::string& name) { return s.scene->add_to_node(node_path, nullptr, name); })
        .def("_remove",
             [](PyScene& s, const std::string& path, bool node) {
                 s.scene->remove({path, node});
             })
        .def("_apply_pending", [](PyScene& s) { s.scene->apply_pending_writes(); })
        .def_property_readonly("_generation", [](const PyScene& s) { return s.scene->generation(); })
        .def("_set_event_listener",
             [](PyScene& s, py::object listener) {
                 if (listener.is_none()) return s.scene->set_event_listener(nullptr);
                 s.scene->set_event_listener([listener](std::string_view event) { listener(std::string(event)); });
             })
        .def("_step_with_dt",
             [](PyScene& s, double dt) {
                 // Sofa.Simulation.animate(root, dt): this step with `dt`, the root's dt unchanged.
                 Node& root = s.scene->simulation().root();
                 const double kept = root.dt();
                 root.set_dt(dt);
                 try {
                     s.scene->step();
                 } catch (...) {
                     root.set_dt(kept);
                     throw;
                 }
                 root.set_dt(kept);
             })
        .def("_reset", [](PyScene& s) { s.scene->reset(); })
        .def("_set_threads",
             [](PyScene& s, int threads) {
                 // Python components run on the calling thread, which holds the GIL
                 if (s.scene->build_options().threads != 1) s.scene->simulation().set_threads(threads);
             })
        .def("_set_gravity_write_delay", [](PyScene& s, bool delay) { s.scene->set_gravity_write_delay(delay); })
        .def("_run_hooks", [](PyScene& s, bool before) { s.call_hooks(before ? s.before_step : s.after_step); })
        .def("_energy_pair",
             [](PyScene& s) { return py::make_tuple(s.scene->kinetic_energy(), s.scene->potential_energy()); })
        .def("_stiffness_matrix", [](PyScene& s, const std::string& path) { return stiffness_matrix(*s.scene, path); })
        .def("_probe_force", [](PyScene& s, const std::string& path, const py::handle& x,
                                const py::handle& v) { return probe_force(*s.scene, path, x, v); })
        .def("_probe_dforce", [](PyScene& s, const std::string& path, const py::handle& dx, double k,
                                 double b) { return probe_dforce(*s.scene, path, dx, k, b); })
        .def("_mass_matrix", [](PyScene& s, const std::string& path) { return mass_matrix(*s.scene, path); });
}

/// The build of a script's tree, SOFA's catalog and the registry's declarations.
void add_module_functions(py::module_& m) {
    m.def(
        "_build_live_tree",
        [](const py::dict& root, const std::filesystem::path& path, const std::vector<std::filesystem::path>& data_dirs,
           std::optional<double> dt, int threads, bool exhaustive, std::vector<std::string> overrides,
           py::object dispatch, py::object resolve, const std::vector<std::string>& quirk_fixes) {
            io::SceneFile file;
            file.path = path;
            file.root = std::make_unique<io::SceneNode>();
            read_node(root, *file.root, 0);
            scene::BuildOptions o;
            o.overrides = std::move(overrides);
            o.data_dirs = data_dirs;
            o.dt = dt;
            o.threads = threads;
            o.exhaustive_detection = exhaustive;
            for (const std::string& name : quirk_fixes)  // --fix-sofa-quirk NAME (docs/sofa-compatibility.md)
                if (!enable_sofa_quirk_fix(o.sofa_quirk_fixes, name))
                    throw py::value_error("fix_sofa_quirks: unknown SOFA quirk '" + name +
                                          "' (penalty info lists them)");
            // Python components run on the calling thread, which holds the GIL: one thread.
            if (has_python_components(root)) o.threads = 1;
            o.external = std::make_shared<PythonComponents>(std::move(dispatch), std::move(resolve));
            PyScene s;
            s.scene = scene::build_scene(std::move(file), o);
            return s;
        },
        py::arg("root"), py::arg("path"), py::arg("data_dirs"), py::arg("dt"), py::arg("threads"),
        py::arg("exhaustive"), py::arg("overrides"), py::arg("dispatch"), py::arg("resolve"),
        py::arg("fix_sofa_quirks") = std::vector<std::string>{},
        "Builds a scene from a SofaPython3 script's tree, with its Python force fields and mappings");
    m.def(
        "_parse_scene_tree",
        [](const std::filesystem::path& path, const std::vector<std::filesystem::path>& data_dirs) {
            const io::SceneFile file = io::parse_scene_file(path, data_dirs);
            return tree_dict(*file.root);
        },
        "A .scn file as nested dicts (name, file, line, attributes, objects, children)");
    m.def(
        "_sofa_data_catalog",
        [](const std::string& type, bool rigid) {
            py::list out;
            for (const scene::CatalogEntry& e : scene::sofa_data_catalog(type, rigid))
                out.append(py::make_tuple(e.name, e.sofa_type, e.python_form, e.default_text, e.link));
            return out;
        },
        "SOFA's Data of a type: (name, SOFA type, Python form, default, is link) rows");
    m.def(
        "_type_fields",
        [](const std::string& type, bool node, bool rigid) {
            py::list out;
            for (const scene::DataField& f : scene::data_fields_of_type(type, node, rigid)) out.append(field_dict(f));
            return out;
        },
        "The Data of a component type (or of nodes), as _data_fields gives them for a built component");
    m.def(
        "_sofa_class_name",
        [](const std::string& type) {
            const scene::ComponentSpec* c = scene::find_component(type);
            return c != nullptr && !c->sofa_class.empty() ? std::string(c->sofa_class) : type;
        },
        "SOFA's class of a type (an older name gives its current class)");
    m.def(
        "_registry_attribute_defaults",
        [](const std::string& type) {
            py::list out;
            if (const scene::ComponentSpec* c = scene::find_component(type)) {
                for (const scene::AttributeSpec& a : c->attributes)
                    out.append(py::make_tuple(std::string(a.name), std::string(a.default_value)));
                for (const scene::AttributeSpec& a : c->shared_attributes)
                    out.append(py::make_tuple(std::string(a.name), std::string(a.default_value)));
            }
            return out;
        },
        "(attribute, default as the registry writes it) of a component type");
    m.def("_component_types", [] {
        py::list out;
        for (const scene::ComponentSpec& c : scene::component_registry()) out.append(std::string(c.type));
        return out;
    });
}

}  // namespace

void bind_live(py::module_& m) {
    auto cls = py::reinterpret_borrow<py::class_<PyScene>>(m.attr("Scene"));
    add_live_methods(cls);
    add_module_functions(m);
}

}  // namespace penalty::python
