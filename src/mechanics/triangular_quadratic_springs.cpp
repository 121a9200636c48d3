#include "penalty/mechanics/triangular_quadratic_springs.hpp"

#include "mechanics/triangle_edge_blocks.hpp"

#include <cmath>

namespace penalty {

namespace {

using edge_blocks::dot3;
using edge_blocks::scaled;
using edge_blocks::times;
using edge_blocks::transpose_times;

}  // namespace

TriangularQuadraticSpringsForceField::TriangularQuadraticSpringsForceField(Vec3Object& state,
                                                                           const MeshTopology& topology,
                                                                           QuadraticSpringParameters p)
    : ForceField<Vec3Types>(state), topology_(&topology), parameters_(p) {
    const edge_blocks::LameCoefficients lame = edge_blocks::checked_lame(
        "TriangularQuadraticSpringsForceField", p.young_modulus, p.poisson_ratio, p.damping_ratio);
    lambda_ = lame.lambda;
    mu_ = lame.mu;
}

void TriangularQuadraticSpringsForceField::init() {
    const auto& edges = topology_->edges();
    const auto& tris = topology_->triangles();
    const std::vector<Vec3>& x0 = state_->rest_position;
    edge_blocks::check_triangle_points("TriangularQuadraticSpringsForceField", tris, x0.size());
    // applyEdgeCreation of every edge, then applyTriangleCreation of every triangle in order
    rest_length_.assign(edges.size(), 0.0);
    edge_stiffness_.assign(edges.size(), 0.0);
    length_.assign(edges.size(), 0.0);
    delta_.assign(edges.size(), 0.0);
    for (std::size_t e = 0; e < edges.size(); ++e) create_edge(e);
    triangles_.assign(tris.size(), TriangleData{});
    for (std::size_t ti = 0; ti < tris.size(); ++ti) create_triangle(ti);
    scatter_.clear();
    product_.invalidate();
}

// applyEdgeCreation: the rest length (Edge::length = √|x_1 − x_0|²), stiffness 0.
void TriangularQuadraticSpringsForceField::create_edge(std::size_t e) {
    const Edge& edge = topology_->edges()[e];
    const std::vector<Vec3>& x0 = state_->rest_position;
    const Vec3 d = x0[static_cast<std::size_t>(edge[1])] - x0[static_cast<std::size_t>(edge[0])];
    rest_length_[e] = std::sqrt(dot3(d, d));
    edge_stiffness_[e] = 0.0;
}

// applyTriangleCreation: rest area (Heron), γ_j and s_j; each s_j added to its edge's stiffness.
void TriangularQuadraticSpringsForceField::create_triangle(std::size_t ti) {
    TriangleData& td = triangles_[ti];
    td = TriangleData{};
    const auto& te = topology_->edges_in_triangle()[ti];
    double rest[3], square[3];
    for (int j = 0; j < 3; ++j) {
        rest[j] = rest_length_[static_cast<std::size_t>(te[static_cast<std::size_t>(j)])];
        square[j] = rest[j] * rest[j];
    }
    double area = 0;  // Heron
    for (int j = 0; j < 3; ++j) area += square[j] * (square[(j + 1) % 3] + square[(j + 2) % 3] - square[j]);
    area = std::sqrt(area) / 4;
    if (!(area > 0))
        throw_invalid_argument("TriangularQuadraticSpringsForceField: triangle ", ti, " has a zero rest area");
    double cotangent[3];
    for (int j = 0; j < 3; ++j) cotangent[j] = (square[(j + 1) % 3] + square[(j + 2) % 3] - square[j]) / (4 * area);
    for (int j = 0; j < 3; ++j) {
        const int k = (j + 1) % 3;
        const int l = (j + 2) % 3;
        const auto sj = static_cast<std::size_t>(j);
        td.gamma[sj] = rest[k] * rest[l] * (2 * cotangent[k] * cotangent[l] * (lambda_ + mu_) - mu_) / (8 * area);
        td.stiffness[sj] = rest[j] * rest[j] * (2 * cotangent[j] * cotangent[j] * (lambda_ + mu_) + mu_) / (8 * area);
        edge_stiffness_[static_cast<std::size_t>(te[sj])] += td.stiffness[sj];
    }
}

void TriangularQuadraticSpringsForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x,
                                                     std::span<const Vec3> v) {
    PENALTY_DEMAND(triangles_.size() == topology_->triangles().size());
    product_.invalidate();  // DfDx[k] computed again below
    const auto& edges = topology_->edges();
    const auto& tris = topology_->triangles();
    const auto& edges_in_triangle = topology_->edges_in_triangle();
    const bool angular = parameters_.use_angular_springs;
    // edge springs (addForce, first loop): f_v1 += F, f_v0 −= F; from OrderedScatter::kMinElements
    // edges or triangles, each loop on TBB's threads with the bits of one thread
    energy_ = scatter_.edge_loop(edges, f, [&](std::size_t e) {
        const auto v0 = static_cast<std::size_t>(edges[e][0]);
        const auto v1 = static_cast<std::size_t>(edges[e][1]);
        const Vec3 dp = x[v0] - x[v1];
        const Vec3 dv = v[v0] - v[v1];
        const double length = std::sqrt(dot3(dp, dp));
        length_[e] = length;
        delta_[e] = length - rest_length_[e] + parameters_.damping_ratio * dot3(dv, dp) / length;
        const double intensity = edge_stiffness_[e] * delta_[e] / length;
        return detail::EdgeTerms{scaled(dp, intensity), scaled(dp, intensity),
                                 edge_stiffness_[e] * delta_[e] * delta_[e] / 2};
    });
    energy_ = scatter_.triangle_loop(tris, f, energy_, [&](std::size_t ti, auto& terms) {
        TriangleData& td = triangles_[ti];
        const Triangle& t = tris[ti];
        const auto& te = edges_in_triangle[ti];
        const auto edge_of = [&](int j) { return static_cast<std::size_t>(te[static_cast<std::size_t>(j)]); };
        const auto at = [&](int j) { return static_cast<std::size_t>(t[static_cast<std::size_t>(j)]); };
        if (angular) {
            for (int j = 0; j < 3; ++j) {
                const int k = (j + 1) % 3;
                const int l = (j + 2) % 3;
                const Vec3 dp = x[at(k)] - x[at(l)];
                const double intensity = delta_[edge_of(k)] * td.gamma[static_cast<std::size_t>(l)] +
                                         delta_[edge_of(l)] * td.gamma[static_cast<std::size_t>(k)];
                const Vec3 scaled_dp = scaled(dp, intensity);
                const double length = length_[edge_of(j)];
                const Vec3 force(scaled_dp[0] / length, scaled_dp[1] / length, scaled_dp[2] / length);
                terms.add(static_cast<std::size_t>(l), force);
                terms.subtract(static_cast<std::size_t>(k), force);
                terms.add_energy(td.gamma[static_cast<std::size_t>(j)] * delta_[edge_of(k)] * delta_[edge_of(l)]);
            }
        }
        // addDForce's DfDx[k] (SOFA computes it at the first addDForce after addForce, from the
        // positions and lengths of that addForce)
        for (int k = 0; k < 3; ++k) {
            const int i = (k + 1) % 3;
            const int j = (k + 2) % 3;
            const auto sk = static_cast<std::size_t>(k);
            Mat3& m = td.dfdx[sk];
            const Vec3 dpk = x[at(i)] - x[at(j)];
            const double lk = length_[edge_of(k)];
            if (!angular) {
                double diagonal = -td.stiffness[sk] * delta_[edge_of(k)];
                diagonal /= lk;
                double along = -td.stiffness[sk] * rest_length_[edge_of(k)];
                along /= lk * lk * lk;
                for (int u = 0; u < 3; ++u) {
                    for (int w = 0; w < 3; ++w) m(u, w) = dpk[u] * dpk[w] * along;
                    m(u, u) += diagonal;
                }
                continue;
            }
            const Vec3 dpj = x[at(i)] - x[at(k)];
            const Vec3 dpi = x[at(j)] - x[at(k)];
            const auto si = static_cast<std::size_t>(i);
            const auto sj = static_cast<std::size_t>(j);
            const double li = length_[edge_of(i)];
            const double lj = length_[edge_of(j)];
            double diagonal = -(td.stiffness[sk] * delta_[edge_of(k)] + td.gamma[si] * delta_[edge_of(j)] +
                                td.gamma[sj] * delta_[edge_of(i)]);
            // SOFA: −val1 − s_k ℓ_k; the Hessian: −val1 − s_k L_k (exact_angular_stiffness)
            const double length_in_along = parameters_.exact_angular_stiffness ? lk : rest_length_[edge_of(k)];
            double along = -diagonal - td.stiffness[sk] * length_in_along;
            diagonal /= lk;
            along /= lk * lk * lk;
            const double val_k = td.gamma[sk] / (lj * li);
            const double val_i = td.gamma[si] / (lj * lk);
            const double val_j = td.gamma[sj] / (lk * li);
            for (int u = 0; u < 3; ++u) {
                for (int w = 0; w < 3; ++w)
                    m(u, w) = dpk[u] * dpk[w] * along + dpj[u] * dpi[w] * val_k - dpj[u] * dpk[w] * val_i +
                              dpk[u] * dpi[w] * val_j;
                m(u, u) += diagonal;
            }
        }
    });
}

void TriangularQuadraticSpringsForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                                      double /*b_factor*/) const {
    PENALTY_DEMAND(triangles_.size() == topology_->triangles().size());
    product_.add_dforce(kernel_path_, scatter_, topology_->triangles(), triangles_, df, dx, k_factor);
}

void TriangularQuadraticSpringsForceField::set_kernel_path(KernelPath path) {
    kernel_path_ = checked_kernel_path(path, "TriangularQuadraticSpringsForceField", /*has_avx512=*/false);
}

void TriangularQuadraticSpringsForceField::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    PENALTY_DEMAND(triangles_.size() == topology_->triangles().size());
    edge_blocks::add_stiffness_triplets(topology_->triangles(), triangles_, t, offset, factor);
}

}  // namespace penalty
