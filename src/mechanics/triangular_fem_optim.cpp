#include "penalty/mechanics/triangular_fem_optim.hpp"

#include "sofa_vector_ops.hpp"

#include <array>

namespace penalty {

using sofa_vec::cross;
using sofa_vec::dot3;
using sofa_vec::scaled;

namespace {

/// TriangularFEMForceFieldOptim::computeTriangleRotation: X = ab, Y = (ab × ac) × ab, normalised.
std::pair<Vec3, Vec3> triangle_frame(const Vec3& ab, const Vec3& ac) {
    const Vec3 n = cross(ab, ac);
    return {sofa_vec::normalized(ab), sofa_vec::normalized(cross(n, ab))};
}

using sofa_vec::in_element;

}  // namespace

std::pair<double, double> TriangularFEMForceFieldOptim::mu_gamma(std::size_t i) const {
    const double e = in_element(p_.young_modulus, i), nu = in_element(p_.poisson_ratio, i);
    return {e / (1 + nu), (e * nu) / (1 - nu * nu)};  // computeMuGamma
}

void TriangularFEMForceFieldOptim::init() {
    const auto& triangles = topology_->triangles();
    const std::vector<Vec3>& x0 = state_->rest_position;
    const std::vector<Vec3>& x = state_->position;
    rest_.assign(triangles.size(), RestTriangle{});
    scatter_.clear();  // made again for these triangles at the next force on threads
    frame_.assign(triangles.size(), Frame{});
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const Triangle& t = triangles[i];
        for (PointId v : t)
            if (v < 0 || static_cast<std::size_t>(v) >= x0.size())
                throw_invalid_argument("TriangularFEMForceFieldOptim: triangle ", i, " uses point ", v,
                                       ", out of range (", x0.size(), " points)");
        const auto at = [&](const std::vector<Vec3>& p, int k) -> const Vec3& {
            return p[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])];
        };
        Vec3 ab = at(x0, 1) - at(x0, 0), ac = at(x0, 2) - at(x0, 0);
        if (p_.rest_scale) {
            ab = scaled(ab, *p_.rest_scale);
            ac = scaled(ac, *p_.rest_scale);
        }
        const auto [fx, fy] = triangle_frame(ab, ac);
        RestTriangle& r = rest_[i];
        r.bx = dot3(fx, ab);
        r.cx = dot3(fx, ac);
        r.cy = dot3(fy, ac);
        if (!(r.bx * r.cy != 0))
            throw_invalid_argument("TriangularFEMForceFieldOptim: triangle ", i, " is degenerate at rest");
        r.ss_factor = 0.5 / (r.bx * r.cy);
        const auto [cx, cy] = triangle_frame(at(x, 1) - at(x, 0), at(x, 2) - at(x, 0));
        frame_[i] = {cx, cy};
    }
}

// TriangularFEMForceFieldOptim::addForce.
void TriangularFEMForceFieldOptim::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> /*v*/) {
    const auto& triangles = topology_->triangles();
    PENALTY_DEMAND(rest_.size() == triangles.size() && frame_.size() == triangles.size());
    energy_ = detail::force_in_order</*Add=*/true>(
        scatter_, std::span<const Triangle>(triangles), f, 1, element_energies_,
        [&](std::size_t first, std::size_t end, const auto& deferred, double* energies) {
            double total = 0.0;
            for (std::size_t i = first; i < end; ++i) {
                const Triangle& t = triangles[i];
                const RestTriangle& r = rest_[i];
                const Vec3& a = x[static_cast<std::size_t>(t[0])];
                const Vec3 ab = x[static_cast<std::size_t>(t[1])] - a, ac = x[static_cast<std::size_t>(t[2])] - a;
                const auto [mu, gamma] = mu_gamma(i);
                const auto [fx, fy] = triangle_frame(ab, ac);
                frame_[i] = {fx, fy};
                const double dbx = r.bx - dot3(fx, ab), dcx = r.cx - dot3(fx, ac), dcy = r.cy - dot3(fy, ac);
                const Vec3 strain(r.cy * dbx, r.bx * dcy, r.bx * dcx - r.cx * dbx);
                const double gamma_xy = gamma * (strain[0] + strain[1]);
                Vec3 stress(mu * strain[0] + gamma_xy, mu * strain[1] + gamma_xy, 0.5 * mu * strain[2]);
                stress = scaled(stress, r.ss_factor);
                const Vec3 fb =
                    scaled(fx, r.cy * stress[0] - r.cx * stress[2]) + scaled(fy, r.cy * stress[2] - r.cx * stress[1]);
                const Vec3 fc = scaled(fx, r.bx * stress[2]) + scaled(fy, r.bx * stress[1]);
                const std::array<Vec3, 3> terms{-fb - fc, fb, fc};
                detail::store_or_apply(deferred, i, terms, [&](std::size_t k, const Vec3& term) {
                    f[static_cast<std::size_t>(t[k])] += term;
                });
                const double energy = 0.5 * dot3(stress, strain);
                if (energies) energies[i] = energy;
                else total += energy;
            }
            return total;
        });
}

// TriangularFEMForceFieldOptim::addDForce.
void TriangularFEMForceFieldOptim::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                              double /*b_factor*/) const {
    const auto& triangles = topology_->triangles();
    PENALTY_DEMAND(rest_.size() == triangles.size() && frame_.size() == triangles.size());
    detail::scatter_in_order</*Add=*/false>(
        scatter_, std::span<const Triangle>(triangles), df, 1,
        [&](std::size_t first, std::size_t end, const auto& deferred) {
            for (std::size_t i = first; i < end; ++i) {
                const Triangle& t = triangles[i];
                const RestTriangle& r = rest_[i];
                const Frame& fr = frame_[i];
                const auto [mu, gamma] = mu_gamma(i);
                const Vec3& da = dx[static_cast<std::size_t>(t[0])];
                const Vec3 dab = dx[static_cast<std::size_t>(t[1])] - da, dac = dx[static_cast<std::size_t>(t[2])] - da;
                const double dbx = dot3(fr.x, dab), dby = dot3(fr.y, dab), dcx = dot3(fr.x, dac), dcy = dot3(fr.y, dac);
                const Vec3 dstrain(r.cy * dbx, r.bx * dcy - r.cx * dby, r.bx * dcx - r.cx * dbx + r.cy * dby);
                const double gamma_xy = gamma * (dstrain[0] + dstrain[1]);
                Vec3 dstress(mu * dstrain[0] + gamma_xy, mu * dstrain[1] + gamma_xy, 0.5 * mu * dstrain[2]);
                dstress = scaled(dstress, r.ss_factor * k_factor);
                const Vec3 dfb = scaled(fr.x, r.cy * dstress[0] - r.cx * dstress[2]) +
                                 scaled(fr.y, r.cy * dstress[2] - r.cx * dstress[1]);
                const Vec3 dfc = scaled(fr.x, r.bx * dstress[2]) + scaled(fr.y, r.bx * dstress[1]);
                const std::array<Vec3, 3> terms{-dfb - dfc, dfb, dfc};
                detail::store_or_apply(deferred, i, terms, [&](std::size_t k, const Vec3& term) {
                    df[static_cast<std::size_t>(t[k])] -= term;
                });
            }
        });
}

// The matrix of add_dforce (TriangularFEMForceFieldOptim::buildStiffnessMatrix's blocks): per
// triangle the 2D map from (b − a, c − a) in the frame to the forces, lifted by the frame.
void TriangularFEMForceFieldOptim::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    const auto& triangles = topology_->triangles();
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const RestTriangle& r = rest_[i];
        const Frame& fr = frame_[i];
        const auto [mu, gamma] = mu_gamma(i);
        // local (dbx, dby, dcx, dcy) → local forces on b and c (x, y each), then −K
        Eigen::Matrix<double, 3, 4> strain_of;  // dstrain = S · (dbx, dby, dcx, dcy)
        strain_of << r.cy, 0, 0, 0, 0, -r.cx, 0, r.bx, -r.cx, r.cy, r.bx, 0;
        Eigen::Matrix3d d;  // dstress = ss · D · dstrain
        d << mu + gamma, gamma, 0, gamma, mu + gamma, 0, 0, 0, 0.5 * mu;
        Eigen::Matrix<double, 4, 3> force_of;  // (fbx, fby, fcx, fcy) = F · dstress
        force_of << r.cy, 0, -r.cx, 0, -r.cx, r.cy, 0, 0, r.bx, 0, r.bx, 0;
        const Eigen::Matrix4d local = r.ss_factor * force_of * d * strain_of;  // df_bc = −local · d_bc
        Eigen::Matrix<double, 2, 3> frame;
        frame.row(0) = fr.x.transpose();
        frame.row(1) = fr.y.transpose();
        // world 3×3 blocks for b, c against b, c: −Fᵀ L_ij F; a = −(b + c) on both sides
        Eigen::Matrix<double, 9, 9> k = Eigen::Matrix<double, 9, 9>::Zero();
        for (int p = 0; p < 2; ++p)
            for (int q = 0; q < 2; ++q) {
                const Mat3 block = -(frame.transpose() * local.block<2, 2>(2 * p, 2 * q) * frame);
                k.block<3, 3>(3 * (p + 1), 3 * (q + 1)) = block;
                k.block<3, 3>(0, 3 * (q + 1)) -= block;
                k.block<3, 3>(3 * (p + 1), 0) -= block;
                k.block<3, 3>(0, 0) += block;
            }
        const Triangle& tri = triangles[i];
        for (int p = 0; p < 3; ++p)
            for (int q = 0; q < 3; ++q)
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b)
                        t.emplace_back(offset + 3 * tri[static_cast<std::size_t>(p)] + a,
                                       offset + 3 * tri[static_cast<std::size_t>(q)] + b,
                                       factor * k(3 * p + a, 3 * q + b));
    }
}

}  // namespace penalty
