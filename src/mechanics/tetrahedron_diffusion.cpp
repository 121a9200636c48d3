// TetrahedronDiffusionFEMForceField<Vec1d> (include/penalty/mechanics/tetrahedron_diffusion.hpp):
// SOFA's edge coefficients of a tetrahedral mesh, then a force per edge. The products keep SOFA's
// operation order (sofa_vector_ops.hpp), so the coefficients have SOFA's bits.
#include "penalty/mechanics/tetrahedron_diffusion.hpp"

#include "penalty/core/error.hpp"
#include "sofa_vector_ops.hpp"

#include <cmath>
#include <string>

namespace penalty {

TetrahedronDiffusionFEMForceField::TetrahedronDiffusionFEMForceField(Vec1Object& state, const MeshTopology& topology)
    : ForceField<Vec1Types>(state), topology_(&topology) {}

void TetrahedronDiffusionFEMForceField::set_anisotropy(double ratio, std::vector<Vec3> directions) {
    ratio_ = ratio;
    directions_ = std::move(directions);
}

void TetrahedronDiffusionFEMForceField::init() {
    using sofa_vec::cross;
    using sofa_vec::dot3;
    const auto& tetrahedra = topology_->tetrahedra();
    const auto& edges = topology_->edges();
    const std::size_t n_points = topology_->num_points();
    const std::string what = "TetrahedronDiffusionFEMForceField: ";
    if (geometry_.size() < n_points)
        throw_invalid_argument(what, "the geometry has ", geometry_.size(), " points, the topology ", n_points);
    if (state_->num_dofs() < n_points)
        throw_invalid_argument(what, "the state has ", state_->num_dofs(), " values, the topology ", n_points,
                               " points");
    // SOFA's init: tetraDiffusionCoefficient given (one per tetrahedron), else the constant for all
    if (per_tetrahedron_.empty()) {
        coefficients_.assign(tetrahedra.size(), constant_);
    } else {
        if (per_tetrahedron_.size() != tetrahedra.size())
            throw_invalid_argument(what, "tetraDiffusionCoefficient has ", per_tetrahedron_.size(), " values for ",
                                   tetrahedra.size(), " tetrahedra");
        coefficients_ = per_tetrahedron_;
    }
    const bool isotropic = ratio_ == 1.0;
    if (!isotropic && directions_.size() < tetrahedra.size())
        throw_invalid_argument(what, "an anisotropic diffusion (anisotropyRatio ", ratio_,
                               ") needs one direction per tetrahedron in "
                               "transverseAnisotropyArray: ",
                               directions_.size(), " for ", tetrahedra.size());
    edge_coefficients_.assign(edges.size(), 0.0);
    for (std::size_t t = 0; t < tetrahedra.size(); ++t) {
        const Tetrahedron& tet = tetrahedra[t];
        std::array<Vec3, 4> p;
        for (int j = 0; j < 4; ++j) p[j] = geometry_[std::size_t(tet[j])];
        const double w = dot3(cross(p[1] - p[0], p[2] - p[0]), p[0] - p[3]);  // 6 × signed volume
        if (!(std::abs(w) > 0.0) || !std::isfinite(w))
            throw_invalid_argument(what, "tetrahedron ", t, " has no volume (SOFA divides by it)");
        std::array<Vec3, 4> shape;
        for (int j = 0; j < 4; ++j) {
            const Vec3 c = cross(p[(j + 2) % 4] - p[(j + 1) % 4], p[(j + 3) % 4] - p[(j + 1) % 4]);
            const Vec3 signed_c = j % 2 == 0 ? Vec3(-c[0], -c[1], -c[2]) : c;
            shape[j] = Vec3(signed_c[0] / w, signed_c[1] / w, signed_c[2] / w);
        }
        const double diff = coefficients_[t] * std::abs(w) / 6;
        for (const auto& [k, l] : MeshTopology::kTetraEdges) {
            const std::int32_t e = topology_->edge_index(tet[std::size_t(k)], tet[std::size_t(l)]);
            PENALTY_DEMAND(e >= 0);
            double value;
            if (isotropic) {
                value = dot3(shape[std::size_t(k)], shape[std::size_t(l)]) * diff;
            } else {
                const Vec3& a = directions_[t];
                const Vec3& sl = shape[std::size_t(l)];
                const double along = (ratio_ - 1) * dot3(a, sl);
                value = dot3(shape[std::size_t(k)],
                             Vec3(sl[0] + a[0] * along, sl[1] + a[1] * along, sl[2] + a[2] * along)) *
                        diff;
            }
            edge_coefficients_[std::size_t(e)] += value;
        }
    }
}

void TetrahedronDiffusionFEMForceField::add_force(std::span<double> f, std::span<const double> x,
                                                  std::span<const double>) {
    const auto& edges = topology_->edges();
    double energy = 0.0;
    for (std::size_t i = 0; i < edges.size(); ++i) {
        const auto v0 = std::size_t(edges[i][0]);
        const auto v1 = std::size_t(edges[i][1]);
        const double d = x[v1] - x[v0];
        const double dp = d * edge_coefficients_[i];
        f[v1] += dp;
        f[v0] -= dp;
        energy -= 0.5 * dp * d;
    }
    energy_ = energy;
}

void TetrahedronDiffusionFEMForceField::add_dforce(std::span<double> df, std::span<const double> dx, double k_factor,
                                                   double /*b_factor*/) const {
    const auto& edges = topology_->edges();
    for (std::size_t i = 0; i < edges.size(); ++i) {
        const auto v0 = std::size_t(edges[i][0]);
        const auto v1 = std::size_t(edges[i][1]);
        const double dp = (dx[v1] - dx[v0]) * edge_coefficients_[i] * k_factor;
        df[v1] += dp;
        df[v0] -= dp;
    }
}

void TetrahedronDiffusionFEMForceField::add_stiffness_triplets(TripletList& triplets, Index offset,
                                                               double factor) const {
    // SOFA's buildStiffnessMatrix: per edge, −c at (v1, v0) and (v0, v1), +c at (v0, v0) and (v1, v1)
    const auto& edges = topology_->edges();
    for (std::size_t i = 0; i < edges.size(); ++i) {
        const Index v0 = offset + Index(edges[i][0]);
        const Index v1 = offset + Index(edges[i][1]);
        const double c = factor * edge_coefficients_[i];
        triplets.emplace_back(v1, v0, -c);
        triplets.emplace_back(v0, v1, -c);
        triplets.emplace_back(v0, v0, c);
        triplets.emplace_back(v1, v1, c);
    }
}

}  // namespace penalty
