#include "penalty/mechanics/pressure_loads.hpp"

#include "sofa_vector_ops.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

namespace {

std::size_t at(PointId i) { return static_cast<std::size_t>(i); }

using sofa_vec::cross_matrix;

template <class Element>
void check_element_indices(const char* who, const char* what, const std::vector<Index>& ids,
                           const std::vector<Element>& elements) {
    for (std::size_t k = 0; k < ids.size(); ++k)
        if (ids[k] < 0 || static_cast<std::size_t>(ids[k]) >= elements.size())
            throw_invalid_argument(who, ": ", what, " index ", ids[k], " (entry ", k, ") is past the topology's ",
                                   elements.size(), " ", what, "s");
}

template <std::size_t N>
void check_points(const char* who, const std::array<PointId, N>& e, std::size_t num_points) {
    for (PointId id : e)
        if (id < 0 || at(id) >= num_points)
            throw_invalid_argument(who, ": an element uses point ", id, ", past the state's ", num_points, " points");
}

}  // namespace

// ---- TrianglePressureForceField -------------------------------------------------------------

TrianglePressureForceField::TrianglePressureForceField(Vec3Object& state, const MeshTopology& topology,
                                                       std::vector<Index> triangles, const Vec3& pressure)
    : ForceField(state), topology_(&topology), triangles_(std::move(triangles)), pressure_(pressure) {
    if (!pressure_.allFinite()) throw_invalid_argument("TrianglePressureForceField: pressure must be finite");
}

// TrianglePressureForceField::initTriangleInformation: A₀ = Triangle::area of the rest positions
// (½|(b⁰−a⁰)×(c⁰−a⁰)|), force = pressure·A₀.
void TrianglePressureForceField::init() {
    const auto& all = topology_->triangles();
    check_element_indices("TrianglePressureForceField", "triangle", triangles_, all);
    subset_last_ = Index(all.size()) - 1;  // setDataSetArraySize at createTopologyHandler
    const std::vector<Vec3>& x0 = state_->rest_position;
    rest_areas_.clear();
    forces_.clear();
    for (Index id : triangles_) {
        const Triangle& t = all[static_cast<std::size_t>(id)];
        check_points("TrianglePressureForceField", t, x0.size());
        const double area = 0.5 * (x0[at(t[1])] - x0[at(t[0])]).cross(x0[at(t[2])] - x0[at(t[0])]).norm();
        rest_areas_.push_back(area);
        forces_.push_back(pressure_ * area);
    }
}

// TrianglePressureForceField::addForce.
void TrianglePressureForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3>) {
    const auto& all = topology_->triangles();
    if (use_constant_force_) {
        // force/3 on each corner
        for (std::size_t k = 0; k < triangles_.size(); ++k) {
            const Triangle& t = all[static_cast<std::size_t>(triangles_[k])];
            const Vec3 share = forces_[k] / 3;
            f[at(t[0])] += share;
            f[at(t[1])] += share;
            f[at(t[2])] += share;
        }
        // −Σ f·x of the constant force (a potential: f = −∂E/∂x)
        energy_ = 0.0;
        for (std::size_t k = 0; k < triangles_.size(); ++k) {
            const Triangle& t = all[static_cast<std::size_t>(triangles_[k])];
            for (PointId id : t) energy_ -= (forces_[k] / 3).dot(x[at(id)]);
        }
        return;
    }
    // σ·((b−a)×(c−a))/6 on each corner, current positions
    for (Index id : triangles_) {
        const Triangle& t = all[static_cast<std::size_t>(id)];
        const Vec3 area_vector = (x[at(t[1])] - x[at(t[0])]).cross(x[at(t[2])] - x[at(t[0])]) / 6.0;
        const Vec3 force = cauchy_stress_ * area_vector;
        for (PointId p : t) f[at(p)] += force;
    }
    energy_ = 0.0;
}

void TrianglePressureForceField::add_dforce(std::span<Vec3>, std::span<const Vec3>, double, double) const {}

void TrianglePressureForceField::add_stiffness_triplets(TripletList&, Index, double) const {}

double TrianglePressureForceField::total_rest_area() const {
    double a = 0.0;
    for (double v : rest_areas_) a += v;
    return a;
}

// ---- EdgePressureForceField -----------------------------------------------------------------

EdgePressureForceField::EdgePressureForceField(Vec3Object& state, const MeshTopology& topology,
                                               std::vector<Index> edges, const Vec3& pressure)
    : ForceField(state), topology_(&topology), edges_(std::move(edges)), pressure_(pressure) {
    if (!pressure_.allFinite()) throw_invalid_argument("EdgePressureForceField: pressure must be finite");
}

// EdgePressureForceField::initEdgeInformation (pressure ≠ 0): L₀ = Edge::length of the rest
// positions, force = pressure·L₀.
void EdgePressureForceField::init() {
    const auto& all = topology_->edges();
    check_element_indices("EdgePressureForceField", "edge", edges_, all);
    const std::vector<Vec3>& x0 = state_->rest_position;
    rest_lengths_.clear();
    forces_.clear();
    for (Index id : edges_) {
        const Edge& e = all[static_cast<std::size_t>(id)];
        check_points("EdgePressureForceField", e, x0.size());
        const double length = (x0[at(e[1])] - x0[at(e[0])]).norm();
        rest_lengths_.push_back(length);
        forces_.push_back(pressure_ * length);
    }
}

// EdgePressureForceField::addForce: force/2 on each end.
void EdgePressureForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3>) {
    const auto& all = topology_->edges();
    energy_ = 0.0;
    for (std::size_t k = 0; k < edges_.size(); ++k) {
        const Edge& e = all[static_cast<std::size_t>(edges_[k])];
        const Vec3 share = forces_[k] / 2;
        f[at(e[0])] += share;
        f[at(e[1])] += share;
        energy_ -= share.dot(x[at(e[0])]) + share.dot(x[at(e[1])]);
    }
}

void EdgePressureForceField::add_dforce(std::span<Vec3>, std::span<const Vec3>, double, double) const {}

void EdgePressureForceField::add_stiffness_triplets(TripletList&, Index, double) const {}

double EdgePressureForceField::total_rest_length() const {
    double l = 0.0;
    for (double v : rest_lengths_) l += v;
    return l;
}

namespace {
/// isPointInPlane of the pressure loads: dmin < p·normal < dmax, for each point.
std::vector<bool> points_in_plane_slab(std::span<const Vec3> points, const Vec3& normal, double dmin, double dmax) {
    std::vector<bool> in(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double d = points[i].dot(normal);
        in[i] = d > dmin && d < dmax;
    }
    return in;
}
}  // namespace

std::vector<Index> edges_between_planes(const MeshTopology& topology, std::span<const Vec3> points, const Vec3& normal,
                                        double dmin, double dmax) {
    const std::vector<bool> in =
        points_in_plane_slab(points, normal, dmin, dmax);  // EdgePressureForceField::isPointInPlane
    std::vector<Index> out;
    const auto& edges = topology.edges();
    for (std::size_t k = 0; k < edges.size(); ++k) {
        check_points("edges_between_planes", edges[k], points.size());
        if (in[at(edges[k][0])] && in[at(edges[k][1])]) out.push_back(static_cast<Index>(k));
    }
    return out;
}

std::vector<Index> edge_indices_of(const MeshTopology& topology, std::span<const Edge> edges) {
    const auto& all = topology.edges();
    std::vector<Index> out(edges.size(), 0);
    for (std::size_t i = 0; i < edges.size(); ++i)
        for (std::size_t j = 0; j < all.size(); ++j)
            if (edges[i][0] == all[j][0] && edges[i][1] == all[j][1]) out[i] = static_cast<Index>(j);
    return out;
}

// ---- QuadPressureForceField ------------------------------------------------------------------

QuadPressureForceField::QuadPressureForceField(Vec3Object& state, const MeshTopology& topology,
                                               std::vector<Index> quads, const Vec3& pressure)
    : ForceField(state), topology_(&topology), quads_(std::move(quads)), pressure_(pressure) {
    if (!pressure_.allFinite()) throw_invalid_argument("QuadPressureForceField: pressure must be finite");
}

// QuadPressureForceField::initQuadInformation: A₀ = geometry::Quad::area of the rest positions,
// Triangle::area(a, b, c) + Triangle::area(a, c, d) (each ½|(q−a)×(r−a)|), force = pressure·A₀.
void QuadPressureForceField::init() {
    const auto& all = topology_->quads();
    check_element_indices("QuadPressureForceField", "quad", quads_, all);
    subset_last_ = Index(all.size()) - 1;  // setDataSetArraySize at createTopologyHandler
    const std::vector<Vec3>& x0 = state_->rest_position;
    rest_areas_.clear();
    forces_.clear();
    for (Index id : quads_) {
        const Quad& q = all[static_cast<std::size_t>(id)];
        check_points("QuadPressureForceField", q, x0.size());
        const Vec3& a = x0[at(q[0])];
        const double abc = 0.5 * (x0[at(q[1])] - a).cross(x0[at(q[2])] - a).norm();
        const double acd = 0.5 * (x0[at(q[2])] - a).cross(x0[at(q[3])] - a).norm();
        rest_areas_.push_back(abc + acd);
        forces_.push_back(pressure_ * (abc + acd));
    }
}

// QuadPressureForceField::addForce: force/4 on each corner.
void QuadPressureForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3>) {
    const auto& all = topology_->quads();
    energy_ = 0.0;
    for (std::size_t k = 0; k < quads_.size(); ++k) {
        const Quad& q = all[static_cast<std::size_t>(quads_[k])];
        const Vec3 share = forces_[k] / 4;
        for (PointId id : q) {
            f[at(id)] += share;
            energy_ -= share.dot(x[at(id)]);
        }
    }
}

void QuadPressureForceField::add_dforce(std::span<Vec3>, std::span<const Vec3>, double, double) const {}

void QuadPressureForceField::add_stiffness_triplets(TripletList&, Index, double) const {}

double QuadPressureForceField::total_rest_area() const {
    double area = 0.0;
    for (double a : rest_areas_) area += a;
    return area;
}

std::vector<Index> quads_between_planes(const MeshTopology& topology, std::span<const Vec3> points, const Vec3& normal,
                                        double dmin, double dmax) {
    const std::vector<bool> in =
        points_in_plane_slab(points, normal, dmin, dmax);  // QuadPressureForceField::isPointInPlane
    std::vector<Index> out;
    const auto& quads = topology.quads();
    for (std::size_t k = 0; k < quads.size(); ++k) {
        check_points("quads_between_planes", quads[k], points.size());
        if (in[at(quads[k][0])] && in[at(quads[k][1])] && in[at(quads[k][2])] && in[at(quads[k][3])])
            out.push_back(static_cast<Index>(k));
    }
    return out;
}

// ---- SurfacePressureForceField --------------------------------------------------------------

SurfacePressureForceField::SurfacePressureForceField(Vec3Object& state, const MeshTopology& topology,
                                                     SurfacePressureParameters parameters, double dt)
    : ForceField(state), topology_(&topology), params_(std::move(parameters)), dt_(dt) {
    if (!std::isfinite(params_.pressure)) throw_invalid_argument("SurfacePressureForceField: pressure must be finite");
    if (!(dt_ > 0.0)) throw_invalid_argument("SurfacePressureForceField: dt must be > 0, got ", dt_);
}

// SurfacePressureForceField::init: the pulse starts at 0, rising when pressure > 0; a pulse
// without speed ramps at |pressure| per second.
void SurfacePressureForceField::init() {
    check_element_indices("SurfacePressureForceField", "triangle", params_.triangle_indices, topology_->triangles());
    check_element_indices("SurfacePressureForceField", "quad", params_.quad_indices, topology_->quads());
    const std::size_t n = state_->position.size();
    for (const Triangle& t : topology_->triangles()) check_points("SurfacePressureForceField", t, n);
    for (const Quad& q : topology_->quads()) check_points("SurfacePressureForceField", q, n);
    increasing_ = params_.pressure > 0;
    if (params_.pulse_mode && params_.pressure_speed == 0.0) params_.pressure_speed = std::fabs(params_.pressure);
    pulse_pressure_ = 0.0;
}

// SurfacePressureForceField::computePulseModePressure: p moves by speed·dt toward the bound it
// heads for, and turns back once it reaches it.
double SurfacePressureForceField::next_pulse_pressure() {
    const double p = params_.pressure;
    if (increasing_) {
        const double upper = p > 0 ? p : params_.pressure_lower_bound;
        pulse_pressure_ += params_.pressure_speed * dt_;
        if (pulse_pressure_ >= upper) {
            pulse_pressure_ = upper;
            increasing_ = false;
        }
        return pulse_pressure_;
    }
    const double lower = p > 0 ? params_.pressure_lower_bound : p;
    pulse_pressure_ -= params_.pressure_speed * dt_;
    if (pulse_pressure_ <= lower) {
        pulse_pressure_ = lower;
        increasing_ = true;
    }
    return pulse_pressure_;
}

// SurfacePressureForceField::isInPressuredBox: no box (both corners zero) takes every point.
bool SurfacePressureForceField::in_box(const Vec3& x) const {
    const Vec3 lo = params_.box_min.value_or(Vec3::Zero());
    const Vec3 hi = params_.box_max.value_or(Vec3::Zero());
    if (lo == Vec3::Zero() && hi == Vec3::Zero()) return true;
    return x.x() >= lo.x() && x.x() <= hi.x() && x.y() >= lo.y() && x.y() <= hi.y() && x.z() >= lo.z() &&
           x.z() <= hi.z();
}

std::size_t SurfacePressureForceField::topology_changed() {
    pressed_triangles_.clear();
    last_x_.clear();
    const auto past_end = [](const std::vector<Index>& ids, std::size_t count) {
        return static_cast<std::size_t>(
            std::count_if(ids.begin(), ids.end(), [count](Index id) { return static_cast<std::size_t>(id) >= count; }));
    };
    return past_end(params_.triangle_indices, topology_->triangles().size()) +
           past_end(params_.quad_indices, topology_->quads().size());
}

// SurfacePressureForceField::computeMeshVolume (a listed index past the topology's end, which only
// a topological change leaves, is skipped: topology_changed).
double SurfacePressureForceField::mesh_volume(std::span<const Vec3> x) const {
    double volume = 0.0;
    const auto& triangles = topology_->triangles();
    const std::size_t nt = params_.triangle_indices.empty() ? triangles.size() : params_.triangle_indices.size();
    for (std::size_t i = 0; i < nt; ++i) {
        const std::size_t id =
            params_.triangle_indices.empty() ? i : static_cast<std::size_t>(params_.triangle_indices[i]);
        if (id >= triangles.size()) continue;
        const Triangle& t = triangles[id];
        volume += x[at(t[0])].cross(x[at(t[1])]).dot(x[at(t[2])]);
    }
    const auto& quads = topology_->quads();
    const std::size_t nq = params_.quad_indices.empty() ? quads.size() : params_.quad_indices.size();
    for (std::size_t i = 0; i < nq; ++i) {
        const std::size_t id = params_.quad_indices.empty() ? i : static_cast<std::size_t>(params_.quad_indices[i]);
        if (id >= quads.size()) continue;
        const Quad& q = quads[id];
        volume += x[at(q[0])].cross(x[at(q[1])]).dot(x[at(q[2])]);
        volume += x[at(q[0])].cross(x[at(q[2])]).dot(x[at(q[3])]);
    }
    return volume / 6.0;
}

// SurfacePressureForceField::addForce, addTriangleSurfacePressure, addQuadSurfacePressure. The
// forces are summed in a buffer first, then added to f (SOFA's m_f).
void SurfacePressureForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3>) {
    double p = params_.pulse_mode ? next_pulse_pressure() : params_.pressure;
    if (params_.volume_conservation) {
        if (params_.default_volume == -1.0) params_.default_volume = mesh_volume(x);
        else if (params_.default_volume != 0.0) p *= params_.default_volume / mesh_volume(x);
    }
    last_pressure_ = p;
    stiffness_scale_ = p / 6.0;
    pressed_triangles_.clear();
    std::vector<Vec3> sum(f.size(), Vec3::Zero());

    const auto& triangles = topology_->triangles();
    const auto press_triangle = [&](std::size_t id) {
        const Triangle& t = triangles[id];
        const Vec3 ab = x[at(t[1])] - x[at(t[0])];
        const Vec3 ac = x[at(t[2])] - x[at(t[0])];
        Vec3 force = ab.cross(ac) * (p / 6.0);
        if (params_.use_tangent_stiffness) pressed_triangles_.push_back(static_cast<Index>(id));
        if (params_.main_direction != Vec3::Zero()) {
            Vec3 n = ab.cross(ac);
            const double len = n.norm();
            if (len > std::numeric_limits<double>::epsilon()) n /= len;
            force *= std::fabs(n.dot(params_.main_direction));
        }
        sum[at(t[0])] += force;
        sum[at(t[1])] += force;
        sum[at(t[2])] += force;
    };
    if (!params_.triangle_indices.empty()) {
        for (Index id : params_.triangle_indices)
            if (static_cast<std::size_t>(id) < triangles.size()) press_triangle(static_cast<std::size_t>(id));
    } else {
        for (std::size_t i = 0; i < triangles.size(); ++i) {
            const Triangle& t = triangles[i];
            if (in_box(x[at(t[0])]) && in_box(x[at(t[1])]) && in_box(x[at(t[2])])) press_triangle(i);
        }
    }

    const auto& quads = topology_->quads();
    const auto press_quad = [&](std::size_t id) {
        const Quad& q = quads[id];
        const Vec3 ab = x[at(q[1])] - x[at(q[0])];
        const Vec3 ac = x[at(q[2])] - x[at(q[0])];
        const Vec3 ad = x[at(q[3])] - x[at(q[0])];
        const Vec3 f1 = ab.cross(ac) * (p / 6.0);
        const Vec3 f2 = ac.cross(ad) * (p / 6.0);
        const Vec3 both = f1 + f2;
        sum[at(q[0])] += both;
        sum[at(q[1])] += f1;
        sum[at(q[2])] += both;
        sum[at(q[3])] += f2;
    };
    if (!params_.quad_indices.empty()) {
        for (Index id : params_.quad_indices)
            if (static_cast<std::size_t>(id) < quads.size()) press_quad(static_cast<std::size_t>(id));
    } else {
        for (std::size_t i = 0; i < quads.size(); ++i) {
            const Quad& q = quads[i];
            if (in_box(x[at(q[0])]) && in_box(x[at(q[1])]) && in_box(x[at(q[2])]) && in_box(x[at(q[3])])) press_quad(i);
        }
    }
    for (std::size_t i = 0; i < f.size(); ++i) f[i] += sum[i];
    energy_ = -p * mesh_volume(x);
    last_x_.assign(x.begin(), x.end());
}

// SurfacePressureForceField::addDForce, in SOFA's operations: per pressed triangle (a, b, c), the
// blocks p/6·[bc]ₓ, p/6·[ca]ₓ, p/6·[ab]ₓ (DcrossDA, DcrossDB, DcrossDC, each entry times p/6) of the
// last add_force, bc = c − b, ca = a − c, ab = b − a; each corner's df += (block·dx_a)·k,
// += (block·dx_b)·k, += (block·dx_c)·k in turn (SOFA's derivTriNormalValues of the corner, in
// triangle order).
void SurfacePressureForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                           double) const {
    if (!params_.use_tangent_stiffness) return;
    const auto& triangles = topology_->triangles();
    for (Index id : pressed_triangles_) {
        const Triangle& t = triangles[static_cast<std::size_t>(id)];
        const Vec3& a = last_x_[at(t[0])];
        const Vec3& b = last_x_[at(t[1])];
        const Vec3& c = last_x_[at(t[2])];
        const Vec3 terms[3] = {
            sofa_vec::scaled(sofa_vec::times(cross_matrix(c - b) * stiffness_scale_, dx[at(t[0])]), k_factor),
            sofa_vec::scaled(sofa_vec::times(cross_matrix(a - c) * stiffness_scale_, dx[at(t[1])]), k_factor),
            sofa_vec::scaled(sofa_vec::times(cross_matrix(b - a) * stiffness_scale_, dx[at(t[2])]), k_factor)};
        for (PointId p : t)
            for (const Vec3& term : terms) df[at(p)] += term;
    }
}

void SurfacePressureForceField::add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const {
    if (!params_.use_tangent_stiffness) return;
    const auto& triangles = topology_->triangles();
    for (Index id : pressed_triangles_) {
        const Triangle& t = triangles[static_cast<std::size_t>(id)];
        const Vec3& a = last_x_[at(t[0])];
        const Vec3& b = last_x_[at(t[1])];
        const Vec3& c = last_x_[at(t[2])];
        const double s = stiffness_scale_ * factor;
        const Mat3 blocks[3] = {cross_matrix(c - b) * s, cross_matrix(a - c) * s, cross_matrix(b - a) * s};
        for (PointId row : t)
            for (std::size_t k = 0; k < 3; ++k) {
                const Index r = offset + 3 * row;
                const Index col = offset + 3 * t[k];
                for (Index i = 0; i < 3; ++i)
                    for (Index j = 0; j < 3; ++j) triplets.emplace_back(r + i, col + j, blocks[k](i, j));
            }
    }
}

}  // namespace penalty
