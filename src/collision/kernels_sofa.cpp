// NewProximity, MinProximity and Discrete element intersectors (spec §5.3–5.5); each method's
// constants (tolerances, normal guards, SOFA's flag quirks) are its row in kernels.hpp.
#include "kernels.hpp"
#include "penalty/core/pair_key.hpp"

#include "penalty/collision/separation.hpp"
#include "penalty/geometry/segment_triangle.hpp"

namespace penalty::detail {

namespace {

// ---------------------------------------------------------------------------------------------
// NewProximity helpers. Every helper tests |d|² < R² (strict) and returns the number of outputs;
// `value` is the raw distance minus `cfull`.

// NP-PP: point p (element 1 side) vs point q (element 2 side), normal by `g`
int np_pp(PairCtx& c, const Vec3& p, const Vec3& q, double R, double cfull, std::int64_t id, Guard g) {
    double len = 0.0;
    Vec3 n;
    if (!within(c, q - p, R, g, len, n)) return 0;
    return push(c, id, p, q, n, len - cfull);
}

// The output of a closest point p of a segment or triangle to the point q; swap: the point is
// element 1 (the output goes from q to p).
int np_closest_output(PairCtx& c, const Vec3& p, const Vec3& q, double R, double cfull, std::int64_t id, bool swap) {
    const Vec3 pq = q - p;
    double len = 0.0;
    Vec3 n;
    if (!within(c, swap ? Vec3(-pq) : pq, R, Guard::None, len, n)) return 0;
    return swap ? push(c, id, q, p, n, len - cfull) : push(c, id, p, q, n, len - cfull);
}

// NP-LP: segment [a, b] vs point q, clamped projection; swap: the point is element 1.
// Zero-length segment: no contact (SOFA computes t = 0/0 and emits NaN, see differences doc).
int np_lp(PairCtx& c, const Vec3& a, const Vec3& b, const Vec3& q, double R, double cfull, std::int64_t id, bool swap) {
    const Vec3 ab = b - a;
    const double A = ab.squaredNorm();
    if (!(A > 0.0)) return 0;
    double alpha = (q - a).dot(ab) / A;
    if (alpha < 0.0) alpha = 0.0;
    else if (alpha > 1.0) alpha = 1.0;
    const Vec3 p = a + ab * alpha;
    return np_closest_output(c, p, q, R, cfull, id, swap);
}

// NP-LL: segment [p1, p2] vs segment [q1, q2] (see LineLineConstants)
int np_ll(PairCtx& c, const Vec3& p1, const Vec3& p2, const Vec3& q1, const Vec3& q2, double R, double cfull,
          std::int64_t id, const LineLineConstants& k) {
    Vec3 p;
    Vec3 q;
    if (!line_line_points(p1, p2, q1, q2, k, p, q)) return 0;
    double len = 0.0;
    Vec3 n;
    if (!within(c, q - p, R, k.guard, len, n)) return 0;
    return push(c, id, p, q, n, len - cfull);
}

// NP-TP: triangle (p1, p2, p3) vs point q, flag checks on vertex/edge regions; swap: the point is
// element 1.
int np_tp(PairCtx& c, const Vec3& p1, const Vec3& p2, const Vec3& p3, std::uint32_t flags, const Vec3& q, double R,
          double cfull, std::int64_t id, bool swap) {
    const Gram g = gram(p1, p2, p3, q);
    if (g.degenerate) return 0;
    double alpha = 0.0;
    double beta = 0.0;
    if (!closest_feature(g, flags, kNewProximity.triangle_point, alpha, beta)) return 0;
    const Vec3 p = p1 + g.ab * alpha + g.ac * beta;
    return np_closest_output(c, p, q, R, cfull, id, swap);
}

// MinProximity's triangle projection: Q, the projection of P strictly inside triangle e1 of m1
// (α, β ≥ interior_lo, α + β ≤ interior_hi); false if outside or the triangle is degenerate.
bool min_triangle_projection(const PairCtx& c, const Vec3& P, Vec3& Q) {
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const Gram g = gram(t.p(c.e1, 0), t.p(c.e1, 1), t.p(c.e1, 2), P);
    const double lo = kMinProximity.interior_lo;
    if (g.degenerate || !inside_triangle(g.alpha, g.beta, lo, kMinProximity.interior_hi)) return false;
    Q = t.p(c.e1, 0) + g.alpha * g.ab + g.beta * g.ac;
    return true;
}

// Whether P is farther than R from the plane of triangle e1 of m1, when the pair runs the
// separation tests (separation.hpp): then no output.
bool beyond_triangle_plane(const PairCtx& c, const Vec3& P, double R) {
    if (!c.separation_tests) return false;
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const Vec3 &p1 = t.p(c.e1, 0), &p2 = t.p(c.e1, 1), &p3 = t.p(c.e1, 2);
    return plane_separates(p1, p2 - p1, p3 - p1, R, P);
}

}  // namespace

// =============================================================================================
// NewProximity
int np_sphere_sphere(PairCtx& c) {
    const SphereElem s1 = sphere_elem(c.m1, c.e1);
    const SphereElem s2 = sphere_elem(c.m2, c.e2);
    const double sk = skins(c);
    return np_pp(c, s1.c, s2.c, c.p.alarm_distance + sk + s1.r + s2.r, c.p.contact_distance + sk + s1.r + s2.r,
                 id_big(c), kNewProximity.point_point_guard);
}

int np_sphere_point(PairCtx& c) {
    const SphereElem s = sphere_elem(c.m1, c.e1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    return np_pp(c, s.c, q, c.p.alarm_distance + sk + s.r, c.p.contact_distance + sk + s.r, id_big(c),
                 kNewProximity.point_point_guard);
}

void np_sphere_point_all(PairCtx& c, std::span<const std::uint64_t> keys) {
    // np_sphere_point's sums: (alarm + skins) + r and (contact + skins) + r, the first terms once
    const auto& points = static_cast<const PointModel&>(c.m2);
    const double alarm = c.p.alarm_distance + skins(c);
    const double contact = c.p.contact_distance + skins(c);
    const auto run = [&](const auto& spheres) {
        for (const std::uint64_t key : keys) {
            c.e1 = Index(pair_key::first(key));
            c.e2 = Index(pair_key::second(key));
            const double r = spheres.radius(c.e1);
            np_pp(c, spheres.center(c.e1), points.point(c.e2), alarm + r, contact + r, id_big(c),
                  kNewProximity.point_point_guard);
        }
    };
    if (c.m1.type() == ModelType::RigidSphere) run(static_cast<const RigidSphereModel&>(c.m1));
    else run(static_cast<const SphereModel&>(c.m1));
}

// Point–point and line–line are one routine in both methods, with the method's constants.
namespace {
int point_point(PairCtx& c, Guard g) {
    const Vec3& p = static_cast<const PointModel&>(c.m1).point(c.e1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    return np_pp(c, p, q, c.p.alarm_distance + sk, c.p.contact_distance + sk, id_big(c), g);
}

int line_line(PairCtx& c, const LineLineConstants& k) {
    const auto& l1 = static_cast<const LineModel&>(c.m1);
    const auto& l2 = static_cast<const LineModel&>(c.m2);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const Vec3 &p1 = l1.p1(c.e1), &p2 = l1.p2(c.e1), &q1 = l2.p1(c.e2), &q2 = l2.p2(c.e2);
    // segment 2 lies in the plane through q1 parallel to both segments (separation.hpp)
    if (c.separation_tests && plane_separates(p1, p2 - p1, q2 - q1, R, q1)) return 0;
    return np_ll(c, p1, p2, q1, q2, R, c.p.contact_distance + sk, id_big(c), k);
}
}  // namespace

int np_point_point(PairCtx& c) { return point_point(c, kNewProximity.point_point_guard); }
int min_point_point(PairCtx& c) { return point_point(c, kMinProximity.point_point_guard); }
int np_line_line(PairCtx& c) { return line_line(c, kNewProximity.line_line); }
int min_line_line(PairCtx& c) { return line_line(c, kMinProximity.line_line); }

int np_line_point(PairCtx& c) {
    const auto& l = static_cast<const LineModel&>(c.m1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    return np_lp(c, l.p1(c.e1), l.p2(c.e1), q, c.p.alarm_distance + sk, c.p.contact_distance + sk, c.e2, false);
}

int np_line_sphere(PairCtx& c) {
    const auto& l = static_cast<const LineModel&>(c.m1);
    const SphereElem s = sphere_elem(c.m2, c.e2);
    const double sk = skins(c);
    return np_lp(c, l.p1(c.e1), l.p2(c.e1), s.c, c.p.alarm_distance + sk + s.r, c.p.contact_distance + sk + s.r, c.e2,
                 false);
}

int np_triangle_point(PairCtx& c) {
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const Vec3 &p1 = t.p(c.e1, 0), &p2 = t.p(c.e1, 1), &p3 = t.p(c.e1, 2);
    if (c.separation_tests && plane_separates(p1, p2 - p1, p3 - p1, R, q)) return 0;
    return np_tp(c, p1, p2, p3, t.flags(c.e1), q, R, c.p.contact_distance + sk, c.e2, false);
}

int np_triangle_sphere(PairCtx& c) {
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const SphereElem s = sphere_elem(c.m2, c.e2);
    const TriangleRegionConstants region = triangle_sphere_region(c.p);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk + s.r;
    const Vec3 &p1 = t.p(c.e1, 0), &p2 = t.p(c.e1, 1), &p3 = t.p(c.e1, 2);
    if (c.separation_tests && plane_separates(p1, p2 - p1, p3 - p1, R, s.c)) return 0;
    const Gram g = gram(p1, p2, p3, s.c);
    if (g.degenerate) return 0;
    double alpha = 0.0;
    double beta = 0.0;
    if (!closest_feature(g, t.flags(c.e1), region, alpha, beta)) return 0;
    const Vec3 p = p1 + g.ab * alpha + g.ac * beta;
    double len = 0.0;
    Vec3 n;
    if (!within(c, s.c - p, R, Guard::Sofa, len, n)) return 0;
    return push(c, c.e2, p, s.point_by_normal(n), n, len - (c.p.contact_distance + sk + s.r));
}

int np_triangle_line(PairCtx& c) {
    using F = TriangleModel::Flags;
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const auto& l = static_cast<const LineModel&>(c.m2);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const double cf = c.p.contact_distance + sk;
    const Vec3& p1 = t.p(c.e1, 0);
    const Vec3& p2 = t.p(c.e1, 1);
    const Vec3& p3 = t.p(c.e1, 2);
    const Vec3& q1 = l.p1(c.e2);
    const Vec3& q2 = l.p2(c.e2);
    // every output joins a point of the triangle's plane to a point of the segment
    if (c.separation_tests && plane_separates(p1, p2 - p1, p3 - p1, R, q1, q2)) return 0;
    const std::uint32_t f = t.flags(c.e1);
    const std::int64_t id = c.e2;
    int n = 0;
    // owned triangle vertices vs the line (vertex is point[0])
    if (f & F::kP1) n += np_lp(c, q1, q2, p1, R, cf, id, true);
    if (f & F::kP2) n += np_lp(c, q1, q2, p2, R, cf, id, true);
    if (f & F::kP3) n += np_lp(c, q1, q2, p3, R, cf, id, true);
    // line end points vs the triangle (no flag check on the line side)
    n += np_tp(c, p1, p2, p3, f, q1, R, cf, id, false);
    n += np_tp(c, p1, p2, p3, f, q2, R, cf, id, false);
    if (c.p.use_line_line) {
        const LineLineConstants& k = kNewProximity.line_line;
        if (f & F::kE12) n += np_ll(c, p1, p2, q1, q2, R, cf, id, k);
        if (f & F::kE23) n += np_ll(c, p2, p3, q1, q2, R, cf, id, k);
        if (f & F::kE31) n += np_ll(c, p3, p1, q1, q2, R, cf, id, k);
    }
    return n;
}

bool np_triangle_triangle_writes_normals(const IntersectionParams& p, const CollisionModel& m1,
                                         const CollisionModel& m2) {
    return p.method == IntersectionMethod::NewProximity && m1.type() == ModelType::Triangle &&
           m2.type() == ModelType::Triangle && !p.quirks.fix_newproximity_triangle_triangle_normal_overwrite &&
           !(m1.params().both_side && m2.params().both_side);
}

bool model_writes_read_only_by_writes(const IntersectionParams& p) {
    return p.method == IntersectionMethod::NewProximity;
}

namespace {
// Two triangles of one model that share a vertex are neighbours: SOFA tests neither.
bool neighbours_in_one_model(const TriangleModel& t1, Index e1, const TriangleModel& t2, Index e2) {
    if (&t1 != &t2) return false;
    for (auto i : t1.triangle(e1))
        for (auto j : t2.triangle(e2))
            if (i == j) return true;
    return false;
}
}  // namespace

// §14.4: before its tests, SOFA stores the other triangle's normal, negated, as a triangle's
// normal: n2 = −n1, or n1 = −n2 when model 1 is two-sided; the last write wins. The outputs
// (geometry below) do not read the stored normals. Only where np_triangle_triangle_writes_normals
// holds.
void np_triangle_triangle_normals(PairCtx& c) {
    auto& t1 = static_cast<TriangleModel&>(c.m1);
    auto& t2 = static_cast<TriangleModel&>(c.m2);
    if (neighbours_in_one_model(t1, c.e1, t2, c.e2)) return;
    if (!t1.params().both_side) t2.set_normal(c.e2, -t1.normal(c.e1));
    else t1.set_normal(c.e1, -t2.normal(c.e2));
}

int np_triangle_triangle_geometry(PairCtx& c) {
    using F = TriangleModel::Flags;
    const auto& t1 = static_cast<const TriangleModel&>(c.m1);
    const auto& t2 = static_cast<const TriangleModel&>(c.m2);
    if (neighbours_in_one_model(t1, c.e1, t2, c.e2)) return 0;
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const double cf = c.p.contact_distance + sk;
    const Vec3 &p1 = t1.p(c.e1, 0), &p2 = t1.p(c.e1, 1), &p3 = t1.p(c.e1, 2);
    const Vec3 &q1 = t2.p(c.e2, 0), &q2 = t2.p(c.e2, 1), &q3 = t2.p(c.e2, 2);
    // every output joins a point of one triangle to a point of the other: a plane holding one
    // triangle with the other beyond R on one side rules them all out
    if (c.separation_tests &&
        (plane_separates(p1, p2 - p1, p3 - p1, R, q1, q2, q3) || plane_separates(q1, q2 - q1, q3 - q1, R, p1, p2, p3)))
        return 0;
    const std::uint32_t f1 = t1.flags(c.e1);
    const std::uint32_t f2 = t2.flags(c.e2);
    const std::int64_t id1 = std::int64_t(c.e1) * 3;
    const std::int64_t id2 = std::int64_t(t1.size()) * 3 + std::int64_t(c.e2) * 12;
    // The separation test per vertex (separation.hpp; beyond SOFA's code, the same outputs): a
    // vertex–triangle output joins the vertex to a point p1 + α AB + β AC of the triangle's
    // plane, so a vertex beyond R from that plane gives none. The models' unit plane normals are
    // zero when not reliable (then never beyond), used only when current (TriangleModel::
    // update_planes, run by CollisionPipeline before the candidates); S² = 12 M² bounds |p|² of
    // every point of both triangles. Tested only before a vertex–triangle test: the edge–edge
    // tests, bounded the same way by both ends of an edge, saved less than the other sides cost.
    const double M = std::max(t1.coordinate_bound(), t2.coordinate_bound());
    const double limit = separation_limit(R, 12.0 * M * M);
    // an underflowing bound would reject too much
    const bool usable = t1.planes_current() && t2.planes_current() && limit > 1e-290;
    const Vec3& n1 = t1.plane_normal(c.e1);
    const Vec3& n2 = t2.plane_normal(c.e2);
    const auto near = [limit, usable](const Vec3& n, const Vec3& v, const Vec3& origin) {
        const double s = n.dot(v - origin);
        return !usable || !(s * s > limit);
    };

    int n = 0;
    // vertices of e1 against e2 (vertex is point[0]); §14.3: vertex 1 without its flag
    const bool v1 = !c.p.quirks.fix_newproximity_triangle_triangle_vertex1_flag || (f1 & F::kP1);
    if (v1 && near(n2, p1, q1)) n += np_tp(c, q1, q2, q3, f2, p1, R, cf, id1 + 0, true);
    if ((f1 & F::kP2) && near(n2, p2, q1)) n += np_tp(c, q1, q2, q3, f2, p2, R, cf, id1 + 1, true);
    if ((f1 & F::kP3) && near(n2, p3, q1)) n += np_tp(c, q1, q2, q3, f2, p3, R, cf, id1 + 2, true);
    // owned vertices of e2 against e1
    if ((f2 & F::kP1) && near(n1, q1, p1)) n += np_tp(c, p1, p2, p3, f1, q1, R, cf, id2 + 0, false);
    if ((f2 & F::kP2) && near(n1, q2, p1)) n += np_tp(c, p1, p2, p3, f1, q2, R, cf, id2 + 1, false);
    if ((f2 & F::kP3) && near(n1, q3, p1)) n += np_tp(c, p1, p2, p3, f1, q3, R, cf, id2 + 2, false);
    if (c.p.use_line_line) {
        const std::uint32_t e[3] = {F::kE12, F::kE23, F::kE31};
        const Vec3* pa[3][2] = {{&p1, &p2}, {&p2, &p3}, {&p3, &p1}};
        const Vec3* qa[3][2] = {{&q1, &q2}, {&q2, &q3}, {&q3, &q1}};
        for (int i = 0; i < 3; ++i) {
            if (!(f1 & e[i])) continue;
            for (int j = 0; j < 3; ++j) {
                if (!(f2 & e[j])) continue;
                n += np_ll(c, *pa[i][0], *pa[i][1], *qa[j][0], *qa[j][1], R, cf, id2 + 3 + 3 * i + j,
                           kNewProximity.line_line);
            }
        }
    }
    return n;
}

int np_triangle_triangle(PairCtx& c) {
    if (np_triangle_triangle_writes_normals(c.p, c.m1, c.m2)) np_triangle_triangle_normals(c);
    return np_triangle_triangle_geometry(c);
}

bool reads_triangle_planes(const KernelParts& kernel) {
    return kernel.reads == &np_triangle_triangle || kernel.reads == &np_triangle_triangle_geometry;
}

bool outputs_join_element_points(const KernelParts& kernel) {
    // each of these ends with within(p − q, R) for p on one element (a triangle's α, β, or a
    // segment's parameter, possibly outside the element but on its plane or line) and q in the
    // other (a point, a sphere's centre or surface point, a clamped or interior segment
    // parameter, an interior or edge point of a triangle_point region). Triangle–Triangle only
    // as np_triangle_triangle: its geometry part is a `reads` only beside the normal writes.
    static constexpr KernelFn kJoining[] = {&np_line_point,        &np_line_sphere,     &np_line_line,
                                            &np_triangle_point,    &np_triangle_sphere, &np_triangle_line,
                                            &np_triangle_triangle, &min_line_point,     &min_line_sphere,
                                            &min_line_line,        &min_triangle_point, &min_triangle_sphere};
    if (kernel.writes != nullptr) return false;
    for (const KernelFn fn : kJoining)
        if (kernel.reads == fn) return true;
    return false;
}

bool outputs_nearest_to_element2(const IntersectionParams& params, const KernelParts& kernel) {
    // each pushes id c.e2, point[0] = P on the line or triangle, value |q − P| − c: np_lp clamps
    // the segment parameter; np_tp's features have α, β, edge parameters ≥ ε (triangle_point
    // constants); the MinProximity and LocalMinDistance ones take a clamped or strict interior
    // parameter (min_line_sphere's mirror, §14.1, maps the interior onto itself)
    static constexpr KernelFn kInBox[] = {&np_line_point,   &np_line_sphere,     &np_triangle_point,   &min_line_point,
                                          &min_line_sphere, &min_triangle_point, &min_triangle_sphere, &lmd_line_point,
                                          &lmd_line_sphere, &lmd_triangle_point, &lmd_triangle_sphere};
    if (kernel.writes != nullptr) return false;
    if (kernel.reads == &np_triangle_sphere) return params.quirks.fix_newproximity_triangle_sphere_edge_range;
    for (const KernelFn fn : kInBox)
        if (kernel.reads == fn) return true;
    return false;
}

// =============================================================================================
// Sphere–sphere routine shared by Discrete, MinProximity and LocalMinDistance (rigid pairs):
// no contact iff |d|² > (Aeff + r1 + r2)² (equality accepted); surface points for rigid spheres.
namespace {
int sphere_sphere_sofa(PairCtx& c, double aeff, double ceff) {
    const SphereElem s1 = sphere_elem(c.m1, c.e1);
    const SphereElem s2 = sphere_elem(c.m2, c.e2);
    const double r = s1.r + s2.r;
    const Vec3 d = s2.c - s1.c;
    const double n2 = d.squaredNorm();
    if (n2 > (aeff + r) * (aeff + r)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    if (!unit_normal(c, d, len, Guard::None, n)) return 0;
    return push(c, id_big(c), s1.point_by_normal(-n), s2.point_by_normal(n), n, len - r - ceff);
}
}  // namespace

int discrete_sphere_sphere(PairCtx& c) { return sphere_sphere_sofa(c, c.p.alarm_distance, c.p.contact_distance); }

int lmd_rigid_sphere_pair(PairCtx& c) { return sphere_sphere_sofa(c, c.p.alarm_distance, c.p.contact_distance); }

int discrete_triangle_line(PairCtx& c) {
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const auto& l = static_cast<const LineModel&>(c.m2);
    const auto x = segment_triangle_crossing(t.p(c.e1, 0), t.p(c.e1, 1), t.p(c.e1, 2), l.p1(c.e2), l.p2(c.e2));
    if (!x) return 0;
    return push(c, c.e2, x->point, x->point, t.normal(c.e1), 0.0);
}

// =============================================================================================
// MinProximity
int min_sphere_sphere(PairCtx& c) {
    const double sk = skins(c);
    return sphere_sphere_sofa(c, c.p.alarm_distance + sk, c.p.contact_distance + sk);
}

int min_sphere_point(PairCtx& c) {
    const SphereElem s = sphere_elem(c.m1, c.e1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    double len = 0.0;
    Vec3 n;
    if (!within(c, q - s.c, c.p.alarm_distance + s.r + sk, Guard::Sofa, len, n)) return 0;
    return push(c, c.e1, s.point_by_normal(-n), q, n, len - (c.p.contact_distance + s.r + sk));
}

int min_line_point(PairCtx& c) {
    const auto& l = static_cast<const LineModel&>(c.m1);
    const Vec3& P = static_cast<const PointModel&>(c.m2).point(c.e2);
    const Vec3& a = l.p1(c.e1);
    const Vec3 ab = l.p2(c.e1) - a;
    const double A = ab.squaredNorm();
    if (!(A > 0.0)) return 0;  // SOFA: t = NaN, no contact
    const double t = (P - a).dot(ab) / A;
    const Vec3 Q = t <= 0.0 ? a : (t >= 1.0 ? Vec3(l.p2(c.e1)) : Vec3(a + t * ab));
    const double sk = skins(c);
    double len = 0.0;
    Vec3 n;
    if (!within(c, P - Q, c.p.alarm_distance + sk, Guard::Sofa, len, n)) return 0;
    return push(c, c.e2, Q, P, n, len - (c.p.contact_distance + sk));
}

int min_line_sphere(PairCtx& c) {
    const auto& l = static_cast<const LineModel&>(c.m1);
    const SphereElem s = sphere_elem(c.m2, c.e2);
    const Vec3& p1 = l.p1(c.e1);
    const Vec3& p2 = l.p2(c.e1);
    const Vec3 ba = p1 - p2;
    const double A = ba.squaredNorm();
    if (!(A > 0.0)) return 0;
    // t measured from p2 toward p1
    const double t = ba.dot(s.c - p2) / A;
    if (t < kMinProximity.interior_lo || t > kMinProximity.interior_hi) return 0;
    // §14.1: SOFA applies t from p1 toward p2 (mirror about the midpoint)
    const Vec3 Q = c.p.quirks.fix_minproximity_line_sphere_mirror ? Vec3(p2 + t * ba) : Vec3(p1 + t * (p2 - p1));
    const double sk = skins(c);
    double len = 0.0;
    Vec3 n;
    if (!within(c, s.c - Q, c.p.alarm_distance + s.r + sk, Guard::Sofa, len, n)) return 0;
    return push(c, c.e2, Q, s.point_by_normal(n), n, len - (c.p.contact_distance + s.r + sk));
}

int min_triangle_point(PairCtx& c) {
    const Vec3& P = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    if (beyond_triangle_plane(c, P, R)) return 0;
    Vec3 Q;
    if (!min_triangle_projection(c, P, Q)) return 0;
    double len = 0.0;
    Vec3 n;
    if (!within(c, P - Q, R, Guard::Sofa, len, n)) return 0;
    if (c.p.use_surface_normals) n = static_cast<const TriangleModel&>(c.m1).normal(c.e1);
    return push(c, c.e2, Q, P, n, len - (c.p.contact_distance + sk));
}

int min_triangle_sphere(PairCtx& c) {
    const SphereElem s = sphere_elem(c.m2, c.e2);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + s.r + sk;
    if (beyond_triangle_plane(c, s.c, R)) return 0;
    Vec3 Q;
    if (!min_triangle_projection(c, s.c, Q)) return 0;
    double len = 0.0;
    Vec3 n;
    if (!within(c, s.c - Q, R, Guard::Sofa, len, n)) return 0;
    return push(c, c.e2, Q, s.point_by_normal(n), n, len - (c.p.contact_distance + s.r + sk));
}

}  // namespace penalty::detail
