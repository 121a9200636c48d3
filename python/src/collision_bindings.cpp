// Collision detection alone: collision models built from numpy arrays, one intersection method,
// detect() returning SOFA's detection outputs as arrays (penalty.collision).
#include "bindings.hpp"

#include "penalty/collision/intersection.hpp"
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/state.hpp"
#include "penalty/mechanics/topology.hpp"
#include "penalty/output/format.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <string>
#include <type_traits>

namespace penalty::python {

namespace {

/// A collision model with the state and topology it reads (owned here, unlike in a scene).
struct PyModel {
    std::unique_ptr<Vec3State> state = std::make_unique<Vec3State>();
    std::unique_ptr<Rigid3State> frames;  ///< rigid models only
    std::unique_ptr<MeshTopology> topology = std::make_unique<MeshTopology>();
    std::unique_ptr<CollisionModel> model;
};

CollisionModelParams model_params(const std::string& name, double contact_distance, double contact_stiffness,
                                  bool simulated, bool moving, bool self_collision, bool both_side,
                                  const std::vector<int>& group) {
    CollisionModelParams p;
    p.name = name;
    p.contact_distance = contact_distance;
    p.contact_stiffness = contact_stiffness;
    p.simulated = simulated;
    p.moving = moving;
    p.self_collision = self_collision;
    p.both_side = both_side;
    p.group = group;
    return p;
}

void fill_points(PyModel& m, const py::handle& points) {
    const auto a = as_points(points, "points");
    const auto* p = reinterpret_cast<const Vec3*>(a.data());
    m.state->position.assign(p, p + a.shape(0));
    m.state->velocity.assign(std::size_t(a.shape(0)), Vec3::Zero());
    m.state->rest_position = m.state->position;
    m.topology->set_num_points(std::size_t(a.shape(0)));
}

template <std::size_t N>
std::vector<std::array<PointId, N>> elements(const py::handle& v, const char* what, std::size_t points) {
    const auto a = as_indices(v, what);
    if (a.size() % py::ssize_t(N) != 0 || a.ndim() > 2 || (a.ndim() == 2 && a.shape(1) != py::ssize_t(N)))
        throw py::value_error(std::string(what) + ": expected shape (n, " + std::to_string(N) + ")");
    std::vector<std::array<PointId, N>> out(std::size_t(a.size()) / N);
    for (std::size_t i = 0; i < out.size() * N; ++i) {
        const std::int64_t id = a.data()[i];
        if (id < 0 || std::size_t(id) >= points)
            throw py::value_error(std::string(what) + ": point index " + std::to_string(id) + " outside 0.." +
                                  std::to_string(points - 1));
        out[i / N][i % N] = PointId(id);
    }
    return out;
}

/// A keyword's value as T; TypeError naming the keyword (pybind11's cast_error names nothing).
template <class T>
T keyword(const py::handle& value, const std::string& name) {
    if constexpr (std::is_same_v<T, double>) {
        if (!py::isinstance<py::float_>(value) && !py::isinstance<py::int_>(value))
            throw py::type_error("detect: " + name + " must be a number");
        if (py::isinstance<py::bool_>(value)) throw py::type_error("detect: " + name + " must be a number, not a bool");
    } else {
        if (!py::isinstance<py::bool_>(value)) throw py::type_error("detect: " + name + " must be True or False");
    }
    return value.cast<T>();
}

/// A radius argument: one number (every sphere) or one per sphere, finite and > 0.
void read_radius(const py::handle& radius, std::size_t spheres, double& uniform, std::vector<double>& list) {
    (void)numeric_kind(radius, "radius");
    const auto r = numbers_array<double>(radius, "radius");
    if (r.ndim() > 1 || (r.ndim() == 1 && std::size_t(r.size()) != spheres))
        throw py::value_error("radius: expected one number or " + std::to_string(spheres) + " radii");
    for (py::ssize_t i = 0; i < r.size(); ++i)
        if (!(std::isfinite(r.data()[i]) && r.data()[i] > 0.0))
            throw py::value_error("radius: " + output::format_number(r.data()[i]) + " must be a finite number > 0");
    if (r.ndim() == 0) uniform = *r.data();
    else list.assign(r.data(), r.data() + r.size());
}

/// The model's own checks (finite positions, indices in range, parameters), at construction
/// rather than at the first detect().
std::unique_ptr<PyModel> validated(std::unique_ptr<PyModel> p) {
    p->model->validate();
    return p;
}

IntersectionParams intersection_params(const std::string& method, const py::kwargs& options) {
    IntersectionParams p;
    if (method == "NewProximity") p = IntersectionParams::new_proximity();
    else if (method == "MinProximity") p = IntersectionParams::min_proximity();
    else if (method == "LocalMinDistance") p = IntersectionParams::local_min_distance();
    else if (method == "Discrete") p = IntersectionParams::discrete();
    else
        throw py::value_error("method: expected NewProximity, MinProximity, LocalMinDistance or Discrete, found '" +
                              method + "'");
    for (const auto& [key, value] : options) {
        const auto k = key.cast<std::string>();
        if (k == "alarm_distance") p.alarm_distance = keyword<double>(value, k);
        else if (k == "contact_distance") p.contact_distance = keyword<double>(value, k);
        else if (k == "use_line_line") p.use_line_line = keyword<bool>(value, k);
        else if (k == "use_sphere_triangle") p.use_sphere_triangle = keyword<bool>(value, k);
        else if (k == "use_point_point") p.use_point_point = keyword<bool>(value, k);
        else if (k == "use_line_point") p.use_line_point = keyword<bool>(value, k);
        else if (k == "use_surface_normals") p.use_surface_normals = keyword<bool>(value, k);
        else if (k == "filter_intersection") p.filter_intersection = keyword<bool>(value, k);
        else if (k == "angle_cone") p.angle_cone = keyword<double>(value, k);
        else if (k == "cone_factor") p.cone_factor = keyword<double>(value, k);
        else if (k == "enable_beyond_sofa_pairs") p.enable_beyond_sofa_pairs = keyword<bool>(value, k);
        else throw py::type_error("detect: unknown intersection parameter '" + k + "'");
    }
    p.validate();
    return p;
}

py::dict outputs_dict(const ModelPairDetection& d) {
    const auto n = py::ssize_t(d.outputs.size());
    py::array_t<std::int64_t> e1(n), e2(n), id(n);
    py::array_t<double> p1({n, py::ssize_t(3)}), p2({n, py::ssize_t(3)}), normal({n, py::ssize_t(3)}), value(n);
    for (py::ssize_t i = 0; i < n; ++i) {
        const DetectionOutput& o = d.outputs[std::size_t(i)];
        e1.mutable_at(i) = o.elem1.value();
        e2.mutable_at(i) = o.elem2.value();
        id.mutable_at(i) = o.id;
        value.mutable_at(i) = o.value;
        for (int j = 0; j < 3; ++j) {
            p1.mutable_at(i, j) = o.point[0][j];
            p2.mutable_at(i, j) = o.point[1][j];
            normal.mutable_at(i, j) = o.normal[j];
        }
    }
    py::dict out;
    out["model1"] = d.model1 != nullptr ? d.model1->name() : std::string();
    out["model2"] = d.model2 != nullptr ? d.model2->name() : std::string();
    out["support"] = pair_support_name(d.support);
    out["skipped"] = d.skipped;
    out["element1"] = e1;
    out["element2"] = e2;
    out["id"] = id;
    out["point1"] = p1;
    out["point2"] = p2;
    out["normal"] = normal;
    out["distance"] = value;
    return out;
}

}  // namespace

void bind_collision(py::module_& parent) {
    py::module_ m = parent.def_submodule("collision", "Collision detection alone, from numpy arrays");
    auto model =
        py::class_<PyModel>(m, "CollisionModel", "A collision model over points it owns")
            .def_property_readonly("type", [](const PyModel& p) { return model_type_name(p.model->type()); })
            .def_property_readonly("name", [](const PyModel& p) { return p.model->name(); })
            .def("__len__", [](const PyModel& p) { return p.model->size(); })
            .def_property(
                "points",
                [](py::object self) {
                    auto& p = self.cast<PyModel&>();
                    if (p.frames) {  // the frame centres (view; the frame is padded to 64 bytes)
                        auto& f = p.frames->position;
                        return view(f.empty() ? nullptr : f.data()->center.data(), py::ssize_t(f.size()), 3,
                                    sizeof(RigidFrame), self);
                    }
                    auto& x = p.state->position;
                    return view(x.empty() ? nullptr : x.data()->data(), py::ssize_t(x.size()), 3, sizeof(Vec3), self);
                },
                [](PyModel& p, const py::handle& v) {
                    const auto a = as_points(v, "points");
                    if (p.frames) {
                        if (std::size_t(a.shape(0)) != p.frames->position.size())
                            throw py::value_error("points: expected " + std::to_string(p.frames->position.size()) +
                                                  " points");
                        for (std::size_t i = 0; i < p.frames->position.size(); ++i)
                            p.frames->position[i].center =
                                Vec3(a.at(py::ssize_t(i), 0), a.at(py::ssize_t(i), 1), a.at(py::ssize_t(i), 2));
                        return;
                    }
                    if (std::size_t(a.shape(0)) != p.state->position.size())
                        throw py::value_error("points: expected " + std::to_string(p.state->position.size()) +
                                              " points");
                    const auto* q = reinterpret_cast<const Vec3*>(a.data());
                    std::copy(q, q + a.shape(0), p.state->position.begin());
                },
                "(n, 3) view of the model's points: move them, then detect() again");

    m.def(
        "PointModel",
        [](const py::handle& points, const std::string& name, double contact_distance, double contact_stiffness,
           bool simulated, bool moving, bool self_collision, const std::vector<int>& group) {
            auto p = std::make_unique<PyModel>();
            fill_points(*p, points);
            p->model = std::make_unique<PointModel>(
                *p->state, p->topology.get(),
                model_params(name.empty() ? "points" : name, contact_distance, contact_stiffness, simulated, moving,
                             self_collision, false, group));
            return validated(std::move(p));
        },
        py::arg("points"), py::kw_only(), py::arg("name") = "", py::arg("contact_distance") = 0.0,
        py::arg("contact_stiffness") = 10.0, py::arg("simulated") = true, py::arg("moving") = true,
        py::arg("self_collision") = false, py::arg("group") = std::vector<int>{});
    m.def(
        "LineModel",
        [](const py::handle& points, const py::handle& edges, const std::string& name, double contact_distance,
           double contact_stiffness, bool simulated, bool moving, bool self_collision, const std::vector<int>& group) {
            auto p = std::make_unique<PyModel>();
            fill_points(*p, points);
            p->topology->set_edges(elements<2>(edges, "edges", p->state->position.size()));
            p->model = std::make_unique<LineModel>(
                *p->state, *p->topology,
                model_params(name.empty() ? "lines" : name, contact_distance, contact_stiffness, simulated, moving,
                             self_collision, false, group));
            return validated(std::move(p));
        },
        py::arg("points"), py::arg("edges"), py::kw_only(), py::arg("name") = "", py::arg("contact_distance") = 0.0,
        py::arg("contact_stiffness") = 10.0, py::arg("simulated") = true, py::arg("moving") = true,
        py::arg("self_collision") = false, py::arg("group") = std::vector<int>{});
    m.def(
        "TriangleModel",
        [](const py::handle& points, const py::handle& triangles, const std::string& name, double contact_distance,
           double contact_stiffness, bool simulated, bool moving, bool self_collision, const std::vector<int>& group) {
            auto p = std::make_unique<PyModel>();
            fill_points(*p, points);
            p->topology->set_triangles(elements<3>(triangles, "triangles", p->state->position.size()));
            p->model = std::make_unique<TriangleModel>(
                *p->state, *p->topology,
                model_params(name.empty() ? "triangles" : name, contact_distance, contact_stiffness, simulated, moving,
                             self_collision, false, group));
            return validated(std::move(p));
        },
        py::arg("points"), py::arg("triangles"), py::kw_only(), py::arg("name") = "", py::arg("contact_distance") = 0.0,
        py::arg("contact_stiffness") = 10.0, py::arg("simulated") = true, py::arg("moving") = true,
        py::arg("self_collision") = false, py::arg("group") = std::vector<int>{});
    m.def(
        "SphereModel",
        [](const py::handle& centers, const py::handle& radius, const std::string& name, double contact_distance,
           double contact_stiffness, bool simulated, bool moving, bool self_collision, const std::vector<int>& group) {
            auto p = std::make_unique<PyModel>();
            fill_points(*p, centers);
            std::vector<double> list;
            double uniform = 1.0;
            read_radius(radius, p->state->position.size(), uniform, list);
            p->model = std::make_unique<SphereModel>(
                *p->state, uniform, std::move(list),
                model_params(name.empty() ? "spheres" : name, contact_distance, contact_stiffness, simulated, moving,
                             self_collision, false, group));
            return validated(std::move(p));
        },
        py::arg("centers"), py::arg("radius") = 1.0, py::kw_only(), py::arg("name") = "",
        py::arg("contact_distance") = 0.0, py::arg("contact_stiffness") = 10.0, py::arg("simulated") = true,
        py::arg("moving") = true, py::arg("self_collision") = false, py::arg("group") = std::vector<int>{});
    m.def(
        "RigidSphereModel",
        [](const py::handle& frames, const py::handle& radius, const std::string& name, double contact_distance,
           double contact_stiffness, bool simulated, bool moving, bool self_collision, const std::vector<int>& group) {
            (void)numeric_kind(frames, "frames");
            const auto a = numbers_array<double>(frames, "frames");
            if (a.ndim() != 2 || (a.shape(1) != 3 && a.shape(1) != 7))
                throw py::value_error("frames: expected shape (n, 7) x y z qx qy qz qw, or (n, 3) centres");
            for (py::ssize_t i = 0; i < a.size(); ++i)
                if (!std::isfinite(a.data()[i]))
                    throw py::value_error("frames: frame " + std::to_string(i / a.shape(1)) + " holds " +
                                          output::format_number(a.data()[i]) + " (every value must be finite)");
            auto p = std::make_unique<PyModel>();
            p->frames = std::make_unique<Rigid3State>();
            for (py::ssize_t i = 0; i < a.shape(0); ++i) {
                RigidFrame f;
                f.center = Vec3(a.at(i, 0), a.at(i, 1), a.at(i, 2));
                if (a.shape(1) == 7) {
                    f.orientation = Quat(a.at(i, 6), a.at(i, 3), a.at(i, 4), a.at(i, 5));
                    if (!(f.orientation.norm() > 0.0))
                        throw py::value_error("frames: zero quaternion in frame " + std::to_string(i));
                    f.orientation.normalize();
                }
                p->frames->position.push_back(f);
            }
            p->frames->velocity.assign(p->frames->position.size(), RigidDeriv{});
            p->frames->rest_position = p->frames->position;
            std::vector<double> list;
            double uniform = 1.0;
            read_radius(radius, p->frames->position.size(), uniform, list);
            p->model = std::make_unique<RigidSphereModel>(
                *p->frames, uniform, std::move(list),
                model_params(name.empty() ? "rigid_spheres" : name, contact_distance, contact_stiffness, simulated,
                             moving, self_collision, false, group));
            return validated(std::move(p));
        },
        py::arg("frames"), py::arg("radius") = 1.0, py::kw_only(), py::arg("name") = "",
        py::arg("contact_distance") = 0.0, py::arg("contact_stiffness") = 10.0, py::arg("simulated") = true,
        py::arg("moving") = true, py::arg("self_collision") = false, py::arg("group") = std::vector<int>{},
        "Spheres on rigid frames (SOFA's SphereCollisionModel<Rigid3d>); points views the centres");
    (void)model;

    m.def(
        "detect",
        [](PyModel& a, PyModel& b, const std::string& method, const py::kwargs& options) {
            const IntersectionParams params = intersection_params(method, options);
            return outputs_dict(detect_model_pair(params, *a.model, *b.model));
        },
        py::arg("model1"), py::arg("model2"), py::arg("method") = "NewProximity",
        "Detection between two models with one intersection method (alarm_distance=, contact_distance=, and the "
        "method's switches as keywords). Returns model1/model2 (SOFA's registered order, which may swap the "
        "arguments), support, skipped, and per output: element1, element2, id, point1, point2, normal (1 -> 2), "
        "distance (distance minus the contact distance, m; < 0 closer)");
}

}  // namespace penalty::python
