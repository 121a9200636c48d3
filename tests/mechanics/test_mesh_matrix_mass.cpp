// MeshMatrixMass: the matrices against integrals computed here by quadrature, SOFA's data
// semantics (totalMass, massDensity, vertexMass, lumping), and add_mdx / energies against M;
// add_mdx on threads the bits of one thread.
#include "penalty/mechanics/mesh_matrix_mass.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/grid_meshes.hpp"
#include "penalty_test/point_state.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <Eigen/Dense>

#include <cstring>
#include <numeric>
#include <random>
#include <string>

namespace penalty {
namespace {

using test::state_at;

/// The unit cube's corners (index x + 2y + 4z) scaled by `size`, and its cut into six tetrahedra
/// around the diagonal 0–7 (each of volume size³/6).
std::vector<Vec3> cube_points(double size) {
    std::vector<Vec3> p;
    for (int i = 0; i < 8; ++i) p.emplace_back(size * (i & 1), size * ((i >> 1) & 1), size * ((i >> 2) & 1));
    return p;
}
MeshTopology cube_of_tetrahedra() {
    MeshTopology t;
    t.set_tetrahedra({{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}});
    return t;
}

/// M as a dense matrix, from add_mass_triplets.
Eigen::MatrixXd dense_mass(const BaseMass& m, std::size_t dofs) {
    TripletList t;
    m.add_mass_triplets(t, 0, 1.0);
    SparseMatrix s(Index(3 * dofs), Index(3 * dofs));
    s.setFromTriplets(t.begin(), t.end());
    return Eigen::MatrixXd(s);
}

/// ∫ρ NᵢNⱼ over linear tetrahedra (one scalar block per vertex pair), by the 4-point quadrature
/// exact for quadratics (points at barycentric (a, b, b, b), weights V/4): a computation apart
/// from MeshMatrixMass's closed form.
Eigen::MatrixXd integrated_tetrahedra(const std::vector<Vec3>& x, const MeshTopology& t, double rho) {
    const double a = 0.5854101966249685, b = 0.1381966011250105;
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(Eigen::Index(x.size()), Eigen::Index(x.size()));
    for (const Tetrahedron& e : t.tetrahedra()) {
        const double volume = std::abs((x[e[1]] - x[e[0]]).cross(x[e[2]] - x[e[0]]).dot(x[e[3]] - x[e[0]])) / 6.0;
        for (int q = 0; q < 4; ++q) {
            std::array<double, 4> n{b, b, b, b};
            n[std::size_t(q)] = a;
            for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 4; ++j)
                    m(e[std::size_t(i)], e[std::size_t(j)]) += rho * volume / 4 * n[std::size_t(i)] * n[std::size_t(j)];
        }
    }
    return m;
}

/// The scalar matrix repeated on the three components (M = m ⊗ I₃).
Eigen::MatrixXd times_identity3(const Eigen::MatrixXd& m) {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(3 * m.rows(), 3 * m.cols());
    for (Eigen::Index i = 0; i < m.rows(); ++i)
        for (Eigen::Index j = 0; j < m.cols(); ++j)
            for (int c = 0; c < 3; ++c) out(3 * i + c, 3 * j + c) = m(i, j);
    return out;
}

TEST(MeshMatrixMass, ACubeOfTetrahedraHasTheIntegratedConsistentMatrix) {
    const std::vector<Vec3> x = cube_points(2.0);
    Vec3Object s = state_at(x);
    const MeshTopology t = cube_of_tetrahedra();
    MeshMatrixMass m(s, t);
    m.set_mass_density({3.0});
    m.init();
    const Eigen::MatrixXd expected = times_identity3(integrated_tetrahedra(x, t, 3.0));
    EXPECT_LT((dense_mass(m, 8) - expected).cwiseAbs().maxCoeff(), 1e-13);
    // the body's mass: ρ·8 m³, the sum of each component's entries and SOFA's totalMass
    EXPECT_NEAR(dense_mass(m, 8).sum() / 3, 24.0, 1e-12);
    EXPECT_NEAR(m.total_mass(), 24.0, 1e-12);
    EXPECT_DOUBLE_EQ(m.lumping_coefficient(), 2.5);
}

TEST(MeshMatrixMass, TrianglesHaveTheIntegratedConsistentMatrix) {
    // two triangles of a 1 × 2 rectangle: ∫ NᵢNⱼ = A (1 + δᵢⱼ) / 12, by the edge-midpoint rule
    const std::vector<Vec3> x{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 2, 0), Vec3(0, 2, 0)};
    Vec3Object s = state_at(x);
    MeshTopology t;
    t.set_triangles({{0, 1, 2}, {0, 2, 3}});
    MeshMatrixMass m(s, t);
    m.set_total_mass(4.0);  // ρ = 2 kg/m²
    m.init();
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(4, 4);
    for (const Triangle& e : t.triangles()) {
        const double area = 0.5 * (x[e[1]] - x[e[0]]).cross(x[e[2]] - x[e[0]]).norm();
        for (int q = 0; q < 3; ++q) {  // midpoint of the edge opposite vertex q: N_q = 0, the others ½
            std::array<double, 3> n{0.5, 0.5, 0.5};
            n[std::size_t(q)] = 0.0;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    expected(e[std::size_t(i)], e[std::size_t(j)]) +=
                        2.0 * area / 3 * n[std::size_t(i)] * n[std::size_t(j)];
        }
    }
    EXPECT_LT((dense_mass(m, 4) - times_identity3(expected)).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_DOUBLE_EQ(m.mass_density()[0], 2.0);
}

TEST(MeshMatrixMass, HexahedraUseSofasVertexAndEdgeShares) {
    // SOFA's hexahedron (applyVertexMassHexahedronCreation, applyEdgeMassHexahedronCreation):
    // ρV/20 per vertex, ρV/40 per edge, no coupling across faces: the totals and row sums are
    // the trilinear element's (ρV, ρV/8), its entries are not (the trilinear diagonal is ρV/27).
    const std::vector<Vec3> x = cube_points(1.0);
    Vec3Object s = state_at(x);
    MeshTopology t;
    t.set_hexahedra({{0, 1, 3, 2, 4, 5, 7, 6}});
    MeshMatrixMass m(s, t);
    m.set_mass_density({8.0});
    m.init();
    const Eigen::MatrixXd mm = dense_mass(m, 8);
    EXPECT_NEAR(mm(0, 0), 8.0 / 20, 1e-15);
    EXPECT_NEAR(mm(0, 3), 8.0 / 40, 1e-15);  // 0–1 is an edge
    EXPECT_EQ(mm(0, 9), 0.0);                // 0–3 is a face diagonal
    EXPECT_EQ(mm(0, 21), 0.0);               // 0–7, the body diagonal
    for (Eigen::Index r = 0; r < 24; ++r) EXPECT_NEAR(mm.row(r).sum(), 1.0, 1e-14) << r;
    EXPECT_NEAR(m.total_mass(), 8.0, 1e-14);
    // gravity uses the row sums: ρV/8 g per vertex
    s.force.assign(8, Vec3::Zero());
    m.add_gravity_force(Vec3(0, -10, 0));
    EXPECT_NEAR(s.force[5].y(), -10.0, 1e-14);
}

TEST(MeshMatrixMass, QuadsUseSofasVertexAndEdgeShares) {
    const std::vector<Vec3> x{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(0, 1, 0)};
    Vec3Object s = state_at(x);
    MeshTopology t;
    t.set_quads({{0, 1, 2, 3}});
    MeshMatrixMass m(s, t);
    m.init();  // totalMass = 1 kg
    const Eigen::MatrixXd mm = dense_mass(m, 4);
    EXPECT_NEAR(mm(0, 0), 1.0 / 8, 1e-15);
    EXPECT_NEAR(mm(0, 3), 1.0 / 16, 1e-15);
    EXPECT_EQ(mm(0, 6), 0.0);  // 0–2 is the diagonal
    EXPECT_NEAR(mm.sum() / 3, 1.0, 1e-14);
    EXPECT_NEAR(m.mass_density()[0], 0.5, 1e-15);
}

TEST(MeshMatrixMass, LumpingPutsTheRowSumsOnTheDiagonal) {
    const std::vector<Vec3> x = cube_points(1.0);
    const MeshTopology t = cube_of_tetrahedra();
    Vec3Object s1 = state_at(x);
    MeshMatrixMass consistent(s1, t);
    consistent.set_total_mass(6.0);
    consistent.init();
    Vec3Object s2 = state_at(x);
    MeshMatrixMass lumped(s2, t);
    lumped.set_total_mass(6.0);
    lumped.set_lumping(true);
    lumped.init();
    const Eigen::MatrixXd c = dense_mass(consistent, 8);
    const Eigen::MatrixXd l = dense_mass(lumped, 8);
    EXPECT_TRUE(l.isDiagonal());
    for (Eigen::Index r = 0; r < 24; ++r) EXPECT_NEAR(l(r, r), c.row(r).sum(), 1e-14) << r;
    EXPECT_NEAR(lumped.total_mass(), 6.0, 1e-14);
    // explicit solvers can invert only the lumped matrix
    Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(24, 1.0, 24.0), a(24);
    lumped.apply_inverse(f, a);
    EXPECT_LT((l * a - f).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_THROW(consistent.apply_inverse(f, a), std::invalid_argument);
}

TEST(MeshMatrixMass, VertexMassWithLumpingIsScaledByTheLumpingCoefficientAsInSofa) {
    // SOFA's initFromVertexMass keeps the given masses, and addMDx multiplies them by c = 2.5:
    // the matrix holds 2.5 × the given mass, while totalMass is the given sum.
    Vec3Object s = state_at(cube_points(1.0));
    const MeshTopology t = cube_of_tetrahedra();
    MeshMatrixMass m(s, t);
    m.set_vertex_masses(std::vector<double>(8, 0.5));
    m.set_lumping(true);
    m.init();
    EXPECT_NEAR(dense_mass(m, 8)(3, 3), 1.25, 1e-15);
    EXPECT_DOUBLE_EQ(m.total_mass(), 4.0);
    Vec3Object s2 = state_at(cube_points(1.0));
    MeshMatrixMass refused(s2, t);
    refused.set_vertex_masses(std::vector<double>(8, 0.5));
    EXPECT_THROW(refused.init(), std::invalid_argument);  // neither lumping nor edgeMass
    refused.set_lumping(true);
    refused.set_vertex_masses(std::vector<double>(7, 0.5));
    EXPECT_THROW(refused.init(), std::invalid_argument);  // one per point
}

TEST(MeshMatrixMass, PerElementDensitiesAndTheirCountAreChecked) {
    Vec3Object s = state_at(cube_points(1.0));
    const MeshTopology t = cube_of_tetrahedra();
    MeshMatrixMass m(s, t);
    m.set_mass_density({1, 2, 3, 4, 5, 6});
    m.init();
    EXPECT_NEAR(m.total_mass(), 21.0 / 6.0, 1e-14);
    m.set_mass_density({1, 2});
    EXPECT_THROW(m.init(), std::invalid_argument);
    EXPECT_THROW(m.set_mass_density({-1.0}), std::invalid_argument);
    EXPECT_THROW(m.set_total_mass(std::nan("")), std::invalid_argument);
}

TEST(MeshMatrixMass, AddMdxAndTheEnergiesAreTheMatrixs) {
    Vec3Object s = state_at(cube_points(1.5));
    const MeshTopology t = cube_of_tetrahedra();
    MeshMatrixMass m(s, t);
    m.set_mass_density({2.0});
    m.init();
    const Eigen::MatrixXd mm = dense_mass(m, 8);
    Eigen::VectorXd dx(24), v(24);
    for (Eigen::Index i = 0; i < 24; ++i) {
        dx[i] = std::sin(1.3 * double(i) + 0.2);
        v[i] = std::cos(0.7 * double(i));
    }
    s.dx.assign(8, Vec3::Zero());
    s.df.assign(8, Vec3::Zero());
    Vec3Object::flat(s.dx) = dx;
    m.add_mdx(-0.25);
    EXPECT_LT((Vec3Object::flat(s.df) - (-0.25) * mm * dx).cwiseAbs().maxCoeff(), 1e-14);
    Vec3Object::flat(s.velocity) = v;
    EXPECT_NEAR(m.kinetic_energy(), 0.5 * v.dot(mm * v), 1e-13);
    // V = −Σ (g·x_i) (row sum of M)_i; f = −∂V/∂x is the gravity force
    const Vec3 g(0.3, -9.81, 1.0);
    double v_expected = 0;
    for (std::size_t i = 0; i < 8; ++i) v_expected -= g.dot(s.position[i]) * mm.row(Eigen::Index(3 * i)).sum();
    EXPECT_NEAR(m.gravity_potential_energy(g), v_expected, 1e-12);
    s.force.assign(8, Vec3::Zero());
    m.add_gravity_force(g);
    const double h = 1e-6;
    for (std::size_t i = 0; i < 8; ++i)
        for (int c = 0; c < 3; ++c) {
            s.position[i][c] += h;
            const double up = m.gravity_potential_energy(g);
            s.position[i][c] -= 2 * h;
            const double down = m.gravity_potential_energy(g);
            s.position[i][c] += h;
            EXPECT_NEAR(s.force[i][c], -(up - down) / (2 * h), 1e-7) << i << " " << c;
        }
}

TEST(MeshMatrixMass, EdgesHaveNoMassInSofaAndTheBarsMassWithEdgeElements) {
    const std::vector<Vec3> x{Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(3, 4, 0)};
    MeshTopology t;
    t.set_edges({{0, 1}, {1, 2}});
    Vec3Object s = state_at(x);
    MeshMatrixMass sofa(s, t);
    sofa.set_mass_density({2.0});
    sofa.init();
    EXPECT_EQ(dense_mass(sofa, 3).cwiseAbs().maxCoeff(), 0.0);
    MeshMatrixMass bar(s, t);
    bar.set_mass_density({2.0});
    bar.set_edge_elements(true);
    bar.init();
    // the linear bar: ∫ρ NᵢNⱼ = ρL (1 + δᵢⱼ) / 6, lengths 3 and 4
    const Eigen::MatrixXd mm = dense_mass(bar, 3);
    EXPECT_NEAR(mm(0, 0), 2.0 * 3 / 3, 1e-15);
    EXPECT_NEAR(mm(3, 3), 2.0 * 3 / 3 + 2.0 * 4 / 3, 1e-14);
    EXPECT_NEAR(mm(0, 3), 2.0 * 3 / 6, 1e-15);
    EXPECT_NEAR(mm(3, 6), 2.0 * 4 / 6, 1e-15);
    EXPECT_NEAR(bar.total_mass(), 14.0, 1e-13);
}

TEST(MeshMatrixMass, AddMdxOnThreadsIsTheBitsOfOneThread) {
    // a 14 × 13 × 10-point Kuhn grid: more than OrderedScatter::kMinElements edges
    const RegularGridTopology grid({14, 13, 10}, Vec3::Zero(), Vec3(1.3, 1.2, 0.9));
    const MeshTopology mesh = test::kuhn_tetrahedra(grid);
    ASSERT_GE(mesh.edges().size(), detail::OrderedScatter::kMinElements);
    Vec3Object s;
    s.position = grid.points();
    s.init();
    MeshMatrixMass m(s, mesh);
    m.set_mass_density({1000.0});
    m.init();
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (Vec3& d : s.dx) d = Vec3(u(rng), u(rng), u(rng));
    std::vector<Vec3> start(s.dx.size());
    for (Vec3& d : start) d = Vec3(u(rng), u(rng), u(rng));
    const auto product = [&](int threads) {
        s.df.assign(start.begin(), start.end());
        tbb::task_arena(threads).execute([&] { m.add_mdx(-0.37); });
        return std::vector<Vec3>(s.df.begin(), s.df.end());
    };
    const std::vector<Vec3> one = product(1);
    EXPECT_EQ(m.product_scatter().chunk_count(), 0U);
    for (const int threads : {2, 3, 8}) {
        const std::vector<Vec3> many = product(threads);
        EXPECT_GT(m.product_scatter().chunk_count(), 1U) << threads;
        EXPECT_GT(m.product_scatter().deferred_terms(), 0U) << threads;
        EXPECT_EQ(std::memcmp(many.data(), one.data(), one.size() * sizeof(Vec3)), 0) << threads << " threads";
    }
}

}  // namespace
}  // namespace penalty
