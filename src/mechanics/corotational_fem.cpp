#include "penalty/mechanics/corotational_fem.hpp"

#include "tetrahedron_large_element.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

namespace penalty {

namespace {
constexpr std::size_t kElementsPerTask = 1024;  // updateStiffnessMatrix's K^e on threads

/// |(p1−p0)·((p2−p0)×(p3−p0))| / 6 (sofa::geometry::Tetrahedron::volume, unsigned), m³.
double tetrahedron_volume(const std::array<Vec3, 4>& p) {
    return std::abs((p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0]))) / 6.0;
}
}  // namespace

TetrahedralCorotationalFEMForceField::TetrahedralCorotationalFEMForceField(Vec3Object& state,
                                                                           std::vector<Tetrahedron> tetrahedra,
                                                                           double young, double poisson,
                                                                           CorotationalFemOptions options)
    : LinearElementForceField<4>(state, std::move(tetrahedra), young, poisson, options.method,
                                 "TetrahedralCorotationalFEMForceField"),
      options_(std::move(options)) {
    for (double factor : options_.local_stiffness_factors)
        if (!std::isfinite(factor))
            throw_invalid_argument(component_, ": localStiffnessFactor must be finite, got ", factor);
}

double TetrahedralCorotationalFEMForceField::stiffness_factor(std::size_t e) const {
    const auto& factors = options_.local_stiffness_factors;
    // TetrahedralCorotationalFEMForceField::computeMaterialStiffness: factor[i·M/N] (integer division)
    return factors.empty() ? 1.0 : factors[e * factors.size() / elements_.size()];
}

bool TetrahedralCorotationalFEMForceField::sofa_operations() const {
    // (method small ignores updateStiffnessMatrix)
    return !options_.assembling && (method_ == FemMethod::Small || !options_.update_stiffness);
}

void TetrahedralCorotationalFEMForceField::init() {
    material_ = isotropic_elasticity(young_, poisson_);
    LinearElementForceField<4>::init();
    rest_volume_.resize(elements_.size());
    for (std::size_t e = 0; e < elements_.size(); ++e) rest_volume_[e] = tetrahedron_volume(rest_local_[e]);
    large_.clear();
    if (!sofa_operations()) return;
    // TetrahedralCorotationalFEMForceField::reinit: computeMaterialStiffness (E·factor, the volume
    // of the world rest positions) and initSmall, initLarge or initPolar (frame, rest coordinates,
    // J) per element; K^e (the assembled stiffness) stays the common path's
    large_.resize(elements_.size());
    const auto& x0 = state_->rest_position;
    for (std::size_t e = 0; e < elements_.size(); ++e) {
        std::array<Vec3, 4> x;
        for (std::size_t k = 0; k < 4; ++k) x[k] = x0[static_cast<std::size_t>(elements_[e][k])];
        const double young = options_.local_stiffness_factors.empty() ? young_ : young_ * stiffness_factor(e);
        large_[e].material = detail::material_over_volume(young, poisson_, x);
        rest_local_[e] = detail::rest_coordinates(method_, x, rotation_[e]);
        large_[e].strain_displacement = detail::strain_displacement(rest_local_[e]);
    }
}

Mat3 TetrahedralCorotationalFEMForceField::element_rotation(const std::array<Vec3, 4>& p) const {
    return tetrahedron_rotation(p, method_);
}

TetrahedralCorotationalFEMForceField::ElementMatrix TetrahedralCorotationalFEMForceField::compute_stiffness(
    const std::array<Vec3, 4>& rest_local, const Eigen::Matrix<double, 6, 6>&, std::size_t e) const {
    const double volume = tetrahedron_volume(rest_local);
    const double scale = std::max({(rest_local[1] - rest_local[0]).norm(), (rest_local[2] - rest_local[0]).norm(),
                                   (rest_local[3] - rest_local[0]).norm()});
    // SOFA divides by the volume (infinite stiffness); penalty refuses the element.
    if (!std::isfinite(volume) || volume <= 1e-12 / 6 * scale * scale * scale)
        throw_invalid_argument(component_, ": tetrahedron ", e, " is degenerate (volume ", volume, ")");
    return stiffness_of_shape(rest_local, volume, e);
}

TetrahedralCorotationalFEMForceField::ElementMatrix TetrahedralCorotationalFEMForceField::stiffness_of_shape(
    const std::array<Vec3, 4>& shape, double rest_volume, std::size_t e) const {
    // TetrahedralCorotationalFEMForceField::computeStrainDisplacement: J's node-k block holds the
    // cofactor vector c_k = 6V·∇N_k of the shape (V signed): c1 = e2×e3, c2 = e3×e1, c3 = e1×e2,
    // c0 = −(c1+c2+c3) with e_k = p_k − p0; defined for a degenerate shape too. The material matrix
    // is D·factor/(36 V⁰) (computeMaterialStiffness), so K^e = factor/(36 V⁰) · J D Jᵀ; at rest
    // this is V⁰·BᵀDB, TetrahedronFEMForceField's stiffness.
    const Vec3 e1 = shape[1] - shape[0], e2 = shape[2] - shape[0], e3 = shape[3] - shape[0];
    const Vec3 c1 = e2.cross(e3), c2 = e3.cross(e1), c3 = e1.cross(e2);
    const std::array<Vec3, 4> cofactors{-(c1 + c2 + c3), c1, c2, c3};
    return tetrahedron_stiffness_from_gradients(cofactors, material_, stiffness_factor(e) / (36.0 * rest_volume));
}

void TetrahedralCorotationalFEMForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x,
                                                     std::span<const Vec3> v) {
    if (sofa_operations()) {
        // accumulateForceSmall / Large / Polar per element, in element order (energy: ½ δᵀF,
        // beyond SOFA)
        PENALTY_DEMAND(large_.size() == elements_.size());
        energy_ = force_in_order</*Add=*/true>(
            f, 1, [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred, double* energies) {
                return sofa_force(first, end, f, x, deferred, energies);
            });
        return;
    }
    if (options_.update_stiffness && method_ != FemMethod::Small) {
        // accumulateForceLarge / accumulateForcePolar with updateStiffnessMatrix: J from the current
        // shape in the element frame, before the force (method small ignores the option).
        PENALTY_DEMAND(rest_volume_.size() == elements_.size());
        const auto update = [&](std::size_t first, std::size_t end) {
            for (std::size_t e = first; e < end; ++e) {
                std::array<Vec3, 4> p;
                for (std::size_t k = 0; k < 4; ++k) p[k] = x[static_cast<std::size_t>(elements_[e][k])];
                const Mat3 r = element_rotation(p);
                std::array<Vec3, 4> shape;
                for (std::size_t k = 0; k < 4; ++k) shape[k] = r * (p[k] - p[0]);
                ke_[e] = stiffness_of_shape(shape, rest_volume_[e], e);
            }
        };
        if (detail::OrderedScatter::worth_threads(elements_.size()))  // (each element its own K^e)
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, elements_.size(), kElementsPerTask),
                              [&](const tbb::blocked_range<std::size_t>& r) { update(r.begin(), r.end()); });
        else update(0, elements_.size());
    }
    if (method_ == FemMethod::Polar && options_.assembling) {
        // accumulateForcePolar with computeGlobalMatrix: SOFA logs "TODO ... polar method" and adds
        // no force, after updating the rotation (and J) that addDForce uses.
        scratch_force_.assign(f.size(), Vec3::Zero());
        LinearElementForceField<4>::add_force(scratch_force_, x, v);
        energy_ = 0.0;
        return;
    }
    LinearElementForceField<4>::add_force(f, x, v);
}

void TetrahedralCorotationalFEMForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                                      double b_factor) const {
    if (!sofa_operations()) {
        LinearElementForceField<4>::add_dforce(df, dx, k_factor, b_factor);
        return;
    }
    // applyStiffnessSmall / Large / Polar per element, in element order: df −= F(dx, kFactor),
    // df −= Rᵀ·F(R·dx, kFactor)
    PENALTY_DEMAND(large_.size() == elements_.size());
    scatter_in_order</*Add=*/false>(df, 1, [&](std::size_t first, std::size_t end, const auto& deferred) {
        for (std::size_t e = first; e < end; ++e) {
            const LargeElement& element = large_[e];
            const std::array<std::size_t, 4> vertex = detail::large_vertices(elements_[e]);
            const std::array<Vec3, 4> terms =
                method_ == FemMethod::Small
                    ? detail::small_element_dforce_terms(vertex, element.strain_displacement, element.material, dx,
                                                         k_factor)
                    : detail::large_element_dforce_terms(vertex, rotation_[e], element.strain_displacement,
                                                         element.material, dx, k_factor);
            detail::store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) { df[vertex[k]] -= term; });
        }
    });
}

double TetrahedralCorotationalFEMForceField::sofa_force(std::size_t first, std::size_t end, std::span<Vec3> f,
                                                        std::span<const Vec3> x, const detail::DeferredTerms& deferred,
                                                        double* energies) {
    double total = 0.0;
    for (std::size_t e = first; e < end; ++e) {
        const std::array<std::size_t, 4> vertex = detail::large_vertices(elements_[e]);
        const LargeElement& element = large_[e];
        double energy = 0.0;
        std::array<Vec3, 4> terms;
        if (method_ == FemMethod::Small) {
            terms = detail::small_element_force_terms(vertex, rest_local_[e], element.strain_displacement,
                                                      element.material, x, energy);
        } else if (method_ == FemMethod::Polar) {
            rotation_[e] = polar_rotation(detail::edge_rows(x[vertex[0]], x[vertex[1]], x[vertex[2]], x[vertex[3]]));
            terms = detail::polar_element_force_terms(vertex, rest_local_[e], rotation_[e], element.strain_displacement,
                                                      element.material, x, energy);
        } else {
            terms = detail::large_element_force_terms(vertex, rest_local_[e], element.strain_displacement,
                                                      element.material, x, energy, rotation_[e]);
        }
        if (energies) energies[e] = energy;
        else total += energy;
        detail::store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) { f[vertex[k]] += term; });
    }
    return total;
}

}  // namespace penalty
