#include "penalty/collision/models.hpp"

#include "kernels/collision/triangle_normals.hpp"
#include "penalty/collision/separation.hpp"
#include "penalty/core/error.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

namespace {

template <class Ids>
void check_indices(const CollisionModel& m, Index elem, const Ids& ids, std::size_t n) {
    for (auto v : ids) {
        if (v < 0 || std::size_t(v) >= n) {
            throw_invalid_argument(model_type_name(m.type()), "Model '", m.name(), "': element ", elem,
                                   ": vertex index ", v, " out of range (state has ", n, " points)");
        }
    }
}

void check_radius(const CollisionModel& m, Index elem, double r, const char* what) {
    if (!(r >= 0.0) || !std::isfinite(r)) {
        throw_invalid_argument(model_type_name(m.type()), "Model '", m.name(), "': element ", elem, ": ", what, " is ",
                               r, " (must be finite and >= 0)");
    }
}

/// The box of a mesh element (SOFA's leaf cube): the vertices' bounds grown by the contact
/// distance cd on every side (Aabb::extend from an empty box, then inflate(cd): the same doubles).
template <std::size_t N>
inline Aabb vertices_box(const std::array<const Vec3*, N>& v, double cd) {
    Aabb b;
    b.min = *v[0];
    b.max = *v[0];
    for (std::size_t k = 1; k < N; ++k) {
        b.min = b.min.cwiseMin(*v[k]);
        b.max = b.max.cwiseMax(*v[k]);
    }
    b.inflate(cd);
    return b;
}

/// Every coordinate of every position is finite (one vectorised pass over the state).
bool positions_finite(const std::vector<Vec3>& x) { return x.empty() || all_finite(x.front().data(), 3 * x.size()); }

}  // namespace

// ---------------------------------------------------------------------------------------------
PointModel::PointModel(const Vec3State& state, const MeshTopology* topology, CollisionModelParams params)
    : CollisionModel(ModelType::Point, std::move(params)), state_(&state), topology_(topology) {}

Aabb PointModel::element_box(Index i) const { return vertices_box<1>({&point(i)}, params().contact_distance); }

void PointModel::element_boxes(std::size_t begin, std::size_t end, Aabb* out) const {
    const double cd = params().contact_distance;
    for (std::size_t i = begin; i < end; ++i) *out++ = vertices_box<1>({&point(Index(i))}, cd);
}

void PointModel::validate() const {
    CollisionModel::validate();
    for (std::size_t i = 0; i < size(); ++i) check_point(point(Index(i)), Index(i), "position");
    validated_state_size_ = state_->size();
}

bool PointModel::elements_unchanged_and_finite() const {
    return validated_state_size_ == state_->size() && positions_finite(state_->position);
}

// ---------------------------------------------------------------------------------------------
LineModel::LineModel(const Vec3State& state, const MeshTopology& topology, CollisionModelParams params)
    : CollisionModel(ModelType::Line, std::move(params)),
      state_(&state),
      topology_(&topology),
      edges_(topology.edges()) {
    const auto& eav = topology.edges_around_vertex();
    flags_.assign(edges_.size(), 0u);
    for (std::size_t i = 0; i < edges_.size(); ++i) {
        for (int k = 0; k < 2; ++k) {
            const auto v = std::size_t(edges_[i][std::size_t(k)]);
            if (v >= eav.size() || eav[v].empty()) continue;
            if (std::size_t(eav[v].front()) == i) flags_[i] |= (k == 0 ? kP1 : kP2);
            if (eav[v].size() == 1) flags_[i] |= (k == 0 ? kBP1 : kBP2);
        }
    }
}

Aabb LineModel::element_box(Index i) const { return vertices_box<2>({&p1(i), &p2(i)}, params().contact_distance); }

void LineModel::element_boxes(std::size_t begin, std::size_t end, Aabb* out) const {
    const double cd = params().contact_distance;
    for (std::size_t i = begin; i < end; ++i) *out++ = vertices_box<2>({&p1(Index(i)), &p2(Index(i))}, cd);
}

void LineModel::validate() const {
    CollisionModel::validate();
    for (std::size_t i = 0; i < edges_.size(); ++i) check_indices(*this, Index(i), edges_[i], state_->size());
    for (std::size_t i = 0; i < edges_.size(); ++i) {
        check_point(p1(Index(i)), Index(i), "vertex 1 position");
        check_point(p2(Index(i)), Index(i), "vertex 2 position");
    }
    validated_state_size_ = state_->size();
}

// the edges are fixed at construction: valid indices stay valid while the state keeps its size
bool LineModel::elements_unchanged_and_finite() const {
    return validated_state_size_ == state_->size() && positions_finite(state_->position);
}

// ---------------------------------------------------------------------------------------------
TriangleModel::TriangleModel(const Vec3State& state, const MeshTopology& topology, CollisionModelParams params)
    : CollisionModel(ModelType::Triangle, std::move(params)), state_(&state), topology_(&topology) {
    const auto& tris = topology.triangles();
    const auto& quads = topology.quads();
    num_topology_triangles_ = tris.size();
    triangles_ = tris;
    // each quad (q0,q1,q2,q3) -> (q1,q2,q0) and (q3,q0,q2), SOFA's split
    for (const Quad& q : quads) {
        triangles_.push_back(Triangle{q[1], q[2], q[0]});
        triangles_.push_back(Triangle{q[3], q[0], q[2]});
    }
    flags_.assign(triangles_.size(), 0u);
    for (std::size_t t = 0; t < tris.size(); ++t) flags_[t] = topology_flags(t);
    partial_feature_count_ = std::size_t(std::count_if(
        flags_.begin(), flags_.end(), [](std::uint32_t f) { return (f & (kPoints | kEdges)) != (kPoints | kEdges); }));
    owns_every_feature_ = partial_feature_count_ == 0;
    normals_.assign(triangles_.size(), Vec3::Zero());
    plane_normals_.assign(triangles_.size(), Vec3::Zero());
}

std::uint32_t TriangleModel::topology_flags(std::size_t t) const {
    const auto& tris = topology_->triangles();
    const auto& tav = topology_->triangles_around_vertex();
    const auto& tae = topology_->triangles_around_edge();
    const auto& eit = topology_->edges_in_triangle();
    std::uint32_t f = 0;
    for (std::size_t j = 0; j < 3; ++j) {
        const auto v = std::size_t(tris[t][j]);
        if (v < tav.size() && !tav[v].empty() && std::size_t(tav[v].front()) == t) f |= (kP1 << j);
        if (t < eit.size()) {
            const auto e = std::size_t(eit[t][j]);  // edge opposite vertex j
            if (e < tae.size() && !tae[e].empty()) {
                if (std::size_t(tae[e].front()) == t) f |= (kE23 << j);
                if (tae[e].size() == 1) f |= (kBE23 << j);
            }
        }
    }
    return f;
}

void TriangleModel::do_update() {
    // SOFA's updateNormals: normalize((p1 − p0) × (p2 − p0)); a zero-area triangle keeps a zero
    // normal here (SOFA normalises without a guard)
    if (compute_normals) detail::triangle_normals(state_->position, triangles_, normals_, best_kernel_path());
    planes_current_ = false;
}

void TriangleModel::update_planes() {
    if (planes_current_) return;
    for (std::size_t i = 0; i < triangles_.size(); ++i) {
        const Vec3& a = p(Index(i), 0);
        const Vec3 ab = p(Index(i), 1) - a;
        const Vec3 ac = p(Index(i), 2) - a;
        const Vec3 n = ab.cross(ac);
        const double n2 = n.squaredNorm();
        plane_normals_[i] = detail::reliable_plane(n2, ab.squaredNorm() * ac.squaredNorm())
                                ? Vec3(n * (1.0 / std::sqrt(n2)))
                                : Vec3::Zero();
    }
    // over the whole state: a bound for the triangles' vertices
    double bound = 0.0;
    for (const Vec3& x : state_->position) bound = std::max({bound, std::abs(x.x()), std::abs(x.y()), std::abs(x.z())});
    coordinate_bound_ = bound;
    planes_current_ = true;
}

Aabb TriangleModel::element_box(Index i) const {
    return vertices_box<3>({&p(i, 0), &p(i, 1), &p(i, 2)}, params().contact_distance);
}

void TriangleModel::element_boxes(std::size_t begin, std::size_t end, Aabb* out) const {
    const double cd = params().contact_distance;
    for (std::size_t i = begin; i < end; ++i)
        *out++ = vertices_box<3>({&p(Index(i), 0), &p(Index(i), 1), &p(Index(i), 2)}, cd);
}

void TriangleModel::validate() const {
    CollisionModel::validate();
    for (std::size_t i = 0; i < triangles_.size(); ++i) check_indices(*this, Index(i), triangles_[i], state_->size());
    for (std::size_t i = 0; i < triangles_.size(); ++i)
        for (int k = 0; k < 3; ++k) check_point(p(Index(i), k), Index(i), "vertex position");
    validated_state_size_ = state_->size();
}

// the triangles are fixed at construction: valid indices stay valid while the state keeps its size
bool TriangleModel::elements_unchanged_and_finite() const {
    return validated_state_size_ == state_->size() && positions_finite(state_->position);
}

// ---------------------------------------------------------------------------------------------
namespace {
/// Box of sphere i of a Vec3 or rigid sphere model: centre ± (radius + contactDistance).
template <class Spheres>
Aabb sphere_box(const Spheres& m, Index i) {
    Aabb b;
    b.extend(m.center(i));
    b.inflate(m.radius(i) + m.params().contact_distance);
    return b;
}
/// Positive finite radii (the default one too) and finite centres.
template <class Spheres>
void check_spheres(const Spheres& m, double default_radius) {
    check_radius(m, -1, default_radius, "radius");
    for (std::size_t i = 0; i < m.size(); ++i) {
        check_radius(m, Index(i), m.radius(Index(i)), "radius");
        m.check_point(m.center(Index(i)), Index(i), "centre");
    }
}
}  // namespace

SphereModel::SphereModel(const Vec3State& state, double radius, std::vector<double> list_radius,
                         CollisionModelParams params)
    : CollisionModel(ModelType::Sphere, std::move(params)),
      state_(&state),
      radius_(radius),
      list_radius_(std::move(list_radius)) {}

Aabb SphereModel::element_box(Index i) const { return sphere_box(*this, i); }

void SphereModel::validate() const {
    CollisionModel::validate();
    check_spheres(*this, radius_);
}

RigidSphereModel::RigidSphereModel(const Rigid3State& state, double radius, std::vector<double> list_radius,
                                   CollisionModelParams params)
    : CollisionModel(ModelType::RigidSphere, std::move(params)),
      state_(&state),
      radius_(radius),
      list_radius_(std::move(list_radius)) {}

Aabb RigidSphereModel::element_box(Index i) const { return sphere_box(*this, i); }

void RigidSphereModel::validate() const {
    CollisionModel::validate();
    check_spheres(*this, radius_);
}

// ---------------------------------------------------------------------------------------------
CylinderModel::CylinderModel(const Rigid3State& state, double default_radius, double default_height,
                             const Vec3& default_local_axis, CollisionModelParams params)
    : CollisionModel(ModelType::Cylinder, std::move(params)),
      state_(&state),
      default_radius_(default_radius),
      default_height_(default_height),
      default_axis_(default_local_axis) {}

double CylinderModel::radius(Index i) const {
    return std::size_t(i) < radii.size() ? radii[std::size_t(i)] : default_radius_;
}
double CylinderModel::height(Index i) const {
    return std::size_t(i) < heights.size() ? heights[std::size_t(i)] : default_height_;
}

Vec3 CylinderModel::local_axis(Index i) const {
    const Vec3 local = std::size_t(i) < local_axes.size() ? local_axes[std::size_t(i)] : default_axis_;
    return local.normalized();
}

Vec3 CylinderModel::radial_direction(Index i) const {
    return (frame(i).orientation * any_orthogonal(local_axis(i))).normalized();
}

CylinderShape CylinderModel::shape(Index i) const {
    const RigidFrame& f = frame(i);
    const Vec3 local = local_axis(i);
    CylinderShape s;
    s.center = f.center;
    s.axis = (f.orientation * local).normalized();
    s.radius = radius(i);
    s.half_height = 0.5 * height(i);
    return s;
}

Aabb CylinderModel::element_box(Index i) const {
    const CylinderShape s = shape(i);
    Aabb b;
    b.extend(s.center - s.half_height * s.axis);
    b.extend(s.center + s.half_height * s.axis);
    b.inflate(s.radius);
    return b;
}

void CylinderModel::validate() const {
    CollisionModel::validate();
    check_radius(*this, -1, default_radius_, "defaultRadius");
    check_radius(*this, -1, default_height_, "defaultHeight");
    for (std::size_t i = 0; i < size(); ++i) {
        check_radius(*this, Index(i), radius(Index(i)), "radius");
        check_radius(*this, Index(i), height(Index(i)), "height");
        check_point(frame(Index(i)).center, Index(i), "centre");
        const Vec3 local = i < local_axes.size() ? local_axes[i] : default_axis_;
        if (!local.allFinite() || !(local.norm() > 0.0)) {
            throw_invalid_argument("CylinderModel '", name(), "': element ", i,
                                   ": local axis must be finite and non-zero");
        }
        if (!frame(Index(i)).orientation.coeffs().allFinite() || !(frame(Index(i)).orientation.norm() > 0.0)) {
            throw_invalid_argument("CylinderModel '", name(), "': element ", i,
                                   ": orientation must be a finite non-zero quaternion");
        }
    }
}

// ---------------------------------------------------------------------------------------------
TetrahedronModel::TetrahedronModel(const Vec3State& state, const MeshTopology& topology, CollisionModelParams params)
    : CollisionModel(ModelType::Tetrahedron, std::move(params)),
      state_(&state),
      tetrahedra_(topology.tetrahedra()),
      coord2bary_(tetrahedra_.size(), Mat3::Zero()) {}

void TetrahedronModel::do_update() {
    for (std::size_t i = 0; i < tetrahedra_.size(); ++i) {
        Mat3 m;
        m.col(0) = p(Index(i), 1) - p(Index(i), 0);
        m.col(1) = p(Index(i), 2) - p(Index(i), 0);
        m.col(2) = p(Index(i), 3) - p(Index(i), 0);
        const double det = m.determinant();
        coord2bary_[i] = det != 0.0 ? Mat3(m.inverse()) : Mat3::Zero();
    }
}

std::array<double, 4> TetrahedronModel::barycentric(Index i, const Vec3& P) const {
    const Vec3 f = coord2bary_[std::size_t(i)] * (P - p(i, 0));
    return {1.0 - f.x() - f.y() - f.z(), f.x(), f.y(), f.z()};
}

Aabb TetrahedronModel::element_box(Index i) const {
    return vertices_box<4>({&p(i, 0), &p(i, 1), &p(i, 2), &p(i, 3)}, params().contact_distance);
}

void TetrahedronModel::element_boxes(std::size_t begin, std::size_t end, Aabb* out) const {
    const double cd = params().contact_distance;
    for (std::size_t i = begin; i < end; ++i)
        *out++ = vertices_box<4>({&p(Index(i), 0), &p(Index(i), 1), &p(Index(i), 2), &p(Index(i), 3)}, cd);
}

void TetrahedronModel::validate() const {
    CollisionModel::validate();
    for (std::size_t i = 0; i < tetrahedra_.size(); ++i) check_indices(*this, Index(i), tetrahedra_[i], state_->size());
    for (std::size_t i = 0; i < tetrahedra_.size(); ++i)
        for (int k = 0; k < 4; ++k) check_point(p(Index(i), k), Index(i), "vertex position");
    validated_state_size_ = state_->size();
}

// the tetrahedra are fixed at construction: valid indices stay valid while the state keeps its size
bool TetrahedronModel::elements_unchanged_and_finite() const {
    return validated_state_size_ == state_->size() && positions_finite(state_->position);
}

}  // namespace penalty
