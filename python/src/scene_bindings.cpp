// Scenes from Python: build (from a .scn file or from the node tree a SofaPython3 script made),
// step, states as numpy views of the C++ vectors, contacts and energies as arrays, run with the
// CLI's writers.
#include "py_scene.hpp"

#include "penalty/io/overrides.hpp"
#include "penalty/io/scene_file.hpp"
#include "penalty/output/format.hpp"
#include "penalty/output/stats_csv.hpp"
#include "penalty/scene/contact_advice.hpp"
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <tbb/global_control.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

namespace penalty::python {

namespace {

using scene::Scene;

Vec3Object* vec3_of(const PyState& s) { return dynamic_cast<Vec3Object*>(s.record->state); }
Rigid3Object* rigid_of(const PyState& s) { return dynamic_cast<Rigid3Object*>(s.record->state); }
Vec1Object* vec1_of(const PyState& s) { return dynamic_cast<Vec1Object*>(s.record->state); }

/// A Vec1d state's values as an (n, 1) view.
py::array_t<double> vec1_view(std::vector<double>& v, py::handle owner) {
    return view(v.data(), py::ssize_t(v.size()), 1, sizeof(double), owner);
}

template <class T>
py::array_t<double> vec3_view(std::vector<T>& v, py::handle owner) {
    static_assert(sizeof(T) == 3 * sizeof(double));
    return view(v.empty() ? nullptr : v.data()->data(), py::ssize_t(v.size()), 3, sizeof(T), owner);
}

py::array_t<double> rigid_deriv_view(std::vector<RigidDeriv>& v, py::handle owner) {
    return view(v.empty() ? nullptr : v.data()->linear.data(), py::ssize_t(v.size()), 6, sizeof(RigidDeriv), owner);
}

/// Rigid frames as (n, 7) x y z qx qy qz qw. A copy: the frame is padded in memory (the
/// quaternion is 16-byte aligned), so no strided view covers the 7 numbers; `centers` and
/// `orientations` are the views.
py::array_t<double> rigid_copy(const std::vector<RigidFrame>& frames) {
    py::array_t<double> out({py::ssize_t(frames.size()), py::ssize_t(7)});
    auto a = out.mutable_unchecked<2>();
    for (std::size_t i = 0; i < frames.size(); ++i) {
        for (int j = 0; j < 3; ++j) a(py::ssize_t(i), j) = frames[i].center[j];
        for (int j = 0; j < 4; ++j) a(py::ssize_t(i), 3 + j) = frames[i].orientation.coeffs()[j];
    }
    return out;
}

/// A ValueError naming `what` and the row when an array to write into a state is not finite.
void check_finite(const py::array_t<double, py::array::c_style | py::array::forcecast>& a, const char* what) {
    const py::ssize_t columns = a.ndim() == 2 ? a.shape(1) : 1;
    for (py::ssize_t i = 0; i < a.size(); ++i)
        if (!std::isfinite(a.data()[i]))
            throw py::value_error(std::string(what) + ": row " + std::to_string(i / std::max<py::ssize_t>(1, columns)) +
                                  " holds " + output::format_number(a.data()[i]) + " (every value must be finite)");
}

void rigid_assign(std::vector<RigidFrame>& frames, const py::handle& value, const char* what) {
    (void)numeric_kind(value, what);
    const auto a = numbers_array<double>(value, what);
    if (a.ndim() != 2 || a.shape(0) != py::ssize_t(frames.size()) || a.shape(1) != 7)
        throw py::value_error(std::string(what) + ": expected shape (" + std::to_string(frames.size()) + ", 7)");
    check_finite(a, what);
    auto r = a.unchecked<2>();
    for (py::ssize_t i = 0; i < r.shape(0); ++i)
        if (!(r(i, 3) * r(i, 3) + r(i, 4) * r(i, 4) + r(i, 5) * r(i, 5) + r(i, 6) * r(i, 6) > 0.0))
            throw py::value_error(std::string(what) + ": frame " + std::to_string(i) + " has a zero quaternion");
    for (std::size_t i = 0; i < frames.size(); ++i) {
        frames[i].center = Vec3(r(py::ssize_t(i), 0), r(py::ssize_t(i), 1), r(py::ssize_t(i), 2));
        frames[i].orientation =
            Quat(r(py::ssize_t(i), 6), r(py::ssize_t(i), 3), r(py::ssize_t(i), 4), r(py::ssize_t(i), 5));
        frames[i].orientation.normalize();
    }
}

template <class T>
void vec_assign(py::array_t<double> target, const py::handle& value, const char* what) {
    (void)numeric_kind(value, what);
    const auto src = numbers_array<double>(value, what);
    if (src.ndim() != target.ndim() || src.shape(0) != target.shape(0) || src.shape(1) != target.shape(1))
        throw py::value_error(std::string(what) + ": expected shape (" + std::to_string(target.shape(0)) + ", " +
                              std::to_string(target.shape(1)) + ")");
    check_finite(src, what);
    auto t = target.mutable_unchecked<2>();
    auto s = src.unchecked<2>();
    for (py::ssize_t i = 0; i < t.shape(0); ++i)
        for (py::ssize_t j = 0; j < t.shape(1); ++j) t(i, j) = s(i, j);
}

enum class Field { positions, velocities, forces, rest_positions, external_forces };

py::object state_field(const py::object& self, Field field) {
    const PyState& s = self.cast<const PyState&>();
    if (Vec3Object* v = vec3_of(s)) {
        switch (field) {
            case Field::positions:
                return vec3_view(v->position, self);
            case Field::velocities:
                return vec3_view(v->velocity, self);
            case Field::forces:
                return vec3_view(v->force, self);
            case Field::rest_positions:
                return vec3_view(v->rest_position, self);
            case Field::external_forces:
                return vec3_view(v->external_force, self);
        }
    }
    if (Rigid3Object* r = rigid_of(s)) {
        switch (field) {
            case Field::positions:
                return rigid_copy(r->position);
            case Field::rest_positions:
                return rigid_copy(r->rest_position);
            case Field::velocities:
                return rigid_deriv_view(r->velocity, self);
            case Field::forces:
                return rigid_deriv_view(r->force, self);
            case Field::external_forces:
                return rigid_deriv_view(r->external_force, self);
        }
    }
    if (Vec1Object* d = vec1_of(s)) {
        switch (field) {
            case Field::positions:
                return vec1_view(d->position, self);
            case Field::velocities:
                return vec1_view(d->velocity, self);
            case Field::forces:
                return vec1_view(d->force, self);
            case Field::rest_positions:
                return vec1_view(d->rest_position, self);
            case Field::external_forces:
                return vec1_view(d->external_force, self);
        }
    }
    throw py::type_error("state '" + output::state_label(*s.record) + "' is neither Vec3d, Rigid3d nor Vec1d");
}

void set_state_field(const py::object& self, Field field, const py::handle& value, const char* what) {
    const PyState& s = self.cast<const PyState&>();
    if (Rigid3Object* r = rigid_of(s)) {
        if (field == Field::positions) return rigid_assign(r->position, value, what);
        if (field == Field::rest_positions) return rigid_assign(r->rest_position, value, what);
    }
    vec_assign<double>(state_field(self, field).cast<py::array_t<double>>(), value, what);
}

py::dict contacts_dict(const Scene& scene) {
    const auto& records = scene.contacts();
    std::size_t n = 0;
    for (const auto& r : records) n += r.field->size();
    const auto rows = py::ssize_t(n);
    py::array_t<std::int64_t> pair_index(rows), element1(rows), element2(rows), age(rows), dof1(rows), dof2(rows);
    py::array_t<std::int8_t> friction(rows);
    py::array_t<double> point1({rows, py::ssize_t(3)}), point2({rows, py::ssize_t(3)}), normal({rows, py::ssize_t(3)}),
        tangential({rows, py::ssize_t(3)}), dist(rows), pen(rows), normal_force(rows), ks(rows);
    auto P1 = point1.mutable_unchecked<2>(), P2 = point2.mutable_unchecked<2>(), N = normal.mutable_unchecked<2>(),
         T = tangential.mutable_unchecked<2>();
    py::list pairs;
    py::ssize_t i = 0;
    for (std::size_t p = 0; p < records.size(); ++p) {
        const output::ContactRecord& r = records[p];
        pairs.append(r.name);
        for (const PenaltyContact& c : r.field->contacts()) {
            pair_index.mutable_at(i) = std::int64_t(p);
            element1.mutable_at(i) = c.index1;
            element2.mutable_at(i) = c.index2;
            dof1.mutable_at(i) = c.m1;
            dof2.mutable_at(i) = c.m2;
            age.mutable_at(i) = c.age;
            friction.mutable_at(i) = std::int8_t(c.friction_state);
            const Vec3& x1 = r.state1->position.at(std::size_t(c.m1));
            const Vec3& x2 = r.state2->position.at(std::size_t(c.m2));
            for (int j = 0; j < 3; ++j) {
                P1(i, j) = x1[j];
                P2(i, j) = x2[j];
                N(i, j) = c.normal[j];
                T(i, j) = c.tangential_force[j];
            }
            dist.mutable_at(i) = c.dist;
            pen.mutable_at(i) = c.pen;
            normal_force.mutable_at(i) = c.normal_force;
            ks.mutable_at(i) = c.ks;
            ++i;
        }
    }
    py::dict d;
    d["pairs"] = pairs;  // names "<model1>-<model2>", indexed by pair_index
    d["pair_index"] = pair_index;
    d["element1"] = element1;
    d["element2"] = element2;
    d["dof1"] = dof1;
    d["dof2"] = dof2;
    d["point1"] = point1;
    d["point2"] = point2;
    d["normal"] = normal;
    d["dist"] = dist;
    d["stiffness"] = ks;
    d["penetration"] = pen;
    d["normal_force"] = normal_force;
    d["tangential_force"] = tangential;
    d["friction_state"] = friction;  // 0 none, 1 sticking, 2 sliding
    d["age"] = age;
    return d;
}

py::dict energies_dict(const Scene& scene) {
    double stored = 0.0, by_damping = 0.0, by_sliding = 0.0;
    for (const auto& r : scene.contacts()) {
        stored += r.field->potential_energy();
        by_damping += r.field->dissipated_by_damping();
        by_sliding += r.field->dissipated_by_sliding();
    }
    py::dict d;
    d["kinetic"] = scene.kinetic_energy();
    d["contact"] = stored;
    d["dissipated_damping"] = by_damping;
    d["dissipated_friction"] = by_sliding;
    d["dissipated"] = by_damping + by_sliding;
    return d;
}

/// The matrix of one component of the file (SofaPython3's ForceField.assembleKMatrix, K with
/// kFactor 1; Mass.assembleMMatrix, M), as (rows, columns, values, size) of its state's scalars:
/// component `index` of the file's node `node_path` (controllers not counted).
py::tuple component_matrix(const Scene& scene, const std::string& node_path, std::size_t index,
                           const std::string& kind) {
    const io::SceneNode* found = nullptr;
    std::function<void(const io::SceneNode&)> visit = [&](const io::SceneNode& sn) {
        if (found == nullptr && sn.path() == node_path) found = &sn;
        for (const auto& child : sn.children) visit(*child);
    };
    visit(*scene.file().root);
    if (found == nullptr || index >= found->components.size())
        throw py::value_error("no such component in the built scene");
    const io::SceneComponent* component = found->components[index].get();
    const Node* node = scene.node_of(*found);
    TripletList triplets;
    std::size_t size = 0;
    if (node != nullptr && kind == "M" && node->mass() != nullptr && scene.component_of(node->mass()) == component) {
        node->mass()->add_mass_triplets(triplets, 0, 1.0);
        size = node->mass()->state()->scalar_size();
    } else if (node != nullptr && kind == "K") {
        for (const auto& ff : node->force_fields()) {
            if (scene.component_of(ff.get()) != component) continue;
            const ForceFieldStates states = ff->states();
            if (states.size() != 1)
                throw py::value_error(component->describe() + ": assembleKMatrix of an interaction force field");
            ff->add_stiffness(
                triplets, [](const BaseState*) { return Index{0}; }, 1.0);
            size = states[0]->scalar_size();
        }
    }
    if (size == 0)
        throw py::value_error(component->describe() +
                              (kind == "M" ? " is not a mass penalty built" : " is not a force field penalty built"));
    std::vector<Index> rows, cols;
    std::vector<double> values;
    for (const Triplet& t : triplets) {
        rows.push_back(t.row());
        cols.push_back(t.col());
        values.push_back(t.value());
    }
    return py::make_tuple(rows, cols, values, size);
}

py::dict info_dict(const Scene& scene) {
    py::list nodes, components, pipelines;
    std::function<void(const io::SceneNode&)> visit = [&](const io::SceneNode& sn) {
        py::dict node;
        node["path"] = sn.path();
        node["name"] = sn.name;
        if (const Node* built = scene.node_of(sn)) {
            node["dt"] = built->dt();
            const Vec3 g = built->gravity();
            node["gravity"] = py::make_tuple(g[0], g[1], g[2]);
        }
        nodes.append(node);
        for (const auto& c : sn.components) {
            py::dict comp;
            comp["node"] = sn.path();
            comp["type"] = c->type;
            comp["name"] = c->name;
            comp["template"] = c->template_name;
            comp["file"] = c->file;
            comp["line"] = c->line;
            const std::string role = scene.role(*c);
            comp["role"] = role;
            comp["built"] = !role.empty();
            components.append(comp);
        }
        for (const auto& child : sn.children) visit(*child);
    };
    visit(*scene.file().root);
    for (const auto& p : scene.pipelines()) {
        py::dict d;
        d["name"] = p.name;
        d["intersection"] = intersection_method_short_name(p.intersection);
        py::list models;
        for (const auto* m : p.models)
            models.append(m->component != nullptr ? m->component->describe() : std::string());
        d["models"] = models;
        pipelines.append(d);
    }
    py::dict d;
    d["nodes"] = nodes;
    d["components"] = components;
    d["pipelines"] = pipelines;
    d["warnings"] = scene.warnings();
    d["text"] = scene::describe_scene(scene);
    return d;
}

// --- the node tree a SofaPython3 script builds, as nested dicts -----------------------------
// node:      {"name", "file", "line", "attributes": [(name, value, line)], "objects": [...],
//             "children": [...]}
// object:    {"type", "name", "template", "file", "line", "attributes": [(name, value, line)]}
// Values are SOFA's text form (the Python front end converts numbers, lists and arrays).

void read_attributes(const py::dict& d, io::SceneElement& e) {
    e.name = d.contains("name") ? d["name"].cast<std::string>() : std::string();
    e.file = d["file"].cast<std::string>();
    e.line = d["line"].cast<int>();
    for (const py::handle a : d["attributes"]) {
        auto t = a.cast<py::tuple>();
        e.attributes.push_back(
            io::SceneAttribute{t[0].cast<std::string>(), t[1].cast<std::string>(), t[2].cast<int>()});
    }
}

void read_tree_node(const py::dict& d, io::SceneNode& node, int depth) {
    if (depth > 256) throw py::value_error("scene tree: nodes nested more than 256 levels deep");
    node.type = "Node";
    read_attributes(d, node);
    for (const py::handle o : d["objects"]) {
        auto od = o.cast<py::dict>();
        auto c = std::make_unique<io::SceneComponent>();
        c->type = od["type"].cast<std::string>();
        read_attributes(od, *c);
        c->template_name = od.contains("template") ? od["template"].cast<std::string>() : std::string();
        c->node = &node;
        c->index = node.components.size();
        node.components.push_back(std::move(c));
    }
    for (const py::handle ch : d["children"]) {
        auto child = std::make_unique<io::SceneNode>();
        child->parent = &node;
        read_tree_node(ch.cast<py::dict>(), *child, depth + 1);
        node.children.push_back(std::move(child));
    }
}

scene::BuildOptions build_options(const std::vector<std::filesystem::path>& data_dirs, std::optional<double> dt,
                                  int threads, bool exhaustive, std::vector<std::string> overrides = {},
                                  const std::vector<std::string>& quirk_fixes = {}) {
    scene::BuildOptions o;
    for (const std::string& name : quirk_fixes)  // --fix-sofa-quirk NAME (docs/sofa-compatibility.md)
        if (!enable_sofa_quirk_fix(o.sofa_quirk_fixes, name))
            throw py::value_error("fix_sofa_quirks: unknown SOFA quirk '" + name + "' (penalty info lists them)");
    o.overrides = std::move(overrides);
    o.data_dirs = data_dirs;
    o.dt = dt;
    o.threads = threads;
    o.exhaustive_detection = exhaustive;
    return o;
}

/// One progress line on stderr when it is a terminal (as `penalty run`).
void print_progress(std::int64_t done, std::int64_t total, double time) {
    const int width = 30;
    const int filled = total > 0 ? int(double(width) * double(done) / double(total)) : width;
    std::fprintf(stderr, "\r[%s%s] %3d%%  step %lld/%lld  t = %.4g s ", std::string(std::size_t(filled), '#').c_str(),
                 std::string(std::size_t(width - filled), '.').c_str(), total > 0 ? int(100 * done / total) : 100,
                 static_cast<long long>(done), static_cast<long long>(total), time);
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
}

/// The summary as `penalty run --summary-json` writes it (scene::summary_json: one definition).
py::dict summary_dict(const scene::RunSummary& s) {
    return py::module_::import("json").attr("loads")(scene::summary_json(s));
}

}  // namespace

void bind_scene(py::module_& m) {
    py::class_<PyState>(m, "State", "A MechanicalObject of a scene; arrays view the C++ memory")
        .def_property_readonly("name", [](const PyState& s) { return s.record->name; })
        .def_property_readonly("node_path", [](const PyState& s) { return s.record->node_path; })
        .def_property_readonly("path", [](const PyState& s) { return output::state_label(*s.record); })
        .def_property_readonly("template",
                               [](const PyState& s) {
                                   return rigid_of(s) ? "Rigid3d" : vec1_of(s) ? "Vec1d" : "Vec3d";
                               })
        .def_property_readonly("size", [](const PyState& s) { return s.record->state->num_dofs(); })
        .def_property_readonly("mapped", [](const PyState& s) { return s.record->mapped; })
        .def_property_readonly("in_solver_subtree", [](const PyState& s) { return s.record->in_solver_subtree; })
        .def_property(
            "positions", [](py::object self) { return state_field(self, Field::positions); },
            [](py::object self, py::handle v) { set_state_field(self, Field::positions, v, "positions"); },
            "(n, 3) view for Vec3d; (n, 7) x y z qx qy qz qw copy for Rigid3d; (n, 1) view for Vec1d (assign to write)")
        .def_property(
            "velocities", [](py::object self) { return state_field(self, Field::velocities); },
            [](py::object self, py::handle v) { set_state_field(self, Field::velocities, v, "velocities"); },
            "(n, 3) view, (n, 6) linear then angular for Rigid3d, (n, 1) for Vec1d")
        .def_property(
            "forces", [](py::object self) { return state_field(self, Field::forces); },
            [](py::object self, py::handle v) { set_state_field(self, Field::forces, v, "forces"); },
            "forces of the last step's last evaluation (view)")
        .def_property(
            "rest_positions", [](py::object self) { return state_field(self, Field::rest_positions); },
            [](py::object self, py::handle v) { set_state_field(self, Field::rest_positions, v, "rest_positions"); })
        .def_property(
            "external_forces", [](py::object self) { return state_field(self, Field::external_forces); },
            [](py::object self, py::handle v) { set_state_field(self, Field::external_forces, v, "external_forces"); },
            "explicit forces applied during the next step, cleared after it (view)")
        .def_property_readonly(
            "centers",
            [](py::object self) -> py::object {
                Rigid3Object* r = rigid_of(self.cast<const PyState&>());
                if (r == nullptr) throw py::attribute_error("centers: only Rigid3d states have frames");
                return view(r->position.empty() ? nullptr : r->position.data()->center.data(),
                            py::ssize_t(r->position.size()), 3, sizeof(RigidFrame), self);
            },
            "(n, 3) view of the frame origins (Rigid3d)")
        .def_property_readonly(
            "orientations",
            [](py::object self) -> py::object {
                Rigid3Object* r = rigid_of(self.cast<const PyState&>());
                if (r == nullptr) throw py::attribute_error("orientations: only Rigid3d states have frames");
                return view(r->position.empty() ? nullptr : r->position.data()->orientation.coeffs().data(),
                            py::ssize_t(r->position.size()), 4, sizeof(RigidFrame), self);
            },
            "(n, 4) view of the quaternions qx qy qz qw (Rigid3d; keep them unit)")
        .def_property_readonly("radius", [](const PyState& s) { return s.record->radius; })
        .def("__repr__", [](const PyState& s) {
            return "<penalty.State '" + output::state_label(*s.record) + "' " + (rigid_of(s) ? "Rigid3d" : "Vec3d") +
                   ", " + std::to_string(s.record->state->num_dofs()) + " DOFs>";
        });

    auto scene_class = py::class_<PyScene>(m, "Scene", "A built scene (from a .scn file or a SofaPython3 script)");
    scene_class.def("step", &PyScene::step, py::arg("n") = 1, "Runs n steps (controllers' hooks around each)")
        .def_property_readonly(
            "time", [](const PyScene& s) { return s.scene->simulation().time(); }, "s")
        .def_property_readonly(
            "dt", [](const PyScene& s) { return s.scene->dt(); }, "s")
        .def_property_readonly("file", [](const PyScene& s) { return s.scene->file().path; })
        .def("_state_list",
             [](py::object self) {
                 py::list out;
                 const PyScene& s = self.cast<const PyScene&>();
                 for (const auto& r : s.scene->states()) out.append(PyState{self, StateRecordRef(self, &r)});
                 return out;
             })
        .def(
            "contacts", [](const PyScene& s) { return contacts_dict(*s.scene); },
            "The live contacts after the last step, one row per contact (dict of arrays)")
        .def(
            "_contact_summary",
            [](const PyScene& s) {
                // the per-step numbers of `penalty run --stats` (output::summarize_contacts)
                const output::ContactSummary c = output::summarize_contacts(s.scene->contacts());
                py::dict d;
                d["contacts"] = c.contacts;
                d["active_contacts"] = c.active_contacts;
                d["max_penetration"] = c.max_penetration;
                d["contact_energy"] = c.contact_energy;
                d["dissipated_energy"] = c.dissipated_energy;
                return d;
            },
            "After a step: contacts, active_contacts, max_penetration (m, at the positions after the step, "
            "0 without a penetrating contact), contact_energy, dissipated_energy (J): --stats' columns")
        .def(
            "energies", [](const PyScene& s) { return energies_dict(*s.scene); },
            "kinetic, contact (stored), dissipated_damping, dissipated_friction, dissipated (J)")
        .def(
            "info", [](const PyScene& s) { return info_dict(*s.scene); }, "What `penalty info` prints, as data")
        .def(
            "_component_matrix",
            [](const PyScene& s, const std::string& node_path, std::size_t index, const std::string& kind) {
                return component_matrix(*s.scene, node_path, index, kind);
            },
            py::arg("node_path"), py::arg("index"), py::arg("kind"))
        .def("warnings", [](const PyScene& s) { return s.scene->warnings(); })
        .def_property(
            "no_tunnelling", [](const PyScene& s) { return tunnelling_mode(*s.scene); },
            [](PyScene& s, const std::string& mode) { set_tunnelling_mode(*s.scene, mode); },
            "tunnelling guard: off, warn, substep or stiffen (docs/no-tunnelling.md)")
        .def_property(
            "reduction",
            [](const PyScene& s) {
                return std::string(s.scene->build_options().blocked_reductions ? "blocked" : "sofa");
            },
            [](PyScene& s, const std::string& mode) {
                if (mode != "sofa" && mode != "blocked")
                    throw py::value_error("reduction: '" + mode + "' is not one of sofa, blocked");
                s.scene->set_blocked_reductions(mode == "blocked");
            },
            "the CG's dot products: sofa (SOFA's chain) or blocked (docs/performance.md, Blocked reductions)")
        .def(
            "tunnelling", [](const PyScene& s) { return tunnelling_report(*s.scene); },
            "The guard's report of the last step (dict), None without a guard")
        .def(
            "contact_advice",
            [](const PyScene& s, std::optional<double> v) { return contact_advice_list(*s.scene, v); },
            py::arg("impact_speed") = py::none(), "`penalty info --contact-advice` per model pair (list of dicts)")
        .def(
            "_contact_advice_text",
            [](const PyScene& s, std::optional<double> v) { return scene::contact_advice(*s.scene, v); },
            py::arg("impact_speed") = py::none())
        .def_property_readonly("last_timings",
                               [](const PyScene& s) {
                                   const auto& t = s.scene->last_timings();
                                   py::dict d;
                                   d["detection_seconds"] = t.detection_seconds;
                                   d["response_seconds"] = t.response_seconds;
                                   d["solve_seconds"] = t.solve_seconds;
                                   return d;
                               })
        .def("_add_hooks",
             [](PyScene& s, py::object before, py::object after) {
                 if (!before.is_none()) s.before_step.push_back(std::move(before));
                 if (!after.is_none()) s.after_step.push_back(std::move(after));
             })
        .def("_run",
             [](PyScene& s, std::int64_t steps, std::optional<std::filesystem::path> vtk, std::int64_t vtk_every,
                std::optional<std::filesystem::path> states, bool export_mapped, std::int64_t export_every,
                std::optional<std::filesystem::path> stats, std::optional<bool> progress, py::object callback,
                double divergence_factor, std::optional<std::filesystem::path> view, std::int64_t view_every) {
                 scene::RunOptions o;
                 o.steps = steps;
                 o.divergence_factor = divergence_factor;
                 o.view_directory = view;
                 o.view_every = view_every;
                 o.view_title = s.scene->file().path.filename().string();
                 o.vtk_directory = vtk;
                 o.vtk_every = vtk_every;
                 o.states_directory = states;
                 o.export_mapped = export_mapped;
                 o.export_every = export_every;
                 o.stats_file = stats;
                 // controllers and a callback may move any state between the steps
                 o.states_change_between_steps = !s.before_step.empty() || !s.after_step.empty() || !callback.is_none();
                 const bool bar = progress.value_or(isatty(STDERR_FILENO) != 0);
                 // Controllers: the first step's "begin" before the run, then after step k its "end"
                 // and step k+1's "begin" (so a "begin" runs before the outputs of its step).
                 if (steps > 0) s.call_hooks(s.before_step);
                 const scene::RunSummary summary = scene::run_scene(
                     *s.scene, o, [&](std::int64_t done, std::int64_t total, const scene::RunSummary& so_far) {
                         s.call_hooks(s.after_step);
                         if (!callback.is_none()) callback(done, total);
                         if (done < total) s.call_hooks(s.before_step);
                         if (bar && (done == total || done % std::max<std::int64_t>(1, total / 100) == 0))
                             print_progress(done, total, so_far.simulated_time);
                         if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                     });
                 return summary_dict(summary);
             });
    bind_scene_topology(scene_class);

    m.def(
        "_load_scene",
        [](const std::filesystem::path& path, const std::vector<std::filesystem::path>& data_dirs,
           std::optional<double> dt, int threads, bool exhaustive, std::vector<std::string> overrides,
           const std::vector<std::string>& quirk_fixes) {
            PyScene s;
            s.scene = scene::load_scene(
                path, build_options(data_dirs, dt, threads, exhaustive, std::move(overrides), quirk_fixes));
            return s;
        },
        py::arg("path"), py::arg("data_dirs"), py::arg("dt"), py::arg("threads"), py::arg("exhaustive"),
        py::arg("overrides") = std::vector<std::string>{}, py::arg("fix_sofa_quirks") = std::vector<std::string>{});
    m.def(
        "_sofa_quirk_names",
        [] {
            std::vector<std::string> out{"all"};
            for (const SofaQuirkInfo& q : sofa_quirk_table()) out.emplace_back(q.name);
            return out;
        },
        "The names --fix-sofa-quirk takes (docs/sofa-compatibility.md)");
    m.def(
        "_check_override",
        [](const std::string& text) {
            const io::Override o = io::parse_override(text);
            return py::make_tuple(o.path, o.attribute, o.value);
        },
        "Parses PATH.attribute=value; ValueError naming what is malformed");
    m.def("_builtin_scene", [](std::optional<double> dt) {
        PyScene s;
        s.scene = scene::build_scene(io::parse_scene_string(scene::default_scene_xml(), "<built-in scene>"),
                                     build_options({}, dt, 0, false));
        return s;
    });
    m.def(
        "_build_tree",
        [](const py::dict& root, const std::filesystem::path& path, const std::vector<std::filesystem::path>& data_dirs,
           std::optional<double> dt, int threads, bool exhaustive, std::vector<std::string> overrides,
           const std::vector<std::string>& quirk_fixes) {
            io::SceneFile file;
            file.path = path;
            file.root = std::make_unique<io::SceneNode>();
            read_tree_node(root, *file.root, 0);
            PyScene s;
            s.scene = scene::build_scene(
                std::move(file), build_options(data_dirs, dt, threads, exhaustive, std::move(overrides), quirk_fixes));
            return s;
        },
        py::arg("root"), py::arg("path"), py::arg("data_dirs"), py::arg("dt"), py::arg("threads"),
        py::arg("exhaustive"), py::arg("overrides") = std::vector<std::string>{},
        py::arg("fix_sofa_quirks") = std::vector<std::string>{},
        "Builds a scene from the node tree of a SofaPython3 script (nested dicts), with the .scn builder");
}

}  // namespace penalty::python
