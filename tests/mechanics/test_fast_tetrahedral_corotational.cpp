// FastTetrahedralCorotationalForceField (SOFA's edge-stored corotational tetrahedra): add_dforce
// and the assembled matrix against finite differences of the force (at a rigidly moved rest
// shape for the corotational methods, anywhere for the linear one), the assembled matrix against
// add_dforce at a deformed shape, zero force under a rigid motion (and not without rotation), and
// the linear method's force equal to TetrahedronFEMForceField's small method, and the force, edge
// stiffness and product on threads the bits of one thread.
#include "penalty/mechanics/fast_tetrahedral_corotational.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/grid_meshes.hpp"
#include "penalty_test/sanitizer.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>

namespace penalty {
namespace {

constexpr FastTetrahedralRotation kAllRotations[] = {FastTetrahedralRotation::qr, FastTetrahedralRotation::polar,
                                                     FastTetrahedralRotation::polar_modified,
                                                     FastTetrahedralRotation::linear};

/// A 2×2×1-cell grid cut into 24 Kuhn tetrahedra, with the field on its state.
struct FastTetraBlock {
    MeshTopology topology = test::kuhn_tetrahedra(RegularGridTopology{{3, 3, 2}, Vec3(0, 0, 0), Vec3(2, 1.5, 1)});
    Vec3Object state;
    FastTetrahedralCorotationalForceField field;
    explicit FastTetraBlock(FastTetrahedralRotation rotation)
        : field(state, topology, {.young_modulus = {30}, .poisson_ratio = {0.45}, .rotation = rotation}) {
        const RegularGridTopology grid{{3, 3, 2}, Vec3(0, 0, 0), Vec3(2, 1.5, 1)};
        const auto points = grid.points();
        state.position.assign(points.begin(), points.end());
        state.init();
        state.dx.assign(state.position.size(), Vec3::Zero());
        state.df.assign(state.position.size(), Vec3::Zero());
        field.init();
    }
    void move_rigidly(const Mat3& r, const Vec3& t) {
        for (std::size_t i = 0; i < state.position.size(); ++i) state.position[i] = r * state.rest_position[i] + t;
    }
    void perturb(double amplitude, unsigned seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(-amplitude, amplitude);
        for (Vec3& p : state.position) p += Vec3(u(rng), u(rng), u(rng));
    }
    double max_force() {
        std::fill(state.force.begin(), state.force.end(), Vec3::Zero());
        field.accumulate_force();
        double m = 0;
        for (const Vec3& f : state.force) m = std::max(m, f.cwiseAbs().maxCoeff());
        return m;
    }
};

const Mat3 kRotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, -0.5).normalized()).toRotationMatrix();

TEST(FastTetrahedralCorotational, RigidMotionGivesNoForceWithTheCorotationalMethods) {
    for (FastTetrahedralRotation rotation : kAllRotations) {
        FastTetraBlock b(rotation);
        b.move_rigidly(kRotation, Vec3(0.3, -1, 2));
        const double f = b.max_force();
        if (rotation == FastTetrahedralRotation::linear) {
            EXPECT_GT(f, 1.0) << "no rotation: a rotated block is strained";  // E = 30 Pa, rotation 0.7 rad
        } else {
            EXPECT_LT(f, 1e-12) << static_cast<int>(rotation);
        }
        b.move_rigidly(Mat3::Identity(), Vec3(0.3, -1, 2));
        EXPECT_LT(b.max_force(), 1e-12) << "a translation is free for every method";
    }
}

TEST(FastTetrahedralCorotational, StiffnessMatchesFiniteDifferencesAtARigidlyMovedRestShape) {
    // unstrained: the rotation's change adds nothing, so K (edge blocks) is ∂f/∂x
    for (FastTetrahedralRotation rotation : kAllRotations) {
        if (rotation == FastTetrahedralRotation::linear) continue;
        FastTetraBlock b(rotation);
        b.move_rigidly(kRotation, Vec3(1, 0, 0));
        const auto d = test::check_force_field_derivatives(
            b.field, b.state, {.dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt});
        EXPECT_GT(d.k_dforce.cwiseAbs().maxCoeff(), 1.0);
        EXPECT_LT((d.k_dforce - d.k_dforce.transpose()).cwiseAbs().maxCoeff(), 1e-12) << "symmetric at rest";
    }
}

TEST(FastTetrahedralCorotational, LinearMethodStiffnessIsExactAnywhere) {
    FastTetraBlock b(FastTetrahedralRotation::linear);
    b.perturb(0.2, 7);
    test::check_force_field_derivatives(
        b.field, b.state, {.dforce_vs_fd = 1e-7, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt});
}

TEST(FastTetrahedralCorotational, AssembledMatrixEqualsTheProductWhenDeformed) {
    for (FastTetrahedralRotation rotation : kAllRotations) {
        FastTetraBlock b(rotation);
        b.move_rigidly(kRotation, Vec3::Zero());
        b.perturb(0.15, 11);
        b.max_force();  // linearise here
        const auto n = static_cast<Eigen::Index>(3 * b.state.num_dofs());
        TripletList t;
        b.field.add_stiffness(
            t, [](const BaseState*) { return Index{0}; }, 1.0);
        SparseMatrix k(n, n);
        k.setFromTriplets(t.begin(), t.end());
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(-1, 1);
        Eigen::VectorXd dx(n);
        for (Eigen::Index i = 0; i < n; ++i) dx[i] = u(rng);
        for (std::size_t i = 0; i < b.state.num_dofs(); ++i)
            b.state.dx[i] = dx.segment<3>(3 * static_cast<Eigen::Index>(i));
        std::fill(b.state.df.begin(), b.state.df.end(), Vec3::Zero());
        b.field.accumulate_dforce(2.5, 0.0);
        const Eigen::VectorXd expected = 2.5 * (k * dx);
        EXPECT_LT((Vec3Object::flat(b.state.df) - expected).cwiseAbs().maxCoeff(),
                  1e-11 * expected.cwiseAbs().maxCoeff())
            << static_cast<int>(rotation);
    }
}

TEST(FastTetrahedralCorotational, LinearMethodGivesTheSmallStrainForceOfTetrahedronFem) {
    // both are V·BᵀDB per tetrahedron with the same Lamé coefficients
    FastTetraBlock b(FastTetrahedralRotation::linear);
    TetrahedronFEMForceField fem(b.state, b.topology, 30, 0.45, FemMethod::Small);
    fem.init();
    b.perturb(0.05, 5);
    const double scale = b.max_force();
    const std::vector<Vec3> fast = b.state.force;
    std::fill(b.state.force.begin(), b.state.force.end(), Vec3::Zero());
    fem.accumulate_force();
    ASSERT_GT(scale, 0.01);
    for (std::size_t i = 0; i < fast.size(); ++i) EXPECT_LT((fast[i] - b.state.force[i]).norm(), 1e-12 * scale) << i;
}

TEST(FastTetrahedralCorotational, EdgesOfTheTopologyCarryTheStiffness) {
    FastTetraBlock b(FastTetrahedralRotation::qr);
    b.max_force();
    ASSERT_EQ(b.field.edge_stiffness().size(), b.topology.edges().size());
    for (const auto& r : b.field.rest_tetrahedra())
        for (std::size_t j = 0; j < 6; ++j) {
            const Edge& e = b.topology.edges()[static_cast<std::size_t>(r.edge[j])];
            EXPECT_TRUE(r.edge_orientation[j] == 1.0 || r.edge_orientation[j] == -1.0);
            EXPECT_EQ(e[0] < e[1], true) << "tetrahedron containers sort their edges' vertices";
        }
    Vec3Object flat;
    flat.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
    flat.init();
    MeshTopology one;
    one.set_tetrahedra({{0, 1, 2, 3}});
    FastTetrahedralCorotationalForceField degenerate(flat, one, {});
    EXPECT_THROW(degenerate.init(), std::invalid_argument);
}

TEST(FastTetrahedralCorotational, ForceEdgeStiffnessAndProductOnThreadsAreTheBitsOfOneThread) {
    // 13 × 12 × 9 cells: 8 424 tetrahedra and more edges (above OrderedScatter::kMinElements),
    // numbered in space or shuffled (the edges then numbered in another order too)
    const RegularGridTopology grid({14, 13, 10}, Vec3::Zero(), Vec3(1.3, 1.2, 0.9));
    const MeshTopology spatial = test::kuhn_tetrahedra(grid);
    std::vector<Tetrahedron> shuffled = spatial.tetrahedra();
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(8));
    MeshTopology random_order;
    random_order.set_tetrahedra(shuffled);
    ASSERT_GE(spatial.tetrahedra().size(), detail::OrderedScatter::kMinElements);
    const auto same_matrices_bits = [](const std::vector<Mat3>& a, const std::vector<Mat3>& b) {
        return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Mat3)) == 0;
    };
    for (const MeshTopology* mesh : {&spatial, static_cast<const MeshTopology*>(&random_order)})
        for (const FastTetrahedralRotation rotation : kAllRotations) {
            Vec3Object state;
            state.position = grid.points();
            state.init();
            FastTetrahedralCorotationalForceField field(
                state, *mesh, {.young_modulus = {3e4}, .poisson_ratio = {0.35}, .rotation = rotation});
            field.init();
            const test::ElementProducts one = test::element_products_on_threads(field, state, 1, 0.02, -0.37);
            const std::vector<Mat3> one_edges = field.edge_stiffness();
            EXPECT_EQ(one.chunks, 0U);
            EXPECT_EQ(field.force_scatter().chunk_count(), 0U);
            EXPECT_GT(std::count_if(one_edges.begin(), one_edges.end(), [](const Mat3& e) { return e.norm() > 0; }),
                      std::ptrdiff_t(one_edges.size() / 2));
            for (const int threads : test::thread_counts_to_compare({2, 3, 8})) {
                const test::ElementProducts many =
                    test::element_products_on_threads(field, state, threads, 0.02, -0.37);
                const std::string where = "rotation " + std::to_string(static_cast<int>(rotation)) + ", " +
                                          std::to_string(threads) + " threads" + (mesh == &spatial ? "" : ", shuffled");
                EXPECT_GT(many.chunks, 1U) << where;  // the product's split of the edges
                EXPECT_GT(many.deferred, 0U) << where;
                EXPECT_GT(field.force_scatter().chunk_count(), 1U) << where;
                EXPECT_GT(field.force_scatter().deferred_terms(), 0U) << where;
                EXPECT_TRUE(test::same_vectors_bits(many.force, one.force)) << where;
                EXPECT_TRUE(same_matrices_bits(field.edge_stiffness(), one_edges)) << where;
                EXPECT_TRUE(test::same_vectors_bits(many.product, one.product)) << where;
            }
        }
}

}  // namespace
}  // namespace penalty
