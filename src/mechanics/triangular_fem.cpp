#include "penalty/mechanics/triangular_fem.hpp"

#include "kernels/mechanics/triangle_fem_large.hpp"
#include "sofa_vector_ops.hpp"
#include "triangle_fem_sofa_order.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

namespace penalty {

namespace {

const char* component_name(TriangleFemFlavor flavor) {
    return flavor == TriangleFemFlavor::TriangularFEM ? "TriangularFEMForceField" : "TriangleFEMForceField";
}

/// The elements: the topology's triangles; for TriangleFEMForceField::init without triangles,
/// each quad q split into (q0, q1, q2), (q0, q2, q3).
std::vector<Triangle> elements_of(const MeshTopology& topology, TriangleFemFlavor flavor) {
    if (flavor == TriangleFemFlavor::TriangleFEM && topology.triangles().empty()) {
        std::vector<Triangle> split;
        split.reserve(2 * topology.quads().size());
        for (const Quad& q : topology.quads()) {
            split.push_back({q[0], q[1], q[2]});
            split.push_back({q[0], q[2], q[3]});
        }
        return split;
    }
    return topology.triangles();
}

/// J of the world triangle (0, b, c) from its x, y coordinates, scaled by 1/|b × c|
/// (TriangleFEMUtils::computeStrainDisplacementGlobal with a = 0); false when degenerate.
bool strain_displacement_global(TriangularFEMForceField::StrainDisplacement& j, const Vec3& b, const Vec3& c) {
    const double det = b.cross(c).norm();
    if (std::abs(det) < std::numeric_limits<double>::epsilon()) return false;
    const double inv = 1 / det;
    const double x13 = (0.0 - c.x()) * inv, x21 = (b.x() - 0.0) * inv, x32 = (c.x() - b.x()) * inv;
    const double y12 = (0.0 - b.y()) * inv, y23 = (b.y() - c.y()) * inv, y31 = (c.y() - 0.0) * inv;
    j << y23, 0, x32,  //
        0, x32, y23,   //
        y31, 0, x13,   //
        0, x13, y31,   //
        y12, 0, x21,   //
        0, x21, y12;
    return true;
}

}  // namespace

TriangularFEMForceField::TriangularFEMForceField(Vec3Object& state, const MeshTopology& topology, double young,
                                                 double poisson, FemMethod method)
    : TriangularFEMForceField(
          state, topology, TriangleFemParameters{.young_modulus = young, .poisson_ratio = poisson, .method = method}) {}

TriangularFEMForceField::TriangularFEMForceField(Vec3Object& state, const MeshTopology& topology,
                                                 const TriangleFemParameters& parameters)
    : ForceField<Vec3Types>(state), triangles_(elements_of(topology, parameters.flavor)), parameters_(parameters) {
    const char* name = component_name(parameters.flavor);
    const double young = parameters.young_modulus, poisson = parameters.poisson_ratio;
    if (!std::isfinite(young) || young <= 0)
        throw_invalid_argument(name, ": youngModulus must be finite and > 0, got ", young);
    if (!std::isfinite(poisson) || poisson <= -1.0 || poisson >= 0.5)
        throw_invalid_argument(name, ": poissonRatio must be in (-1, 0.5), got ", poisson);
    if (!std::isfinite(parameters.thickness) || parameters.thickness <= 0)
        throw_invalid_argument(name, ": thickness must be finite and > 0, got ", parameters.thickness);
}

void TriangularFEMForceField::init() {
    blocks_current_ = false;
    const std::size_t n = triangles_.size();
    for_each_element_array([n](auto& v) { v.resize(n); });
    for (std::size_t e = 0; e < n; ++e) init_element(e);
    scatter_.clear();  // made again for these triangles at the next product on threads
}

void TriangularFEMForceField::init_element(std::size_t e) {
    const char* kComponent = component_name(parameters_.flavor);
    const bool triangular = parameters_.flavor == TriangleFemFlavor::TriangularFEM;
    const auto& x0 = state_->rest_position;
    rotation_[e] = Mat3::Identity();
    for (const PointId v : triangles_[e])
        if (v < 0 || static_cast<std::size_t>(v) >= x0.size())
            throw_invalid_argument(kComponent, ": triangle ", e, " uses point ", v, " but the state has ", x0.size(),
                                   " points");
    const Vec3& a = x0[static_cast<std::size_t>(triangles_[e][0])];
    const Vec3& b = x0[static_cast<std::size_t>(triangles_[e][1])];
    const Vec3& c = x0[static_cast<std::size_t>(triangles_[e][2])];
    bool ok = false;
    if (!triangular) {
        // TriangleFEMForceField::initLarge / initSmall, SOFA's operations (the rest local
        // coordinates R·b − R·a, R·c − R·a)
        if (parameters_.method == FemMethod::Large) {
            const Mat3 r0 = triangle_fem_sofa::rotation(a, b, c);
            rest_local_[e] = triangle_fem_sofa::rest_local_large(r0, a, b, c);
            rotation_[e] = r0.transpose();
        } else {
            rest_local_[e] = {Vec3(b[0] - a[0], b[1] - a[1], b[2] - a[2]), Vec3(c[0] - a[0], c[1] - a[1], c[2] - a[2])};
        }
        ok = triangle_fem_sofa::strain_displacement_local(j_[e], rest_local_[e][0], rest_local_[e][1]);
    } else if (parameters_.method == FemMethod::Large) {
        // initLarge: rest coordinates in the rest frame R_0_1·(b − a), R_0_1·(c − a) (SOFA's
        // Mat·Vec row sums), area = ½ r_bx·r_cy
        const Mat3 r0 = triangle_fem_sofa::rotation(a, b, c);
        rest_local_[e] = {sofa_vec::times(r0, Vec3(b[0] - a[0], b[1] - a[1], b[2] - a[2])),
                          sofa_vec::times(r0, Vec3(c[0] - a[0], c[1] - a[1], c[2] - a[2]))};
        rotation_[e] = r0.transpose();
        ok = triangle_fem_sofa::strain_displacement_local(j_[e], rest_local_[e][0], rest_local_[e][1]);
        area_[e] = rest_local_[e][0].x() * rest_local_[e][1].y() * 0.5;
    } else {
        // initSmall: world edge vectors, area = ½ |(b − a) × (c − a)|
        rest_local_[e] = {b - a, c - a};
        ok = strain_displacement_global(j_[e], rest_local_[e][0], rest_local_[e][1]);
        area_[e] = rest_local_[e][0].cross(rest_local_[e][1]).norm() * 0.5;
    }
    if (!ok) throw_invalid_argument(kComponent, ": triangle ", e, " is degenerate at rest (zero area)");
    const double p = parameters_.poisson_ratio;
    const double young = parameters_.young_modulus;
    Mat3 d;
    if (triangular) {
        // TriangularFEMForceField::computeMaterialStiffness: plane stress times the rest area
        d << 1, p, 0, p, 1, 0, 0, 0, (1.0 - p) * 0.5;
        material_[e] = d * ((young / (1.0 - p * p)) * area_[e]);
    } else {
        // TriangleFEMForceField::computeMaterialStiffnesses: times thickness·½|(b−a)×(c−a)|
        area_[e] = triangle_fem_sofa::area(a, b, c);
        const double volume = parameters_.thickness * area_[e];
        if (parameters_.plane_strain) {
            d << 1 - p, p, 0, p, 1 - p, 0, 0, 0, 0.5 - p;
            material_[e] = d * (young / ((1 + p) * (1 - 2 * p)) * volume);
        } else {
            d << 1, p, 0, p, 1, 0, 0, 0, 0.5 * (1 - p);
            material_[e] = d * (young / (1 - p * p) * volume);
        }
    }
}

bool TriangularFEMForceField::element_terms_sofa_order(std::size_t e, std::span<const Vec3> x,
                                                       ElementForce& out) const {
    const auto [ia, ib, ic] = triangles_[e];
    const Vec3& pa = x[static_cast<std::size_t>(ia)];
    const Vec3& pb = x[static_cast<std::size_t>(ib)];
    const Vec3& pc = x[static_cast<std::size_t>(ic)];
    const bool large = parameters_.method == FemMethod::Large;
    const Vec3 ab(pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]);
    const Vec3 ac(pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]);
    Mat3 r = Mat3::Identity();  // R_0_2 (rows = local axes)
    Vec3 db = ab, dc = ac;
    if (large) {
        r = triangle_fem_sofa::rotation(pa, pb, pc);
        db = sofa_vec::times(r, ab);
        dc = sofa_vec::times(r, ac);
    }
    Vec3 strain, stress;
    triangle_fem_sofa::Displacement nodal;
    if (!triangle_fem_sofa::element_forces(large, rest_local_[e], db, dc, material_[e], out.j, strain, stress, nodal))
        return false;
    out.to_world = r.transpose();  // R_2_0 (small: the identity, init's)
    for (std::size_t k = 0; k < 3; ++k) {
        const auto i = static_cast<Eigen::Index>(2 * k);
        const Vec3 local(nodal[i], nodal[i + 1], 0.0);
        out.terms[k] = large ? sofa_vec::times(out.to_world, local) : local;
    }
    out.energy = 0.5 * strain.dot(stress);
    return true;
}

/// TriangularFEMForceField "large" runs SOFA's TriangleFEMUtils, as TriangleFEMForceField does
/// (accumulateForceLarge, applyStiffnessLarge): the same operations in the same order.
bool TriangularFEMForceField::uses_sofa_order() const {
    return parameters_.flavor == TriangleFemFlavor::TriangleFEM || parameters_.method == FemMethod::Large;
}

bool TriangularFEMForceField::element_terms(std::size_t e, std::span<const Vec3> x, ElementForce& out) const {
    if (uses_sofa_order()) return element_terms_sofa_order(e, x, out);
    const auto [ia, ib, ic] = triangles_[e];
    const Vec3& pa = x[static_cast<std::size_t>(ia)];
    const Vec3& pb = x[static_cast<std::size_t>(ib)];
    const Vec3& pc = x[static_cast<std::size_t>(ic)];
    const auto& [rb, rc] = rest_local_[e];
    Eigen::Matrix<double, 6, 1> displacement;
    out.to_world = Mat3::Identity();
    {
        // TriangularFEMForceField small: accumulateForceSmall / computeDisplacementSmall, world
        // x, y of the edges
        const Vec3 db = pb - pa;
        const Vec3 dc = pc - pa;
        displacement << 0, 0, rb.x() - db.x(), rb.y() - db.y(), rc.x() - dc.x(), rc.y() - dc.y();
        if (!strain_displacement_global(out.j, db, dc)) return false;
    }
    const Vec3 strain = out.j.transpose() * displacement;  // (εxx, εyy, γxy)
    const Vec3 stress = material_[e] * strain;             // area-weighted σ (N/m)
    const Eigen::Matrix<double, 6, 1> nodal = out.j * stress;
    for (std::size_t k = 0; k < 3; ++k) {
        const auto i = static_cast<Eigen::Index>(2 * k);
        out.terms[k] = out.to_world * Vec3(nodal[i], nodal[i + 1], 0);
    }
    out.energy = 0.5 * strain.dot(stress);
    return true;
}

void TriangularFEMForceField::add_force_in_order(std::span<Vec3> f, std::span<const Vec3> x) {
    energy_ = 0.0;
    ElementForce element;
    for (std::size_t e = 0; e < triangles_.size(); ++e) {
        if (!element_terms(e, x, element)) break;
        for (std::size_t k = 0; k < 3; ++k) f[static_cast<std::size_t>(triangles_[e][k])] += element.terms[k];
        j_[e] = element.j;
        rotation_[e] = element.to_world;
        energy_ += element.energy;
    }
}

void TriangularFEMForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3>) {
    blocks_current_ = false;  // new frames and J
    // each triangle f_k += its term, J and frame kept for the product, energy Σ ½ ε·σ in order;
    // SOFA logs a null determinant and stops the pass (accumulateForceLarge's catch: break): the
    // triangles after it keep their J and frame and add nothing
    const std::size_t count = triangles_.size();
    if (!detail::OrderedScatter::worth_threads(count)) {
        add_force_in_order(f, x);
        return;
    }
    // On TBB's threads, as if no triangle were degenerate: J and frames into the next buffers, the
    // terms in element order (detail::force_in_order). A degenerate triangle found: f as it was,
    // and the loop above on one thread.
    force_before_.assign(f.begin(), f.end());
    next_j_.resize(count);
    next_rotation_.resize(count);
    std::atomic<bool> degenerate{false};
    const double energy = detail::force_in_order</*Add=*/true>(
        scatter_, std::span<const Triangle>(triangles_), f, 1, energies_,
        [&](std::size_t first, std::size_t end, const auto& deferred, double* energies) {
            double total = 0.0;
            ElementForce element;
            for (std::size_t e = first; e < end; ++e) {
                if (!element_terms(e, x, element)) {
                    degenerate.store(true, std::memory_order_relaxed);
                    return 0.0;
                }
                detail::store_or_apply(deferred, e, element.terms, [&](std::size_t k, const Vec3& term) {
                    f[static_cast<std::size_t>(triangles_[e][k])] += term;
                });
                next_j_[e] = element.j;
                next_rotation_[e] = element.to_world;
                if (energies != nullptr) energies[e] = element.energy;
                else total += element.energy;
            }
            return total;
        });
    if (degenerate.load()) {
        std::copy(force_before_.begin(), force_before_.end(), f.begin());
        add_force_in_order(f, x);
        return;
    }
    j_.swap(next_j_);
    rotation_.swap(next_rotation_);
    energy_ = energy;
}

Eigen::Matrix<double, 6, 6> TriangularFEMForceField::local_stiffness(std::size_t e) const {
    return -(j_[e] * material_[e] * j_[e].transpose());
}

template <class Deferred>
void TriangularFEMForceField::dforce_range_sofa_order(std::size_t first, std::size_t end, std::span<Vec3> df,
                                                      std::span<const Vec3> dx, double k_factor,
                                                      const Deferred& deferred) const {
    // TriangleFEMForceField::applyStiffnessSmall (h = 1): world x, y of dx; df += (−F_x, −F_y, 0)·k
    // (method large: detail::triangle_fem_large_dforce)
    for (std::size_t e = first; e < end; ++e) {
        triangle_fem_sofa::Displacement world_dx;
        for (std::size_t k = 0; k < 3; ++k) {
            const Vec3& d = dx[static_cast<std::size_t>(triangles_[e][k])];
            world_dx[static_cast<Eigen::Index>(2 * k)] = d[0];
            world_dx[static_cast<Eigen::Index>(2 * k + 1)] = d[1];
        }
        const triangle_fem_sofa::Displacement nodal =
            triangle_fem_sofa::stiffness_forces(false, j_[e], material_[e], world_dx);
        std::array<Vec3, 3> terms;
        for (std::size_t k = 0; k < 3; ++k) {
            const auto i = static_cast<Eigen::Index>(2 * k);
            terms[k] = sofa_vec::scaled(Vec3(-nodal[i], -nodal[i + 1], 0.0), k_factor);
        }
        detail::store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) {
            df[static_cast<std::size_t>(triangles_[e][k])] += term;
        });
    }
}

template <class Deferred>
void TriangularFEMForceField::dforce_range(std::size_t first, std::size_t end, std::span<Vec3> df,
                                           std::span<const Vec3> dx, double k_factor, const Deferred& deferred) const {
    // applyStiffnessLarge / applyStiffnessSmall: dx in the element frame, local x, y only
    for (std::size_t e = first; e < end; ++e) {
        const Mat3& to_world = rotation_[e];
        const Mat3 to_local = to_world.transpose();
        Eigen::Matrix<double, 6, 1> local_dx;
        for (std::size_t k = 0; k < 3; ++k) {
            const Vec3 d = to_local * dx[static_cast<std::size_t>(triangles_[e][k])];
            local_dx[static_cast<Eigen::Index>(2 * k)] = d.x();
            local_dx[static_cast<Eigen::Index>(2 * k + 1)] = d.y();
        }
        const Vec3 stress = material_[e] * (j_[e].transpose() * local_dx);
        const Eigen::Matrix<double, 6, 1> nodal = j_[e] * stress;
        std::array<Vec3, 3> terms;
        for (std::size_t k = 0; k < 3; ++k) {
            const auto i = static_cast<Eigen::Index>(2 * k);
            terms[k] = (to_world * Vec3(-nodal[i], -nodal[i + 1], 0)) * k_factor;
        }
        detail::store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) {
            df[static_cast<std::size_t>(triangles_[e][k])] += term;
        });
    }
}

void TriangularFEMForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double) const {
    // on TBB's threads from OrderedScatter::kMinElements triangles, with the bits of one thread
    // (the force stays on one thread: SOFA's pass stops at a null determinant, and so the
    // elements after it keep their frames)
    const bool large_sofa_order = uses_sofa_order() && parameters_.method == FemMethod::Large;
    if (large_sofa_order && !blocks_current_) {
        detail::fill_triangle_fem_large_blocks(large_blocks_, triangles_, rotation_, j_, material_);
        blocks_current_ = true;
    }
    detail::scatter_in_order</*Add=*/true>(scatter_, std::span<const Triangle>(triangles_), df, 1,
                                           [&](std::size_t first, std::size_t end, const auto& deferred) {
                                               if (large_sofa_order)
                                                   detail::triangle_fem_large_dforce(kernel_path_, large_blocks_, first,
                                                                                     end, df.data(), dx.data(),
                                                                                     k_factor, deferred);
                                               else if (uses_sofa_order())
                                                   dforce_range_sofa_order(first, end, df, dx, k_factor, deferred);
                                               else dforce_range(first, end, df, dx, k_factor, deferred);
                                           });
}

void TriangularFEMForceField::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    // buildStiffnessMatrix: −R [J Dₐ Jᵀ]_xy Rᵀ per 3×3 vertex block (R = rotation_, columns = axes)
    for (std::size_t e = 0; e < triangles_.size(); ++e) {
        const Eigen::Matrix<double, 6, 6> k = local_stiffness(e);
        const Mat3& r = rotation_[e];
        for (std::size_t a = 0; a < 3; ++a)
            for (std::size_t b = 0; b < 3; ++b) {
                Mat3 local = Mat3::Zero();
                local.topLeftCorner<2, 2>() =
                    k.block<2, 2>(static_cast<Eigen::Index>(2 * a), static_cast<Eigen::Index>(2 * b));
                const Mat3 blk = factor * r * local * r.transpose();
                const Index ra = offset + 3 * triangles_[e][a];
                const Index cb = offset + 3 * triangles_[e][b];
                for (Index i = 0; i < 3; ++i)
                    for (Index j = 0; j < 3; ++j) t.emplace_back(ra + i, cb + j, blk(i, j));
            }
    }
}

void TriangularFEMForceField::set_kernel_path(KernelPath path) {
    kernel_path_ = checked_kernel_path(path, "TriangularFEMForceField", /*has_avx512=*/false);
}

}  // namespace penalty
