// SOFA's MeshTetraStuffing (header: the steps). The lattice, the classification, the snapping, the
// cut points and the cases of the cut tetrahedra follow MeshTetraStuffing::doUpdate, addTetra,
// addFinalTetra, needFlip, flipDiag and getEdgePoint2 step by step, so that the output points and
// tetrahedra come in SOFA's order with SOFA's coordinates.
#include "penalty/mechanics/mesh_tetra_stuffing.hpp"

#include "penalty/core/error.hpp"
#include "sofa_vector_ops.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace penalty {

namespace {

using sofa_vec::cross;
using sofa_vec::dot3;

/// Directions of a lattice point's 14 edges: 0..5 the axis edges to the same grid (axis e/2,
/// towards − for even e, + for odd e), 6..13 the diagonal edges to the other grid; e and e^1 are
/// opposite. SOFA's EDGESHELL.
constexpr int kStuffingDirections = 14;

/// A ray's crossing of a surface triangle (TriangleOctree::traceResult): parameter t along the
/// ray (in edge lengths), then the crossing's sign: −1 entering (against the outward normal), +1 leaving.
struct Crossing {
    int sign = 0;  ///< the triangle's index until classified, as SOFA's tid
    double t = 0;
    bool operator<(const Crossing& o) const { return t < o.t; }
};

/// sofa::geometry::Triangle::rayIntersection (Möller–Trumbore, ε = machine epsilon): the ray
/// origin + t·direction, t ≥ ε, crosses triangle (n0, n1, n2) within barycentric ±ε.
bool ray_crosses(const Vec3& n0, const Vec3& n1, const Vec3& n2, const Vec3& origin, const Vec3& direction, double& t) {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const Vec3 e0 = n1 - n0, e1 = n2 - n0;
    const Vec3 pvec = cross(direction, e1);
    const double det = dot3(e0, pvec);
    if (std::fabs(det) <= eps) return false;
    const double inv_det = 1.0 / det;
    const Vec3 tvec = origin - n0;
    const double u = dot3(tvec, pvec) * inv_det;
    if (u < 0.0 - eps || u > 1.0 + eps) return false;
    const Vec3 qvec = cross(tvec, e0);
    const double v = dot3(direction, qvec) * inv_det;
    if (v < 0.0 - eps || (u + v) > 1.0 + eps) return false;
    t = dot3(e1, qvec) * inv_det;
    return !(t < eps || t != t || v != v || u != u);
}

class Stuffing {
public:
    Stuffing(std::span<const Vec3> surface_points, std::vector<Triangle> triangles,
             const MeshTetraStuffingParameters& p)
        : in_points_(surface_points), in_triangles_(std::move(triangles)), p_(p) {}

    StuffedVolume run(std::size_t max_points) {
        make_lattice(max_points);
        classify_points();
        if (p_.snap_points) snap_points();
        if (p_.split_tetrahedra) make_cut_points();
        make_tetrahedra();
        return finish();
    }

private:
    // ---- the lattice (doUpdate's grids, getEdgePoint2, getEdgeSize2) ----
    void make_lattice(std::size_t max_points);
    [[nodiscard]] int neighbor(int p, int e) const;
    static double edge_size2(int e) { return e < 6 ? 4.0 : 3.0; }  // squared length in (cell/2)²
    [[nodiscard]] double alpha(int e) const { return e < 6 ? p_.alpha_long : p_.alpha_short; }
    // ---- steps ----
    void classify_points();
    void trace_line(int start, int e);
    void snap_points();
    void wrap_outside_points(std::set<int>& violated_inside, const std::set<int>& violated_outside,
                             std::vector<bool>& violated);
    void wrap_inside_points(const std::set<int>& violated_inside, std::vector<bool>& violated);
    void move_onto_surface(int p, int toward, double fraction, std::vector<bool>& violated);
    void make_cut_points();
    void make_tetrahedra();
    void add_lattice_tetrahedron(int p1, int p2, int p3, int p4);
    void add_cut_tetrahedra_two_inside(int p1, int p2, int p3, int p4, const int* pos, const int* neg, int zero);
    void add_cut_tetrahedra_three_inside(int p1, int p2, int p3, int p4, const int* pos, int neg);
    void add_final(int p1, int p2, int p3, int p4, bool flip);
    [[nodiscard]] static bool need_flip(int p1, int p2, int p3, int p4, int q1, int q2, int q3, int q4);
    [[nodiscard]] bool flip_diagonal(int a, int b, int c, int e) const;
    [[nodiscard]] int cut_point(int from, int to);
    StuffedVolume finish();

    [[nodiscard]] double volume6(int p1, int p2, int p3, int p4) const {
        const Vec3 a = points_[std::size_t(p2)] - points_[std::size_t(p1)];
        const Vec3 b = points_[std::size_t(p3)] - points_[std::size_t(p1)];
        const Vec3 c = points_[std::size_t(p4)] - points_[std::size_t(p1)];
        return dot3(a, cross(b, c));
    }

    std::span<const Vec3> in_points_;
    std::vector<Triangle> in_triangles_;
    MeshTetraStuffingParameters p_;
    double cell_ = 0;
    std::array<int, 3> g_size_{}, h_size_{};
    Vec3 g0_, h0_;
    int h_first_ = 0;  ///< SOFA's ph0: index of H's first point
    std::vector<Vec3> points_;
    std::vector<int> inside_;                                        ///< > 0 inside, < 0 outside, 0 on the surface
    std::vector<std::array<double, kStuffingDirections>> distance_;  ///< SOFA's eBDist
    std::map<std::pair<int, int>, int> cut_points_;
    std::vector<Tetrahedron> tetrahedra_;
    std::size_t invalid_splits_ = 0;
};

void Stuffing::make_lattice(std::size_t max_points) {
    Vec3 lo = in_points_[0], hi = in_points_[0];
    for (std::size_t i = 1; i < in_points_.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            if (in_points_[i][c] < lo[c]) lo[c] = in_points_[i][c];
            else if (in_points_[i][c] > hi[c]) hi[c] = in_points_[i][c];
        }
    std::array<Vec3, 2> box{Vec3::Zero(), Vec3::Zero()};
    if (p_.box) box = *p_.box;
    if (box[0][0] >= box[1][0]) box = {lo - (hi - lo) * 0.01, hi + (hi - lo) * 0.01};
    cell_ = p_.size;
    if (cell_ < 0) {
        const Vec3 extent = box[1] - box[0];
        double largest = extent[0];
        if (extent[1] > largest) largest = extent[1];
        if (extent[2] > largest) largest = extent[2];
        cell_ = largest / -cell_;
    }
    if (!std::isfinite(cell_) || !(cell_ > 0))
        throw_invalid_argument("MeshTetraStuffing: the cell size must be finite and positive, found ", cell_);
    const Vec3 centre = (box[0] + box[1]) / 2;
    double count = 1;
    for (int c = 0; c < 3; ++c) {
        const double below = (centre[c] - box[0][c]) / cell_, above = (box[1][c] - centre[c]) / cell_;
        if (!(below < 1e6 && above < 1e6)) throw_invalid_argument("MeshTetraStuffing: too many cells for the box");
        const int first = -(int(below) + 2), last = int(above) + 2;
        g_size_[std::size_t(c)] = last - first + 1;
        g0_[c] = centre[c] + first * cell_;
        h_size_[std::size_t(c)] = g_size_[std::size_t(c)] + 1;
        h0_[c] = g0_[c] - cell_ / 2;
        count *= double(h_size_[std::size_t(c)]);
    }
    if (2 * count > double(max_points))
        throw_invalid_argument("MeshTetraStuffing: the lattice would have over ", max_points, " points");
    h_first_ = g_size_[0] * g_size_[1] * g_size_[2];
    points_.reserve(std::size_t(h_first_) + std::size_t(h_size_[0] * h_size_[1] * h_size_[2]));
    for (const auto& [size, origin] : {std::pair{g_size_, g0_}, std::pair{h_size_, h0_}})
        for (int z = 0; z < size[2]; ++z)
            for (int y = 0; y < size[1]; ++y)
                for (int x = 0; x < size[0]; ++x) points_.push_back(origin + Vec3(x * cell_, y * cell_, z * cell_));
    inside_.assign(points_.size(), 0);
    distance_.assign(points_.size(), {});
}

int Stuffing::neighbor(int p, int e) const {
    const bool in_g = p < h_first_;
    const std::array<int, 3>& size = in_g ? g_size_ : h_size_;
    int q = in_g ? p : p - h_first_;
    std::array<int, 3> c{};
    c[0] = q % size[0], q /= size[0];
    c[1] = q % size[1], q /= size[1];
    c[2] = q;
    if (e < 6) {  // same grid, one step along axis e/2
        const auto axis = std::size_t(e >> 1);
        c[axis] += (e & 1) ? 1 : -1;
        if (c[axis] < 0 || c[axis] >= size[axis]) return -1;
        return (in_g ? 0 : h_first_) + c[0] + size[0] * (c[1] + size[1] * c[2]);
    }
    const int k = e - 6;  // the other grid: offset (k&1, (k>>1 ^ k)&1, (k>>2 ^ k)&1), minus 1 from H
    const std::array<int, 3> step{k & 1, ((k >> 1) ^ k) & 1, ((k >> 2) ^ k) & 1};
    if (in_g) {
        for (std::size_t i = 0; i < 3; ++i) c[i] += step[i];
        return h_first_ + c[0] + h_size_[0] * (c[1] + h_size_[1] * c[2]);
    }
    for (std::size_t i = 0; i < 3; ++i) {
        c[i] += step[i] - 1;
        if (unsigned(c[i]) >= unsigned(g_size_[i])) return -1;
    }
    return c[0] + g_size_[0] * (c[1] + g_size_[1] * c[2]);
}

void Stuffing::classify_points() {
    const int n = int(points_.size());
    for (int p = 0; p < n; ++p)
        for (int e = 0; e < kStuffingDirections; e += 2)  // a line is traced from its first point
            if (neighbor(p, e) != -1 && neighbor(p, e + 1) == -1) trace_line(p, e);
    for (int& in : inside_)
        if (in == 0) in = -1;  // uncertain points are outside
}

void Stuffing::trace_line(int start, int e) {
    const Vec3 origin = points_[std::size_t(start)];
    const Vec3 direction = points_[std::size_t(neighbor(start, e))] - origin;
    std::vector<Crossing> hits;
    for (std::size_t t = 0; t < in_triangles_.size(); ++t) {
        const Triangle& tri = in_triangles_[t];
        Crossing h{int(t), 0.0};
        if (ray_crosses(in_points_[std::size_t(tri[0])], in_points_[std::size_t(tri[1])],
                        in_points_[std::size_t(tri[2])], origin, direction, h.t))
            hits.push_back(h);
    }
    if (hits.empty()) return;
    std::sort(hits.begin(), hits.end());
    for (Crossing& h : hits) {
        const Triangle& tri = in_triangles_[std::size_t(h.sign)];
        const Vec3& a = in_points_[std::size_t(tri[0])];
        const Vec3 normal = cross(in_points_[std::size_t(tri[1])] - a, in_points_[std::size_t(tri[2])] - a);
        h.sign = dot3(normal, direction) < 0 ? -1 : 1;
    }
    const std::size_t n = hits.size();
    std::size_t i = 0;
    int d = 0;  // the point's position along the line, in edges
    for (int p = start; p != -1; p = neighbor(p, e), ++d) {
        while (i < n && hits[i].t < d) ++i;
        int& in = inside_[std::size_t(p)];
        // vote by the nearest crossing: the one after it (its sign) or before it (the opposite)
        if (i >= n) in -= hits[n - 1].sign;
        else if (i == 0) in += hits[0].sign;
        else if ((d - hits[i - 1].t) < (hits[i].t - d)) in += hits[i].sign;
        else in -= hits[i - 1].sign;
        if (i < n) distance_[std::size_t(p)][std::size_t(e)] = hits[i].t - d;
        if (i > 0) distance_[std::size_t(p)][std::size_t(e) + 1] = d - hits[i - 1].t;
    }
}

void Stuffing::snap_points() {
    const int n = int(points_.size());
    std::vector<bool> violated(std::size_t(n), false);
    std::set<int> violated_inside, violated_outside;
    for (int p = 0; p < n; ++p) {
        const bool in1 = inside_[std::size_t(p)] > 0;
        bool v = false;
        for (int e = 0; e < kStuffingDirections && !v; ++e) {
            const int q = neighbor(p, e);
            if (q == -1 || in1 == (inside_[std::size_t(q)] > 0)) continue;
            const double dist = distance_[std::size_t(p)][std::size_t(e)];
            v = dist != 0.0 && dist < alpha(e);
        }
        violated[std::size_t(p)] = v;
        if (v) (in1 ? violated_inside : violated_outside).insert(p);
    }
    wrap_outside_points(violated_inside, violated_outside, violated);
    wrap_inside_points(violated_inside, violated);
}

void Stuffing::move_onto_surface(int p, int toward, double fraction, std::vector<bool>& violated) {
    Vec3& x = points_[std::size_t(p)];
    x += (points_[std::size_t(toward)] - x) * fraction;
    inside_[std::size_t(p)] = 0;
    violated[std::size_t(p)] = false;
}

void Stuffing::wrap_outside_points(std::set<int>& violated_inside, const std::set<int>& violated_outside,
                                   std::vector<bool>& violated) {
    // first the violated outside points, each toward an outside, unviolated neighbour across its
    // shortest violated edge, until a pass moves none
    int moved = 0;
    do {
        moved = 0;
        for (const int p : violated_outside) {
            if (inside_[std::size_t(p)] == 0) continue;  // already on the surface
            double best = 0;
            int best_edge = -1;
            for (int e = 0; e < kStuffingDirections; ++e) {
                const int q = neighbor(p, e);
                if (q == -1 || inside_[std::size_t(q)] > 0 || violated[std::size_t(q)]) continue;
                const double dist = distance_[std::size_t(p)][std::size_t(e)];
                if (dist == 0.0 || dist >= alpha(e)) continue;
                const double length2 = dist * dist * edge_size2(e);
                if (best_edge == -1 || length2 < best) best_edge = e, best = length2;
            }
            if (best_edge == -1) continue;
            move_onto_surface(p, neighbor(p, best_edge), distance_[std::size_t(p)][std::size_t(best_edge)], violated);
            ++moved;
            for (int e = 0; e < kStuffingDirections; ++e) {
                distance_[std::size_t(p)][std::size_t(e)] = 0;  // no crossing from p any more
                const int q = neighbor(p, e);
                if (q == -1) continue;
                distance_[std::size_t(q)][std::size_t(e ^ 1)] = 0;  // nor toward p
                if (!violated[std::size_t(q)] || inside_[std::size_t(q)] <= 0) continue;
                // is q still violated? (SOFA takes the threshold of p's edge e, not of q's edge)
                bool still = false;
                for (int e2 = 0; e2 < kStuffingDirections && !still; ++e2) {
                    const int r = neighbor(q, e2);
                    if (r == -1 || inside_[std::size_t(r)] >= 0) continue;
                    const double dist = distance_[std::size_t(q)][std::size_t(e2)];
                    still = dist != 0.0 && dist < alpha(e);
                }
                if (!still) {
                    violated[std::size_t(q)] = false;
                    violated_inside.erase(q);
                }
            }
        }
    } while (moved > 0);
}

void Stuffing::wrap_inside_points(const std::set<int>& violated_inside, std::vector<bool>& violated) {
    // then the remaining violated inside points, each toward an outside neighbour
    for (const int p : violated_inside) {
        if (inside_[std::size_t(p)] == 0) continue;  // SOFA: "already wrapped" (an error message)
        double best = 0;
        int best_edge = -1;
        for (int e = 0; e < kStuffingDirections; ++e) {
            const int q = neighbor(p, e);
            if (q == -1 || inside_[std::size_t(q)] >= 0) continue;
            const double dist = distance_[std::size_t(p)][std::size_t(e)];
            if (dist == 0.0 || dist >= alpha(e)) continue;
            const double length2 = dist * dist * edge_size2(e);
            if (best_edge == -1 || length2 < best) best_edge = e, best = length2;
        }
        if (best_edge == -1) continue;  // SOFA: "has no violated edges" (an error message)
        move_onto_surface(p, neighbor(p, best_edge), distance_[std::size_t(p)][std::size_t(best_edge)], violated);
        for (int e = 0; e < kStuffingDirections; ++e) {
            distance_[std::size_t(p)][std::size_t(e)] = 0;
            const int q = neighbor(p, e);
            if (q != -1) distance_[std::size_t(q)][std::size_t(e ^ 1)] = 0;
        }
    }
}

void Stuffing::make_cut_points() {
    const int n = int(points_.size());
    for (int p = 0; p < n; ++p) {
        if (inside_[std::size_t(p)] >= 0) continue;
        for (int e = 0; e < kStuffingDirections; ++e) {
            const int q = neighbor(p, e);
            if (q == -1 || inside_[std::size_t(q)] <= 0) continue;
            const int cut = int(points_.size());
            const Vec3 from = points_[std::size_t(p)];
            points_.push_back(from + (points_[std::size_t(q)] - from) * distance_[std::size_t(p)][std::size_t(e)]);
            cut_points_[{p, q}] = cut;
        }
    }
}

void Stuffing::make_tetrahedra() {
    // the 4 lattice tetrahedra around each edge of G (toward −x, −y, −z), G's points in order
    const int g01 = g_size_[0] * g_size_[1], h0 = h_size_[0], h01 = h_size_[0] * h_size_[1];
    for (int p = 0, ph = h_first_, z = 0; z < g_size_[2]; ++z, ph += h0)
        for (int y = 0; y < g_size_[1]; ++y, ++ph)
            for (int x = 0; x < g_size_[0]; ++x, ++p, ++ph) {
                const auto around = [&](int other, std::array<int, 4> shell) {
                    for (std::size_t i = 0; i < 4; ++i) add_lattice_tetrahedron(p, other, shell[(i + 1) % 4], shell[i]);
                };
                if (x > 0) around(p - 1, {ph, ph + h0, ph + h0 + h01, ph + h01});
                if (y > 0) around(p - g_size_[0], {ph, ph + h01, ph + 1 + h01, ph + 1});
                if (z > 0) around(p - g01, {ph, ph + 1, ph + 1 + h0, ph + h0});
            }
}

void Stuffing::add_lattice_tetrahedron(int p1, int p2, int p3, int p4) {
    if (volume6(p1, p2, p3, p4) < 0) std::swap(p3, p4);
    std::array<int, 4> pos{}, neg{}, zero{};
    int n_pos = 0, n_neg = 0, n_zero = 0;
    for (int q : {p1, p2, p3, p4}) {
        const int in = inside_[std::size_t(q)];
        if (in < 0) neg[std::size_t(n_neg++)] = q;
        else if (in > 0) pos[std::size_t(n_pos++)] = q;
        else zero[std::size_t(n_zero++)] = q;
    }
    if (n_pos == 0 && n_neg > 0) return;  // outside
    if (n_neg == 0 || !p_.split_tetrahedra) {
        add_final(p1, p2, p3, p4, false);  // whole
    } else if (n_pos == 1) {
        // one tetrahedron: the outside vertices move to the cut points toward the inside one
        const int in = pos[0];
        const auto moved = [&](int q) { return inside_[std::size_t(q)] < 0 ? cut_point(q, in) : q; };
        add_final(moved(p1), moved(p2), moved(p3), moved(p4), false);
    } else if (n_pos == 2) {
        add_cut_tetrahedra_two_inside(p1, p2, p3, p4, pos.data(), neg.data(), n_neg == 1 ? zero[0] : -1);
    } else {
        add_cut_tetrahedra_three_inside(p1, p2, p3, p4, pos.data(), neg[0]);
    }
}

void Stuffing::add_cut_tetrahedra_two_inside(int p1, int p2, int p3, int p4, const int* pos, const int* neg, int zero) {
    if (zero != -1) {  // one outside, one on the surface: a prism cut in two
        const int cut1 = cut_point(neg[0], pos[0]), cut2 = cut_point(neg[0], pos[1]);
        const bool flip_d = flip_diagonal(pos[0], pos[1], cut2, neg[0]);
        const bool flip_t = need_flip(zero, pos[0], pos[1], neg[0], p1, p2, p3, p4);
        if (!flip_d) {
            add_final(zero, pos[0], pos[1], cut2, flip_t);
            add_final(zero, pos[0], cut2, cut1, flip_t);
        } else {
            add_final(zero, pos[0], pos[1], cut1, flip_t);
            add_final(zero, pos[1], cut2, cut1, flip_t);
        }
        return;
    }
    // two outside: a prism between the inside edge and the four cut points, in three
    const int cut1 = cut_point(neg[0], pos[0]), cut2 = cut_point(neg[0], pos[1]);
    const int cut3 = cut_point(neg[1], pos[0]), cut4 = cut_point(neg[1], pos[1]);
    const bool flip_a = flip_diagonal(pos[0], pos[1], cut2, neg[0]);
    const bool flip_b = flip_diagonal(pos[0], pos[1], cut4, neg[1]);
    const bool flip_t = need_flip(pos[0], pos[1], neg[0], neg[1], p1, p2, p3, p4);
    if (!flip_a && flip_b) {
        add_final(pos[0], pos[1], cut2, cut3, flip_t);
        add_final(pos[0], cut2, cut1, cut3, flip_t);
        add_final(pos[1], cut2, cut3, cut4, flip_t);
    } else if (flip_a && !flip_b) {
        add_final(pos[0], pos[1], cut1, cut4, flip_t);
        add_final(pos[1], cut1, cut4, cut2, flip_t);
        add_final(pos[0], cut1, cut3, cut4, flip_t);
    } else {
        ++invalid_splits_;  // SOFA: "Invalid tetra split" (nothing added)
    }
}

void Stuffing::add_cut_tetrahedra_three_inside(int p1, int p2, int p3, int p4, const int* pos, int neg) {
    // one outside: the lattice tetrahedron minus a corner, in three
    const int cut1 = cut_point(neg, pos[0]), cut2 = cut_point(neg, pos[1]), cut3 = cut_point(neg, pos[2]);
    const bool flip1 = flip_diagonal(pos[0], pos[1], cut2, neg);
    const bool flip2 = flip_diagonal(pos[1], pos[2], cut3, neg);
    bool flip3 = flip_diagonal(pos[2], pos[0], cut1, neg);
    if (flip1 == flip2 && flip2 == flip3) {
        ++invalid_splits_;  // SOFA: "Invalid tetra split", then goes on with the third turned
        flip3 = !flip1;
    }
    const int pp0 = (flip1 && !flip2) ? pos[1] : (flip2 && !flip3) ? pos[2] : pos[0];
    const int pc0 = (!flip1 && flip2) ? cut2 : (!flip2 && flip3) ? cut3 : cut1;
    const bool flip_t = need_flip(neg, pos[0], pos[1], pos[2], p1, p2, p3, p4);
    add_final(pp0, cut1, cut3, cut2, flip_t);
    add_final(pc0, pos[0], pos[1], pos[2], flip_t);
    if (flip1 == flip2)
        add_final(pos[1], cut2, pp0, pc0, need_flip(pos[1], neg, pp0, pp0 == pos[0] ? pos[2] : pos[0], p1, p2, p3, p4));
    else if (flip2 == flip3)
        add_final(pos[2], cut3, pp0, pc0, need_flip(pos[2], neg, pp0, pp0 == pos[0] ? pos[1] : pos[0], p1, p2, p3, p4));
    else
        add_final(pos[0], cut1, pp0, pc0, need_flip(pos[0], neg, pp0, pp0 == pos[1] ? pos[2] : pos[1], p1, p2, p3, p4));
}

void Stuffing::add_final(int p1, int p2, int p3, int p4, bool flip) {
    if (flip) std::swap(p3, p4);
    if (volume6(p1, p2, p3, p4) < 0) std::swap(p3, p4);
    tetrahedra_.push_back({p1, p2, p3, p4});
}

bool Stuffing::need_flip(int p1, int p2, int p3, int p4, int q1, int q2, int q3, int q4) {
    // MeshTetraStuffing::needFlip: rotate each quadruple until its smallest index comes first (each
    // rotation of four is odd), then its second smallest second (rotations of three, even); the
    // orientations differ when, after that, the third of one is the fourth of the other
    bool flip = false;
    while (p1 > p2 || p1 > p3 || p1 > p4) {
        const int t = p1;
        p1 = p2, p2 = p3, p3 = p4, p4 = t;
        flip = !flip;
    }
    while (q1 > q2 || q1 > q3 || q1 > q4) {
        const int t = q1;
        q1 = q2, q2 = q3, q3 = q4, q4 = t;
        flip = !flip;
    }
    while (p2 > p3 || p2 > p4) {
        const int t = p2;
        p2 = p3, p3 = p4, p4 = t;
    }
    while (q2 > q3 || q2 > q4) {
        const int t = q2;
        q2 = q3, q3 = q4, q4 = t;
    }
    if (p3 == q4) flip = !flip;
    return flip;
}

bool Stuffing::flip_diagonal(int a, int b, int c, int e) const {
    // MeshTetraStuffing::flipDiag: should the quad a b c d be cut along bd rather than ac? Along
    // the long (same-grid) edge when there is one; else by the parity of the coordinates of a
    // above c's, reversed on grid H
    if (e < h_first_) {
        if (a < h_first_) return true;
        if (b < h_first_) return false;
    } else {
        if (a >= h_first_) return true;
        if (b >= h_first_) return false;
    }
    int above = 0;
    for (int i = 0; i < 3; ++i)
        if (points_[std::size_t(a)][i] > points_[std::size_t(c)][i]) ++above;
    return (above & 1) != (a < h_first_ ? 1 : 0);
}

int Stuffing::cut_point(int from, int to) {
    if (const auto it = cut_points_.find({from, to}); it != cut_points_.end()) return it->second;
    if (const auto it = cut_points_.find({to, from}); it != cut_points_.end()) return it->second;
    ++invalid_splits_;  // SOFA: "Cut point ... not found", and uses `from`
    return from;
}

StuffedVolume Stuffing::finish() {
    StuffedVolume out;
    out.grid_points = std::size_t(h_first_) + std::size_t(h_size_[0] * h_size_[1] * h_size_[2]);
    // keep the used points in their order
    std::vector<int> new_index(points_.size(), 0);
    for (const Tetrahedron& t : tetrahedra_)
        for (PointId q : t) new_index[std::size_t(q)] = 1;
    int kept = 0;
    for (std::size_t q = 0; q < new_index.size(); ++q) {
        if (new_index[q] == 0) {
            new_index[q] = -1;
            continue;
        }
        new_index[q] = kept++;
        out.points.push_back(points_[q]);
    }
    for (Tetrahedron& t : tetrahedra_) {
        for (PointId& q : t) q = new_index[std::size_t(q)];
        const Vec3 a = out.points[std::size_t(t[1])] - out.points[std::size_t(t[0])];
        const Vec3 b = out.points[std::size_t(t[2])] - out.points[std::size_t(t[0])];
        const Vec3 c = out.points[std::size_t(t[3])] - out.points[std::size_t(t[0])];
        if (dot3(a, cross(b, c)) < 0) {  // SOFA warns "tetra is inverted" and turns it
            std::swap(t[2], t[3]);
            ++out.inverted_turned;
        }
    }
    out.tetrahedra = std::move(tetrahedra_);
    out.invalid_splits = invalid_splits_;
    return out;
}

}  // namespace

StuffedVolume mesh_tetra_stuffing(std::span<const Vec3> points, std::span<const Triangle> triangles,
                                  std::span<const Quad> quads, const MeshTetraStuffingParameters& p,
                                  std::size_t max_points) {
    if (points.empty() || (triangles.empty() && quads.empty()))
        throw_invalid_argument("MeshTetraStuffing: empty input surface (inputPoints and inputTriangles or inputQuads)");
    for (const Vec3& x : points)
        if (!x.allFinite()) throw_invalid_argument("MeshTetraStuffing: an input point is not finite");
    std::vector<Triangle> all(triangles.begin(), triangles.end());
    for (const Quad& q : quads) {  // doUpdate: each quad as (0, 1, 2) and (0, 2, 3)
        all.push_back({q[0], q[1], q[2]});
        all.push_back({q[0], q[2], q[3]});
    }
    for (const Triangle& t : all)
        for (PointId v : t)
            if (v < 0 || std::size_t(v) >= points.size())
                throw_invalid_argument("MeshTetraStuffing: surface index ", v, " outside the ", points.size(),
                                       " input points");
    if (!(p.alpha_long >= 0 && p.alpha_short >= 0))
        throw_invalid_argument("MeshTetraStuffing: alphaLong and alphaShort must be >= 0");
    return Stuffing(points, std::move(all), p).run(max_points);
}

}  // namespace penalty
