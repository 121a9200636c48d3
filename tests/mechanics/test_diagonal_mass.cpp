#include "penalty/mechanics/diagonal_mass.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/grid_meshes.hpp"
#include "penalty_test/point_state.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cstring>
#include <random>

namespace penalty {
namespace {

/// The 8 corners of the unit cube, vertex index = x + 2y + 4z.
std::vector<Vec3> unit_cube_points() {
    std::vector<Vec3> p;
    for (int i = 0; i < 8; ++i) p.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    return p;
}

/// The unit cube cut in the 6 tetrahedra around its diagonal 0–7 (each of volume 1/6).
MeshTopology kuhn_cube() {
    MeshTopology t;
    t.set_tetrahedra({{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}});
    return t;
}

using test::state_at;

TEST(DiagonalMass, TetrahedraShareAQuarterOfTheirMassWithEachVertex) {
    Vec3Object s = state_at(unit_cube_points());
    const MeshTopology t = kuhn_cube();
    DiagonalMass m(s, t);
    m.set_mass_density(2.0);
    m.init();
    EXPECT_EQ(m.element_kind(), LumpedElementKind::tetrahedron);
    // Vertices 0 and 7 belong to the 6 tetrahedra, the others to 2: 2·6·(1/6)/4 and 2·2·(1/6)/4.
    for (int i = 0; i < 8; ++i) EXPECT_NEAR(m.vertex_masses()[i], (i == 0 || i == 7) ? 0.5 : 1.0 / 6.0, 1e-15) << i;
    EXPECT_NEAR(m.total_mass(), 2.0, 1e-14);
    EXPECT_DOUBLE_EQ(m.mass_density(), 2.0);
}

TEST(DiagonalMass, TotalMassScalesTheLumpedSharesAndSetsTheDensity) {
    Vec3Object s = state_at(unit_cube_points());
    for (auto& x : s.rest_position) x *= 2.0;  // lumping reads the rest positions: volume 8
    const MeshTopology t = kuhn_cube();
    DiagonalMass m(s, t);
    m.set_total_mass(10.0);
    m.set_mass_density(99.0);  // totalMass wins
    m.init();
    EXPECT_NEAR(m.vertex_masses()[0], 2.5, 1e-14);
    EXPECT_NEAR(m.vertex_masses()[3], 10.0 / 12.0, 1e-14);
    EXPECT_DOUBLE_EQ(m.total_mass(), 10.0);
    EXPECT_NEAR(m.mass_density(), 10.0 / 8.0, 1e-15);
}

TEST(DiagonalMass, WithoutDataTheTotalMassIsOneKilogram) {
    Vec3Object s = state_at(unit_cube_points());
    const MeshTopology t = kuhn_cube();
    DiagonalMass m(s, t);
    m.init();
    double sum = 0.0;
    for (double mi : m.vertex_masses()) sum += mi;
    EXPECT_NEAR(sum, 1.0, 1e-15);
    EXPECT_NEAR(m.vertex_masses()[7], 0.25, 1e-15);
}

TEST(DiagonalMass, HexahedraWinOverTetrahedraAndShareAnEighth) {
    Vec3Object s = state_at(unit_cube_points());
    MeshTopology t = kuhn_cube();
    t.set_hexahedra({{0, 1, 3, 2, 4, 5, 7, 6}});  // SOFA's hexahedron order: bottom face, then top
    DiagonalMass m(s, t);
    m.set_mass_density(3.0);
    m.init();
    EXPECT_EQ(m.element_kind(), LumpedElementKind::hexahedron);
    for (double mi : m.vertex_masses()) EXPECT_NEAR(mi, 3.0 / 8.0, 1e-15);
    EXPECT_NEAR(m.total_mass(), 3.0, 1e-14);
}

TEST(DiagonalMass, QuadsTrianglesAndEdgesUseAreaAndLength) {
    // Unit square 0 (0,0), 1 (1,0), 2 (1,1), 3 (0,1) in the plane z = 0.
    const std::vector<Vec3> square{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    {
        Vec3Object s = state_at(square);
        MeshTopology t;
        t.set_quads({{0, 1, 2, 3}});
        t.set_triangles({{0, 1, 2}});  // quads win over triangles
        DiagonalMass m(s, t);
        m.set_mass_density(4.0);
        m.init();
        EXPECT_EQ(m.element_kind(), LumpedElementKind::quad);
        for (double mi : m.vertex_masses()) EXPECT_NEAR(mi, 1.0, 1e-15);
    }
    {
        Vec3Object s = state_at(square);
        MeshTopology t;
        t.set_triangles({{0, 1, 2}, {0, 2, 3}});
        DiagonalMass m(s, t);
        m.set_mass_density(3.0);
        m.init();
        EXPECT_EQ(m.element_kind(), LumpedElementKind::triangle);
        // 3 · (1/2) / 3 per triangle and vertex; 0 and 2 are in both triangles.
        EXPECT_NEAR(m.vertex_masses()[0], 1.0, 1e-15);
        EXPECT_NEAR(m.vertex_masses()[1], 0.5, 1e-15);
        EXPECT_NEAR(m.vertex_masses()[2], 1.0, 1e-15);
        EXPECT_NEAR(m.vertex_masses()[3], 0.5, 1e-15);
    }
    {
        Vec3Object s = state_at({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0)});
        MeshTopology t;
        t.set_edges({{0, 1}, {1, 2}});
        DiagonalMass m(s, t);
        m.init();  // totalMass 1 over a length 3: ρ = 1/3
        EXPECT_EQ(m.element_kind(), LumpedElementKind::edge);
        EXPECT_NEAR(m.vertex_masses()[0], 1.0 / 3.0, 1e-15);
        EXPECT_NEAR(m.vertex_masses()[1], 0.5, 1e-15);
        EXPECT_NEAR(m.vertex_masses()[2], 1.0 / 6.0, 1e-15);
        EXPECT_NEAR(m.mass_density(), 1.0 / 3.0, 1e-15);
    }
}

TEST(DiagonalMass, VertexMassListIsPaddedWithItsLastValue) {
    Vec3Object s = state_at(unit_cube_points());
    const MeshTopology t = kuhn_cube();
    DiagonalMass m(s, t);
    m.set_vertex_masses({3.0, 2.0});
    m.init();
    EXPECT_EQ(m.vertex_masses(), (std::vector<double>{3, 2, 2, 2, 2, 2, 2, 2}));
    EXPECT_DOUBLE_EQ(m.total_mass(), 17.0);
    EXPECT_NEAR(m.mass_density(), 17.0, 1e-14);  // the cube's volume is 1
    m.set_vertex_masses(std::vector<double>(9, 1.0));
    EXPECT_THROW(m.init(), std::invalid_argument);
    EXPECT_THROW(m.set_mass_density(-1.0), std::invalid_argument);
    MeshTopology empty;
    DiagonalMass none(s, empty);
    EXPECT_THROW(none.init(), std::invalid_argument);
}

TEST(DiagonalMass, MechanicsUseTheVertexMasses) {
    Vec3Object s = state_at({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0)});
    MeshTopology t;
    t.set_edges({{0, 1}, {1, 2}});
    DiagonalMass m(s, t);
    m.set_mass_density(2.0);
    m.init();  // masses 2, 3, 1
    const std::vector<double> mass{2.0, 3.0, 1.0};
    ASSERT_EQ(m.vertex_masses(), mass);
    EXPECT_DOUBLE_EQ(m.total_mass(), 6.0);

    const Vec3 g(0, -9.81, 0);
    for (auto& f : s.force) f.setZero();
    m.add_gravity_force(g);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(s.force[i], g * mass[i]);

    s.velocity = {Vec3(1, 0, 0), Vec3(0, 2, 0), Vec3(0, 0, 3)};
    EXPECT_DOUBLE_EQ(m.kinetic_energy(), 0.5 * (2 * 1 + 3 * 4 + 1 * 9));
    // −Σ m g·x: only vertex 2 has y ≠ 0.
    EXPECT_DOUBLE_EQ(m.gravity_potential_energy(g), 9.81 * 1.0);

    s.dx = {Vec3(1, 1, 1), Vec3(1, 2, 3), Vec3(-1, 0, 1)};
    s.df.assign(3, Vec3::Zero());
    m.add_mdx(0.5);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(s.df[i], s.dx[i] * (0.5 * mass[i]));

    Eigen::VectorXd f(9), a(9);
    f << 2, 4, 6, 3, 6, 9, 1, 2, 3;
    m.apply_inverse(f, a);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(a.segment<3>(3 * i), Vec3(1, 2, 3));

    TripletList triplets;
    m.add_mass_triplets(triplets, 6, -2.0);
    ASSERT_EQ(triplets.size(), 9U);
    for (std::size_t k = 0; k < 9; ++k) {
        EXPECT_EQ(triplets[k].row(), Index(6 + k));
        EXPECT_EQ(triplets[k].col(), Index(6 + k));
        EXPECT_DOUBLE_EQ(triplets[k].value(), -2.0 * mass[k / 3]);
    }
}

// A large state's M·dx on threads (each DOF its own range's), with factor 1 and another: the bits
// of one thread.
TEST(DiagonalMass, AddMdxOnThreadsIsTheBitsOfOneThread) {
    const RegularGridTopology grid({24, 22, 20}, Vec3::Zero(), Vec3(1.3, 1.2, 0.9));
    ASSERT_GE(grid.points().size(), detail::OrderedScatter::kMinElements);
    const MeshTopology mesh = test::kuhn_tetrahedra(grid);
    Vec3Object s;
    s.position = grid.points();
    s.init();
    DiagonalMass m(s, mesh);
    m.set_mass_density(1000.0);
    m.init();
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (Vec3& d : s.dx) d = Vec3(u(rng), u(rng), u(rng));
    std::vector<Vec3> start(s.dx.size());
    for (Vec3& d : start) d = Vec3(u(rng), u(rng), u(rng));
    for (const double factor : {1.0, -0.37}) {
        const auto product = [&](int threads) {
            s.df.assign(start.begin(), start.end());
            tbb::task_arena(threads).execute([&] { m.add_mdx(factor); });
            return std::vector<Vec3>(s.df.begin(), s.df.end());
        };
        const std::vector<Vec3> one = product(1);
        EXPECT_NE(std::memcmp(one.data(), start.data(), one.size() * sizeof(Vec3)), 0);
        for (const int threads : {2, 8}) {
            const std::vector<Vec3> many = product(threads);
            EXPECT_EQ(std::memcmp(many.data(), one.data(), one.size() * sizeof(Vec3)), 0)
                << threads << " threads, factor " << factor;
        }
    }
}

}  // namespace
}  // namespace penalty
