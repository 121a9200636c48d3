#include "penalty/mechanics/nonuniform_hexahedron_fem.hpp"

#include "sofa_vector_ops.hpp"

#include <cmath>

namespace penalty {

namespace {

/// NonUniformHexahedronFEMForceFieldAndMass::FINE_TO_COARSE: weight of coarse corner c in fine
/// corner f of child `child` (children and corners numbered by their bits x, y, z).
double fine_to_coarse(int child, int f, int c) {
    // corner f of child `child`, in half-cells of the coarse cell, then the trilinear weight of c
    const int hx = (child & 1) + (f & 1), hy = ((child >> 1) & 1) + ((f >> 1) & 1),
              hz = ((child >> 2) & 1) + ((f >> 2) & 1);
    const auto weight = [](int half, int bit) { return bit ? half * 0.5 : 1.0 - half * 0.5; };
    return weight(hx, c & 1) * weight(hy, (c >> 1) & 1) * weight(hz, (c >> 2) & 1);
}

/// The grid corner order of SOFA's hexahedra (x, y, z bits → vertex): 0 1 3 2 4 5 7 6.
constexpr int kVertexOfBits[8] = {0, 1, 3, 2, 4, 5, 7, 6};

/// T(child)[fine vertex][coarse vertex] in the hexahedra's vertex order (SOFA's table is written
/// in that order: FINE_TO_COARSE[i][j] gives fine vertex j of child i from the coarse vertices).
struct FineToCoarse {
    double t[8][8][8];
    FineToCoarse() {
        for (int child_bits = 0; child_bits < 8; ++child_bits)
            for (int f_bits = 0; f_bits < 8; ++f_bits)
                for (int c_bits = 0; c_bits < 8; ++c_bits)
                    t[child_bits][kVertexOfBits[f_bits]][kVertexOfBits[c_bits]] =
                        fine_to_coarse(child_bits, f_bits, c_bits);
    }
};

/// addFineToCoarse: coarse += Tᵀ·fine·T with SOFA's sums (A = fine·T row by row, then coarse(i, j)
/// += T(k, i)·A(k, j) for k in order), the terms SOFA multiplies by an exact 0 left out.
void add_fine_to_coarse(HexahedronMatrix& coarse, const HexahedronMatrix& fine, const double (&t)[8][8]) {
    HexahedronMatrix a;
    for (int i = 0; i < 24; ++i)
        for (int j = 0; j < 24; ++j) {
            double s = 0.0;
            bool first = true;
            for (int k = j % 3; k < 24; k += 3) {
                const double w = t[k / 3][j / 3];
                if (w == 0.0) continue;
                s = first ? fine(i, k) * w : s + fine(i, k) * w;
                first = false;
            }
            a(i, j) = s;
        }
    for (int i = 0; i < 24; ++i)
        for (int j = 0; j < 24; ++j)
            for (int k = i % 3; k < 24; k += 3) {
                const double w = t[k / 3][i / 3];
                if (w != 0.0) coarse(i, j) += w * a(k, j);
            }
}

/// HexahedronFEMForceField's element stiffness of one cell (its corners `p`) times `coefficient`.
HexahedronMatrix cell_stiffness(const std::array<Vec3, 8>& p, double young, double poisson, double coefficient) {
    Vec3Object cell;
    cell.position.assign(p.begin(), p.end());
    cell.init();
    MeshTopology topology;
    topology.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}});
    HexahedronFEMForceField ff(cell, topology, young, poisson, FemMethod::Large);
    ff.set_stiffness_factors({coefficient});
    ff.init();
    return ff.element_stiffness()[0];
}

/// HexahedronFEMForceFieldAndMass::computeElementMass: every 3×3 block m·I with
/// m = V·(Σ of SOFA's integrateMass terms)·ρ, times `coefficient`.
HexahedronMatrix cell_mass(const std::array<Vec3, 8>& p, double density, double coefficient) {
    const auto norm = [](const Vec3& v) { return std::sqrt(sofa_vec::dot3(v, v)); };
    const double volume = norm(p[1] - p[0]) * norm(p[3] - p[0]) * norm(p[4] - p[0]);
    const double integral =
        (1.0 / 72.0 + 1.0 / 72.0 + 1.0 / 216.0 + 1.0 / 24.0 + 1.0 / 8.0 + 1.0 / 72.0 + 1.0 / 24.0 + 1.0 / 24.0) *
        density;
    const double m = volume * integral;
    HexahedronMatrix mass = HexahedronMatrix::Zero();
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
            for (int a = 0; a < 3; ++a) mass(3 * i + a, 3 * j + a) = m;
    return mass * coefficient;
}

struct Condenser {
    double young, poisson, density;
    bool fill_weighted;
    Vec3 scale;
    int levels;
    FineToCoarse table;

    /// computeMechanicalMatricesByCondensation(K, M, element, level) on `grid` (level `level`).
    void condense(const SparseGridTopology& grid, std::size_t element, int level, HexahedronMatrix& k,
                  HexahedronMatrix& m) const {
        if (level == levels) {  // computeClassicalMechanicalMatrices
            const Hexahedron& h = grid.hexahedra()[element];
            std::array<Vec3, 8> p;
            for (std::size_t v = 0; v < 8; ++v) p[v] = grid.points()[std::size_t(h[v])].cwiseProduct(scale);
            const double c = grid.coefficients(fill_weighted)[element];
            k = cell_stiffness(p, young, poisson, c);
            m = cell_mass(p, density, c);
            return;
        }
        k.setZero();
        m.setZero();
        const std::array<Index, 8>& children = grid.children()[element];
        for (int i = 0; i < 8; ++i) {
            if (children[std::size_t(i)] < 0) continue;
            HexahedronMatrix fine_k, fine_m;
            condense(*grid.finer(), std::size_t(children[std::size_t(i)]), level + 1, fine_k, fine_m);
            add_fine_to_coarse(k, fine_k, table.t[i]);
            add_fine_to_coarse(m, fine_m, table.t[i]);
        }
    }
};

}  // namespace

CondensedHexahedra condense_hexahedra(const SparseGridTopology& grid, int levels, double young_modulus,
                                      double poisson_ratio, double density, bool fill_weighted, const Vec3& scale) {
    if (levels < 1 || levels > grid.finer_levels())
        throw_invalid_argument("NonUniformHexahedronFEMForceFieldAndMass: ", levels,
                               " virtual finer levels asked, the grid has ", grid.finer_levels());
    Condenser c{young_modulus, poisson_ratio, density, fill_weighted, scale, levels, {}};
    CondensedHexahedra out;
    out.stiffness.resize(grid.hexahedra().size());
    out.mass.resize(grid.hexahedra().size());
    for (std::size_t e = 0; e < grid.hexahedra().size(); ++e) c.condense(grid, e, 0, out.stiffness[e], out.mass[e]);
    return out;
}

// ---- mass -------------------------------------------------------------------------------------
HexahedronMatrixMass::HexahedronMatrixMass(Vec3Object& state, std::vector<Hexahedron> hexahedra,
                                           std::vector<HexahedronMatrix> element_mass,
                                           std::vector<double> mass_coefficients, Parameters p)
    : state_(&state),
      hexahedra_(std::move(hexahedra)),
      element_mass_(std::move(element_mass)),
      mass_coefficients_(std::move(mass_coefficients)),
      p_(p) {}

// NonUniformHexahedronFEMForceFieldAndMass::init's mass part.
void HexahedronMatrixMass::init() {
    const std::vector<Vec3>& x0 = state_->position;  // SOFA's d_initialPoints
    if (element_mass_.size() != hexahedra_.size() || mass_coefficients_.size() != hexahedra_.size())
        throw_invalid_argument("NonUniformHexahedronFEMForceFieldAndMass: ", element_mass_.size(),
                               " mass matrices and ", mass_coefficients_.size(), " coefficients for ",
                               hexahedra_.size(), " hexahedra");
    particle_masses_.assign(x0.size(), 0.0);
    lumped_.clear();
    if (!p_.use_mass) {
        const double m = p_.total_mass / double(hexahedra_.size());
        std::fill(particle_masses_.begin(), particle_masses_.end(), m);
        return;
    }
    const auto norm = [](const Vec3& v) { return std::sqrt(sofa_vec::dot3(v, v)); };
    for (std::size_t e = 0; e < hexahedra_.size(); ++e) {
        std::array<Vec3, 8> p;
        for (std::size_t k = 0; k < 8; ++k) {
            const PointId v = hexahedra_[e][k];
            if (v < 0 || std::size_t(v) >= x0.size())
                throw_invalid_argument("NonUniformHexahedronFEMForceFieldAndMass: hexahedron ", e, " uses vertex ", v,
                                       " out of range (", x0.size(), " DOFs)");
            p[k] = x0[std::size_t(v)];
        }
        double volume = norm(p[1] - p[0]) * norm(p[3] - p[0]) * norm(p[4] - p[0]);
        volume *= mass_coefficients_[e];
        const double m = (volume * p_.density) / 8.0;
        for (const PointId v : hexahedra_[e]) particle_masses_[std::size_t(v)] += m;
    }
    if (p_.lumped) {
        lumped_.assign(x0.size(), Vec3::Zero());
        for (std::size_t e = 0; e < hexahedra_.size(); ++e)
            for (int w = 0; w < 8; ++w)
                for (int j = 0; j < 24; ++j)
                    for (int a = 0; a < 3; ++a)
                        lumped_[std::size_t(hexahedra_[e][std::size_t(w)])][a] += element_mass_[e](3 * w + a, j);
        for (Vec3& l : lumped_) l = l.cwiseAbs();
    }
}

void HexahedronMatrixMass::add_gravity_force(const Vec3& gravity) {
    for (std::size_t i = 0; i < particle_masses_.size(); ++i) state_->force[i] += gravity * particle_masses_[i];
}

// HexahedronFEMForceFieldAndMass::addMDx (or NonUniform's diagonal one without useMass).
void HexahedronMatrixMass::multiply_add(std::span<Vec3> y, std::span<const Vec3> x, double factor) const {
    if (!p_.use_mass) {
        for (std::size_t i = 0; i < x.size(); ++i) y[i] += (x[i] * particle_masses_[i]) * factor;
        return;
    }
    if (p_.lumped) {
        for (std::size_t i = 0; i < lumped_.size(); ++i)
            for (int a = 0; a < 3; ++a) y[i][a] += lumped_[i][a] * x[i][a] * factor;
        return;
    }
    for (std::size_t e = 0; e < hexahedra_.size(); ++e) {
        Eigen::Matrix<double, 24, 1> dx;
        for (std::size_t k = 0; k < 8; ++k) dx.segment<3>(Eigen::Index(3 * k)) = x[std::size_t(hexahedra_[e][k])];
        const HexahedronMatrix& m = element_mass_[e];
        for (int w = 0; w < 8; ++w) {
            Vec3 f;
            for (int a = 0; a < 3; ++a) {
                const int r = 3 * w + a;
                double s = m(r, 0) * dx[0];
                for (int j = 1; j < 24; ++j) s += m(r, j) * dx[j];
                f[a] = s;
            }
            y[std::size_t(hexahedra_[e][std::size_t(w)])] += f * factor;
        }
    }
}

void HexahedronMatrixMass::add_mdx(double factor) { multiply_add(state_->df, state_->dx, factor); }

void HexahedronMatrixMass::apply_inverse(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) const {
    throw_invalid_argument(
        "NonUniformHexahedronFEMForceFieldAndMass: no inverse mass (SOFA's accFromF is not implemented): "
        "use an implicit solver");
}

void HexahedronMatrixMass::add_mass_triplets(TripletList& t, Index offset, double factor) const {
    if (!p_.use_mass || p_.lumped) {
        for (std::size_t i = 0; i < particle_masses_.size(); ++i)
            for (Index a = 0; a < 3; ++a)
                t.emplace_back(offset + 3 * Index(i) + a, offset + 3 * Index(i) + a,
                               (p_.use_mass ? lumped_[i][a] : particle_masses_[i]) * factor);
        return;
    }
    for (std::size_t e = 0; e < hexahedra_.size(); ++e)
        for (int r = 0; r < 24; ++r)
            for (int c = 0; c < 24; ++c)
                t.emplace_back(offset + 3 * Index(hexahedra_[e][std::size_t(r / 3)]) + r % 3,
                               offset + 3 * Index(hexahedra_[e][std::size_t(c / 3)]) + c % 3,
                               element_mass_[e](r, c) * factor);
}

double HexahedronMatrixMass::kinetic_energy() const {
    std::vector<Vec3> mv(state_->velocity.size(), Vec3::Zero());
    multiply_add(mv, state_->velocity, 1.0);
    double energy = 0.0;
    for (std::size_t i = 0; i < mv.size(); ++i) energy += 0.5 * mv[i].dot(state_->velocity[i]);
    return energy;
}

double HexahedronMatrixMass::gravity_potential_energy(const Vec3& gravity) const {
    double energy = 0.0;
    for (std::size_t i = 0; i < particle_masses_.size(); ++i)
        energy -= particle_masses_[i] * gravity.dot(state_->position[i]);
    return energy;
}

double HexahedronMatrixMass::total_mass() const {
    double total = 0.0;
    for (const double m : particle_masses_) total += m;
    return total;
}

}  // namespace penalty
