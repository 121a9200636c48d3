#include "penalty/mechanics/triangular_tensor_mass.hpp"

#include "sofa_vector_ops.hpp"
#include "triangle_edge_blocks.hpp"

#include <cmath>

namespace penalty {

namespace {

using sofa_vec::times;            // M·v in SOFA's Mat::operator*(Vec) order
using sofa_vec::transpose_times;  // Mᵀ·v in SOFA's order

/// |v|² as SOFA's norm2: (x² + y²) + z².
double squared_norm(const Vec3& v) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; }

}  // namespace

TriangularTensorMassForceField::TriangularTensorMassForceField(Vec3Object& state, const MeshTopology& topology,
                                                               TensorMassParameters p)
    : ForceField<Vec3Types>(state), topology_(&topology) {
    if (!std::isfinite(p.young_modulus) || p.young_modulus < 0)
        throw_invalid_argument("TriangularTensorMassForceField: youngModulus must be finite and >= 0, got ",
                               p.young_modulus);
    if (!std::isfinite(p.poisson_ratio) || p.poisson_ratio * p.poisson_ratio == 1.0)
        throw_invalid_argument("TriangularTensorMassForceField: poissonRatio must be finite and not +-1, got ",
                               p.poisson_ratio);
    // TriangularTensorMassForceField::updateLameCoefficients, operation by operation
    const double e = p.young_modulus;
    const double nu = p.poisson_ratio;
    lambda_ = e * nu / (1 - nu * nu);
    mu_ = e * (1 - nu) / (1 - nu * nu);
}

void TriangularTensorMassForceField::init() {
    const auto& triangles = topology_->triangles();
    const auto& edges = topology_->edges();
    const auto& edges_in_triangle = topology_->edges_in_triangle();
    rest_ = state_->rest_position;
    for (const Triangle& t : triangles)
        for (const PointId v : t)
            if (v < 0 || static_cast<std::size_t>(v) >= rest_.size())
                throw_invalid_argument("TriangularTensorMassForceField: point ", v, " out of range for a state of ",
                                       rest_.size(), " points");
    tensors_.assign(edges.size(), Mat3::Zero());
    scatter_.clear();
    // TriangularTensorMassForceField::applyTriangleCreation, triangles in order
    for (std::size_t ti = 0; ti < triangles.size(); ++ti) {
        const Triangle& t = triangles[ti];
        Vec3 point[3];
        for (int j = 0; j < 3; ++j) point[j] = rest_[static_cast<std::size_t>(t[static_cast<std::size_t>(j)])];
        double square_length[3];
        for (int j = 0; j < 3; ++j) square_length[j] = squared_norm(point[(j + 1) % 3] - point[(j + 2) % 3]);
        // Heron: 16 A² = Σ_j ℓ_j² (ℓ_{j+1}² + ℓ_{j+2}² − ℓ_j²)
        double area = 0;
        for (int j = 0; j < 3; ++j)
            area += square_length[j] * (square_length[(j + 1) % 3] + square_length[(j + 2) % 3] - square_length[j]);
        area = std::sqrt(area) / 4;
        if (!(area > 0))
            throw_invalid_argument("TriangularTensorMassForceField: triangle ", ti, " has a zero rest area");
        const double lambda_star = lambda_ / (4 * area);
        const double mu_star = mu_ / (8 * area);
        double cotangent[3];
        for (int j = 0; j < 3; ++j)
            cotangent[j] = (square_length[(j + 1) % 3] + square_length[(j + 2) % 3] - square_length[j]) / (4 * area);
        for (int j = 0; j < 3; ++j) {
            const int k = (j + 1) % 3;
            const int l = (j + 2) % 3;
            const auto edge = static_cast<std::size_t>(edges_in_triangle[ti][static_cast<std::size_t>(j)]);
            Mat3& m = tensors_[edge];
            const Vec3 dpl = point[j] - point[k];
            const Vec3 dpk = point[j] - point[l];
            const double diagonal = -cotangent[j] * (lambda_ + mu_) / 2;
            // the tensor as seen from the edge's first vertex: transposed when it is not t_l
            const bool as_is = edges[edge][0] == t[static_cast<std::size_t>(l)];
            for (int u = 0; u < 3; ++u) {
                for (int v = 0; v < 3; ++v) {
                    const double term = lambda_star * dpl[u] * dpk[v] + mu_star * dpk[u] * dpl[v];
                    if (as_is) m(u, v) += term;
                    else m(v, u) += term;
                }
                m(u, u) += diagonal;
            }
        }
    }
}

// f_v1 += D δ, f_v0 −= Dᵀ δ with δ = u_v1 − u_v0 (u = x − x₀), E −= ½ (u_v1·f1 − u_v0·f0); from
// OrderedScatter::kMinElements edges on TBB's threads with the bits of one thread.
void TriangularTensorMassForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3>) {
    PENALTY_DEMAND(tensors_.size() == topology_->edges().size());
    const auto& edges = topology_->edges();
    energy_ = scatter_.edge_loop(edges, f, [&](std::size_t i) {
        const auto v0 = static_cast<std::size_t>(edges[i][0]);
        const auto v1 = static_cast<std::size_t>(edges[i][1]);
        const Vec3 u0 = x[v0] - rest_[v0];
        const Vec3 u1 = x[v1] - rest_[v1];
        const Vec3 delta = u1 - u0;
        const Vec3 f1 = times(tensors_[i], delta);
        const Vec3 f0 = transpose_times(tensors_[i], delta);
        return detail::EdgeTerms{f1, f0, -(0.5 * (u1.dot(f1) - u0.dot(f0)))};  // (E − e is E + (−e))
    });
}

void TriangularTensorMassForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                                double /*b_factor*/) const {
    PENALTY_DEMAND(tensors_.size() == topology_->edges().size());
    const auto& edges = topology_->edges();
    // TriangularTensorMassForceField::addDForce: (D δ)·k and (Dᵀ δ)·k; from
    // OrderedScatter::kMinElements edges with more than one thread, in the scatter's chunks with
    // the bits of the loop, else the loop itself (one thread: no terms between the loop and df)
    const auto terms = [&](std::size_t i) {
        const Vec3 delta = dx[static_cast<std::size_t>(edges[i][1])] - dx[static_cast<std::size_t>(edges[i][0])];
        const Vec3 a = times(tensors_[i], delta);
        const Vec3 b = transpose_times(tensors_[i], delta);
        return detail::EdgeTerms{Vec3(a[0] * k_factor, a[1] * k_factor, a[2] * k_factor),
                                 Vec3(b[0] * k_factor, b[1] * k_factor, b[2] * k_factor), 0.0};
    };
    if (detail::OrderedScatter::worth_threads(edges.size())) {
        (void)scatter_.edge_loop(edges, df, terms);
        return;
    }
    for (std::size_t i = 0; i < edges.size(); ++i) {
        const auto v0 = static_cast<std::size_t>(edges[i][0]);
        const auto v1 = static_cast<std::size_t>(edges[i][1]);
        const Vec3 delta = dx[v1] - dx[v0];
        const Vec3 a = times(tensors_[i], delta);
        const Vec3 b = transpose_times(tensors_[i], delta);
        df[v1] += Vec3(a[0] * k_factor, a[1] * k_factor, a[2] * k_factor);
        df[v0] -= Vec3(b[0] * k_factor, b[1] * k_factor, b[2] * k_factor);
    }
}

void TriangularTensorMassForceField::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    PENALTY_DEMAND(tensors_.size() == topology_->edges().size());
    const auto& edges = topology_->edges();
    // ∂f_v1/∂x_v1 = D, ∂f_v1/∂x_v0 = −D, ∂f_v0/∂x_v1 = −Dᵀ, ∂f_v0/∂x_v0 = Dᵀ
    for (std::size_t i = 0; i < edges.size(); ++i) {
        const Index r0 = offset + 3 * edges[i][0];
        const Index r1 = offset + 3 * edges[i][1];
        edge_blocks::add_edge_block_triplets(t, r1, r0, factor * tensors_[i]);
    }
}

}  // namespace penalty
