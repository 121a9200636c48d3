#include "penalty/mechanics/quad_bending_fem.hpp"

#include "sofa_vector_ops.hpp"

#include <cmath>

namespace penalty {

namespace {

using sofa_vec::in_element;

using QuadStrainDisplacement = Eigen::Matrix<double, 32, 20>;

/// Node k's (m, n) corner signs in the element's [−1, 1]² (SOFA's idx 0..3).
constexpr std::array<std::array<double, 2>, 4> kQuadCorner{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};

/// computeBendingStrainDisplacement at Gauss point (g1, g2).
QuadStrainDisplacement bending_strain(double g1, double g2, double l, double h) {
    QuadStrainDisplacement jb = QuadStrainDisplacement::Zero();
    for (int k = 0; k < 4; ++k) {
        const double m = kQuadCorner[static_cast<std::size_t>(k)][0], n = kQuadCorner[static_cast<std::size_t>(k)][1];
        const int r = 8 * k, c = 5 * k;
        jb(r, c) = jb(r + 2, c + 1) = m * (1 + n * g2) / (4 * l);
        jb(r + 1, c + 1) = jb(r + 2, c) = n * (1 + m * g1) / (4 * h);
    }
    return jb;
}

/// computeShearStrainDisplacement (one Gauss point at the centre).
QuadStrainDisplacement shear_strain(double l, double h) {
    QuadStrainDisplacement js = QuadStrainDisplacement::Zero();
    for (int k = 0; k < 4; ++k) {
        const double m = kQuadCorner[static_cast<std::size_t>(k)][0], n = kQuadCorner[static_cast<std::size_t>(k)][1];
        const int r = 8 * k, c = 5 * k;
        js(r + 3, c + 3) = js(r + 5, c + 4) = m / (4 * l);
        js(r + 4, c + 4) = js(r + 5, c + 3) = n / (4 * h);
        js(r + 6, c + 2) = m / (4 * l);
        js(r + 7, c + 2) = n / (4 * h);
        js(r + 6, c + 3) = js(r + 7, c + 4) = -1.0 / 4.0;
    }
    return js;
}

double half_norm(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) / 2; }

}  // namespace

void QuadBendingFEMForceField::init() {
    const auto& quads = topology_->quads();
    const std::vector<Vec3>& x0 = state_->rest_position;
    material_.clear();
    rest_offsets_.clear();
    scatter_.clear();
    const double t = p_.thickness;
    for (std::size_t i = 0; i < quads.size(); ++i) {
        const Quad& q = quads[i];
        for (PointId v : q)
            if (v < 0 || static_cast<std::size_t>(v) >= x0.size())
                throw_invalid_argument("QuadBendingFEMForceField: quad ", i, " uses point ", v, ", out of range (",
                                       x0.size(), " points)");
        const auto at = [&](int k) -> const Vec3& {
            return x0[static_cast<std::size_t>(q[static_cast<std::size_t>(k)])];
        };
        if (half_norm(at(1) - at(0)) == 0 || half_norm(at(3) - at(0)) == 0)
            throw_invalid_argument("QuadBendingFEMForceField: quad ", i, " has a zero-length side at rest");
        const Vec3 centroid = (at(0) + at(2)) / 2;
        rest_offsets_.push_back({at(0) - centroid, at(1) - centroid, at(2) - centroid, at(3) - centroid});
        const double y = in_element(p_.young_modulus, i), p = in_element(p_.poisson_ratio, i);
        Material mat{};
        mat.cb00 = y * t / (1 - p * p);  // computeBendingMaterialStiffness
        mat.cb01 = p * y * t / (1 - p * p);
        mat.cb11 = y * t / (1 - p * p);
        mat.cb22 = y * t * (1 - p) / (2 - 2 * p * p);
        constexpr double k = 5.0 / 6.0;  // computeShearMaterialStiffness
        mat.cs33 = y * t * t * t / (12 - 12 * p * p);
        mat.cs34 = p * y * t * t * t / (12 - 12 * p * p);
        mat.cs44 = y * t * t * t / (12 - 12 * p * p);
        mat.cs55 = (p * y * t * t * t) * (1 - p) / (24 - 24 * p * p);
        mat.cs66 = k * y * t / (2 + 2 * p);
        mat.cs77 = k * y * t / (2 + 2 * p);
        material_.push_back(mat);
    }
}

// QuadBendingFEMForceField::computeElementStiffness, entry by entry in SOFA's operation order.
QuadBendingFEMForceField::Stiffness QuadBendingFEMForceField::element_stiffness(std::size_t qi,
                                                                                std::span<const Vec3> x) const {
    const Quad& q = topology_->quads()[qi];
    const double length = half_norm(x[static_cast<std::size_t>(q[1])] - x[static_cast<std::size_t>(q[0])]);
    const double height = half_norm(x[static_cast<std::size_t>(q[3])] - x[static_cast<std::size_t>(q[0])]);
    const Material& c = material_[qi];
    const double g = std::sqrt(3.0) / 3;
    const std::array<QuadStrainDisplacement, 4> jb{
        bending_strain(g, g, length, height), bending_strain(-g, g, length, height),
        bending_strain(g, -g, length, height), bending_strain(-g, -g, length, height)};
    const double wb = 1;
    Stiffness kb = Stiffness::Zero();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            std::array<std::array<double, 4>, 4> part{};  // per Gauss point: (0,0), (0,1), (1,0), (1,1)
            for (std::size_t gp = 0; gp < 4; ++gp) {
                const QuadStrainDisplacement& b = jb[gp];
                const auto bt = [&](int row, int col) { return b(col, row); };  // Jb_t
                part[gp][0] = length * height *
                              (bt(5 * i, 8 * i) * c.cb00 * b(8 * j, 5 * j) +
                               bt(5 * i, 8 * i + 2) * c.cb22 * b(8 * j + 2, 5 * j)) *
                              wb;
                part[gp][1] = length * height *
                              (bt(5 * i, 8 * i) * c.cb01 * b(8 * j + 1, 5 * j + 1) +
                               bt(5 * i, 8 * i + 2) * c.cb22 * b(8 * j + 2, 5 * j + 1)) *
                              wb;
                part[gp][2] = length * height *
                              (bt(5 * i + 1, 8 * i + 1) * c.cb01 * b(8 * j, 5 * j) +
                               bt(5 * i + 1, 8 * i + 2) * c.cb22 * b(8 * j + 2, 5 * j)) *
                              wb;
                part[gp][3] = length * height *
                              (bt(5 * i + 1, 8 * i + 1) * c.cb11 * b(8 * j + 1, 5 * j + 1) +
                               bt(5 * i + 1, 8 * i + 2) * c.cb22 * b(8 * j + 2, 5 * j + 1)) *
                              wb;
            }
            const int rows[4] = {5 * i, 5 * i, 5 * i + 1, 5 * i + 1}, cols[4] = {5 * j, 5 * j + 1, 5 * j, 5 * j + 1};
            for (int e = 0; e < 4; ++e)
                kb(rows[e], cols[e]) = part[0][static_cast<std::size_t>(e)] + part[1][static_cast<std::size_t>(e)] +
                                       part[2][static_cast<std::size_t>(e)] + part[3][static_cast<std::size_t>(e)];
        }
    const QuadStrainDisplacement js = shear_strain(length, height);
    const auto jt = [&](int row, int col) { return js(col, row); };  // Js_t
    const double ws = 2;
    Stiffness ks = Stiffness::Zero();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const double lh = length * height;
            ks(5 * i + 2, 5 * j + 2) = lh *
                                       (jt(5 * i + 2, 8 * i + 6) * c.cs66 * js(8 * j + 6, 5 * j + 2) +
                                        jt(5 * i + 2, 8 * i + 7) * c.cs77 * js(8 * j + 7, 5 * j + 2)) *
                                       ws * ws;
            ks(5 * i + 2, 5 * j + 3) = lh * (jt(5 * i + 2, 8 * i + 6) * c.cs66 * js(8 * j + 6, 5 * j + 3)) * ws * ws;
            ks(5 * i + 2, 5 * j + 4) = lh * (jt(5 * i + 2, 8 * i + 7) * c.cs77 * js(8 * j + 7, 5 * j + 4)) * ws * ws;
            ks(5 * i + 3, 5 * j + 2) = lh * (jt(5 * i + 3, 8 * i + 6) * c.cs66 * js(8 * j + 6, 5 * j + 2)) * ws * ws;
            ks(5 * i + 3, 5 * j + 3) = lh *
                                       (jt(5 * i + 3, 8 * i + 3) * c.cs33 * js(8 * j + 3, 5 * j + 3) +
                                        jt(5 * i + 3, 8 * i + 5) * c.cs55 * js(8 * j + 5, 5 * j + 3) +
                                        jt(5 * i + 3, 8 * i + 6) * c.cs66 * js(8 * j + 6, 5 * j + 3)) *
                                       ws * ws;
            ks(5 * i + 3, 5 * j + 4) = lh *
                                       (jt(5 * i + 3, 8 * i + 3) * c.cs34 * js(8 * j + 4, 5 * j + 4) +
                                        jt(5 * i + 3, 8 * i + 5) * c.cs55 * js(8 * j + 5, 5 * j + 4)) *
                                       ws * ws;
            ks(5 * i + 4, 5 * j + 2) = lh * (jt(5 * i + 4, 8 * i + 7) * c.cs77 * js(8 * j + 7, 5 * j + 2)) * ws * ws;
            ks(5 * i + 4, 5 * j + 3) = lh *
                                       (jt(5 * i + 4, 8 * i + 4) * c.cs34 * js(8 * j + 3, 5 * j + 3) +
                                        jt(5 * i + 4, 8 * i + 5) * c.cs55 * js(8 * j + 5, 5 * j + 3)) *
                                       ws * ws;
            ks(5 * i + 4, 5 * j + 4) = lh *
                                       (jt(5 * i + 4, 8 * i + 4) * c.cs44 * js(8 * j + 4, 5 * j + 4) +
                                        jt(5 * i + 4, 8 * i + 5) * c.cs55 * js(8 * j + 5, 5 * j + 4) +
                                        jt(5 * i + 4, 8 * i + 7) * c.cs77 * js(8 * j + 7, 5 * j + 4)) *
                                       ws * ws;
        }
    return kb + ks;
}

const QuadBendingFEMForceField::Stiffness& QuadBendingFEMForceField::stiffness_at(std::size_t q,
                                                                                  Stiffness& scratch) const {
    if (q < stiffness_.size()) return stiffness_[q];
    scratch = element_stiffness(q, state_->position);
    return scratch;
}

// computeForce: the translations' rows, each the sum of its non-zero terms in SOFA's order.
std::array<double, 20> QuadBendingFEMForceField::force_of(const Stiffness& k, const std::array<double, 20>& d) {
    std::array<double, 20> f{};
    constexpr int in_plane[8] = {0, 1, 5, 6, 10, 11, 15, 16};
    constexpr int normal[4] = {2, 7, 12, 17};
    for (int node = 0; node < 4; ++node) {
        for (int a = 0; a < 2; ++a) {
            const int r = 5 * node + a;
            double s = k(r, in_plane[0]) * d[static_cast<std::size_t>(in_plane[0])];
            for (int c = 1; c < 8; ++c) s += k(r, in_plane[c]) * d[static_cast<std::size_t>(in_plane[c])];
            f[static_cast<std::size_t>(r)] = s;
        }
        const int r = 5 * node + 2;
        double s = k(r, normal[0]) * d[static_cast<std::size_t>(normal[0])];
        for (int c = 1; c < 4; ++c) s += k(r, normal[c]) * d[static_cast<std::size_t>(normal[c])];
        f[static_cast<std::size_t>(r)] = s;
    }
    return f;
}

// accumulateForceSmall per quad (computeDisplacementSmall, computeForce); from
// OrderedScatter::kMinElements quads on TBB's threads with the bits of one thread.
void QuadBendingFEMForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> /*v*/) {
    const auto& quads = topology_->quads();
    stiffness_.resize(quads.size());
    const bool on_threads = detail::OrderedScatter::worth_threads(quads.size());
    if (on_threads) energy_terms_.resize(quads.size());
    energy_ = 0;
    const auto pass = [&](std::size_t first, std::size_t end, const auto& deferred) {
        for (std::size_t i = first; i < end; ++i) {
            const Quad& q = quads[i];
            const auto at = [&](int k) -> const Vec3& { return x[static_cast<std::size_t>(q[k])]; };
            const Vec3 centroid = (at(0) + at(2)) / 2;
            std::array<double, 20> d{};
            for (std::size_t k = 0; k < 4; ++k) {
                const Vec3 deform = at(k) - centroid;
                for (std::size_t a = 0; a < 3; ++a) d[5 * k + a] = rest_offsets_[i][k][a] - deform[a];
            }
            stiffness_[i] = element_stiffness(i, x);
            const std::array<double, 20> force = force_of(stiffness_[i], d);
            std::array<Vec3, 4> terms;
            for (std::size_t k = 0; k < 4; ++k) terms[k] = Vec3(force[5 * k], force[5 * k + 1], force[5 * k + 2]);
            detail::store_or_apply(deferred, i, terms,
                                   [&](std::size_t k, const Vec3& t) { f[static_cast<std::size_t>(q[k])] += t; });
            // E += ½ d·F, term by term in the loop's order
            for (std::size_t k = 0; k < 4; ++k)
                for (std::size_t a = 0; a < 3; ++a) {
                    const double e = 0.5 * d[5 * k + a] * force[5 * k + a];
                    if (on_threads) energy_terms_[i][3 * k + a] = e;
                    else energy_ += e;
                }
        }
    };
    detail::scatter_in_order</*Add=*/true>(scatter_, std::span<const Quad>(quads), f, 1, pass);
    if (on_threads)
        for (const auto& terms : energy_terms_)
            for (const double e : terms) energy_ += e;
}

// applyStiffnessSmall with h = 1: df_k += (−F_k)·k_factor, F = K(x)·dx, x the state's positions.
void QuadBendingFEMForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                          double /*b_factor*/) const {
    const auto& quads = topology_->quads();
    const auto pass = [&](std::size_t first, std::size_t end, const auto& deferred) {
        Stiffness scratch;
        for (std::size_t i = first; i < end; ++i) {
            const Quad& q = quads[i];
            std::array<double, 20> d{};
            for (std::size_t k = 0; k < 4; ++k)
                for (std::size_t a = 0; a < 3; ++a) d[5 * k + a] = dx[static_cast<std::size_t>(q[k])][a];
            const std::array<double, 20> force = force_of(stiffness_at(i, scratch), d);
            const double h = 1;
            std::array<Vec3, 4> terms;
            for (std::size_t k = 0; k < 4; ++k)
                terms[k] = Vec3(-h * force[5 * k], -h * force[5 * k + 1], -h * force[5 * k + 2]) * k_factor;
            detail::store_or_apply(deferred, i, terms,
                                   [&](std::size_t k, const Vec3& t) { df[static_cast<std::size_t>(q[k])] += t; });
        }
    };
    detail::scatter_in_order</*Add=*/true>(scatter_, std::span<const Quad>(quads), df, 1, pass);
}

void QuadBendingFEMForceField::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    const auto& quads = topology_->quads();
    Stiffness scratch;
    for (std::size_t i = 0; i < quads.size(); ++i) {
        const Stiffness& k = stiffness_at(i, scratch);
        const Quad& q = quads[i];
        for (int m = 0; m < 4; ++m)
            for (int n = 0; n < 4; ++n)
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) {
                        if ((a == 2) != (b == 2)) continue;  // computeForce: in-plane and normal rows apart
                        t.emplace_back(offset + 3 * q[static_cast<std::size_t>(m)] + a,
                                       offset + 3 * q[static_cast<std::size_t>(n)] + b,
                                       -factor * k(5 * m + a, 5 * n + b));
                    }
    }
}

}  // namespace penalty
