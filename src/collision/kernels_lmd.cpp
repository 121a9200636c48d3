// LocalMinDistance element intersectors and validity filters (spec §5.5, "LMD").
#include "kernels.hpp"

namespace penalty::detail {

namespace {

// normalise in place unless (near) zero, as SOFA's Vec::normalize leaves a zero vector alone
Vec3 safe_normalized(const Vec3& v) {
    const double n = v.norm();
    return n > 1e-300 ? Vec3(v / n) : v;
}

bool filters_on(const PairCtx& c) { return c.p.filter_intersection && !c.p.use_lmd_filters; }

// point filter; pq: from the point toward the other element
bool valid_point(const PairCtx& c, const PointModel& m, Index i, const Vec3& pq) {
    if (!filters_on(c)) return true;
    if (!m.node_has_line_model || m.topology() == nullptr) return true;
    const MeshTopology& topo = *m.topology();
    const auto& x = m.state().position;
    const Vec3& pt = x[std::size_t(i)];
    const auto& tav = topo.triangles_around_vertex();
    const auto& eav = topo.edges_around_vertex();
    static const std::vector<std::int32_t> kNone;
    const auto& tris = std::size_t(i) < tav.size() ? tav[std::size_t(i)] : kNone;
    const auto& edges = std::size_t(i) < eav.size() ? eav[std::size_t(i)] : kNone;
    Vec3 n_mean = Vec3::Zero();
    for (auto t : tris) {
        const Triangle& tr = topo.triangles()[std::size_t(t)];
        n_mean += safe_normalized(
            (x[std::size_t(tr[1])] - x[std::size_t(tr[0])]).cross(x[std::size_t(tr[2])] - x[std::size_t(tr[0])]));
    }
    if (tris.empty()) {
        for (auto e : edges) {
            const Edge& ed = topo.edges()[std::size_t(e)];
            n_mean += safe_normalized((pt - x[std::size_t(ed[0])]) + (pt - x[std::size_t(ed[1])]));
        }
    }
    const double pq_norm = pq.norm();
    if (n_mean.norm() > 1e-10) {
        n_mean.normalize();
        if (n_mean.dot(pq) < -c.p.angle_cone * pq_norm && !m.params().both_side) return false;
    }
    for (auto e : edges) {
        const Edge& ed = topo.edges()[std::size_t(e)];
        const Vec3 l = safe_normalized((pt - x[std::size_t(ed[0])]) + (pt - x[std::size_t(ed[1])]));
        double cone = n_mean.dot(l) * c.p.cone_factor;
        if (cone < 0.0) cone = 0.0;
        cone += c.p.angle_cone;
        if (l.dot(pq) < -cone * pq_norm) return false;
    }
    return true;
}

// line filter; pq: from the line toward the other element
bool valid_line(const PairCtx& c, const LineModel& m, Index i, const Vec3& pq) {
    if (!filters_on(c)) return true;
    const Edge& edge = m.edge(i);
    const Vec3 ab = safe_normalized(m.p2(i) - m.p1(i));
    const MeshTopology& topo = m.topology();
    const auto& tae = topo.triangles_around_edge();
    const auto& x = m.state().position;
    if (std::size_t(i) < tae.size() && tae[std::size_t(i)].size() == 2) {
        const auto& around = tae[std::size_t(i)];
        const Triangle& t0 = topo.triangles()[std::size_t(around[0])];
        const bool t0_left = (edge[0] == t0[0] && edge[1] == t0[1]) || (edge[0] == t0[1] && edge[1] == t0[2]) ||
                             (edge[0] == t0[2] && edge[1] == t0[0]);
        const Triangle& right = topo.triangles()[std::size_t(t0_left ? around[1] : around[0])];
        const Triangle& left = topo.triangles()[std::size_t(t0_left ? around[0] : around[1])];
        auto tri_normal = [&x](const Triangle& t) {
            return safe_normalized(
                (x[std::size_t(t[1])] - x[std::size_t(t[0])]).cross(x[std::size_t(t[2])] - x[std::size_t(t[0])]));
        };
        const Vec3 n1 = tri_normal(right);
        const Vec3 t1 = safe_normalized(n1.cross(ab));
        const Vec3 n2 = tri_normal(left);
        const Vec3 t2 = safe_normalized(ab.cross(n2));
        const Vec3 n_mean = safe_normalized(n1 + n2);
        if (n_mean.dot(pq) < 0.0 && !m.params().both_side) return false;
        const double pq_norm = pq.norm();
        double cone = n_mean.dot(t1) * c.p.cone_factor;
        if (cone < 0.0) cone = 0.0;
        cone += c.p.angle_cone;
        if (t1.dot(pq) < -cone * pq_norm) return false;
        cone = n_mean.dot(t2) * c.p.cone_factor;
        if (cone < 0.0) cone = 0.0;
        cone += c.p.angle_cone;
        if (t2.dot(pq) < -cone * pq_norm) return false;
        return true;
    }
    const Vec3 n1 = safe_normalized(pq);
    return !(std::abs(ab.dot(n1)) > c.p.angle_cone + 0.0001);
}

// triangle filter; pq: from the triangle toward the other element
bool valid_triangle(const PairCtx& c, const TriangleModel& m, Index i, const Vec3& pq) {
    if (!filters_on(c) || m.params().both_side) return true;
    const Vec3 n = (m.p(i, 1) - m.p(i, 0)).cross(m.p(i, 2) - m.p(i, 0));
    return n.dot(pq) >= 0.0;
}

// strict interior projection Q = A + t·AB of P on segment [A, B] (t ∈ [interior_lo,
// interior_hi]); false for a segment degenerate against |AP| (SOFA's guard) or P beyond it
bool segment_interior(const Vec3& a, const Vec3& b, const Vec3& P, Vec3& Q) {
    const Vec3 ab = b - a;
    const Vec3 ap = P - a;
    const double A = ab.squaredNorm();
    if (ab.norm() < kLocalMinDistance.degenerate_segment * ap.norm() || !(A > 0.0)) return false;
    const double t = ap.dot(ab) / A;
    if (t < kLocalMinDistance.interior_lo || t > kLocalMinDistance.interior_hi) return false;
    Q = a + t * ab;
    return true;
}

// output with the LMD convention: normal = d/|d| without guard (zero-distance policy applies)
int lmd_push(PairCtx& c, std::int64_t id, const Vec3& p0, const Vec3& p1, double cfull) {
    const Vec3 d = p1 - p0;
    const double len = d.norm();
    Vec3 n;
    if (!unit_normal(c, d, len, Guard::None, n)) return 0;
    return push(c, id, p0, p1, n, len - cfull);
}

}  // namespace

int lmd_sphere_sphere(PairCtx& c) {
    const SphereElem s1 = sphere_elem(c.m1, c.e1);
    const SphereElem s2 = sphere_elem(c.m2, c.e2);
    const double c1 = c.m1.params().contact_distance;
    const double c2 = c.m2.params().contact_distance;
    const double R = c.p.alarm_distance + s1.r + c1 + s2.r + c2;
    if (!((s2.c - s1.c).squaredNorm() < R * R)) return 0;
    return lmd_push(c, id_big(c), s1.c, s2.c, c.p.contact_distance + s1.r + c1 + s2.r + c2);
}

int lmd_sphere_point(PairCtx& c) {
    const SphereElem s = sphere_elem(c.m1, c.e1);
    const auto& pm = static_cast<const PointModel&>(c.m2);
    const Vec3& P = pm.point(c.e2);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + s.r + sk;
    if (!((P - s.c).squaredNorm() < R * R)) return 0;
    if (!valid_point(c, pm, c.e2, s.c - P)) return 0;
    return lmd_push(c, id_big(c), s.c, P, c.p.contact_distance + s.r + sk);
}

int lmd_point_point(PairCtx& c) {
    const auto& m1 = static_cast<const PointModel&>(c.m1);
    const auto& m2 = static_cast<const PointModel&>(c.m2);
    const Vec3& p = m1.point(c.e1);
    const Vec3& q = m2.point(c.e2);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const Vec3 pq = q - p;
    if (!(pq.squaredNorm() < R * R)) return 0;
    if (!valid_point(c, m1, c.e1, pq) || !valid_point(c, m2, c.e2, -pq)) return 0;
    return lmd_push(c, id_big(c), p, q, c.p.contact_distance + sk);
}

int lmd_line_point(PairCtx& c) {
    const auto& l = static_cast<const LineModel&>(c.m1);
    const auto& pm = static_cast<const PointModel&>(c.m2);
    const Vec3& P = pm.point(c.e2);
    Vec3 Q;
    if (!segment_interior(l.p1(c.e1), l.p2(c.e1), P, Q)) return 0;
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const Vec3 qp = P - Q;
    if (!(qp.squaredNorm() < R * R)) return 0;
    if (!valid_line(c, l, c.e1, qp) || !valid_point(c, pm, c.e2, -qp)) return 0;
    return lmd_push(c, c.e2, Q, P, c.p.contact_distance + sk);
}

int lmd_line_line(PairCtx& c) {
    const auto& l1 = static_cast<const LineModel&>(c.m1);
    const auto& l2 = static_cast<const LineModel&>(c.m2);
    Vec3 P;
    Vec3 Q;
    if (!line_line_points(l1.p1(c.e1), l1.p2(c.e1), l2.p1(c.e2), l2.p2(c.e2), kLocalMinDistance.line_line, P, Q))
        return 0;
    const Vec3 pq = Q - P;
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    if (!(pq.squaredNorm() < R * R)) return 0;
    if (!valid_line(c, l1, c.e1, pq) || !valid_line(c, l2, c.e2, -pq)) return 0;
    return lmd_push(c, id_big(c), P, Q, c.p.contact_distance + sk);
}

int lmd_line_sphere(PairCtx& c) {
    const auto& l = static_cast<const LineModel&>(c.m1);
    const SphereElem s = sphere_elem(c.m2, c.e2);
    Vec3 Q;
    if (!segment_interior(l.p1(c.e1), l.p2(c.e1), s.c, Q)) return 0;
    const double sk = skins(c);
    const double R = c.p.alarm_distance + s.r + sk;
    const Vec3 qp = s.c - Q;
    if (!(qp.squaredNorm() < R * R)) return 0;
    if (!valid_line(c, l, c.e1, qp)) return 0;
    return lmd_push(c, c.e2, Q, s.c, c.p.contact_distance + s.r + sk);
}

namespace {
bool lmd_interior(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& q, Vec3& Q) {
    const Vec3 ab = p2 - p1, ac = p3 - p1, aq = q - p1;
    const double g00 = ab.dot(ab), g11 = ac.dot(ac), g01 = ab.dot(ac);
    const double det = g00 * g11 - g01 * g01;
    if (!(det > 0.0)) return false;  // zero-area triangle: no contact (SOFA: NaN)
    const double b0 = aq.dot(ab), b1 = aq.dot(ac);
    const double alpha = (b0 * g11 - b1 * g01) / det;
    const double beta = (b1 * g00 - b0 * g01) / det;
    const double lo = kLocalMinDistance.interior_lo;
    if (alpha < lo || beta < lo || alpha + beta > kLocalMinDistance.interior_hi) return false;
    Q = p1 + ab * alpha + ac * beta;
    return true;
}
}  // namespace

int lmd_triangle_point(PairCtx& c) {
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const auto& pm = static_cast<const PointModel&>(c.m2);
    const Vec3& P = pm.point(c.e2);
    Vec3 Q;
    if (!lmd_interior(t.p(c.e1, 0), t.p(c.e1, 1), t.p(c.e1, 2), P, Q)) return 0;
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const Vec3 qp = P - Q;
    if (!(qp.squaredNorm() < R * R)) return 0;
    if (!valid_point(c, pm, c.e2, -qp) || !valid_triangle(c, t, c.e1, qp)) return 0;
    return lmd_push(c, c.e2, Q, P, c.p.contact_distance + sk);
}

int lmd_triangle_sphere(PairCtx& c) {
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const SphereElem s = sphere_elem(c.m2, c.e2);
    Vec3 Q;
    if (!lmd_interior(t.p(c.e1, 0), t.p(c.e1, 1), t.p(c.e1, 2), s.c, Q)) return 0;
    const double sk = skins(c);
    const double R = c.p.alarm_distance + s.r + sk;
    const Vec3 qp = s.c - Q;
    if (!(qp.squaredNorm() < R * R)) return 0;
    if (!valid_triangle(c, t, c.e1, qp)) return 0;
    return lmd_push(c, c.e2, Q, s.c, c.p.contact_distance + s.r + sk);
}

}  // namespace penalty::detail
