#include "penalty/mechanics/hexahedral_fem.hpp"

#include "kernels/mechanics/hexahedron_stiffness.hpp"
#include "sofa_vector_ops.hpp"

#include <cmath>

namespace penalty {

namespace {

/// Signs (ξ, η, ζ) of the reference corners, SOFA's vertex order (HexahedralFEMForceField::_coef).
constexpr int kCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                               {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

/// ∫ over [−1, 1]³ of ∂N_i/∂ξ_a · ∂N_j/∂ξ_b for the trilinear shape functions
/// N_i = ⅛ Π_c (1 + s_c^i ξ_c): s_a^i s_b^j / 64 · Π_c f_c with f_c = 2 when c is a or b (a linear
/// factor integrates to 2) and f_c = 2 + ⅔ s_c^i s_c^j otherwise.
double gradient_product_integral(int i, int j, int a, int b) {
    double value = kCorner[i][a] * kCorner[j][b] / 64.0;
    for (int c = 0; c < 3; ++c) value *= (c == a || c == b) ? 2.0 : 2.0 + (2.0 / 3.0) * kCorner[i][c] * kCorner[j][c];
    return value;
}

/// SOFA's HexahedralFEMForceField::integrateStiffness for the corner pair (i, j): the 3×3 block of
/// ∫ Bᵢᵀ D Bⱼ over the reference cube with J⁻¹ = diag(inv_j), its diagonal entries scaled by
/// (J⁻¹_aa)² throughout (see the header), each entry rounded to float as SOFA does.
Mat3 integrated_block(int i, int j, double lambda_2mu, double lambda, double mu, const Vec3& inv_j) {
    Mat3 k;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            double value;
            if (a == b) {
                value = lambda_2mu * gradient_product_integral(i, j, a, a);
                for (int c = 0; c < 3; ++c)
                    if (c != a) value += mu * gradient_product_integral(i, j, c, c);
                value *= inv_j[a] * inv_j[a];
            } else {
                value = (lambda * gradient_product_integral(i, j, a, b) + mu * gradient_product_integral(i, j, b, a)) *
                        inv_j[a] * inv_j[b];
            }
            k(a, b) = static_cast<double>(static_cast<float>(value));
        }
    return k;
}

/// SOFA's hexahedron volume for FEM and mass: the product of the lengths of the edges 0→1, 0→3, 0→4
/// (exact for rectangular boxes).
double box_volume(const std::array<Vec3, 8>& p) {
    return (p[1] - p[0]).norm() * (p[3] - p[0]).norm() * (p[4] - p[0]).norm();
}

}  // namespace

// ---- HexahedralFEMForceField ------------------------------------------------------------------
HexahedralFEMForceField::HexahedralFEMForceField(Vec3Object& state, const MeshTopology& topology, double young,
                                                 double poisson, FemMethod method)
    : HexahedronElementForceField(state, topology.hexahedra(), young, poisson, method, "HexahedralFEMForceField") {
    if (method == FemMethod::Small) throw_invalid_argument("HexahedralFEMForceField: method must be large or polar");
}

// HexahedralFEMForceField::computeElementStiffness on the world rest positions.
HexahedralFEMForceField::ElementMatrix HexahedralFEMForceField::compute_stiffness(const std::array<Vec3, 8>&,
                                                                                  const Eigen::Matrix<double, 6, 6>& d,
                                                                                  std::size_t e) const {
    std::array<Vec3, 8> p;
    for (std::size_t k = 0; k < 8; ++k) p[k] = state_->rest_position[static_cast<std::size_t>(elements_[e][k])];
    const Vec3 l = p[6] - p[0];
    if (!(l.array() != 0.0).all() || !l.allFinite())
        throw_invalid_argument(component_, ": hexahedron ", e, " has a diagonal 0→6 with a zero component (",
                               l.transpose(), "): SOFA's stiffness needs a box aligned with the axes");
    const Vec3 inv_j(2.0 / l.x(), 2.0 / l.y(), 2.0 / l.z());
    const double volume_factor = box_volume(p) / 8.0;
    ElementMatrix k = ElementMatrix::Zero();
    for (int i = 0; i < 8; ++i)
        for (int j = i; j < 8; ++j)
            k.block<3, 3>(3 * i, 3 * j) = volume_factor * integrated_block(i, j, d(0, 0), d(0, 1), d(3, 3), inv_j);
    // SOFA keeps the upper triangle and mirrors it
    for (int r = 0; r < 24; ++r)
        for (int c = r + 1; c < 24; ++c) k(c, r) = k(r, c);
    return k;
}

void HexahedralFEMForceField::init() {
    LinearElementForceField<8>::init();
    rotated_rest_.clear();
    if (method_ != FemMethod::Large) return;
    rotated_rest_.resize(elements_.size());
    for (std::size_t e = 0; e < elements_.size(); ++e) {
        std::array<Vec3, 8> p;
        for (std::size_t w = 0; w < 8; ++w) p[w] = state_->rest_position[std::size_t(elements_[e][w])];
        const Mat3 r0 = hexahedron_edge_frame(p);
        for (std::size_t w = 0; w < 8; ++w) rotated_rest_[e][w] = sofa_vec::times(r0, p[w]);
        rotation_[e] = r0;
    }
}

void HexahedralFEMForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) {
    if (method_ != FemMethod::Large) {
        LinearElementForceField<8>::add_force(f, x, v);
        return;
    }
    energy_ = 0.0;
    for (std::size_t e = 0; e < elements_.size(); ++e) {
        std::array<Vec3, 8> p;
        for (std::size_t w = 0; w < 8; ++w) p[w] = x[std::size_t(elements_[e][w])];
        const Mat3 r = hexahedron_edge_frame(p);  // R_0_2 (rows = the element's axes)
        rotation_[e] = r;
        const Mat3 to_world = r.transpose();  // SOFA's hexahedronInf.rotation
        Eigen::Matrix<double, 24, 1> d;
        for (std::size_t w = 0; w < 8; ++w) {
            const Vec3 deformed = sofa_vec::times(r, p[w]);
            for (std::size_t a = 0; a < 3; ++a)
                d[Eigen::Index(3 * w + a)] = rotated_rest_[e][w][Eigen::Index(a)] - deformed[Eigen::Index(a)];
        }
        const Eigen::Matrix<double, 24, 1> force = detail::hexahedron_stiffness_times(kernel_path_, ke_[e], d);
        for (std::size_t w = 0; w < 8; ++w) {
            const auto i = Eigen::Index(3 * w);
            f[std::size_t(elements_[e][w])] += sofa_vec::times(to_world, Vec3(force[i], force[i + 1], force[i + 2]));
        }
        energy_ += 0.5 * d.dot(force);
    }
}

void HexahedralFEMForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                         double b_factor) const {
    if (method_ != FemMethod::Large) {
        LinearElementForceField<8>::add_dforce(df, dx, k_factor, b_factor);
        return;
    }
    for (std::size_t e = 0; e < elements_.size(); ++e) {
        const Mat3& r = rotation_[e];  // R_0_2
        const Mat3 to_world = r.transpose();
        Eigen::Matrix<double, 24, 1> local;
        for (std::size_t w = 0; w < 8; ++w) {
            const Vec3 l = sofa_vec::scaled(sofa_vec::times(r, dx[std::size_t(elements_[e][w])]), k_factor);
            for (std::size_t a = 0; a < 3; ++a) local[Eigen::Index(3 * w + a)] = l[Eigen::Index(a)];
        }
        const Eigen::Matrix<double, 24, 1> force = detail::hexahedron_stiffness_times(kernel_path_, ke_[e], local);
        for (std::size_t w = 0; w < 8; ++w) {
            const auto i = Eigen::Index(3 * w);
            df[std::size_t(elements_[e][w])] -= sofa_vec::times(to_world, Vec3(force[i], force[i + 1], force[i + 2]));
        }
    }
}

Mat3 hexahedron_polar_frame(const std::array<Vec3, 8>& p) {
    Mat3 edges;
    edges.row(0) = ((p[1] - p[0] + p[2] - p[3] + p[5] - p[4] + p[6] - p[7]) * 0.25).transpose();
    edges.row(1) = ((p[3] - p[0] + p[2] - p[1] + p[7] - p[4] + p[6] - p[5]) * 0.25).transpose();
    edges.row(2) = ((p[4] - p[0] + p[5] - p[1] + p[7] - p[3] + p[6] - p[2]) * 0.25).transpose();
    return polar_rotation(edges);
}

Mat3 HexahedralFEMForceField::element_rotation(const std::array<Vec3, 8>& p) const {
    return method_ == FemMethod::Polar ? hexahedron_polar_frame(p) : hexahedron_edge_frame(p);
}

// ---- HexahedronElementMass ----------------------------------------------------------------------
HexahedronElementMass::HexahedronElementMass(Vec3Object& state, std::vector<Hexahedron> hexahedra, double density,
                                             bool lumped, const char* component, HexahedronMassFormula formula)
    : state_(&state),
      hexahedra_(std::move(hexahedra)),
      density_(density),
      lumped_(lumped),
      component_(component),
      formula_(formula) {
    if (!std::isfinite(density) || density <= 0)
        throw_invalid_argument(component, ": density must be finite and > 0, got ", density);
}

// HexahedralFEMForceFieldAndMass::computeElementMasses / computeParticleMasses / computeLumpedMasses
// (HexahedronFEMForceFieldAndMass::init and computeElementMasses: the same values).
void HexahedronElementMass::init() {
    const auto& x0 = state_->rest_position;
    if (!mass_factors_.empty() && mass_factors_.size() != hexahedra_.size())
        throw_invalid_argument(component_, ": ", mass_factors_.size(), " mass factors for ", hexahedra_.size(),
                               " hexahedra");
    if (rotated_rest_source_ != nullptr && rotated_rest_source_->rotated_rest_count() != hexahedra_.size())
        throw_invalid_argument(component_, ": its force field has ", rotated_rest_source_->rotated_rest_count(),
                               " initialized hexahedra, the mass ", hexahedra_.size());
    element_weights_.assign(hexahedra_.size(), 0.0);
    particle_masses_.assign(x0.size(), 0.0);
    lumped_masses_.assign(lumped_ ? x0.size() : 0, 0.0);
    // the reference integral of node i (SOFA's integrateVolume / integrateMass with |signs| = 1),
    // summed in SOFA's order: 8/27 but for its last bit
    constexpr double kNodeIntegral =
        1.0 / 72.0 + 1.0 / 72.0 + 1.0 / 216.0 + 1.0 / 24.0 + 1.0 / 8.0 + 1.0 / 72.0 + 1.0 / 24.0 + 1.0 / 24.0;
    for (std::size_t e = 0; e < hexahedra_.size(); ++e) {
        std::array<Vec3, 8> p;
        for (std::size_t k = 0; k < 8; ++k) {
            const PointId v = hexahedra_[e][k];
            if (v < 0 || static_cast<std::size_t>(v) >= x0.size())
                throw_invalid_argument(component_, ": hexahedron ", e, " uses vertex ", v, " out of range (", x0.size(),
                                       " DOFs)");
            p[k] = x0[static_cast<std::size_t>(v)];
        }
        const double factor = mass_factors_.empty() ? 1.0 : mass_factors_[e];
        const double volume = box_volume(p);
        const double element_mass = volume * factor * density_;  // (particle masses: the rest positions)
        const double matrix_volume =
            rotated_rest_source_ != nullptr ? box_volume(rotated_rest_source_->rotated_rest(e)) : volume;
        // HexahedronFEMForceFieldAndMass::computeElementMass: V·(∫·ρ), then times c;
        // HexahedralFEMForceFieldAndMass's: (V·ρ)·∫
        element_weights_[e] = formula_ == HexahedronMassFormula::hexahedron
                                  ? (matrix_volume * (kNodeIntegral * density_)) * factor
                                  : (matrix_volume * density_) * kNodeIntegral;
        for (const PointId v : hexahedra_[e]) {
            particle_masses_[static_cast<std::size_t>(v)] += element_mass * 0.125;
            // the row sum, entry by entry (8 blocks) into the running sum, as SOFA's
            if (lumped_)
                for (int block = 0; block < 8; ++block)
                    lumped_masses_[static_cast<std::size_t>(v)] += element_weights_[e];
        }
    }
}

void HexahedronElementMass::multiply_add(std::span<Vec3> y, std::span<const Vec3> x, double factor) const {
    if (lumped_) {
        for (std::size_t i = 0; i < lumped_masses_.size(); ++i) y[i] += (x[i] * lumped_masses_[i]) * factor;
        return;
    }
    // M^e x_e = Σ_k w_e·x_k on each of its 8 vertices, summed as SOFA's 24×24 product (addMDx)
    for (std::size_t e = 0; e < hexahedra_.size(); ++e) {
        const double w = element_weights_[e];
        Vec3 sum = Vec3::Zero();
        for (const PointId v : hexahedra_[e]) sum += x[static_cast<std::size_t>(v)] * w;
        const Vec3 f = sum * factor;
        for (const PointId v : hexahedra_[e]) y[static_cast<std::size_t>(v)] += f;
    }
}

void HexahedronElementMass::add_gravity_force(const Vec3& gravity) {
    for (std::size_t i = 0; i < particle_masses_.size(); ++i) state_->force[i] += gravity * particle_masses_[i];
}

void HexahedronElementMass::add_mdx(double factor) { multiply_add(state_->df, state_->dx, factor); }

void HexahedronElementMass::apply_inverse(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) const {
    throw_invalid_argument(component_,
                           ": no inverse mass (SOFA's accFromF is not implemented): use an implicit solver");
}

void HexahedronElementMass::add_mass_triplets(TripletList& t, Index offset, double factor) const {
    if (lumped_) {
        for (std::size_t i = 0; i < lumped_masses_.size(); ++i)
            for (Index a = 0; a < 3; ++a)
                t.emplace_back(offset + 3 * static_cast<Index>(i) + a, offset + 3 * static_cast<Index>(i) + a,
                               lumped_masses_[i] * factor);
        return;
    }
    for (std::size_t e = 0; e < hexahedra_.size(); ++e)
        for (const PointId r : hexahedra_[e])
            for (const PointId c : hexahedra_[e])
                for (Index a = 0; a < 3; ++a)
                    t.emplace_back(offset + 3 * Index{r} + a, offset + 3 * Index{c} + a, element_weights_[e] * factor);
}

double HexahedronElementMass::kinetic_energy() const {
    std::vector<Vec3> mv(state_->velocity.size(), Vec3::Zero());
    multiply_add(mv, state_->velocity, 1.0);
    double energy = 0.0;
    for (std::size_t i = 0; i < mv.size(); ++i) energy += 0.5 * mv[i].dot(state_->velocity[i]);
    return energy;
}

double HexahedronElementMass::gravity_potential_energy(const Vec3& gravity) const {
    double energy = 0.0;
    for (std::size_t i = 0; i < particle_masses_.size(); ++i)
        energy -= particle_masses_[i] * gravity.dot(state_->position[i]);
    return energy;
}

double HexahedronElementMass::total_mass() const {
    double total = 0.0;
    for (const double m : particle_masses_) total += m;
    return total;
}

}  // namespace penalty
