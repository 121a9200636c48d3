// SubtreeSystem (simulation/subtree_system.cpp, subtree_products.cpp): the matrix-free operator equals
// the assembled one through chained mappings (FEM volume -> barycentric points; rigid frame ->
// rigid-mapped points) and interaction springs; the fused CG passes; rows mapped and cleared; the
// cache of systems (SOFA's summation orders: test_mapping_graph_order.cpp).
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/penalty_interaction.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace penalty {
namespace {

/// Makes `block` a hexahedral FEM block on `grid`: 2 kg, E = 1000, ν = 0.3, method large, at
/// the grid's points; returns its state.
Vec3Object& make_fem_block(Node& block, const RegularGridTopology& grid) {
    auto& bx = block.add_state<Vec3Types>("block");
    bx.position = grid.points();
    block.set_mass<UniformMass<Vec3Types>>(bx).set_total_mass(2.0);
    block.add_force_field<HexahedronFEMForceField>(bx, grid.mesh(), 1000.0, 0.3, FemMethod::Large);
    return bx;
}

/// A rigid body of 1.5 kg in a child "rigid" of `root`, with two rigid-mapped points; returns
/// the points' state.
Vec3Object& add_rigid_with_points(Node& root) {
    Node& rigid = root.add_child("rigid");
    auto& rx = rigid.add_state<Rigid3Types>("rigid");
    rx.position = {{Vec3(3, 0.5, 0.5), Quat(Eigen::AngleAxisd(0.4, Vec3(0, 1, 1).normalized()))}};
    rigid.set_mass<UniformMass<Rigid3Types>>(rx).set_vertex_mass(1.5);
    Node& rpts = rigid.add_child("points");
    auto& rp = rpts.add_state<Vec3Types>("rigid_points");
    rpts.set_mapping<RigidMapping>(rx, rp).set_points({Vec3(-0.5, 0.1, 0), Vec3(0.2, -0.3, 0.4)});
    return rp;
}

TEST(SubtreeSystem, MatrixFreeOperatorEqualsAssembledThroughMappings) {
    Simulation sim;
    Node& root = sim.root();
    root.set_ode_solver<EulerImplicitSolver>();
    // Deformable hexahedral block.
    RegularGridTopology grid({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1));
    Node& block = root.add_child("block");
    auto& bx = make_fem_block(block, grid);
    // Points mapped into the block, then a point mapped on those (chain of two mappings).
    Node& surf = block.add_child("surface");
    auto& sx = surf.add_state<Vec3Types>("surface");
    auto& bary = surf.set_mapping<BarycentricMapping>(bx, sx);
    const std::vector<Vec3> pts = {Vec3(1.9, 0.9, 0.9), Vec3(0.5, 0.2, 0.7), Vec3(1.2, 0.6, 0.1)};
    map_on_regular_grid(bary, grid, pts);
    Node& contact = surf.add_child("contact");
    auto& cx = contact.add_state<Vec3Types>("contact");
    contact.set_mapping<BarycentricMapping>(sx, cx).set_weights({{{0, 0.2}, {1, 0.3}, {2, 0.5}}});
    // Rigid body with rigid-mapped points.
    auto& rp = add_rigid_with_points(root);
    // Interaction springs: contact point <-> rigid point 0; rigid point 1 <-> block DOF 5.
    auto& s1 = root.add_force_field<SpringForceField>(cx, rp);
    s1.add_spring({0, 0, 300.0, 0.0, 0.4});
    auto& s2 = root.add_force_field<SpringForceField>(rp, bx);
    s2.add_spring({1, 5, 200.0, 0.0, 0.3});
    sim.init();
    // Deform a bit and linearise.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    for (auto& p : bx.position) p += Vec3(u(rng), u(rng), u(rng));
    SubtreeSystem sys(root);
    ASSERT_EQ(sys.size(), 3 * 12 + 6);
    EXPECT_EQ(sys.mappings().size(), 3u);
    sys.propagate_positions_and_velocities();
    Eigen::VectorXd f;
    sys.compute_force(f);
    EXPECT_GT(f.norm(), 1.0);
    const double m = 1.3, k = -0.7;
    const SparseMatrix a = sys.assemble(m, k);
    for (int trial = 0; trial < 3; ++trial) {
        Eigen::VectorXd p = Eigen::VectorXd::NullaryExpr(sys.size(), [&] { return u(rng); });
        Eigen::VectorXd q;
        sys.apply_mbk(p, q, m, 0.0, k, false);
        const Eigen::VectorXd qa = a * p;
        EXPECT_LT((q - qa).cwiseAbs().maxCoeff(), 1e-11 * std::max(1.0, q.cwiseAbs().maxCoeff()));
        EXPECT_GT(q.norm(), 1e-3);
    }
    // The assembled stiffness part is symmetric (springs and corotational FEM blocks are).
    const Eigen::MatrixXd dense = Eigen::MatrixXd(a);
    EXPECT_TRUE(dense.isApprox(dense.transpose(), 1e-10));
}

/// Bits of a vector, for exact comparisons (zeros' signs included).
std::vector<std::uint64_t> bits_of(const Eigen::VectorXd& v) {
    std::vector<std::uint64_t> out(static_cast<std::size_t>(v.size()));
    for (Eigen::Index i = 0; i < v.size(); ++i) out[static_cast<std::size_t>(i)] = std::bit_cast<std::uint64_t>(v[i]);
    return out;
}

TEST(SubtreeSystem, CgsFusedPassesGiveTheBitsOfTheProductAndDotApart) {
    // Vec3 states (3-wide DOFs) and a rigid one (6-wide), mappings and interaction springs; with
    // and without a constraint projecting the product. The fused passes against apply_mbk, dot
    // and Eigen's vector expressions, then whole CG solves against the unfused CG, bit for bit.
    for (const bool constrained : {false, true}) {
        SCOPED_TRACE(constrained ? "with a fixed DOF" : "without constraints");
        Simulation sim;
        Node& root = sim.root();
        root.set_ode_solver<EulerImplicitSolver>();
        const RegularGridTopology grid({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1));
        Node& block = root.add_child("block");
        auto& bx = make_fem_block(block, grid);
        if (constrained) block.add_constraint<FixedProjectiveConstraint>(bx).set_indices({1, 4});
        Node& surf = block.add_child("surface");
        auto& sx = surf.add_state<Vec3Types>("surface");
        const std::vector<Vec3> points = {Vec3(1.9, 0.9, 0.9), Vec3(0.5, 0.2, 0.7)};
        map_on_regular_grid(surf.set_mapping<BarycentricMapping>(bx, sx), grid, points);
        auto& rp = add_rigid_with_points(root);
        root.add_force_field<SpringForceField>(sx, rp).add_spring({0, 0, 300.0, 0.0, 0.4});
        root.add_force_field<SpringForceField>(rp, bx).add_spring({1, 5, 200.0, 0.0, 0.3});
        sim.init();
        std::mt19937 rng(17);
        std::uniform_real_distribution<double> u(-0.05, 0.05);
        for (auto& p : bx.position) p += Vec3(u(rng), u(rng), u(rng));
        SubtreeSystem sys(root);
        ASSERT_EQ(sys.size(), 3 * 12 + 6);
        sys.propagate_positions_and_velocities();
        Eigen::VectorXd f;
        sys.compute_force(f);
        const double m = 1.07, b = -0.01, k = -0.013;
        const auto random = [&] { return Eigen::VectorXd::NullaryExpr(sys.size(), [&] { return u(rng); }).eval(); };

        // direction_and_mbk: p = r or r + β·p, q = A·p projected, p·q
        for (const bool first : {true, false}) {
            const Eigen::VectorXd r = random();
            const Eigen::VectorXd p0 = random();
            const double beta = 0.37;
            Eigen::VectorXd p_apart = first ? r : (r + beta * p0).eval();
            Eigen::VectorXd q_apart;
            sys.apply_mbk(p_apart, q_apart, m, b, k, true);
            const double den_apart = sys.dot(p_apart, q_apart);
            Eigen::VectorXd p_fused = p0;
            Eigen::VectorXd q_fused;
            const double den_fused = sys.direction_and_mbk(r, beta, first, p_fused, q_fused, m, b, k);
            EXPECT_EQ(bits_of(p_fused), bits_of(p_apart));
            EXPECT_EQ(bits_of(q_fused), bits_of(q_apart));
            EXPECT_EQ(std::bit_cast<std::uint64_t>(den_fused), std::bit_cast<std::uint64_t>(den_apart));
            EXPECT_GT(q_apart.norm(), 1e-3);
            // the constraint's rows are zero in q
            if (constrained) {
                EXPECT_EQ(q_fused.segment<3>(3).norm() + q_fused.segment<3>(12).norm(), 0.0);
            }
        }
        // update_and_residual: x += α·p, r −= α·q, r·r
        {
            const Eigen::VectorXd p = random();
            const Eigen::VectorXd q = random();
            Eigen::VectorXd x_apart = random();
            Eigen::VectorXd r_apart = random();
            Eigen::VectorXd x_fused = x_apart;
            Eigen::VectorXd r_fused = r_apart;
            const double alpha = -1.93;
            x_apart += alpha * p;
            r_apart -= alpha * q;
            const double rr_apart = sys.dot(r_apart, r_apart);
            const double rr_fused = sys.update_and_residual(alpha, p, q, x_fused, r_fused);
            EXPECT_EQ(bits_of(x_fused), bits_of(x_apart));
            EXPECT_EQ(bits_of(r_fused), bits_of(r_apart));
            EXPECT_EQ(std::bit_cast<std::uint64_t>(rr_fused), std::bit_cast<std::uint64_t>(rr_apart));
        }
        // whole solves: the fused passes against the product and the dot apart
        const Eigen::VectorXd rhs = random();
        for (const int iterations : {1, 2, 7, 40}) {
            CGLinearSolver apart_cg;
            CGLinearSolver fused_cg;
            for (CGLinearSolver* cg : {&apart_cg, &fused_cg}) {
                cg->iterations = iterations;
                cg->tolerance = 1e-12;
                cg->threshold = 1e-30;
            }
            Eigen::VectorXd x_apart;
            Eigen::VectorXd x_fused;
            const CgStats apart = apart_cg.solve(
                [&](const Eigen::VectorXd& p, Eigen::VectorXd& q) { sys.apply_mbk(p, q, m, b, k, true); }, rhs, x_apart,
                [&](const Eigen::VectorXd& a, const Eigen::VectorXd& c) { return sys.dot(a, c); });
            MbkCgSystem fused_system(sys, m, b, k);
            const CgStats fused = fused_cg.solve(fused_system, rhs, x_fused);
            EXPECT_EQ(fused.iterations, apart.iterations);
            EXPECT_EQ(fused.end_condition, apart.end_condition);
            EXPECT_EQ(std::bit_cast<std::uint64_t>(fused.error), std::bit_cast<std::uint64_t>(apart.error));
            EXPECT_EQ(bits_of(x_fused), bits_of(x_apart));
            EXPECT_GT(x_fused.norm(), 1e-3);
        }
    }
}

/// A force field that adds nothing and cannot tell which DOFs it reads (BaseForceField's
/// default): on a mapped state it makes the solver map every row of that state's dx.
class OpaqueNoOpField final : public ForceField<Vec3Types> {
public:
    using ForceField::ForceField;
    void add_force(std::span<Vec3>, std::span<const Vec3>, std::span<const Vec3>) override {}
    void add_dforce(std::span<Vec3>, std::span<const Vec3>, double, double) const override {}
    void add_stiffness_triplets(TripletList&, Index, double) const override {}
};

/// A block with a mapped collision surface of many points, read in a few rows only: a contact
/// point mapped on it and a penalty interaction between two of its points.
struct SurfaceScene {
    Simulation sim;
    PenaltyForceField field;
    Vec3Object* surface = nullptr;
    explicit SurfaceScene(bool opaque_reader) {
        Node& root = sim.root();
        root.set_ode_solver<EulerImplicitSolver>();
        const RegularGridTopology grid({4, 3, 3}, Vec3(0, 0, 0), Vec3(3, 2, 2));
        Node& block = root.add_child("block");
        auto& bx = make_fem_block(block, grid);
        Node& surf = block.add_child("surface");
        auto& sx = surf.add_state<Vec3Types>("surface");
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> u(0.05, 0.95);
        std::vector<Vec3> pts(60);
        for (auto& p : pts) p = Vec3(3 * u(rng), 2 * u(rng), 2 * u(rng));
        map_on_regular_grid(surf.set_mapping<BarycentricMapping>(bx, sx), grid, pts);
        Node& contact = surf.add_child("contact");
        auto& cx = contact.add_state<Vec3Types>("contact");
        contact.set_mapping<BarycentricMapping>(sx, cx).set_weights({{{2, 0.3}, {7, 0.7}}, {{40, 1.0}}});
        root.add_force_field<SpringForceField>(cx, bx).add_spring({0, 5, 300.0, 0.0, 0.4});
        surf.add_force_field<PenaltyInteraction>(sx, sx, field);
        field.add_contact(DofIndex(3), DofIndex(50), ElementIndex(0), ElementIndex(0), Vec3(0, 1, 0), 10.0, 100.0);
        field.add_contact(DofIndex(20), DofIndex(33), ElementIndex(0), ElementIndex(0), Vec3(1, 0, 0), 10.0, 80.0);
        if (opaque_reader) surf.add_force_field<OpaqueNoOpField>(sx);
        surface = &sx;
        sim.init();
        std::mt19937 move(5);
        std::uniform_real_distribution<double> d(-0.05, 0.05);
        for (auto& p : bx.position) p += Vec3(d(move), d(move), d(move));
    }
};

TEST(SubtreeSystem, MapsDxOnlyInTheRowsReadWithTheSameBits) {
    // The selective path (the surface's dx mapped only where the contact mapping and the penalty
    // interaction read it; Jᵀ of its few forced rows) against the full one (an opaque reader on
    // the surface): the same forces and products, bit for bit.
    SurfaceScene selective(false), full(true);
    SubtreeSystem sys_s(selective.sim.root()), sys_f(full.sim.root());
    sys_s.propagate_positions_and_velocities();
    sys_f.propagate_positions_and_velocities();
    Eigen::VectorXd f_s, f_f;
    sys_s.compute_force(f_s);
    sys_f.compute_force(f_f);
    ASSERT_EQ(f_s.size(), f_f.size());
    for (Eigen::Index i = 0; i < f_s.size(); ++i)
        EXPECT_EQ(std::bit_cast<std::uint64_t>(f_s[i]), std::bit_cast<std::uint64_t>(f_f[i])) << i;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int trial = 0; trial < 3; ++trial) {
        const Eigen::VectorXd p = Eigen::VectorXd::NullaryExpr(sys_s.size(), [&] { return u(rng); });
        for (auto& d : selective.surface->dx) d = Vec3(nan, nan, nan);  // rows not read stay NaN
        for (auto& d : selective.surface->df) d = Vec3(nan, nan, nan);  // rows not counted: never read
        Eigen::VectorXd q_s, q_f;
        sys_s.apply_mbk(p, q_s, 1.3, -0.02, -0.7, true);
        sys_f.apply_mbk(p, q_f, 1.3, -0.02, -0.7, true);
        ASSERT_EQ(q_s.size(), q_f.size());
        EXPECT_GT(q_s.norm(), 1e-3);
        for (Eigen::Index i = 0; i < q_s.size(); ++i)
            EXPECT_EQ(std::bit_cast<std::uint64_t>(q_s[i]), std::bit_cast<std::uint64_t>(q_f[i]))
                << "trial " << trial << " row " << i;
        // Rows read: 2, 7, 40 (contact mapping), 3, 50, 20, 33 (penalty interaction); row 0 is not.
        for (const std::size_t read : {2, 3, 7, 20, 33, 40, 50})
            EXPECT_TRUE(selective.surface->dx[read].allFinite()) << read;
        EXPECT_TRUE(std::isnan(selective.surface->dx[0][0]));
    }
}

/// A FEM block under a solver held by penalty contacts against a static obstacle of `points`
/// points outside the solver's subtree: the obstacle is an external state of the block's system,
/// its force, dx and df scratch.
struct ObstacleScene {
    Simulation sim;
    PenaltyForceField field;
    Node* body = nullptr;
    Vec3Object* block = nullptr;
    Vec3Object* obstacle = nullptr;
    int points = 0;
    explicit ObstacleScene(bool obstacle_static, int obstacle_points = 2500) : points(obstacle_points) {
        Node& root = sim.root();
        body = &root.add_child("body");
        body->set_ode_solver<EulerImplicitSolver>();
        const RegularGridTopology grid({3, 3, 3}, Vec3(0, 0, 0), Vec3(1, 1, 1));
        block = &make_fem_block(*body, grid);
        obstacle = &root.add_child("floor").add_state<Vec3Types>("obstacle");
        for (int i = 0; i < points; ++i) obstacle->position.push_back(Vec3(0.02 * (i % 50), -0.02, 0.02 * (i / 50)));
        body->add_force_field<PenaltyInteraction>(*block, *obstacle, field);
        sim.init();
        obstacle->set_static(obstacle_static);
    }
    /// Step k's contacts: block vertices 0, 1, 2 (its bottom) on obstacle rows that change with k.
    void set_contacts(int k) {
        field.clear();
        for (const auto& [vertex, row] : std::array<std::pair<Index, Index>, 3>{
                 {{0, (7 * k) % points}, {1, (7 * k + 150) % points}, {2, points - 1 - 3 * k}}})
            field.add_contact(DofIndex(vertex), DofIndex(row), ElementIndex(0), ElementIndex(0), Vec3(0, 1, 0), 0.05,
                              500.0);
    }
};

TEST(SubtreeSystem, AStaticObstaclesScratchIsClearedOnlyWhereSolvesWroteIt) {
    // The same solves against a static obstacle (its scratch cleared in the rows its contacts
    // use now and used before) and against the same obstacle not marked static (its scratch
    // cleared whole): the same obstacle vectors and system vectors, bit for bit, while the
    // contacts move over the obstacle's rows; rows no solve uses are never written.
    ObstacleScene fast(true), whole(false);
    ASSERT_GE(fast.obstacle->num_dofs(), SubtreeSystem::kMinDofsForScratchRows);
    SubtreeSystem sys_fast(*fast.body), sys_whole(*whole.body);
    const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
    const auto same_vectors = [&](const std::vector<Vec3>& a, const std::vector<Vec3>& b, const char* what, int k) {
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(bits(a[i][c]), bits(b[i][c])) << what << " row " << i << " step " << k;
    };
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1, 1);
    const auto solve = [&](int k) {
        for (ObstacleScene* scene : {&fast, &whole}) scene->set_contacts(k);
        Eigen::VectorXd f_fast, f_whole;
        sys_fast.compute_force(f_fast);
        sys_whole.compute_force(f_whole);
        for (Eigen::Index i = 0; i < f_fast.size(); ++i) ASSERT_EQ(bits(f_fast[i]), bits(f_whole[i])) << "f " << i;
        const SubtreeSystem::FixedReaders readers_fast(sys_fast), readers_whole(sys_whole);
        for (int product = 0; product < 2; ++product) {
            const Eigen::VectorXd p = Eigen::VectorXd::NullaryExpr(sys_fast.size(), [&] { return u(rng); });
            Eigen::VectorXd q_fast, q_whole;
            sys_fast.apply_mbk(p, q_fast, 1.0, -0.01, -0.3, true);
            sys_whole.apply_mbk(p, q_whole, 1.0, -0.01, -0.3, true);
            for (Eigen::Index i = 0; i < q_fast.size(); ++i) ASSERT_EQ(bits(q_fast[i]), bits(q_whole[i])) << "q " << i;
        }
    };
    for (int k = 0; k < 6; ++k) {
        solve(k);
        same_vectors(fast.obstacle->force, whole.obstacle->force, "force", k);
        same_vectors(fast.obstacle->dx, whole.obstacle->dx, "dx", k);
        same_vectors(fast.obstacle->df, whole.obstacle->df, "df", k);
        // the contacts act: force and df on exactly the three rows of step k (none of step k − 1's)
        std::size_t forced = 0, with_df = 0;
        for (std::size_t i = 0; i < fast.obstacle->num_dofs(); ++i) {
            forced += fast.obstacle->force[i] != Vec3::Zero();
            with_df += fast.obstacle->df[i] != Vec3::Zero();
        }
        EXPECT_EQ(forced, 3u) << k;
        EXPECT_EQ(with_df, 3u) << k;
        EXPECT_NE(fast.obstacle->force[std::size_t(fast.points - 1 - 3 * k)], Vec3::Zero()) << k;
    }
    // A row no solve used (200) is left as it is: no pass over the whole obstacle.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    fast.obstacle->force[200] = fast.obstacle->dx[200] = fast.obstacle->df[200] = Vec3(nan, nan, nan);
    solve(6);
    EXPECT_TRUE(std::isnan(fast.obstacle->force[200].x()) && std::isnan(fast.obstacle->dx[200].y()) &&
                std::isnan(fast.obstacle->df[200].z()));
    // Marked again, the records are forgotten: the next solve clears the whole vectors.
    fast.obstacle->set_static(false);
    fast.obstacle->set_static(true);
    solve(7);
    same_vectors(fast.obstacle->force, whole.obstacle->force, "force", 7);
    same_vectors(fast.obstacle->dx, whole.obstacle->dx, "dx", 7);
    same_vectors(fast.obstacle->df, whole.obstacle->df, "df", 7);
}

TEST(SubtreeSystem, ASmallStaticObstaclesScratchIsClearedWhole) {
    // Below kMinDofsForScratchRows DOFs the pass is cheaper than listing the contacts' rows.
    ObstacleScene small(true, 400);
    ASSERT_LT(small.obstacle->num_dofs(), SubtreeSystem::kMinDofsForScratchRows);
    SubtreeSystem sys(*small.body);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int k = 0; k < 2; ++k) {
        small.set_contacts(k);
        small.obstacle->force[200] = small.obstacle->dx[200] = small.obstacle->df[200] = Vec3(nan, nan, nan);
        Eigen::VectorXd f, q;
        sys.compute_force(f);
        const SubtreeSystem::FixedReaders readers(sys);
        sys.apply_mbk(Eigen::VectorXd::Ones(sys.size()), q, 1.0, 0.0, -0.3, true);
        EXPECT_EQ(small.obstacle->force[200], Vec3::Zero()) << k;
        EXPECT_EQ(small.obstacle->dx[200], Vec3::Zero()) << k;
        EXPECT_EQ(small.obstacle->df[200], Vec3::Zero()) << k;
        EXPECT_NE(small.obstacle->force[std::size_t(small.points - 1 - 3 * k)], Vec3::Zero()) << k;
    }
}

TEST(SubtreeSystemCache, BuiltOnceAndRebuiltWhenTheGraphChanges) {
    // A free point under gravity: the solver's system is built at the first solve and reused;
    // adding a force field, removing it, or setting a gravity builds it again, and the step then
    // uses the new graph.
    Simulation sim;
    sim.root().set_dt(0.01);
    Node& anchor_node = sim.root().add_child("anchor");
    auto& anchor = anchor_node.add_state<Vec3Types>();
    anchor.position = {Vec3(0, 1, 0)};
    Node& body = sim.root().add_child("body");
    auto& solver = body.set_ode_solver<EulerImplicitSolver>();
    auto& x = body.add_state<Vec3Types>();
    x.position = {Vec3(0, 0, 0)};
    body.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(1.0);
    sim.init();
    const std::uint64_t v0 = body.structure_version();
    EXPECT_EQ(v0, sim.root().structure_version());  // one version for the whole graph
    for (int i = 0; i < 3; ++i) sim.step();
    EXPECT_EQ(solver.system_cache().builds(), 1);
    EXPECT_EQ(body.structure_version(), v0);  // stepping does not change the structure
    EXPECT_LT(x.velocity[0].y(), 0.0);        // falls

    // A spring pulling up (rest length 0, 1e4 N/m): the next solve sees it.
    auto& spring = body.add_force_field<SpringForceField>(anchor, x);
    spring.add_spring({0, 0, 1e4, 0.0, 0.0});
    spring.init();
    EXPECT_GT(body.structure_version(), v0);
    const double vy = x.velocity[0].y();
    sim.step();
    EXPECT_EQ(solver.system_cache().builds(), 2);
    EXPECT_GT(x.velocity[0].y(), vy);  // pulled up

    // Removing it, then switching gravity off: each change rebuilds once.
    ASSERT_TRUE(body.remove_force_field(&spring));
    sim.step();
    EXPECT_EQ(solver.system_cache().builds(), 3);
    sim.root().set_gravity(Vec3::Zero());
    const Vec3 v_before = x.velocity[0];
    sim.step();
    EXPECT_EQ(solver.system_cache().builds(), 4);
    EXPECT_TRUE(x.velocity[0].isApprox(v_before, 1e-12));  // no force: constant velocity
    sim.step();
    EXPECT_EQ(solver.system_cache().builds(), 4);
}

}  // namespace
}  // namespace penalty
