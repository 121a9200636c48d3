// The assembled global matrix (m·M + b·B + k·K, mapped fields through Jᵀ·J, contact blocks with
// damping, the consistent mass matrix) against the matrix-free product column by column; the
// constraints on the matrix; the direct solvers against a tight CG.
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/fixed_plane_constraint.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/mesh_matrix_mass.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/rest_shape_springs.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/direct_linear_solver.hpp"
#include "penalty/simulation/global_matrix_assembly.hpp"
#include "penalty/simulation/penalty_interaction.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>

namespace penalty {
namespace {

/// A subtree with every kind of contribution: a hexahedral FEM block with a consistent mass
/// matrix, points mapped into it (barycentric) with a spring between two of them, a rigid body
/// with mapped points, springs between bodies, a penalty contact with normal damping between a
/// mapped point and a rigid-mapped point (B ≠ 0), and rest-shape springs on the block.
struct AssemblyScene {
    Simulation sim;
    RegularGridTopology grid{{3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1)};
    MeshTopology mesh = grid.mesh();  // the mass keeps a reference to its topology
    PenaltyForceField contact_field{PenaltyParameters{.damping = 3.5}};
    Vec3Object* block = nullptr;
    Vec3Object* surface = nullptr;
    Vec3Object* rigid_points = nullptr;
    Rigid3Object* rigid = nullptr;

    explicit AssemblyScene(bool fixed) {
        Node& root = sim.root();
        root.set_ode_solver<EulerImplicitSolver>();
        Node& b = root.add_child("block");
        block = &b.add_state<Vec3Types>("block");
        block->position = grid.points();
        b.set_mass<MeshMatrixMass>(*block, mesh).set_total_mass(2.0);
        b.add_force_field<HexahedronFEMForceField>(*block, mesh, 1000.0, 0.3, FemMethod::Large);
        auto& rest = b.add_force_field<RestShapeSpringsForceField<Vec3Types>>(*block);
        rest.set_points({2, 7});
        rest.set_stiffness({40.0, 15.0});
        rest.set_active_directions({true, false, true});
        rest.set_sofa_assembly(false);
        if (fixed) {
            b.add_constraint<FixedProjectiveConstraint>(*block).set_indices({0, 3});
            b.add_constraint<FixedPlaneProjectiveConstraint>(*block, Vec3(0, 0, 1)).set_indices({5});
        }
        Node& surf = b.add_child("surface");
        surface = &surf.add_state<Vec3Types>("surface");
        const std::vector<Vec3> mapped_points{Vec3(1.9, 0.9, 0.9), Vec3(0.5, 0.2, 0.7), Vec3(1.2, 0.6, 0.1)};
        map_on_regular_grid(surf.set_mapping<BarycentricMapping>(*block, *surface), grid, mapped_points);
        surf.add_force_field<SpringForceField>(*surface, *surface).add_spring({0, 2, 500.0, 0.0, 0.5});
        Node& r = root.add_child("rigid");
        rigid = &r.add_state<Rigid3Types>("rigid");
        rigid->position = {{Vec3(3, 0.5, 0.5), Quat(Eigen::AngleAxisd(0.4, Vec3(0, 1, 1).normalized()))}};
        r.set_mass<UniformMass<Rigid3Types>>(*rigid).set_vertex_mass(1.5);
        Node& rp = r.add_child("points");
        rigid_points = &rp.add_state<Vec3Types>("rigid_points");
        rp.set_mapping<RigidMapping>(*rigid, *rigid_points).set_points({Vec3(-0.5, 0.1, 0), Vec3(0.2, -0.3, 0.4)});
        root.add_force_field<SpringForceField>(*rigid_points, *block).add_spring({1, 5, 200.0, 0.0, 0.3});
        root.add_force_field<PenaltyInteraction>(*surface, *rigid_points, contact_field);
        sim.init();
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u(-0.05, 0.05);
        for (auto& p : block->position) p += Vec3(u(rng), u(rng), u(rng));
        // a contact pressed in: point 0 of the surface against rigid point 0
        contact_field.clear(1);
        contact_field.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3(1, 0, 0), 1.5,
                                  800.0);
        for (auto& v : block->velocity) v = Vec3(u(rng), u(rng), u(rng));
    }
};

TEST(GlobalMatrixAssembly, EqualsTheMatrixFreeProductColumnByColumn) {
    AssemblyScene scene(false);
    SubtreeSystem sys(scene.sim.root());
    sys.propagate_positions_and_velocities();
    Eigen::VectorXd f;
    sys.compute_force(f);  // linearises the fields (and activates the contact)
    ASSERT_GT(scene.contact_field.contacts()[0].pen, 0.0);
    const double m = 1.25, b = -0.02, k = -4e-4;  // EulerImplicitSolver's factors, h = 0.02
    const ColumnSparseMatrix a = assemble_mbk_matrix(sys, m, b, k);
    ASSERT_EQ(a.rows(), sys.size());
    const Eigen::MatrixXd dense(a);
    double largest_b_part = 0.0;
    for (Eigen::Index j = 0; j < sys.size(); ++j) {
        Eigen::VectorXd e = Eigen::VectorXd::Zero(sys.size()), column, without_b;
        e[j] = 1.0;
        sys.apply_mbk(e, column, m, b, k, false);
        EXPECT_LT((dense.col(j) - column).cwiseAbs().maxCoeff(), 1e-12 * std::max(1.0, column.cwiseAbs().maxCoeff()))
            << "column " << j;
        sys.apply_mbk(e, without_b, m, 0.0, k, false);
        largest_b_part = std::max(largest_b_part, (column - without_b).cwiseAbs().maxCoeff());
    }
    EXPECT_GT(largest_b_part, 1e-3);  // the contact's damping is in the product, and so in the matrix
    // the mass part alone is M (consistent: off-diagonal blocks), the total mass in it
    const Eigen::MatrixXd mass(assemble_mbk_matrix(sys, 1.0, 0.0, 0.0));
    EXPECT_NEAR(mass.topLeftCorner(36, 36).sum() / 3, 2.0, 1e-12);
    EXPECT_NE(mass(0, 3), 0.0);
}

TEST(GlobalMatrixAssembly, ConstraintsDiscardRowsAsSofaAndTheDirectSolveMatchesAProjectedCg) {
    AssemblyScene scene(true);
    SubtreeSystem sys(scene.sim.root());
    sys.propagate_positions_and_velocities();
    Eigen::VectorXd f;
    sys.compute_force(f);
    const double m = 1.25, b = -0.02, k = -4e-4;
    ColumnSparseMatrix a = assemble_mbk_matrix(sys, m, b, k);
    apply_projective_constraints(sys, a);
    const Eigen::MatrixXd dense(a);
    for (Eigen::Index r : {0, 1, 2, 9, 10, 11, 17}) {  // DOFs 0 and 3, and z of DOF 5
        for (Eigen::Index c = 0; c < dense.cols(); ++c) {
            EXPECT_EQ(dense(r, c), r == c ? 1.0 : 0.0) << r << " " << c;
            EXPECT_EQ(dense(c, r), r == c ? 1.0 : 0.0) << c << " " << r;
        }
    }
    // Δv of the direct solvers = Δv of CG run to 1e-14 on the same projected right-hand side
    Eigen::VectorXd rhs = f;
    sys.project(rhs);
    Eigen::VectorXd cg_x;
    CGLinearSolver cg;
    cg.iterations = 2000;
    cg.tolerance = 1e-15;
    cg.threshold = 1e-30;
    MbkCgSystem cg_system(sys, m, b, k);
    cg.solve(cg_system, rhs, cg_x);
    ASSERT_GT(cg_x.norm(), 1e-6);
    for (FactorizationMethod method :
         {FactorizationMethod::ldlt, FactorizationMethod::llt, FactorizationMethod::lu, FactorizationMethod::qr}) {
        for (FillOrdering ordering : {FillOrdering::amd, FillOrdering::colamd, FillOrdering::natural}) {
            DirectLinearSolver direct;
            direct.method = method;
            direct.ordering = ordering;
            Eigen::VectorXd x;
            direct.solve(sys, m, b, k, rhs, x);
            EXPECT_LT((x - cg_x).cwiseAbs().maxCoeff(), 1e-10 * cg_x.cwiseAbs().maxCoeff())
                << factorization_name(method) << " " << ordering_name(ordering);
            // discarded rows are decoupled: Δv = b = 0 there (exactly for the triangular factorizations)
            for (Eigen::Index r : {0, 1, 2, 9, 10, 11, 17}) {
                if (method == FactorizationMethod::qr) EXPECT_LT(std::abs(x[r]), 1e-13 * cg_x.cwiseAbs().maxCoeff());
                else EXPECT_EQ(x[r], 0.0) << factorization_name(method);
            }
        }
    }
}

TEST(GlobalMatrixAssembly, AConstraintWithoutDiscardedRowsAppliesAsItsProjector) {
    // FixedPlaneProjectiveConstraint along an oblique direction: SOFA's matrix discards every
    // component the direction touches; the projector P = I − n nᵀ (the CG's) keeps the plane.
    struct ObliquePlane final : BaseProjectiveConstraint {
        FixedPlaneProjectiveConstraint plane;
        ObliquePlane(BaseState& s, const Vec3& n) : plane(s, n) { plane.set_indices({4, 6}); }
        void project_response(Eigen::Ref<Eigen::VectorXd> v) const override { plane.project_response(v); }
        void project_velocity() override {}
        [[nodiscard]] BaseState* state() const override { return plane.state(); }
    };
    AssemblyScene scene(false);
    const Vec3 n = Vec3(1, 2, 2).normalized();
    Node& block_node = *scene.sim.root().children()[0];
    block_node.add_constraint<ObliquePlane>(*scene.block, n);
    SubtreeSystem sys(scene.sim.root());
    sys.propagate_positions_and_velocities();
    Eigen::VectorXd f;
    sys.compute_force(f);
    Eigen::VectorXd rhs = f;
    sys.project(rhs);
    CGLinearSolver cg;
    cg.iterations = 2000;
    cg.tolerance = 1e-15;
    cg.threshold = 1e-30;
    Eigen::VectorXd cg_x, x;
    MbkCgSystem cg_system(sys, 1.0, -0.01, -1e-4);
    cg.solve(cg_system, rhs, cg_x);
    DirectLinearSolver direct;
    direct.solve(sys, 1.0, -0.01, -1e-4, rhs, x);
    EXPECT_LT((x - cg_x).cwiseAbs().maxCoeff(), 1e-10 * cg_x.cwiseAbs().maxCoeff());
    EXPECT_LT(std::abs(x.segment<3>(12).dot(n)), 1e-13 * x.cwiseAbs().maxCoeff());
    EXPECT_GT(x.segment<3>(12).norm(), 1e-8);
}

TEST(GlobalMatrixAssembly, TheSymbolicAnalysisIsKeptWhileThePatternIsTheSame) {
    AssemblyScene scene(true);
    SubtreeSystem sys(scene.sim.root());
    sys.propagate_positions_and_velocities();
    Eigen::VectorXd f, x;
    sys.compute_force(f);
    sys.project(f);
    DirectLinearSolver direct;
    direct.solve(sys, 1.0, -0.01, -1e-4, f, x);
    direct.solve(sys, 1.0, -0.02, -4e-4, f, x);
    EXPECT_EQ(direct.factorizations(), 2);
    EXPECT_EQ(direct.symbolic_analyses(), 1);
    scene.contact_field.clear(0);  // the contact's blocks stay in the pattern, as zeros
    sys.compute_force(f);
    sys.project(f);
    direct.solve(sys, 1.0, -0.02, -4e-4, f, x);
    EXPECT_EQ(direct.symbolic_analyses(), 1);
    scene.contact_field.add_contact(DofIndex(1), DofIndex(1), ElementIndex(1), ElementIndex(1), Vec3(1, 0, 0), 4.0,
                                    800.0);  // active, its blocks at new places
    sys.compute_force(f);
    sys.project(f);
    direct.solve(sys, 1.0, -0.02, -4e-4, f, x);
    EXPECT_EQ(direct.symbolic_analyses(), 2);
    EXPECT_EQ(direct.factorizations(), 4);
}

TEST(GlobalMatrixAssembly, ASingularMatrixIsANamedError) {
    // a free point without mass nor stiffness: A = 0, a scene defect (not a divergence) naming
    // the solver
    Simulation sim;
    Node& n = sim.root();
    n.set_ode_solver<EulerImplicitSolver>();
    auto& s = n.add_state<Vec3Types>("massless");
    s.position = {Vec3(0, 0, 0)};
    sim.init();
    SubtreeSystem sys(n);
    Eigen::VectorXd rhs = Eigen::VectorXd::Ones(3), x;
    DirectLinearSolver direct;
    try {
        direct.solve(sys, 1.0, 0.0, 0.0, rhs, x);
        ADD_FAILURE() << "no error";
    } catch (const SingularSystemError& e) {
        EXPECT_EQ(e.solver(), &direct);
    }
}

}  // namespace
}  // namespace penalty
