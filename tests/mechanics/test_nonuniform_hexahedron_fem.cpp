// SOFA's sparse-grid hierarchy (SparseGridTopology::buildFromFiner) on a cube surface with
// closed-form cells, children and coefficients, and NonUniformHexahedronFEMForceFieldAndMass's
// condensed matrices: a fully filled cell condenses to the classical element of its size, the
// condensed stiffness is blind to rigid translations, the condensed mass keeps SOFA's total, and
// the assembled matrices equal add_dforce and add_mdx.
#include "penalty/mechanics/nonuniform_hexahedron_fem.hpp"

#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/point_state.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

namespace penalty {
namespace {

struct CubeSurface {
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
    CubeSurface() {
        for (int k = 0; k < 8; ++k) positions.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (const auto& q : quads) {
            triangles.push_back({q[0], q[1], q[2]});
            triangles.push_back({q[0], q[2], q[3]});
        }
    }
};

/// The unit cube voxelised on 9³ points from −1.1 to 2.1 (cells of 0.4): the 4³ block of cells
/// 2…5, its shell BOUNDARY and its 2³ core INSIDE; then one coarser level.
std::shared_ptr<const SparseGridTopology> fine_cube() {
    const CubeSurface cube;
    return std::make_shared<const SparseGridTopology>(SparseGridTopology::from_surface(
        {9, 9, 9}, Vec3::Constant(-1.1), Vec3::Constant(2.1), cube.positions, cube.triangles));
}

TEST(SparseGridHierarchy, CoarserLevelOfTheCubeInClosedForm) {
    const auto fine = fine_cube();
    ASSERT_EQ(fine->hexahedra().size(), 64u);
    const SparseGridTopology coarse = SparseGridTopology::from_finer(fine, true);
    EXPECT_EQ(coarse.grid().n(), (std::array<int, 3>{5, 5, 5}));
    EXPECT_NEAR(coarse.grid().max().x(), 2.1, 1e-15);
    EXPECT_EQ(coarse.finer_levels(), 1);
    // coarse cells 1…2 per axis cover the fine block: 8 cells, each holding shell cells: BOUNDARY
    ASSERT_EQ(coarse.hexahedra().size(), 8u);
    for (const SparseCellType t : coarse.cell_types()) EXPECT_EQ(t, SparseCellType::boundary);
    EXPECT_EQ(coarse.points().size(), 27u);
    // each coarse cell has its 8 fine children, one of them a core (INSIDE) cell: coefficient
    // (7·0.5 + 1)/8 with fillWeighted, 1 without
    for (std::size_t e = 0; e < 8; ++e) {
        int inside = 0;
        for (const Index child : coarse.children()[e]) {
            ASSERT_GE(child, 0);
            inside += fine->cell_types()[std::size_t(child)] == SparseCellType::inside ? 1 : 0;
        }
        EXPECT_EQ(inside, 1);
    }
    for (const double c : coarse.coefficients(true)) EXPECT_EQ(c, (7 * 0.5 + 1) / 8);
    for (const double c : SparseGridTopology::from_finer(fine, false).coefficients(false)) EXPECT_EQ(c, 1.0);
    // the first coarse cell (loop order x slowest) is (1,1,1): its child 0 is the fine cell (2,2,2)
    const Vec3 corner = coarse.points()[std::size_t(coarse.hexahedra()[0][0])];
    EXPECT_NEAR((corner - Vec3::Constant(-0.3)).norm(), 0.0, 1e-15);
    const Vec3 child_corner = fine->points()[std::size_t(fine->hexahedra()[std::size_t(coarse.children()[0][0])][0])];
    EXPECT_NEAR((child_corner - corner).norm(), 0.0, 1e-15);
}

TEST(NonUniformHexahedronFEM, AFullCellCondensesToTheClassicalElement) {
    // a 2×2×2 block of coefficient-1 cells (fillWeighted off) under one coarse cell: Σ Tᵀ K T over
    // the children integrates the coarse trilinear field exactly, so K is the coarse element's
    const CubeSurface cube;
    const auto fine = std::make_shared<const SparseGridTopology>(
        SparseGridTopology::from_surface({3, 3, 3}, Vec3::Zero(), Vec3::Ones(), cube.positions, cube.triangles));
    const SparseGridTopology coarse = SparseGridTopology::from_finer(fine, false);
    ASSERT_EQ(coarse.hexahedra().size(), 1u);
    ASSERT_EQ(fine->hexahedra().size(), 8u);
    const CondensedHexahedra m = condense_hexahedra(coarse, 1, 1000.0, 0.3, 7.0, false);
    Vec3Object cell;
    for (const PointId v : coarse.hexahedra()[0]) cell.position.push_back(coarse.points()[std::size_t(v)]);
    cell.init();
    MeshTopology t;
    t.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}});
    HexahedronFEMForceField classical(cell, t, 1000.0, 0.3);
    classical.init();
    EXPECT_TRUE(m.stiffness[0].isApprox(classical.element_stiffness()[0], 1e-12));
    // the mass keeps SOFA's element total per direction, 64·(8/27)·ρ·V of each child
    double total = 0;
    for (int r = 0; r < 24; r += 3)
        for (int c = 0; c < 24; c += 3) total += m.mass[0](r, c);
    EXPECT_NEAR(total, 8 * 64 * (8.0 / 27.0) * 7.0 * 0.125, 1e-12);
    // a rigid translation costs nothing
    Eigen::Matrix<double, 24, 1> shift;
    for (int k = 0; k < 8; ++k) shift.segment<3>(3 * k) = Vec3(0.3, -0.2, 0.7);
    EXPECT_LT((m.stiffness[0] * shift).cwiseAbs().maxCoeff(), 1e-10 * m.stiffness[0].cwiseAbs().maxCoeff());
    EXPECT_THROW(static_cast<void>(condense_hexahedra(coarse, 2, 1000.0, 0.3, 7.0, false)), std::invalid_argument);
}

// NonUniformHexahedronFEMForceFieldAndMass is a HexahedronFEMForceField whose init puts the
// condensed matrices in place of computeElementStiffness's: with given matrices equal to the
// computed ones, the force and the product are HexahedronFEMForceField's to the bit (SOFA's
// accumulateForceLarge and addDForce; the generic corotational path of the other FEMs rounds
// otherwise, which parted NonUniformHexahedronFEMForceFieldAndMass.scn from SOFA HEAD at step 1).
TEST(NonUniformHexahedronFEM, GivenStiffnessRunsHexahedronFEMForceFieldsOperations) {
    const auto fine = fine_cube();
    const SparseGridTopology coarse = SparseGridTopology::from_finer(fine, true);
    const MeshTopology topology = coarse.mesh();
    const auto make_state = [&] {
        Vec3Object s;
        s.position = coarse.points();
        s.init();
        return s;
    };
    Vec3Object computed_state = make_state(), given_state = make_state();
    HexahedronFEMForceField computed(computed_state, topology, 500.0, 0.3);
    computed.init();
    HexahedronFEMForceField given(given_state, topology, 500.0, 0.3);
    given.set_element_stiffness(computed.element_stiffness());
    given.init();
    // turned and stretched: every element's frame and force away from rest
    const Quat q(Eigen::AngleAxisd(0.7, Vec3(1, 2, 0.5).normalized()));
    for (Vec3Object* s : {&computed_state, &given_state})
        for (std::size_t i = 0; i < s->position.size(); ++i)
            s->position[i] = q * Vec3(s->position[i].x() * 1.1, s->position[i].y(), s->position[i].z() * 0.93);
    const std::vector<Vec3> f_computed = test::force_of(computed, computed_state);
    const std::vector<Vec3> f_given = test::force_of(given, given_state);
    ASSERT_EQ(f_computed.size(), f_given.size());
    double largest = 0;
    for (std::size_t i = 0; i < f_computed.size(); ++i) {
        EXPECT_EQ(f_computed[i], f_given[i]) << "point " << i;
        largest = std::max(largest, f_computed[i].norm());
    }
    EXPECT_GT(largest, 1.0);
    for (Vec3Object* s : {&computed_state, &given_state}) {
        for (std::size_t i = 0; i < s->dx.size(); ++i) s->dx[i] = Vec3(0.1 * double(i % 5), -0.3, 0.2 * double(i % 3));
        std::fill(s->df.begin(), s->df.end(), Vec3::Zero());
    }
    computed.accumulate_dforce(-0.01, 0.0);
    given.accumulate_dforce(-0.01, 0.0);
    for (std::size_t i = 0; i < computed_state.df.size(); ++i)
        EXPECT_EQ(computed_state.df[i], given_state.df[i]) << "point " << i;
    // one matrix per hexahedron
    Vec3Object short_state = make_state();
    HexahedronFEMForceField too_few(short_state, topology, 500.0, 0.3);
    too_few.set_element_stiffness({computed.element_stiffness().front()});
    EXPECT_THROW(too_few.init(), std::invalid_argument);
}

TEST(NonUniformHexahedronFEM, AssembledMatricesEqualTheProducts) {
    const auto fine = fine_cube();
    const SparseGridTopology coarse = SparseGridTopology::from_finer(fine, true);
    CondensedHexahedra m = condense_hexahedra(coarse, 1, 500.0, 0.3, 3.0, true);
    Vec3Object s;
    s.position = coarse.points();
    s.init();
    const MeshTopology topology = coarse.mesh();
    HexahedronFEMForceField ff(s, topology, 500.0, 0.3);
    ff.set_element_stiffness(m.stiffness);
    ff.init();
    // at rest (rigidly turned), the corotational field's df = K dx is exact
    const Quat q(Eigen::AngleAxisd(0.5, Vec3(1, 1, 0).normalized()));
    for (Vec3& x : s.position) x = q * x;
    static_cast<void>(test::check_force_field_derivatives(
        ff, s, {.dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt}));
    for (const bool lumped : {false, true}) {
        HexahedronMatrixMass mass(s, coarse.hexahedra(), m.mass, coarse.coefficients(true),
                                  {.density = 3.0, .lumped = lumped});
        mass.init();
        const auto n = Eigen::Index(3 * s.num_dofs());
        Eigen::MatrixXd product(n, n);
        for (Eigen::Index j = 0; j < n; ++j) {
            std::fill(s.dx.begin(), s.dx.end(), Vec3::Zero());
            std::fill(s.df.begin(), s.df.end(), Vec3::Zero());
            Vec3Object::flat(s.dx)[j] = 1.0;
            mass.add_mdx(1.0);
            product.col(j) = Vec3Object::flat(s.df);
        }
        TripletList t;
        mass.add_mass_triplets(t, 0, 1.0);
        SparseMatrix assembled(n, n);
        assembled.setFromTriplets(t.begin(), t.end());
        EXPECT_TRUE(Eigen::MatrixXd(assembled).isApprox(product, 1e-14)) << (lumped ? "lumped" : "full");
        // particle masses: ρ·c·V/8 of each cell, V = 0.8³
        EXPECT_NEAR(mass.total_mass(), 8 * 0.5625 * 3.0 * 0.512, 1e-12);
    }
}

}  // namespace
}  // namespace penalty
