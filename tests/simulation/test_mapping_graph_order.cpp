// order_as_mapping_graph (mapping_graph_order.cpp): a subtree's force steps in the order of SOFA
// HEAD's MappingGraph (MappingGraphMechanicalOperations::computeForce) instead of its visitors':
// the force fields grouped by the list of states they act on, in the graph's breadth-first order,
// then each mapping's Jᵀ·f bottom-up. Told apart by the rounding of sums of 1e16 and 1.
#include "penalty/mechanics/external_loads.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

ConstantForceFieldParameters graph_forces_at_point_0(const Vec3& f) {
    ConstantForceFieldParameters p;
    p.indices = {0};
    p.forces = {f};
    return p;
}

// SOFA sums the forces on a state in its visiting order (MechanicalComputeForceVisitor): top-down,
// the node's own force fields; bottom-up (post-order), each mapped child's Jᵀ·f, first child
// first. SOFA HEAD's EulerImplicitSolver computes f through its MappingGraph instead
// (MappingGraphMechanicalOperations::computeForce; SubtreeSystem's mapping_graph_order): every
// force field first, then each mapping's Jᵀ·f in the reverse of the graph's breadth-first order
// (MappingGraphAlgorithms::traverseBottomUp), so two mapped siblings add into their parent last
// child first. With 1e16 and 1 the rounding of a double tells the orders apart:
// ((−1e16 + 1e16) + 1) = 1 first child first, ((−1e16 + 1) + 1e16) = 0 last child first.
TEST(SubtreeSystem, SumsForcesInSofasVisitingAndMappingGraphOrders) {
    Simulation sim;
    Node& root = sim.root();
    root.set_ode_solver<EulerImplicitSolver>();
    Node& body = root.add_child("body");
    auto& x = body.add_state<Vec3Types>("body");
    x.position = {Vec3(0, 0, 0)};
    body.add_force_field<ConstantForceField>(x, graph_forces_at_point_0(Vec3(-1e16, 0, 0)));
    const auto mapped_child = [&](const char* name, double force) {
        Node& child = body.add_child(name);
        auto& cx = child.add_state<Vec3Types>(name);
        cx.position = {Vec3(0, 0, 0)};
        child.set_mapping<IdentityMapping>(x, cx);
        child.add_force_field<ConstantForceField>(cx, graph_forces_at_point_0(Vec3(force, 0, 0)));
    };
    mapped_child("first", 1e16);
    mapped_child("second", 1.0);
    sim.init();
    SubtreeSystem visitors(root);
    visitors.propagate_positions_and_velocities();
    Eigen::VectorXd f;
    visitors.compute_force(f);
    ASSERT_EQ(f.size(), 3);
    EXPECT_EQ(f[0], 1.0);  // (own −1e16 + first child's 1e16) + second child's 1
    SubtreeSystem sys(root, true);
    sys.propagate_positions_and_velocities();
    sys.compute_force(f);
    ASSERT_EQ(f.size(), 3);
    EXPECT_EQ(f[0], 0.0);  // (own −1e16 + second child's 1) + first child's 1e16
    // A grandchild adds its Jᵀ·f into its parent before that parent maps into the body (deeper
    // first); the other way round its force would never reach the body.
    Simulation sim2;
    Node& root2 = sim2.root();
    root2.set_ode_solver<EulerImplicitSolver>();
    Node& body2 = root2.add_child("body");
    auto& x2 = body2.add_state<Vec3Types>("body");
    x2.position = {Vec3(0, 0, 0)};
    body2.add_force_field<ConstantForceField>(x2, graph_forces_at_point_0(Vec3(5, 0, 0)));
    Node& a = body2.add_child("a");
    auto& ax = a.add_state<Vec3Types>("a");
    ax.position = {Vec3(0, 0, 0)};
    a.set_mapping<IdentityMapping>(x2, ax);
    a.add_force_field<ConstantForceField>(ax, graph_forces_at_point_0(Vec3(2, 0, 0)));
    Node& a1 = a.add_child("a1");
    auto& a1x = a1.add_state<Vec3Types>("a1");
    a1x.position = {Vec3(0, 0, 0)};
    a1.set_mapping<IdentityMapping>(ax, a1x);
    a1.add_force_field<ConstantForceField>(a1x, graph_forces_at_point_0(Vec3(1.0, 0, 0)));
    sim2.init();
    for (const bool graph : {false, true}) {
        SubtreeSystem sys2(root2, graph);
        sys2.propagate_positions_and_velocities();
        sys2.compute_force(f);
        ASSERT_EQ(f.size(), 3);
        EXPECT_EQ(f[0], 8.0);  // 5 + (2 + 1)
    }
}

// The MappingGraph's force fields go by the list of states they act on, each list (a group) a
// node of the graph after its states, the groups in order of first appearance. The root holds a
// spring between bodies x and y pulling x by exactly 1 (ks 1, rest 0, length 1); x holds loads
// of 1e16 and −1e16. Both orders sum the spring's group first, ((1 + 1e16) − 1e16) = 0: SOFA
// HEAD (2a278d8) leaves x where it is after a step of this scene written as a .scn, where the
// spring alone moves it by 1e-4.
TEST(MappingGraphOrder, FieldsActingOnTheSameStatesAreSummedTogether) {
    Simulation sim;
    Node& root = sim.root();
    root.set_ode_solver<EulerImplicitSolver>();
    Node& body = root.add_child("x");
    auto& x = body.add_state<Vec3Types>("x");
    x.position = {Vec3(0, 0, 0)};
    Node& other = root.add_child("y");
    auto& y = other.add_state<Vec3Types>("y");
    y.position = {Vec3(1, 0, 0)};
    root.add_force_field<SpringForceField>(x, y).add_spring({0, 0, 1.0, 0.0, 0.0});
    body.add_force_field<ConstantForceField>(x, graph_forces_at_point_0(Vec3(1e16, 0, 0)));
    body.add_force_field<ConstantForceField>(x, graph_forces_at_point_0(Vec3(-1e16, 0, 0)));
    sim.init();
    for (const bool graph : {false, true}) {
        Eigen::VectorXd f;
        SubtreeSystem sys(root, graph);
        sys.propagate_positions_and_velocities();
        sys.compute_force(f);
        ASSERT_EQ(f.size(), 6);
        EXPECT_EQ(f[Eigen::Index(sys.offset(&x))], 0.0) << graph;
        EXPECT_EQ(f[Eigen::Index(sys.offset(&y))], -1.0) << graph;  // the spring's other end
    }
}

}  // namespace
}  // namespace penalty
