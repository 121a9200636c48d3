// Mappings and constraints of the scene builder (scene/builder/mappings_and_constraints.cpp):
// RigidMapping, BarycentricMapping, SubsetMapping and IdentityMapping carrying masses and forces
// back to their inputs, FixedProjectiveConstraint and its older name FixedConstraint: the
// inputs' states after 20 steps are SOFA HEAD's (2a278d8, `sofa-head SCENE 20 OUT`, %.17g), bit
// for bit. The mapped points as built (local points, positions matched by radius), the
// `penalty info` lines, the fixed DOFs' velocity, and the refusals naming the file, line,
// component and attribute.
#include "builder_scenes.hpp"

#include "penalty/mechanics/state.hpp"

namespace {

using namespace penalty::test_builder_scenes;
using ::testing::ElementsAre;

const std::string kMapped = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Rigid">
    <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="50" tolerance="1e-15" threshold="1e-15"/>
    <MechanicalObject template="Rigid3d" name="frame" position="0 0 0 0 0 0 1"/>
    <UniformMass totalMass="1"/>
    <Node name="Points">
      <MechanicalObject name="points" position="1 0 0  0 0.5 0.2"/>
      <UniformMass totalMass="0.4"/>
      <RigidMapping/>
    </Node>
  </Node>
  <Node name="Tet">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="50" tolerance="1e-15" threshold="1e-15"/>
    <MechanicalObject name="tet" position="0 0 0  1 0 0  0 1 0  0 0 1"/>
    <MeshTopology tetrahedra="0 1 2 3"/>
    <UniformMass totalMass="1"/>
    <TetrahedronFEMForceField youngModulus="1000" poissonRatio="0.3"/>
    <FixedProjectiveConstraint indices="0 1"/>
    <Node name="Bary">
      <MechanicalObject name="inside" position="0.2 0.2 0.2  0.1 0.6 0.1"/>
      <UniformMass totalMass="0.5"/>
      <BarycentricMapping/>
    </Node>
  </Node>
  <Node name="Sub">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="50" tolerance="1e-15" threshold="1e-15"/>
    <MechanicalObject name="chain" position="0 0 0  1 0 0  2 0 0"/>
    <MeshTopology edges="0 1  1 2"/>
    <UniformMass totalMass="0.3"/>
    <MeshSpringForceField stiffness="50"/>
    <FixedConstraint indices="0"/>
    <Node name="End">
      <MechanicalObject name="end" position="2 0 0"/>
      <SubsetMapping indices="2"/>
      <ConstantForceField forces="1 0 0"/>
    </Node>
    <Node name="Copy">
      <MechanicalObject name="copy"/>
      <IdentityMapping/>
      <ConstantForceField forces="0 3 0  0 0 0  0 0 2"/>
    </Node>
  </Node>
</Node>)";

const BaseState& mapped_state_at(const scene::Scene& s, const std::string& node_path) {
    for (const auto& r : s.states())
        if (r.node_path == node_path) return *r.state;
    throw std::logic_error("no state at " + node_path);
}
const std::vector<Vec3>& mapped_points_at(const scene::Scene& s, const std::string& node_path) {
    return dynamic_cast<const Vec3Object&>(mapped_state_at(s, node_path)).position;
}

TEST(MappingsAndConstraints, MappedMassesAndForcesMoveTheirInputsAsSofaHead) {
    auto s = build(kMapped);
    for (int k = 0; k < 20; ++k) s->step();
    const auto& frame = dynamic_cast<const Rigid3Object&>(mapped_state_at(*s, "/Rigid")).position.at(0);
    EXPECT_EQ(frame.center, Vec3(-3.3175435042643769e-19, -0.20600999999999994, -3.9933368298303993e-19));
    EXPECT_EQ(frame.orientation.coeffs(),
              Eigen::Vector4d(2.9528402339342366e-18, -3.713180682526039e-20, -3.50190320308448e-18, 1));
    EXPECT_THAT(mapped_points_at(*s, "/Tet"),
                ElementsAre(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0.97517950592613178, 0.098599839042017995),
                            Vec3(0, -0.12371110428835244, 1.0034846867108054)));
    EXPECT_THAT(mapped_points_at(*s, "/Sub"),
                ElementsAre(Vec3(0, 0, 0), Vec3(1.014091250012507, -0.18591743338873701, 0.03660426005076662),
                            Vec3(1.987718356386371, -0.20335291278422282, 0.37788289677922826)));
    // the outputs follow their inputs
    EXPECT_EQ(mapped_points_at(*s, "/Sub/End")[0], mapped_points_at(*s, "/Sub")[2]);
    EXPECT_EQ(mapped_points_at(*s, "/Sub/Copy"), mapped_points_at(*s, "/Sub"));
}

TEST(MappingsAndConstraints, EachSaysWhatItMapsOrFixesInPenaltyInfo) {
    auto s = build(kMapped);
    const io::SceneNode& root = *s->file().root;
    EXPECT_EQ(s->role(*root.children[0]->children[0]->components[2]),
              "maps /Rigid onto this node's 2 points (rigid: points fixed in the frames)");
    EXPECT_EQ(s->role(*root.children[1]->children[0]->components[2]),
              "maps /Tet onto this node's 2 points (barycentric: in the input's tetrahedra)");
    EXPECT_EQ(s->role(*root.children[1]->components[6]), "fixes 2 of 4 DOFs");
    EXPECT_EQ(s->role(*root.children[2]->components[6]), "fixes 1 of 3 DOFs");
    EXPECT_EQ(s->role(*root.children[2]->children[0]->components[1]),
              "maps /Sub onto this node's 1 point (subset: one input point per output point)");
    EXPECT_EQ(s->role(*root.children[2]->children[1]->components[1]), "maps /Sub onto this node's 3 points (identity)");
    auto all =
        build(R"(<Node name="root"><MechanicalObject position="0 0 0  1 0 0"/><FixedConstraint fixAll="1"/></Node>)");
    EXPECT_EQ(all->role(*all->file().root->components[1]), "fixes all 2 DOFs");
}

TEST(MappingsAndConstraints, RigidMappingPointsAreLocalOrWorldAndSubsetsMatchByPosition) {
    // the frame at (1, 0, 0) turned 90° about z: local (1, 0, 0) is world (1, 1, 0)
    const std::string frame = R"(<Node name="root" gravity="0 0 0">
  <Node name="R">
    <MechanicalObject template="Rigid3d" position="1 0 0  0 0 0.70710678118654757 0.70710678118654757"/>
    <Node name="P">
      <MechanicalObject position="1 0 0"/>
      )";
    auto local = build(frame + "<RigidMapping/>\n    </Node>\n  </Node>\n</Node>");
    EXPECT_TRUE(mapped_points_at(*local, "/R/P")[0].isApprox(Vec3(1, 1, 0), 1e-15));
    auto world = build(frame + "<RigidMapping globalToLocalCoords=\"1\"/>\n    </Node>\n  </Node>\n</Node>");
    EXPECT_TRUE(mapped_points_at(*world, "/R/P")[0].isApprox(Vec3(1, 0, 0), 1e-15));  // where it was written
    auto given = build(frame + "<RigidMapping initialPoints=\"0 2 0\"/>\n    </Node>\n  </Node>\n</Node>");
    EXPECT_TRUE(mapped_points_at(*given, "/R/P")[0].isApprox(Vec3(-1, 0, 0), 1e-15));
    EXPECT_EQ(error_of(frame + "<RigidMapping initialPoints=\"0 2\"/>\n    </Node>\n  </Node>\n</Node>"),
              "test.scn:6: RigidMapping: attribute 'initialPoints': expected 3 numbers per point, found 2");
    // SubsetMapping without indices: the nearest input point closer than radius
    const std::string subset = R"(<Node name="root">
  <Node name="A">
    <MechanicalObject position="0 0 0  1 0 0  2 0 0"/>
    <Node name="S">
      <MechanicalObject position="2 0.001 0  0 0 0"/>
      )";
    auto matched = build(subset + "<SubsetMapping radius=\"0.01\"/>\n    </Node>\n  </Node>\n</Node>");
    EXPECT_THAT(mapped_points_at(*matched, "/A/S"), ElementsAre(Vec3(2, 0, 0), Vec3(0, 0, 0)));
    EXPECT_EQ(error_of(subset + "<SubsetMapping/>\n    </Node>\n  </Node>\n</Node>"),
              "test.scn:6: SubsetMapping: output point 0 matches no input point within radius 1e-05 (SOFA would "
              "leave it fixed)");
}

TEST(MappingsAndConstraints, FixedDofsKeepTheirVelocityUnlessProjected) {
    // SOFA HEAD after 2 steps: the fixed point, given a velocity, moves with it (the constraint
    // projects the solve's dv only), unless activate_projectVelocity sets it to 0 after each step
    const auto after_steps = [](const std::string& attributes) {
        auto s = build(R"(<Node name="root" dt="0.1" gravity="0 -10 0">
  <EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-20" threshold="1e-20"/>
  <MechanicalObject name="dofs" position="0 0 0  1 0 0" velocity="1 0 0  0 0 0"/>
  <UniformMass totalMass="2"/>
  <FixedProjectiveConstraint indices="0" )" +
                       attributes + R"(/>
</Node>)");
        s->step();
        s->step();
        const auto& state = dynamic_cast<const Vec3Object&>(*s->simulation().root().state());
        return std::pair{state.position, state.velocity};
    };
    const auto kept = after_steps("");
    EXPECT_THAT(kept.first, ElementsAre(Vec3(0.20000000000000001, 0, 0), Vec3(1, -0.30000000000000004, 0)));
    EXPECT_EQ(kept.second[0], Vec3(1, 0, 0));
    const auto projected = after_steps("activate_projectVelocity=\"1\"");
    EXPECT_THAT(projected.first, ElementsAre(Vec3(0, 0, 0), Vec3(1, -0.30000000000000004, 0)));
    EXPECT_EQ(projected.second[0], Vec3(0, 0, 0));
}

TEST(MappingsAndConstraints, BadMappingsAndConstraintsAreRefusedNamingTheAttribute) {
    const auto child = [](const std::string& parent_state, const std::string& child_body) {
        return "<Node name=\"root\">\n  <Node name=\"A\">\n    " + parent_state + "\n    <Node name=\"B\">\n      " +
               child_body + "\n    </Node>\n  </Node>\n</Node>\n";
    };
    const std::string points = R"(<MechanicalObject name="p" position="0 0 0  1 0 0  0 1 0"/>)";
    EXPECT_EQ(error_of(child(points, "<IdentityMapping/>")),
              "test.scn:5: IdentityMapping: needs a MechanicalObject in its node (its output)");
    EXPECT_EQ(error_of(child(points + "<UniformMass name=\"m\" totalMass=\"1\"/>",
                             "<MechanicalObject/><IdentityMapping input=\"@../m\"/>")),
              "test.scn:5: IdentityMapping: attribute 'input': must link to a node or a MechanicalObject");
    EXPECT_EQ(error_of(child(points, "<MechanicalObject/><IdentityMapping output=\"@../p\"/>")),
              "test.scn:5: IdentityMapping: attribute 'output': must be the MechanicalObject of the mapping's own "
              "node");
    EXPECT_EQ(error_of(child(points, "<MechanicalObject/><RigidMapping/>")),
              "test.scn:5: RigidMapping: attribute 'input': RigidMapping needs a Rigid3d input");
    EXPECT_EQ(error_of(child(points, "<MechanicalObject/><BarycentricMapping/>")),
              "test.scn:5: BarycentricMapping: attribute 'input': the input's node has no topology to map onto");
    EXPECT_EQ(
        error_of(child(points + "<MeshTopology triangles=\"0 1 2\"/>", "<MechanicalObject/><BarycentricMapping/>")),
        "test.scn:5: BarycentricMapping: the input topology has no tetrahedra or hexahedra (penalty maps onto "
        "volumes only)");
    EXPECT_EQ(error_of(child(R"(<MechanicalObject template="Rigid3d" position="0 0 0 0 0 0 1"/>)",
                             "<MechanicalObject template=\"Rigid3d\"/><RigidMapping initialPoints=\"0 0 0 0 0\"/>")),
              "test.scn:5: RigidMapping: attribute 'initialPoints': expected 7 numbers (x y z qx qy qz qw) per frame, "
              "found 5");
    EXPECT_EQ(
        error_of("<Node name=\"root\">\n  " + points + "\n  <FixedProjectiveConstraint indices=\"1 3\"/>\n</Node>\n"),
        "test.scn:3: FixedProjectiveConstraint: attribute 'indices': index 3 out of range (3 DOFs)");
}

}  // namespace
