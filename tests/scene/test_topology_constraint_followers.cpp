// Projective constraints following a topological change with SOFA's rules
// (docs/topological-changes.md, "What follows"): LinearMovementProjectiveConstraint and
// DirectionProjectiveConstraint, PartialFixed- and ParabolicProjectiveConstraint keep the same
// points (their indices are SOFA's TopologySubsetIndices), and what SOFA keeps outside the
// topology data (LinearMovement's x0 indexed by point, Direction's origins by slot) stays as it was.
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/prescribed_motion_constraints.hpp"
#include "penalty/mechanics/projective_constraints.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <sstream>

namespace penalty {
namespace {

template <class T>
T* tcf_find(Node& n) {
    for (const auto& k : n.constraints())
        if (auto* t = dynamic_cast<T*>(k.get())) return t;
    for (const auto& child : n.children())
        if (T* t = tcf_find<T>(*child)) return t;
    return nullptr;
}

/// A 2×2×2-cell tetrahedral cube (27 points, 40 tetrahedra) with a modifier and `components`.
std::string tcf_body(const std::string& components) {
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="body">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <TetrahedronSetTopologyContainer name="volume" position=")" +
           test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass totalMass="1"/>
  <FixedProjectiveConstraint indices="0 1 2 9 13 26"/>
  )" + components +
           "\n</Node></Node>\n";
}

Vec3Object& tcf_state(scene::Scene& s) { return dynamic_cast<Vec3Object&>(*s.states().at(0).state); }

TEST(TopologyConstraintFollowers, LinearMovementKeepsItsPointsAndSofasPointIndexedX0) {
    // points 1, 2, 9, 13 move from x0 by m(t) = (t, 0, 0); 0 and 26 (the corners of tetrahedra 0
    // and 38 alone) are removed and renumber others
    auto s = test::build(tcf_body(R"(<LinearMovementProjectiveConstraint indices="0 1 2 9 13 26" keyTimes="0 1"
      movements="0 0 0  1 0 0" relativeMovements="1"/>)"));
    s->step();  // the first projection takes x0
    auto* moving = tcf_find<LinearMovementProjectiveConstraint<Vec3Types>>(s->simulation().root());
    const auto* fixed = tcf_find<FixedProjectiveConstraint>(s->simulation().root());
    ASSERT_TRUE(moving && fixed);
    const std::vector<Vec3> x0 = moving->initial_positions();
    ASSERT_EQ(x0.size(), 27u);

    s->remove_elements("volume", ElementType::tetrahedron, {0, 38});
    const Vec3Object& x = tcf_state(*s);
    ASSERT_LT(x.num_dofs(), 27u);
    // the same points as the fixed constraint's (TopologySubsetIndices, both): 1, 2, 9, 13 by rest position
    EXPECT_EQ(moving->indices(), fixed->indices());
    std::set<std::array<double, 3>> kept;
    for (const Index i : moving->indices()) {
        const Vec3& p = x.rest_position[std::size_t(i)];
        kept.insert({p.x(), p.y(), p.z()});
    }
    EXPECT_EQ(kept, (std::set<std::array<double, 3>>{{0.1, 0, 0}, {0.2, 0, 0}, {0, 0, 0.1}, {0.1, 0.1, 0.1}}));
    // x0 is SOFA's: left as it was, indexed by point
    EXPECT_EQ(moving->initial_positions(), x0);

    s->step();
    moving->project_position();
    // x_i = x0_i + m(t) for every listed index, m the same for all and along x
    const Vec3 m = x.position[std::size_t(moving->indices()[0])] - x0[std::size_t(moving->indices()[0])];
    EXPECT_GT(m.x(), 0.0);
    EXPECT_LT(m.x(), 1.0);
    for (const Index i : moving->indices()) {
        const Vec3 d = x.position[std::size_t(i)] - x0[std::size_t(i)];
        EXPECT_NEAR((d - Vec3(m.x(), 0, 0)).norm(), 0.0, 1e-15) << i;
    }
}

TEST(TopologyConstraintFollowers, DirectionKeepsItsPointsAndSofasProjectionAndOrigins) {
    auto s = test::build(tcf_body(R"(<DirectionProjectiveConstraint indices="0 1 2 9 13 26" direction="0 2 0"/>)"));
    auto* along = tcf_find<DirectionProjectiveConstraint>(s->simulation().root());
    const auto* fixed = tcf_find<FixedProjectiveConstraint>(s->simulation().root());
    ASSERT_TRUE(along && fixed);
    const std::vector<Vec3> origins = along->origins();
    ASSERT_EQ(origins.size(), 6u);

    s->remove_elements("volume", ElementType::tetrahedron, {0, 38});
    const Vec3Object& x = tcf_state(*s);
    EXPECT_EQ(along->indices(), fixed->indices());
    // SOFA's jacobian and m_origin are made by reinit only: the responses are still projected at
    // the points init constrained (26 now past the end), the origins stay in their slots
    const std::vector<Index> sorted{0, 1, 2, 9, 13};
    EXPECT_EQ(along->projected_points(), (std::vector<Index>{0, 1, 2, 9, 13, 26}));
    EXPECT_EQ(along->origins(), origins);

    // the response: P = n nᵀ = e_y e_yᵀ at those points, identity elsewhere
    Eigen::VectorXd v = Eigen::VectorXd::Ones(Eigen::Index(3 * x.num_dofs()));
    along->project_response(v);
    for (std::size_t i = 0; i < x.num_dofs(); ++i) {
        const bool on = std::binary_search(sorted.begin(), sorted.end(), Index(i));
        EXPECT_EQ(v(Eigen::Index(3 * i)), on ? 0.0 : 1.0) << i;
        EXPECT_EQ(v(Eigen::Index(3 * i + 1)), 1.0) << i;
        EXPECT_EQ(v(Eigen::Index(3 * i + 2)), on ? 0.0 : 1.0) << i;
    }
    // positions after steps: each listed point on the line along y through its slot's origin
    for (int k = 0; k < 3; ++k) s->step();
    for (std::size_t k = 0; k < along->indices().size(); ++k) {
        const Vec3 d = x.position[std::size_t(along->indices()[k])] - origins[k];
        EXPECT_EQ(d.x(), 0.0) << k;  // on the line of slot k's origin along y
        EXPECT_EQ(d.z(), 0.0) << k;
    }
}

TEST(TopologyConstraintFollowers, PartialFixedAndParabolicKeepTheirPointsAsIfBuiltAfresh) {
    // PartialFixed inherits FixedProjectiveConstraint's TopologySubsetIndices, Parabolic has its
    // own: after removals that renumber points both name the fixed constraint's points, and
    // project as the same constraints built on the reduced mesh with those indices
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    const auto constraints = [](const std::string& indices) {
        return R"(<PartialFixedProjectiveConstraint indices=")" + indices + R"(" fixedDirections="1 0 1"/>
  <ParabolicProjectiveConstraint indices=")" +
               indices + R"(" P1="0 0.2 0" P2="0.1 0.3 0" P3="0.2 0.2 0.1" BeginTime="0" EndTime="1"/>)";
    };
    auto s = test::build(tcf_body(constraints("0 1 2 9 13 26")));
    s->remove_elements("volume", ElementType::tetrahedron, {0, 38});
    Node& root = s->simulation().root();
    auto* partial = tcf_find<PartialFixedProjectiveConstraint>(root);
    auto* arc = tcf_find<ParabolicProjectiveConstraint<Vec3Types>>(root);
    const auto* fixed = tcf_find<FixedProjectiveConstraint>(root);
    ASSERT_TRUE(partial && arc && fixed);
    EXPECT_EQ(fixed->indices(), (std::vector<Index>{1, 2, 9, 13}));
    EXPECT_EQ(partial->indices(), fixed->indices());
    EXPECT_EQ(arc->indices(), fixed->indices());

    // the fresh scene: the reduced mesh, the followed indices (its own fixed constraint's too)
    const Vec3Object& x = tcf_state(*s);
    std::string indices;
    for (const Index i : partial->indices()) indices += std::to_string(i) + " ";
    const MeshTopology& mesh = s->topology_container("volume").mesh();
    // UniformMass keeps its per-DOF mass (1/27 kg) when the DOF count changes
    std::ostringstream mass_text;
    mass_text.precision(17);
    mass_text << 1.0 / 27.0;
    const std::string vertex_mass = mass_text.str();
    const std::string fresh_text = R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="body">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <TetrahedronSetTopologyContainer name="volume" position=")" +
                                   test::points_text(x.rest_position) + R"(" tetrahedra=")" +
                                   test::elements_text(mesh.tetrahedra()) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass=")" + vertex_mass +
                                   R"("/>
  <FixedProjectiveConstraint indices=")" +
                                   indices + R"("/>
  )" + constraints(indices) + "\n</Node></Node>\n";
    auto fresh = test::build(fresh_text);
    Node& fresh_root = fresh->simulation().root();
    const auto n = Eigen::Index(3 * x.num_dofs());
    Eigen::VectorXd a = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0), b = a;
    partial->project_response(a);
    tcf_find<PartialFixedProjectiveConstraint>(fresh_root)->project_response(b);
    EXPECT_EQ(a, b);
    EXPECT_NE(a, Eigen::VectorXd::LinSpaced(n, 1.0, 2.0));
    a = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0), b = a;
    arc->project_response(a);
    tcf_find<ParabolicProjectiveConstraint<Vec3Types>>(fresh_root)->project_response(b);
    EXPECT_EQ(a, b);
    for (int k = 0; k < 2; ++k) {
        s->step();
        fresh->step();
    }
    EXPECT_EQ(x.position, tcf_state(*fresh).position);
    EXPECT_EQ(x.velocity, tcf_state(*fresh).velocity);
    for (const Index i : arc->indices())
        EXPECT_EQ(x.position[std::size_t(i)], x.position[std::size_t(arc->indices()[0])]);
}

}  // namespace
}  // namespace penalty
