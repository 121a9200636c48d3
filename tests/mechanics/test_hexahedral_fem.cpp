// HexahedralFEMForceField (SOFA's box stiffness, methods large and polar) and the element mass of
// the …FEMForceFieldAndMass components.
#include "penalty/mechanics/hexahedral_fem.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <random>

namespace penalty {
namespace {

/// The 8 corners of the unit cube [0, side]³ in SOFA's vertex order, one hexahedron.
MeshTopology cube_topology(Vec3Object& s, double side) {
    RegularGridTopology g({2, 2, 2}, Vec3(0, 0, 0), Vec3(side, side, side));
    s.position = g.points();
    s.init();
    return g.mesh();
}

TEST(HexahedralFEM, CubeStiffnessIsTheExactTrilinearStiffness) {
    // On a cube SOFA's closed form is the exact integral, as HexahedronFEMForceField's 2×2×2 Gauss
    // rule; each entry was rounded to float: agreement to float precision.
    for (const double side : {1.0, 0.25}) {
        Vec3Object s;
        const MeshTopology topo = cube_topology(s, side);
        HexahedralFEMForceField box(s, topo, 1000.0, 0.3);
        HexahedronFEMForceField gauss(s, topo, 1000.0, 0.3);
        box.init();
        gauss.init();
        const auto& kb = box.element_stiffness().at(0);
        const auto& kg = gauss.element_stiffness().at(0);
        const double scale = kg.cwiseAbs().maxCoeff();
        EXPECT_GT(scale, 100.0 * side);
        EXPECT_LT((kb - kg).cwiseAbs().maxCoeff(), 1e-6 * scale) << "side " << side;
        EXPECT_EQ(kb, kb.transpose());
        // rigid translations are in the kernel
        for (int a = 0; a < 3; ++a) {
            Eigen::Matrix<double, 24, 1> t = Eigen::Matrix<double, 24, 1>::Zero();
            for (int k = 0; k < 8; ++k) t(3 * k + a) = 1.0;
            EXPECT_LT((kb * t).cwiseAbs().maxCoeff(), 1e-5 * scale);
        }
    }
}

TEST(HexahedralFEM, DiagonalEntriesScaleEveryTermByTheirOwnAxisAsSofa) {
    // A 2×1×1 box: J⁻¹ = diag(1, 2, 2), V/8 = 1/4. For node 0 with itself ∫g_c g_c = 2/9 on every
    // axis. SOFA's K_00(x, x) = [(λ+2μ)·2/9 + μ·(2/9 + 2/9)]·(J⁻¹_xx)²·V/8, the exact one
    // (HexahedronFEMForceField's) [(λ+2μ)·2/9 + μ·(4·2/9 + 4·2/9)]·V/8; the coupling entries
    // K(x, y) agree.
    RegularGridTopology g({2, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1));
    Vec3Object s;
    s.position = g.points();
    s.init();
    HexahedralFEMForceField box(s, g.mesh(), 1000.0, 0.3);
    HexahedronFEMForceField gauss(s, g.mesh(), 1000.0, 0.3);
    box.init();
    gauss.init();
    const Eigen::Matrix<double, 6, 6> d = isotropic_elasticity(1000.0, 0.3);
    const double l2m = d(0, 0), mu = d(3, 3);
    const double sofa = static_cast<double>(static_cast<float>(l2m * 2.0 / 9.0 + mu * 4.0 / 9.0)) * 0.25;
    const double exact = (l2m * 2.0 / 9.0 + mu * 16.0 / 9.0) * 0.25;
    const auto& kb = box.element_stiffness().at(0);
    const auto& kg = gauss.element_stiffness().at(0);
    EXPECT_DOUBLE_EQ(kb(0, 0), sofa);
    EXPECT_NEAR(kg(0, 0), exact, 1e-9 * exact);
    EXPECT_GT(exact - sofa, 0.1 * exact);  // the quirk is not small
    for (int r = 0; r < 24; ++r)
        for (int c = 0; c < 24; ++c)
            if (r % 3 != c % 3) {
                EXPECT_NEAR(kb(r, c), kg(r, c), 1e-6 * kg.cwiseAbs().maxCoeff()) << r << " " << c;
            }
}

TEST(HexahedralFEM, RefusesBoxesNotAlignedWithTheAxes) {
    Vec3Object s;
    const MeshTopology topo = cube_topology(s, 1.0);
    const Hexahedron& h = topo.hexahedra().at(0);
    s.rest_position[static_cast<std::size_t>(h[6])].x() =
        s.rest_position[static_cast<std::size_t>(h[0])].x();  // diagonal 0→6 without x
    HexahedralFEMForceField ff(s, topo, 1000.0, 0.3);
    EXPECT_THROW(ff.init(), std::invalid_argument);
}

/// Derivative check at a rigid motion of a 2×1×2 block of cubes (the corotational K leaves out the
/// rotation's derivative, as SOFA: exact at stress-free configurations only).
void check_derivatives(FemMethod method) {
    RegularGridTopology g({3, 2, 3}, Vec3(0, 0, 0), Vec3(1, 0.5, 1));
    Vec3Object s;
    s.position = g.points();
    s.init();
    HexahedralFEMForceField ff(s, g.mesh(), 500.0, 0.35, method);
    ff.init();
    const Mat3 r = Eigen::AngleAxisd(0.8, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
    const Vec3 t(0.3, -1, 2);
    for (std::size_t i = 0; i < s.position.size(); ++i) s.position[i] = r * s.rest_position[i] + t;
    const test::DerivativeTolerances tol{
        .dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt};
    const test::ForceFieldDerivatives d = test::check_force_field_derivatives(ff, s, tol);
    EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 10.0);
    EXPECT_TRUE(d.k_dforce.isApprox(d.k_dforce.transpose(), 1e-12));
    if (method != FemMethod::Large) {
        EXPECT_LT(d.force.cwiseAbs().maxCoeff(), 1e-10);  // a rigid motion is stress-free
        return;
    }
    // large, as SOFA's accumulateForceLarge: D = R₀x⁰ − R·x with absolute positions, so a
    // translation t leaves D = −R·t on every node (R₀ = I for these axis-aligned cubes, R = rᵀ),
    // and the float-rounded entries of SOFA's K do not quite annihilate it: f = r·K·(−rᵀt) per
    // element, small but not zero (SOFA's own residual force under a rigid motion)
    Eigen::VectorXd expected = Eigen::VectorXd::Zero(d.force.size());
    for (std::size_t e = 0; e < ff.hexahedra().size(); ++e) {
        Eigen::Matrix<double, 24, 1> displacement;
        for (int w = 0; w < 8; ++w) displacement.segment<3>(3 * w) = -(r.transpose() * t);
        const Eigen::Matrix<double, 24, 1> local = ff.element_stiffness()[e] * displacement;
        for (int w = 0; w < 8; ++w)
            expected.segment<3>(3 * ff.hexahedra()[e][std::size_t(w)]) += r * local.segment<3>(3 * w);
    }
    EXPECT_GT(expected.cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_LT((d.force - expected).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(HexahedralFEM, LargeStiffnessMatchesFiniteDifferences) { check_derivatives(FemMethod::Large); }

TEST(HexahedralFEM, PolarStiffnessMatchesFiniteDifferences) { check_derivatives(FemMethod::Polar); }

TEST(HexahedralFEM, ForcesRotateWithTheBody) {
    // A deformed block, rotated, gives the rotated forces (large and polar).
    for (const FemMethod method : {FemMethod::Large, FemMethod::Polar}) {
        RegularGridTopology g({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1));
        Vec3Object s;
        s.position = g.points();
        s.init();
        HexahedralFEMForceField ff(s, g.mesh(), 100, 0.3, method);
        ff.init();
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(-0.05, 0.05);
        std::vector<Vec3> deformed = s.rest_position;
        for (auto& p : deformed) p += Vec3(u(rng), u(rng), u(rng));
        s.position = deformed;
        ff.accumulate_force();
        const std::vector<Vec3> f1 = s.force;
        const Mat3 r = Eigen::AngleAxisd(1.1, Vec3(0.2, 1, -0.4).normalized()).toRotationMatrix();
        for (std::size_t i = 0; i < deformed.size(); ++i) s.position[i] = r * deformed[i];
        std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
        ff.accumulate_force();
        double fmax = 0;
        for (std::size_t i = 0; i < f1.size(); ++i) {
            EXPECT_LT((s.force[i] - r * f1[i]).norm(), 1e-10);
            fmax = std::max(fmax, f1[i].norm());
        }
        EXPECT_GT(fmax, 1e-2);
    }
}

TEST(HexahedralFEM, PolarAndLargeAgreeOnAStretch) {
    // A stretch along the axes leaves both frames at identity: the same forces.
    RegularGridTopology g({2, 2, 2}, Vec3(0, 0, 0), Vec3(1, 1, 1));
    Vec3Object s;
    s.position = g.points();
    s.init();
    HexahedralFEMForceField large(s, g.mesh(), 100, 0.3, FemMethod::Large);
    HexahedralFEMForceField polar(s, g.mesh(), 100, 0.3, FemMethod::Polar);
    large.init();
    polar.init();
    for (auto& p : s.position) p = Vec3(1.1 * p.x(), 0.95 * p.y(), p.z());
    large.accumulate_force();
    const std::vector<Vec3> f_large = s.force;
    std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
    polar.accumulate_force();
    for (std::size_t i = 0; i < f_large.size(); ++i) EXPECT_LT((s.force[i] - f_large[i]).norm(), 1e-9);
    EXPECT_GT(f_large[6].norm(), 1.0);
}

// ---- element mass ---------------------------------------------------------------------------
TEST(HexahedronElementMass, UnitCubeClosedForm) {
    // One unit cube, density ρ: particle masses ρ/8 (total ρ); every 3×3 block of the element
    // matrix is w = ρ·8/27 · I (SOFA's computeElementMass), so M·1 = 8w = 64ρ/27 per vertex.
    const double rho = 3.0;
    for (const bool lumped : {false, true}) {
        Vec3Object s;
        const MeshTopology topo = cube_topology(s, 1.0);
        HexahedronElementMass m(s, topo.hexahedra(), rho, lumped, "test");
        m.init();
        EXPECT_DOUBLE_EQ(m.total_mass(), rho);
        for (const double pm : m.particle_masses()) EXPECT_DOUBLE_EQ(pm, rho / 8);
        ASSERT_EQ(m.element_weights().size(), 1u);
        EXPECT_NEAR(m.element_weights()[0], rho * 8.0 / 27.0, 1e-15);
        std::fill(s.dx.begin(), s.dx.end(), Vec3(1, -2, 0.5));
        std::fill(s.df.begin(), s.df.end(), Vec3::Zero());
        m.add_mdx(2.0);
        for (const Vec3& f : s.df) EXPECT_LT((f - 2.0 * 64.0 * rho / 27.0 * Vec3(1, -2, 0.5)).norm(), 1e-12);
        // gravity acts on the particle masses
        std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
        m.add_gravity_force(Vec3(0, -10, 0));
        for (const Vec3& f : s.force) EXPECT_LT((f - Vec3(0, -10 * rho / 8, 0)).norm(), 1e-14);
        const Eigen::VectorXd in = Eigen::VectorXd::Zero(24);
        Eigen::VectorXd out(24);
        EXPECT_THROW(m.apply_inverse(in, out), std::invalid_argument);
    }
}

TEST(HexahedronElementMass, AssembledMatrixIsTheProductAndTheKineticEnergy) {
    RegularGridTopology g({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 0.5, 1.5));
    for (const bool lumped : {false, true}) {
        Vec3Object s;
        s.position = g.points();
        s.init();
        HexahedronElementMass m(s, g.mesh().hexahedra(), 2.0, lumped, "test");
        m.init();
        EXPECT_NEAR(m.total_mass(), 2.0 * 2 * 0.5 * 1.5, 1e-12);
        const auto n = static_cast<Eigen::Index>(3 * s.num_dofs());
        TripletList t;
        m.add_mass_triplets(t, 0, 1.0);
        SparseMatrix mat(n, n);
        mat.setFromTriplets(t.begin(), t.end());
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u(-1, 1);
        for (auto& v : s.dx) v = Vec3(u(rng), u(rng), u(rng));
        std::fill(s.df.begin(), s.df.end(), Vec3::Zero());
        m.add_mdx(1.0);
        const Eigen::VectorXd expected = mat * Vec3Object::flat(s.dx);
        const Eigen::VectorXd df = Vec3Object::flat(s.df);
        ASSERT_EQ(df.size(), expected.size());
        for (Eigen::Index i = 0; i < df.size(); ++i) EXPECT_NEAR(df[i], expected[i], 1e-12) << i;
        s.velocity = s.dx;
        const Eigen::VectorXd v = Vec3Object::flat(s.velocity);
        const Eigen::VectorXd momentum = mat * v;
        EXPECT_NEAR(m.kinetic_energy(), 0.5 * v.dot(momentum), 1e-12);
    }
}

TEST(HexahedronElementMass, CellFactorsScaleTheElementMatrixAndTheParticleMasses) {
    // Two unit cubes side by side along x, factors 0.5 and 1 (a sparse grid's boundary and inside
    // cells): w = c·ρ·8/27, particle masses c·ρ/8 summed over the cells of each vertex.
    RegularGridTopology g({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1));
    Vec3Object s;
    s.position = g.points();
    s.init();
    HexahedronElementMass m(s, g.mesh().hexahedra(), 4.0, false, "test");
    m.set_mass_factors({0.5, 1.0});
    m.init();
    EXPECT_NEAR(m.element_weights()[0], 0.5 * 4.0 * 8.0 / 27.0, 1e-15);
    EXPECT_NEAR(m.element_weights()[1], 4.0 * 8.0 / 27.0, 1e-15);
    EXPECT_NEAR(m.total_mass(), 0.5 * 4.0 + 4.0, 1e-14);
    // the middle vertices (x = 1) belong to both cells: (0.5 + 1)·ρ/8; the x = 0 ones: 0.5·ρ/8
    for (std::size_t i = 0; i < s.position.size(); ++i) {
        const double x = s.rest_position[i].x();
        const double expected = x == 0.0 ? 0.25 : x == 1.0 ? 0.75 : 0.5;
        EXPECT_NEAR(m.particle_masses()[i], expected, 1e-15) << i;
    }
    m.set_mass_factors({1.0});
    EXPECT_THROW(m.init(), std::invalid_argument);  // one factor per hexahedron
}

// SOFA's arithmetic to the bit (HexahedronFEMForceFieldAndMass::computeElementMass and addMDx,
// HexahedralFEMForceFieldAndMass's): the node integral summed term by term (not 8/27, which differs
// in its last bit), V·(∫·ρ)·c or (V·ρ)·∫, M·dx as the 24×24 product Σ_k w·dx_k, the lumped row
// sum added entry by entry. A 10-iteration CG amplified the last bits to SOFA's criterion 1.3e-4
// in SparseGridRamificationTopology.scn.
TEST(HexahedronElementMass, SofaArithmeticToTheBit) {
    const double terms[] = {1.0 / 72.0, 1.0 / 72.0, 1.0 / 216.0, 1.0 / 24.0,
                            1.0 / 8.0,  1.0 / 72.0, 1.0 / 24.0,  1.0 / 24.0};
    double integral = 0.0;
    for (const double t : terms) integral += t;
    ASSERT_NE(integral, 8.0 / 27.0);  // the quirk the test is about
    const RegularGridTopology g({2, 2, 2}, Vec3(0, 0, 0), Vec3(0.3, 0.7, 1.1));
    const std::vector<Hexahedron> hexahedra = g.mesh().hexahedra();
    const Hexahedron& h = hexahedra.at(0);
    const double rho = 3.0, c = 0.375, factor = -0.7;
    for (const auto formula : {HexahedronMassFormula::hexahedron, HexahedronMassFormula::hexahedral}) {
        for (const bool lumped : {false, true}) {
            Vec3Object s;
            s.position = g.points();
            s.init();
            HexahedronElementMass m(s, hexahedra, rho, lumped, "test", formula);
            if (formula == HexahedronMassFormula::hexahedron) m.set_mass_factors({c});
            m.init();
            const double volume = 0.3 * 0.7 * 1.1;  // (each edge length is exact in the grid's points)
            std::array<Vec3, 8> p;
            for (std::size_t k = 0; k < 8; ++k) p[k] = s.rest_position[std::size_t(h[k])];
            const double v = (p[1] - p[0]).norm() * (p[3] - p[0]).norm() * (p[4] - p[0]).norm();
            EXPECT_NEAR(v, volume, 1e-15);
            const double w =
                formula == HexahedronMassFormula::hexahedron ? (v * (integral * rho)) * c : (v * rho) * integral;
            ASSERT_EQ(m.element_weights()[0], w);
            std::mt19937 rng(11);
            std::uniform_real_distribution<double> u(-1, 1);
            for (auto& x : s.dx) x = Vec3(u(rng), u(rng), u(rng));
            std::fill(s.df.begin(), s.df.end(), Vec3::Zero());
            m.add_mdx(factor);
            Vec3 sum = Vec3::Zero();
            for (const PointId k : h) sum += s.dx[std::size_t(k)] * w;
            Vec3 plain = Vec3::Zero();  // w·Σdx would not pass: the data tell the two orders apart
            for (const PointId k : h) plain += s.dx[std::size_t(k)];
            const bool reassociation_differs = (plain * w) * factor != sum * factor;
            for (std::size_t i = 0; i < s.df.size(); ++i) {
                double lumped_mass = 0.0;
                for (int block = 0; block < 8; ++block) lumped_mass += w;
                const Vec3 expected = lumped ? Vec3((s.dx[i] * lumped_mass) * factor) : Vec3(sum * factor);
                for (int a = 0; a < 3; ++a) EXPECT_EQ(s.df[i][a], expected[a]) << i << " " << a;
            }
            if (!lumped) {
                EXPECT_TRUE(reassociation_differs);
            }
        }
    }
}

// HexahedronFEMForceFieldAndMass::computeElementMass measures the element on the force field's
// _rotatedInitialElements (R₀·x⁰), the particle masses on the rest positions: on a rotated body
// the two volumes differ in their last bits (NonUniformHexahedronFEMForceFieldAndMass.scn's
// "uniform" body, ry = 25, parted from SOFA at step 1 by 4e-16 before).
TEST(HexahedronElementMass, ElementMatrixOnTheForceFieldsRotatedRestCorners) {
    const RegularGridTopology g({2, 2, 2}, Vec3(0, 0, 0), Vec3(0.3, 0.7, 1.1));
    const Mat3 r = Eigen::AngleAxisd(0.4363323129985824, Vec3(0.2, 1, 0.3).normalized()).toRotationMatrix();
    Vec3Object s;
    for (const Vec3& p : g.points()) s.position.push_back(r * p + Vec3(0.1, -0.2, 0.3));
    s.init();
    HexahedronFEMForceField fem(s, g.mesh(), 1e4, 0.3, FemMethod::Large);
    fem.init();
    const double rho = 3.0, c = 0.625;
    const std::vector<Hexahedron> hexahedra = g.mesh().hexahedra();
    const auto volume = [](const std::array<Vec3, 8>& p) {
        return (p[1] - p[0]).norm() * (p[3] - p[0]).norm() * (p[4] - p[0]).norm();
    };
    std::array<Vec3, 8> rest;
    for (std::size_t k = 0; k < 8; ++k) rest[k] = s.rest_position[std::size_t(hexahedra[0][k])];
    const double integral =
        1.0 / 72.0 + 1.0 / 72.0 + 1.0 / 216.0 + 1.0 / 24.0 + 1.0 / 8.0 + 1.0 / 72.0 + 1.0 / 24.0 + 1.0 / 24.0;
    const double rotated_volume = volume(fem.rotated_rest(0));
    ASSERT_NE(rotated_volume, volume(rest));  // the data tell the two volumes apart
    HexahedronElementMass m(s, hexahedra, rho, false, "test");
    m.set_mass_factors({c});
    m.set_rotated_rest_source(&fem);
    m.init();
    EXPECT_EQ(m.element_weights()[0], (rotated_volume * (integral * rho)) * c);
    for (const double pm : m.particle_masses()) EXPECT_EQ(pm, ((volume(rest) * c) * rho) * 0.125);
    // a force field on other hexahedra is refused
    const RegularGridTopology two({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1));
    Vec3Object s2;
    s2.position = two.points();
    s2.init();
    HexahedronElementMass other(s2, two.mesh().hexahedra(), rho, false, "test");
    other.set_rotated_rest_source(&fem);
    EXPECT_THROW(other.init(), std::invalid_argument);
}

// Method large's K·d on the scalar and AVX paths (kernels/mechanics/hexahedron_stiffness): force,
// product and energy the same bits; avx512 (eight lanes) is refused.
TEST(HexahedralFEM, KernelPathsGiveTheSameBits) {
    const RegularGridTopology grid({5, 4, 4}, Vec3::Zero(), Vec3(0.4, 0.3, 0.3));
    Vec3Object state;
    state.position = grid.points();
    state.init();
    HexahedralFEMForceField fem(state, grid.mesh(), 2e4, 0.3, FemMethod::Large);
    fem.init();
    EXPECT_EQ(fem.kernel_path(), best_kernel_path());
    EXPECT_THROW(fem.set_kernel_path(KernelPath::avx512), std::invalid_argument);
    test::expect_kernel_paths_give_the_same_bits(fem, state, "method large");
}

}  // namespace
}  // namespace penalty
