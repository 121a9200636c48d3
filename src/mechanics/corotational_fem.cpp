#include "penalty/mechanics/corotational_fem.hpp"

#include "tetrahedron_large_blocks.hpp"
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
    if (!sofa_operations()) {
        detail::resize_large_blocks(blocks_, 0, kernel_path_);
        return;
    }
    // TetrahedralCorotationalFEMForceField::reinit: computeMaterialStiffness (E·factor, the volume
    // of the world rest positions) and initSmall, initLarge or initPolar (frame, rest coordinates,
    // J) per element; K^e (the assembled stiffness) is the common path's, made when first asked for
    detail::resize_large_blocks(blocks_, elements_.size(), kernel_path_);
    const auto& x0 = state_->rest_position;
    for (std::size_t e = 0; e < elements_.size(); ++e) {
        std::array<Vec3, 4> x;
        for (std::size_t k = 0; k < 4; ++k) x[k] = x0[static_cast<std::size_t>(elements_[e][k])];
        const double young = options_.local_stiffness_factors.empty() ? young_ : young_ * stiffness_factor(e);
        Mat3 r0;
        rest_local_[e] = detail::rest_coordinates(method_, x, r0);
        detail::store_large_element(blocks_, e, detail::material_over_volume(young, poisson_, x), rest_local_[e], r0);
    }
}

void TetrahedralCorotationalFEMForceField::set_kernel_path(KernelPath path) {
    kernel_path_ = checked_kernel_path(path, component_, /*has_avx512=*/true);
    // after init: the data move to the path's width (before, init gives them that width)
    if (sofa_operations()) detail::resize_large_blocks(blocks_, elements_.size(), kernel_path_);
}

Mat3 TetrahedralCorotationalFEMForceField::element_rotation(const std::array<Vec3, 4>& p) const {
    return tetrahedron_rotation(p, method_);
}

void TetrahedralCorotationalFEMForceField::check_rest_element(const std::array<Vec3, 4>& rest_local,
                                                              std::size_t e) const {
    const double volume = tetrahedron_volume(rest_local);
    const double scale = std::max({(rest_local[1] - rest_local[0]).norm(), (rest_local[2] - rest_local[0]).norm(),
                                   (rest_local[3] - rest_local[0]).norm()});
    // SOFA divides by the volume (infinite stiffness); penalty refuses the element.
    if (!std::isfinite(volume) || volume <= 1e-12 / 6 * scale * scale * scale)
        throw_invalid_argument(component_, ": tetrahedron ", e, " is degenerate (volume ", volume, ")");
}

TetrahedralCorotationalFEMForceField::ElementMatrix TetrahedralCorotationalFEMForceField::compute_stiffness(
    const std::array<Vec3, 4>& rest_local, const Eigen::Matrix<double, 6, 6>&, std::size_t e) const {
    check_rest_element(rest_local, e);
    return stiffness_of_shape(rest_local, tetrahedron_volume(rest_local), e);
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
        // (the chunks' first elements on a lane block's boundary: eight lanes, four dividing it)
        PENALTY_DEMAND(detail::large_blocks_fit(blocks_, elements_.size(), kernel_path_));
        energy_ = force_in_order</*Add=*/true>(
            f, 8, [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred, double* energies) {
                if (method_ == FemMethod::Small || method_ == FemMethod::Polar)
                    return detail::per_element_blocks_force(blocks_, method_, rest_local_, elements_, {first, end}, f,
                                                            x, deferred, energies, nullptr);
                return detail::large_blocks_force(blocks_, kernel_path_, rest_local_, elements_, {first, end}, f, x,
                                                  deferred, energies);
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
    PENALTY_DEMAND(detail::large_blocks_fit(blocks_, elements_.size(), kernel_path_));
    scatter_in_order</*Add=*/false>(df, 8, [&](std::size_t first, std::size_t end, const auto& deferred) {
        if (method_ == FemMethod::Small)
            detail::small_blocks_dforce(blocks_, elements_, {first, end}, df, dx, k_factor, deferred);
        else detail::large_blocks_dforce(blocks_, kernel_path_, elements_, {first, end}, df, dx, k_factor, deferred);
    });
}

void TetrahedralCorotationalFEMForceField::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    if (!sofa_operations()) {
        LinearElementForceField<4>::add_stiffness_triplets(t, offset, factor);
        return;
    }
    (void)element_stiffness();  // (add_element_triplets reads it)
    for (std::size_t e = 0; e < elements_.size(); ++e)
        add_element_triplets(t, offset, factor, e, detail::large_block_rotation(blocks_, e));
}

}  // namespace penalty
