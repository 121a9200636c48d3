#include "penalty/mechanics/triangular_biquadratic_springs.hpp"

#include "mechanics/triangle_edge_blocks.hpp"

#include <cmath>

namespace penalty {

namespace {

using edge_blocks::dot3;
using edge_blocks::scaled;
using edge_blocks::times;
using edge_blocks::transpose_times;
using sofa_vec::cross;
using sofa_vec::divided;

/// update_stiffness's triangles a task on threads.
constexpr std::size_t kTrianglesPerTask = 1024;

}  // namespace

TriangularBiquadraticSpringsForceField::TriangularBiquadraticSpringsForceField(Vec3Object& state,
                                                                               const MeshTopology& topology,
                                                                               BiquadraticSpringParameters p)
    : ForceField<Vec3Types>(state), topology_(&topology), parameters_(p) {
    const edge_blocks::LameCoefficients lame = edge_blocks::checked_lame(
        "TriangularBiquadraticSpringsForceField", p.young_modulus, p.poisson_ratio, p.damping_ratio);
    lambda_ = lame.lambda;
    mu_ = lame.mu;
}

void TriangularBiquadraticSpringsForceField::init() {
    const auto& edges = topology_->edges();
    const auto& tris = topology_->triangles();
    const std::vector<Vec3>& x0 = state_->rest_position;
    edge_blocks::check_triangle_points("TriangularBiquadraticSpringsForceField", tris, x0.size());
    // applyEdgeCreation of every edge, then applyTriangleCreation of every triangle in order
    rest_square_length_.assign(edges.size(), 0.0);
    edge_stiffness_.assign(edges.size(), 0.0);
    square_length_.assign(edges.size(), 0.0);
    delta_.assign(edges.size(), 0.0);
    for (std::size_t e = 0; e < edges.size(); ++e) create_edge(e);
    triangles_.assign(tris.size(), TriangleData{});
    for (std::size_t ti = 0; ti < tris.size(); ++ti) create_triangle(ti);
    scatter_.clear();
    product_.invalidate();
}

// applyEdgeCreation: the rest squared length, stiffness 0.
void TriangularBiquadraticSpringsForceField::create_edge(std::size_t e) {
    const Edge& edge = topology_->edges()[e];
    const std::vector<Vec3>& x0 = state_->rest_position;
    const Vec3 d = x0[static_cast<std::size_t>(edge[1])] - x0[static_cast<std::size_t>(edge[0])];
    rest_square_length_[e] = dot3(d, d);
    edge_stiffness_[e] = 0.0;
}

// applyTriangleCreation: rest area (Heron, from the edges' rest squared lengths), normal, γ_j and
// s_j; each s_j added to its edge's stiffness.
void TriangularBiquadraticSpringsForceField::create_triangle(std::size_t ti) {
    const std::vector<Vec3>& x0 = state_->rest_position;
    TriangleData& td = triangles_[ti];
    td = TriangleData{};
    const Triangle& t = topology_->triangles()[ti];
    const auto& te = topology_->edges_in_triangle()[ti];
    double square[3];
    for (int j = 0; j < 3; ++j)
        square[j] = rest_square_length_[static_cast<std::size_t>(te[static_cast<std::size_t>(j)])];
    double area = 0;  // Heron: 16 A² = Σ ℓ_j² (ℓ_{j+1}² + ℓ_{j+2}² − ℓ_j²)
    for (int j = 0; j < 3; ++j) area += square[j] * (square[(j + 1) % 3] + square[(j + 2) % 3] - square[j]);
    area = std::sqrt(area) / 4;
    if (!(area > 0))
        throw_invalid_argument("TriangularBiquadraticSpringsForceField: triangle ", ti, " has a zero rest area");
    td.rest_area = area;
    const Vec3& p0 = x0[static_cast<std::size_t>(t[0])];
    td.normal =
        divided(cross(x0[static_cast<std::size_t>(t[1])] - p0, x0[static_cast<std::size_t>(t[2])] - p0), 2 * area);
    td.last_valid_normal = td.normal;
    double cotangent[3];
    for (int j = 0; j < 3; ++j) cotangent[j] = (square[(j + 1) % 3] + square[(j + 2) % 3] - square[j]) / (4 * area);
    for (int j = 0; j < 3; ++j) {
        const int k = (j + 1) % 3;
        const int l = (j + 2) % 3;
        td.gamma[static_cast<std::size_t>(j)] = (2 * cotangent[k] * cotangent[l] * (lambda_ + mu_) - mu_) / (16 * area);
        td.stiffness[static_cast<std::size_t>(j)] =
            (2 * cotangent[j] * cotangent[j] * (lambda_ + mu_) + mu_) / (16 * area);
        edge_stiffness_[static_cast<std::size_t>(te[static_cast<std::size_t>(j)])] +=
            td.stiffness[static_cast<std::size_t>(j)];
    }
}

// From OrderedScatter::kMinElements edges or triangles, each loop on TBB's threads with the bits
// of one thread (detail::EdgeTriangleScatter).
void TriangularBiquadraticSpringsForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x,
                                                       std::span<const Vec3> v) {
    PENALTY_DEMAND(triangles_.size() == topology_->triangles().size());
    product_.invalidate();  // DfDx[k] computed again below
    const auto& edges = topology_->edges();
    const auto& tris = topology_->triangles();
    const auto& edges_in_triangle = topology_->edges_in_triangle();
    const double area_stiffness = (lambda_ + mu_) * 3;
    // edge springs on the squared lengths (addForce, first loop): f_v1 += F, f_v0 −= F
    energy_ = scatter_.edge_loop(edges, f, [&](std::size_t e) {
        const auto v0 = static_cast<std::size_t>(edges[e][0]);
        const auto v1 = static_cast<std::size_t>(edges[e][1]);
        const Vec3 dp = x[v0] - x[v1];
        const Vec3 dv = v[v0] - v[v1];
        const double length2 = dot3(dp, dp);
        square_length_[e] = length2;
        delta_[e] = length2 - rest_square_length_[e] + parameters_.damping_ratio * dot3(dv, dp) / length2;
        const Vec3 force = scaled(dp, edge_stiffness_[e] * delta_[e]);
        return detail::EdgeTerms{force, force, edge_stiffness_[e] * delta_[e] * delta_[e] / 4};
    });
    if (parameters_.use_angular_springs) {
        energy_ = scatter_.triangle_loop(tris, f, energy_, [&](std::size_t ti, auto& terms) {
            TriangleData& td = triangles_[ti];
            const Triangle& t = tris[ti];
            const auto& te = edges_in_triangle[ti];
            const auto delta_of = [&](int j) {
                return delta_[static_cast<std::size_t>(te[static_cast<std::size_t>(j)])];
            };
            const auto at = [&](int j) { return static_cast<std::size_t>(t[static_cast<std::size_t>(j)]); };
            for (int j = 0; j < 3; ++j) {
                const int k = (j + 1) % 3;
                const int l = (j + 2) % 3;
                td.dp[static_cast<std::size_t>(j)] = x[at(l)] - x[at(k)];
                const double intensity = delta_of(k) * td.gamma[static_cast<std::size_t>(l)] +
                                         delta_of(l) * td.gamma[static_cast<std::size_t>(k)];
                const Vec3 force = scaled(-td.dp[static_cast<std::size_t>(j)], intensity);
                terms.add(static_cast<std::size_t>(l), force);
                terms.subtract(static_cast<std::size_t>(k), force);
                terms.add_energy(td.gamma[static_cast<std::size_t>(j)] * delta_of(k) * delta_of(l) / 2);
            }
            if (!parameters_.compressible) return;
            // area term of a compressed triangle
            td.normal = -cross(td.dp[2], td.dp[1]);
            td.area = std::sqrt(dot3(td.normal, td.normal)) / 2;
            td.j = td.area / td.rest_area;
            if (!(td.j < 1)) return;
            const double jj = td.j - 1;
            if (td.j < 1e-2) {
                td.normal = td.last_valid_normal;  // too flat: keep the last trusted normal
            } else {
                td.normal = divided(td.normal, 2 * td.area);
                if (dot3(td.normal, td.last_valid_normal) > -0.5) td.last_valid_normal = td.normal;
                else td.normal = scaled(td.normal, -1.0);  // flipped: SOFA turns it back
            }
            const double intensity = area_stiffness * jj * jj * jj;
            for (std::size_t j = 0; j < 3; ++j) {
                td.area_vector[j] = divided(cross(td.normal, td.dp[j]), 2);
                terms.subtract(j, scaled(td.area_vector[j], intensity));
            }
            terms.add_energy(area_stiffness * td.rest_area * jj * jj * jj * jj / 4);
        });
    }
    update_stiffness();
}

void TriangularBiquadraticSpringsForceField::update_stiffness() {
    // addDForce's DfDx[k] (SOFA computes it at the first addDForce after addForce, from the same data)
    const auto& edges_in_triangle = topology_->edges_in_triangle();
    const double area_stiffness = (lambda_ + mu_) * 3;
    // each triangle's blocks its own: in ranges on TBB's threads from OrderedScatter::kMinElements
    detail::for_each_range(triangles_.size(), kTrianglesPerTask, [&](std::size_t first, std::size_t end) {
        for (std::size_t ti = first; ti < end; ++ti) {
            TriangleData& td = triangles_[ti];
            const auto& te = edges_in_triangle[ti];
            const auto delta_of = [&](int j) {
                return delta_[static_cast<std::size_t>(te[static_cast<std::size_t>(j)])];
            };
            for (int k = 0; k < 3; ++k) {
                Mat3& m = td.dfdx[static_cast<std::size_t>(k)];
                const auto sk = static_cast<std::size_t>(k);
                const Vec3 dpk = -td.dp[sk];  // x_i − x_j with i = k+1, j = k+2
                if (!parameters_.use_angular_springs) {
                    const double diagonal = -td.stiffness[sk] * delta_of(k);
                    const double along = -2 * td.stiffness[sk];
                    for (int u = 0; u < 3; ++u) {
                        for (int w = 0; w < 3; ++w) m(u, w) = dpk[u] * dpk[w] * along;
                        m(u, u) += diagonal;
                    }
                    continue;
                }
                const int i = (k + 1) % 3;
                const int j = (k + 2) % 3;
                const auto si = static_cast<std::size_t>(i);
                const auto sj = static_cast<std::size_t>(j);
                const Vec3 dpj = td.dp[sj];   // x_i − x_k
                const Vec3 dpi = -td.dp[si];  // x_j − x_k
                const double diagonal =
                    -(td.stiffness[sk] * delta_of(k) + td.gamma[si] * delta_of(j) + td.gamma[sj] * delta_of(i));
                const double along = -2 * td.stiffness[sk];
                const double val_k = 2 * td.gamma[sk];
                const double val_i = 2 * td.gamma[si];
                const double val_j = 2 * td.gamma[sj];
                for (int u = 0; u < 3; ++u) {
                    for (int w = 0; w < 3; ++w)
                        m(u, w) = dpk[u] * dpk[w] * along + dpj[u] * dpi[w] * val_k - dpj[u] * dpk[w] * val_i +
                                  dpk[u] * dpi[w] * val_j;
                    m(u, u) += diagonal;
                }
            }
            if (!(parameters_.use_angular_springs && parameters_.compressible && td.j < 1.0)) continue;
            // SOFA's regularised area term (addDForce): h = 1 − J weighs the tensor product of the
            // area vectors against its trace times I
            const double jj = td.j - 1;
            const double h = -jj;
            const double val2 = 3 * area_stiffness * jj * jj / td.rest_area;
            double val1 = area_stiffness * jj * jj * jj / 2;
            const Vec3 skew = scaled(-td.normal, val1);  // vector of the antisymmetric part
            val1 /= 2 * td.area;
            Mat3 nn;
            for (int u = 0; u < 3; ++u)
                for (int w = 0; w < 3; ++w) nn(u, w) = td.normal[u] * td.normal[w] * val1;
            double length_square[3];
            for (int e = 0; e < 3; ++e)
                length_square[e] = square_length_[static_cast<std::size_t>(te[static_cast<std::size_t>(e)])];
            const double total = length_square[0] + length_square[1] + length_square[2];
            for (int k = 0; k < 3; ++k) {
                Mat3& m = td.dfdx[static_cast<std::size_t>(k)];
                const double weight = total - 2 * length_square[k];
                m(0, 1) += skew[2];
                m(0, 2) -= skew[1];
                m(1, 0) -= skew[2];
                m(1, 2) += skew[0];
                m(2, 0) += skew[1];
                m(2, 1) -= skew[0];
                const Vec3& ai = td.area_vector[static_cast<std::size_t>((k + 1) % 3)];
                const Vec3& aj = td.area_vector[static_cast<std::size_t>((k + 2) % 3)];
                const double trace = dot3(ai, aj);
                for (int u = 0; u < 3; ++u)
                    for (int w = 0; w < 3; ++w) {
                        m(u, w) += (1 - h) * ai[u] * aj[w] * val2;
                        m(u, w) += nn(u, w) * weight;
                        if (u == w) m(u, w) += h * val2 * trace;
                    }
            }
        }
    });
}

void TriangularBiquadraticSpringsForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                                        double /*b_factor*/) const {
    PENALTY_DEMAND(triangles_.size() == topology_->triangles().size());
    product_.add_dforce(kernel_path_, scatter_, topology_->triangles(), triangles_, df, dx, k_factor);
}

void TriangularBiquadraticSpringsForceField::set_kernel_path(KernelPath path) {
    kernel_path_ = checked_kernel_path(path, "TriangularBiquadraticSpringsForceField", /*has_avx512=*/false);
}

void TriangularBiquadraticSpringsForceField::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    PENALTY_DEMAND(triangles_.size() == topology_->triangles().size());
    edge_blocks::add_stiffness_triplets(topology_->triangles(), triangles_, t, offset, factor);
}

}  // namespace penalty
