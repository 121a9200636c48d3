#pragma once
// Internal: the element intersectors ("kernels") of every method, called through the dispatch
// table in intersection.cpp. Each kernel receives the two models in registered order.

#include "penalty/collision/intersection.hpp"
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/kernel_path.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace penalty::detail {

/// Everything a kernel needs for one element pair.
struct PairCtx {
    const IntersectionParams& p;
    CollisionModel& m1;
    CollisionModel& m2;
    Index e1;
    Index e2;
    DetectionOutputList& out;
    /// Run the early outs of penalty/collision/separation.hpp (the same outputs, sooner): set by
    /// the narrow phase for model pairs with elements long against R (worth_separating).
    bool separation_tests = false;
    /// The pair's constants, computed once for all its candidates (skins, id_big)
    double skin = m1.params().contact_distance + m2.params().contact_distance;
    bool id_of_e1 = m1.size() > m2.size();
};

using KernelFn = int (*)(PairCtx&);

/// The element intersector of the pair (m1, m2) for `params` (intersect_elements' lookup, done
/// once per model pair by the narrow phase); throws as intersect_elements does for a wrong order
/// or a pair with no active intersector.
[[nodiscard]] KernelFn pair_kernel(const IntersectionParams& params, const CollisionModel& m1,
                                   const CollisionModel& m2);

/// A pair's kernel split into its writes to the models and the rest, which only reads them:
/// `pair_kernel(…)(ctx)` ≡ `writes(ctx); reads(ctx)`, and no `reads` reads what a `writes`
/// writes. The narrow phase runs the writes over the candidates in their order (SOFA's), then
/// the reads in parallel. `writes` is nullptr for every kernel but NewProximity Triangle–Triangle
/// with SOFA's normal overwrite (§14.4, see np_triangle_triangle_writes_normals).
struct KernelParts {
    /// Reads only the models and the element pair: never the output list or separation_tests.
    void (*writes)(PairCtx&) = nullptr;
    KernelFn reads = nullptr;
    /// Optional: appends to `kept`, in order, the candidates of `keys` (PairKey(element 1,
    /// element 2).bits()) that may give `reads` an output, decided by the kernel's own first tests with
    /// the same operations (so every candidate dropped gives no output, and the outputs of the
    /// kept ones are those of all): cheaper a candidate than the kernel, for the kernels whose
    /// candidates mostly fail those tests: NewProximity's and MinProximity's Triangle–Point,
    /// Triangle–Sphere and Line–Line (filter_triangle_candidates, filter_line_line_candidates).
    void (*filter)(const IntersectionParams&, const CollisionModel& m1, const CollisionModel& m2,
                   std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept) = nullptr;
    /// Optional: `reads` over every candidate of `keys` (PairKey(element 1, element 2).bits()), in order,
    /// the same operations with the pair's constants and its models' types taken once (for
    /// cheap kernels whose call per candidate costs a good part of their work: NewProximity
    /// Sphere–Point). Not for a pair within one node (elements_may_collide is not asked).
    void (*reads_all)(PairCtx&, std::span<const std::uint64_t> keys) = nullptr;
};
[[nodiscard]] KernelParts pair_kernel_parts(const IntersectionParams& params, const CollisionModel& m1,
                                            const CollisionModel& m2);

/// Whether the kernel's reads are NewProximity Triangle–Triangle's, whose separation tests read
/// both TriangleModels' planes when current (call TriangleModel::update_planes before them).
[[nodiscard]] bool reads_triangle_planes(const KernelParts& kernel);

/// Whether NewProximity Triangle–Triangle overwrites the stored normals of (m1, m2) (§14.4:
/// unless the quirk is fixed or both models are two-sided).
[[nodiscard]] bool np_triangle_triangle_writes_normals(const IntersectionParams& params, const CollisionModel& m1,
                                                       const CollisionModel& m2);

/// Whether, in a detection with these parameters, what the kernels' writes (KernelParts::writes)
/// write is read by writes alone: no kernel's reads, no filter and no traversal reads it. Then
/// the writes of all the detection's pairs may run after the pairs' reads, in pair order and
/// over each pair's candidates in their order, for the same outputs and the same models at the
/// end. NewProximity: the only writes are Triangle–Triangle's normal overwrite, and no
/// NewProximity kernel reads the stored normals (outputs from positions, separation tests from
/// TriangleModel::update_planes); the stored normals are read by Discrete Triangle–Line and by
/// MinProximity with surface normals, which never share a detection with NewProximity kernels.
[[nodiscard]] bool model_writes_read_only_by_writes(const IntersectionParams& params);

/// Whether every output of the kernel joins, for either element that is a Triangle or a Line, a
/// point of its plane or line to a point within the other element's box, and needs their
/// computed distance below box_margin plus the radius of a sphere element (which its box
/// includes): the NewProximity and MinProximity kernels of Triangle, Line, Point and spheres,
/// when they do not write the models. Then a box farther than box_margin from a Triangle or
/// Line element (ElementPlanes::clears) holds no partner of that element with an output.
[[nodiscard]] bool outputs_join_element_points(const KernelParts& kernel);

/// Whether every output of the kernel (with these parameters) has id e2, a first point P in the
/// box of element 1's vertices, and value |q − P| − c, with q element e2's point (with_element_points) and c the
/// same for every output of one e2 (the pair's contact distances and element 2's radius): the
/// Line and Triangle kernels against a Point or a sphere that take P on the segment (clamped or
/// interior parameter) or on an owned feature or the interior of the triangle. Then no output of
/// e2 with element 1 is shorter than the distance from q to element 1's box.
/// NewProximity Triangle–Sphere only with its edge range fixed: under SOFA's range (§14.2) its
/// edges AB and AC take any parameter below 1, so P may lie on the edge's line beyond A (bounds
/// by the distances to those lines, or to the triangle's plane, were tried: near a surface most
/// of them pass closer to q than its nearest output, and they pruned 3 % of the candidates).
[[nodiscard]] bool outputs_nearest_to_element2(const IntersectionParams& params, const KernelParts& kernel);

/// A sphere element of either SphereModel or RigidSphereModel.
struct SphereElem {
    Vec3 c;
    double r;
    bool rigid;
    /// SOFA's getContactPointByNormal(n): Vec3 sphere → centre; rigid sphere → c − n r.
    [[nodiscard]] Vec3 point_by_normal(const Vec3& n) const { return rigid ? Vec3(c - n * r) : c; }
};

inline SphereElem sphere_elem(const CollisionModel& m, Index i) {
    if (m.type() == ModelType::RigidSphere) {
        const auto& s = static_cast<const RigidSphereModel&>(m);
        return {s.center(i), s.radius(i), true};
    }
    const auto& s = static_cast<const SphereModel&>(m);
    return {s.center(i), s.radius(i), false};
}

/// f(point_of), point_of(e) the point of element e of a Point model or the centre of element e
/// of a Sphere or RigidSphere model: the model's type is switched on once, outside f's loops.
template <class F>
void with_element_points(const CollisionModel& m, F&& f) {
    if (m.type() == ModelType::Sphere)
        f([&s = static_cast<const SphereModel&>(m)](Index e) -> const Vec3& { return s.center(e); });
    else if (m.type() == ModelType::RigidSphere)
        f([&s = static_cast<const RigidSphereModel&>(m)](Index e) -> const Vec3& { return s.center(e); });
    else f([&p = static_cast<const PointModel&>(m)](Index e) -> const Vec3& { return p.point(e); });
}

/// The two models' contact distances, summed (PairCtx::skin).
inline double skins(const PairCtx& c) { return c.skin; }

/// SOFA's "id_big": index of the element of the model with more elements (ties → e2).
inline std::int64_t id_big(const PairCtx& c) { return c.id_of_e1 ? std::int64_t(c.e1) : std::int64_t(c.e2); }

/// Whether SOFA's routine has the 1e-15 zero-distance guard (→ (1,0,0)).
enum class Guard : std::uint8_t { None, Sofa };

/// Unit normal d/len. Guard::Sofa: (1,0,0) if len ≤ 1e-15 (SOFA's behaviour). Guard::None:
/// SOFA divides blindly; for len == 0 apply the zero-distance policy. Returns false if the
/// output must be dropped.
inline bool unit_normal(const PairCtx& c, const Vec3& d, double len, Guard g, Vec3& n) {
    if (g == Guard::Sofa) {
        n = len > 1e-15 ? Vec3(d / len) : Vec3::UnitX();
        return true;
    }
    if (len > 0.0) {
        n = d / len;
        if (n.allFinite()) return true;
    }
    switch (c.p.quirks.zero_distance_normal) {
        case ZeroDistanceNormal::FallbackX:
            n = Vec3::UnitX();
            return true;
        case ZeroDistanceNormal::Drop:
            return false;
        case ZeroDistanceNormal::SofaNaN:
            n = d / len;
            return true;
    }
    return false;
}

/// The closing test of SOFA's proximity routines, d from the point on one element to the point
/// on the other: true iff |d|² < R² (strict) and a normal n = d/|d| is given by `g` (see
/// unit_normal), with len = |d|.
inline bool within(const PairCtx& c, const Vec3& d, double R, Guard g, double& len, Vec3& n) {
    const double n2 = d.squaredNorm();
    if (!(n2 < R * R)) return false;
    len = std::sqrt(n2);
    return unit_normal(c, d, len, g, n);
}

inline int push(PairCtx& c, std::int64_t id, const Vec3& p0, const Vec3& p1, const Vec3& n, double value) {
    DetectionOutput o;
    o.elem1 = ElementIndex(c.e1);
    o.elem2 = ElementIndex(c.e2);
    o.id = id;
    o.point = {p0, p1};
    o.normal = n;
    o.value = value;
    c.out.push_back(o);
    return 1;
}

// ---- the constants of each method's routines (SOFA's values), one row per method ----

/// Segment–segment closest points p = p1 + α (p2 − p1), q = q1 + β (q2 − q1): the 2 × 2 normal
/// equations are solved unless |det| ≤ parallel (near-parallel segments: α = β = ½), and an
/// output exists only if α, β ∈ [lo, hi] (interior closest points).
struct LineLineConstants {
    double parallel;
    double lo;
    double hi;
    Guard guard;  ///< normal at zero distance
};

/// NewProximity's closest feature of a triangle (p1, p2, p3) to a point, from the barycentric
/// α, β of its projection and the edge parameters p_AB, p_AC, p_BC: the face iff α, β ≥ inside_lo
/// and α + β ≤ inside_hi; else vertex A iff p_AB < inside_lo and p_AC < vertex_a_ac, edge AB iff
/// p_AB ∈ [edge_lo, inside_hi) and β < inside_lo, edge AC likewise, else along BC (vertex B below
/// inside_lo, C above inside_hi). A feature gives an output only if the triangle owns it (its
/// flag; SOFA's triangle–sphere routine checks other edges' flags, see edge_ac_flag / edge_bc_flag).
struct TriangleRegionConstants {
    double inside_lo;
    double inside_hi;
    double vertex_a_ac;
    double edge_lo;
    std::uint32_t edge_ac_flag;
    std::uint32_t edge_bc_flag;
};

/// NewProximity (SOFA's NewProximityIntersection::doIntersection* routines).
struct NewProximityConstants {
    Guard point_point_guard;                  ///< point–point, sphere–sphere, sphere–point
    LineLineConstants line_line;              ///< line–line, triangle–line, triangle–triangle edges
    TriangleRegionConstants triangle_point;   ///< triangle–point, triangle–line, triangle–triangle
    TriangleRegionConstants triangle_sphere;  ///< as SOFA (quirks may fix the range and flags)
};
inline constexpr NewProximityConstants kNewProximity{
    .point_point_guard = Guard::None,
    .line_line = {.parallel = 1e-12, .lo = 1e-6, .hi = 0.999999, .guard = Guard::None},
    .triangle_point = {.inside_lo = std::numeric_limits<double>::epsilon(),
                       .inside_hi = 1.0 - std::numeric_limits<double>::epsilon(),
                       .vertex_a_ac = std::numeric_limits<double>::epsilon(),
                       .edge_lo = std::numeric_limits<double>::epsilon(),
                       .edge_ac_flag = TriangleModel::kE31,
                       .edge_bc_flag = TriangleModel::kE23},
    .triangle_sphere = {.inside_lo = 1e-6,
                        .inside_hi = 0.999999,
                        .vertex_a_ac = 1e-7,
                        .edge_lo = -std::numeric_limits<double>::infinity(),
                        .edge_ac_flag = TriangleModel::kE12,
                        .edge_bc_flag = TriangleModel::kE31},
};

/// Gram system of point q against triangle (p1, p2, p3): α, β with q ≈ p1 + α AB + β AC.
struct Gram {
    Vec3 ab, ac;
    double g00, g01, g11, b0, b1, det, alpha, beta;
    bool degenerate;
};
inline Gram gram(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& q) {
    Gram g;
    g.ab = p2 - p1;
    g.ac = p3 - p1;
    const Vec3 aq = q - p1;
    g.g00 = g.ab.dot(g.ab);
    g.g11 = g.ac.dot(g.ac);
    g.g01 = g.ab.dot(g.ac);
    g.b0 = aq.dot(g.ab);
    g.b1 = aq.dot(g.ac);
    g.det = g.g00 * g.g11 - g.g01 * g.g01;
    // zero-area triangle: SOFA divides by det = 0 (NaN/inf); we report no contact
    g.degenerate = !(g.det > 0.0) || !(g.g00 > 0.0) || !(g.g11 > 0.0) || !(g.g00 + g.g11 - 2.0 * g.g01 > 0.0);
    g.alpha = g.degenerate ? 0.0 : (g.b0 * g.g11 - g.b1 * g.g01) / g.det;
    g.beta = g.degenerate ? 0.0 : (g.b1 * g.g00 - g.b0 * g.g01) / g.det;
    return g;
}

/// Whether the projection's α, β are inside the triangle: not (α < lo or β < lo or α + β > hi),
/// so true on NaN (the callers drop degenerate triangles, whose α, β may be NaN, before).
/// NewProximity's face region and MinProximity's strict interior.
inline bool inside_triangle(double alpha, double beta, double lo, double hi) {
    return !(alpha < lo || beta < lo || alpha + beta > hi);
}

/// NewProximity's closest feature of the triangle to the projected point (see
/// TriangleRegionConstants): its α, β, or false if the triangle does not own it (`flags`).
inline bool closest_feature(const Gram& g, std::uint32_t flags, const TriangleRegionConstants& k, double& alpha,
                            double& beta) {
    using F = TriangleModel::Flags;
    alpha = g.alpha;
    beta = g.beta;
    if (inside_triangle(alpha, beta, k.inside_lo, k.inside_hi)) return true;
    const double pAB = g.b0 / g.g00;
    const double pAC = g.b1 / g.g11;
    if (pAB < k.inside_lo && pAC < k.vertex_a_ac) {
        if (!(flags & F::kP1)) return false;
        alpha = 0.0;
        beta = 0.0;
    } else if (pAB < k.inside_hi && pAB >= k.edge_lo && beta < k.inside_lo) {
        if (!(flags & F::kE12)) return false;
        alpha = pAB;
        beta = 0.0;
    } else if (pAC < k.inside_hi && pAC >= k.edge_lo && alpha < k.inside_lo) {
        if (!(flags & k.edge_ac_flag)) return false;
        alpha = 0.0;
        beta = pAC;
    } else {
        const double pBC = (g.b1 - g.b0 + g.g00 - g.g01) / (g.g00 + g.g11 - 2.0 * g.g01);
        if (pBC < k.inside_lo) {
            if (!(flags & F::kP2)) return false;
            alpha = 1.0;
            beta = 0.0;
        } else if (pBC > k.inside_hi) {
            if (!(flags & F::kP3)) return false;
            alpha = 0.0;
            beta = 1.0;
        } else {
            if (!(flags & k.edge_bc_flag)) return false;
            alpha = 1.0 - pBC;
            beta = pBC;
        }
    }
    return true;
}

/// NewProximity Triangle–Sphere's region constants under `params`' quirks (§14.2: SOFA's edge
/// range and its checks of FLAG_E12 on edge AC and FLAG_E31 on BC, each fixable).
inline TriangleRegionConstants triangle_sphere_region(const IntersectionParams& params) {
    TriangleRegionConstants region = kNewProximity.triangle_sphere;
    if (params.quirks.fix_newproximity_triangle_sphere_edge_range)
        region.vertex_a_ac = region.edge_lo = region.inside_lo;
    if (params.quirks.fix_newproximity_triangle_sphere_edge_flags) {
        region.edge_ac_flag = kNewProximity.triangle_point.edge_ac_flag;
        region.edge_bc_flag = kNewProximity.triangle_point.edge_bc_flag;
    }
    return region;
}

/// KernelParts::filter of the NewProximity and MinProximity Triangle–Point and Triangle–Sphere
/// kernels and of their Line–Line kernels: keep_triangle_candidates and
/// keep_line_line_candidates (penalty/collision/candidate_filters.hpp) on best_kernel_path().
void filter_triangle_candidates(const IntersectionParams& params, const CollisionModel& m1, const CollisionModel& m2,
                                std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept);
void filter_line_line_candidates(const IntersectionParams& params, const CollisionModel& m1, const CollisionModel& m2,
                                 std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept);

/// MinProximity (SOFA's MinProximityIntersection::doIntersection* routines).
struct MinProximityConstants {
    Guard point_point_guard;  ///< point–point
    LineLineConstants line_line;
    double interior_lo;  ///< strict interior of a segment (t) or triangle (α, β, α + β)
    double interior_hi;
};
inline constexpr MinProximityConstants kMinProximity{
    .point_point_guard = Guard::Sofa,
    .line_line = {.parallel = 1e-15, .lo = 1e-6, .hi = 0.999999, .guard = Guard::Sofa},
    .interior_lo = 1e-6,
    .interior_hi = 0.999999,
};

/// LocalMinDistance (SOFA's LocalMinDistance::computeIntersection routines).
struct LocalMinDistanceConstants {
    LineLineConstants line_line;
    double interior_lo;  ///< strict interior of a segment (t) or triangle (α, β, α + β)
    double interior_hi;
    double degenerate_segment;  ///< no contact if |AB| < this · |AP| (segment–point, segment–sphere)
};
inline constexpr LocalMinDistanceConstants kLocalMinDistance{
    .line_line = {.parallel = 1e-30, .lo = 1e-15, .hi = 1.0 - 1e-15, .guard = Guard::None},
    .interior_lo = 1e-6,
    .interior_hi = 0.999999,
    .degenerate_segment = 1e-12,
};

/// The closest points of SOFA's line–line routines (see LineLineConstants); false: no output.
inline bool line_line_points(const Vec3& p1, const Vec3& p2, const Vec3& q1, const Vec3& q2, const LineLineConstants& k,
                             Vec3& p, Vec3& q) {
    const Vec3 ab = p2 - p1;
    const Vec3 cd = q2 - q1;
    const Vec3 ac = q1 - p1;
    const double a00 = ab.dot(ab);
    const double a11 = cd.dot(cd);
    const double a01 = -cd.dot(ab);
    const double b0 = ab.dot(ac);
    const double b1 = -cd.dot(ac);
    const double det = a00 * a11 - a01 * a01;
    double alpha = 0.5;
    double beta = 0.5;
    if (det < -k.parallel || det > k.parallel) {
        alpha = (b0 * a11 - b1 * a01) / det;
        beta = (b1 * a00 - b0 * a01) / det;
        if (alpha < k.lo || alpha > k.hi || beta < k.lo || beta > k.hi) return false;
    }
    p = p1 + ab * alpha;
    q = q1 + cd * beta;
    return true;
}

/// exhaustive_narrow_phase's loop over the element pairs, on models already validated and
/// update()d (CollisionPipeline::refit does both once per detection, as SOFA's
/// computeBoundingTree does; intersection.cpp).
void exhaustive_element_pairs(const IntersectionParams& params, CollisionModel& m1, CollisionModel& m2,
                              DetectionOutputList& out, std::vector<Aabb>& box_scratch);

// ---- kernels, by method (definitions in the kernels_*.cpp files) ----
// NewProximity
int np_sphere_sphere(PairCtx&);                                           // Sphere/RigidSphere pairs (centres)
int np_sphere_point(PairCtx&);                                            // Sphere–Point, RigidSphere–Point
void np_sphere_point_all(PairCtx&, std::span<const std::uint64_t> keys);  // KernelParts::reads_all
int np_point_point(PairCtx&);
int np_line_point(PairCtx&);
int np_line_line(PairCtx&);
int np_line_sphere(PairCtx&);  // Line–Sphere, Line–RigidSphere
int np_triangle_point(PairCtx&);
int np_triangle_sphere(PairCtx&);  // Triangle–Sphere, Triangle–RigidSphere
int np_triangle_line(PairCtx&);
int np_triangle_triangle(PairCtx&);           // ≡ the two parts below in turn
void np_triangle_triangle_normals(PairCtx&);  // SOFA's normal overwrite, where it applies (writes the models)
int np_triangle_triangle_geometry(PairCtx&);  // the outputs (reads the positions only)
// MinProximity
int min_sphere_sphere(PairCtx&);
int min_sphere_point(PairCtx&);
int min_point_point(PairCtx&);
int min_line_point(PairCtx&);
int min_line_line(PairCtx&);
int min_line_sphere(PairCtx&);
int min_triangle_point(PairCtx&);
int min_triangle_sphere(PairCtx&);
// Discrete
int discrete_sphere_sphere(PairCtx&);
int discrete_triangle_line(PairCtx&);
// LocalMinDistance
int lmd_sphere_sphere(PairCtx&);  // Sphere–Sphere (Vec3); rigid pairs use the Discrete routine
int lmd_rigid_sphere_pair(PairCtx&);
int lmd_sphere_point(PairCtx&);
int lmd_point_point(PairCtx&);
int lmd_line_point(PairCtx&);
int lmd_line_line(PairCtx&);
int lmd_line_sphere(PairCtx&);
int lmd_triangle_point(PairCtx&);
int lmd_triangle_sphere(PairCtx&);
// Beyond SOFA
int cylinder_sphere(PairCtx&);  // Cylinder–Sphere, Cylinder–RigidSphere
int cylinder_cylinder(PairCtx&);
int cylinder_triangle(PairCtx&);
int tetrahedron_point(PairCtx&);

}  // namespace penalty::detail
