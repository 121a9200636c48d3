// The wiring of the components that follow a dynamic topology (src/scene/topology/
// component_followers.cpp): UniformMass keeping its mass per point through removals and an
// addition (against SOFA HEAD) unless preserveTotalMass; a BarycentricMapping's points mapped
// again onto the tetrahedra left (an affine motion of the body carried exactly, also by an
// extrapolated point); an IdentityMapping onto a state of the same points; line and tetrahedron
// collision models taking the elements left; what has no rule blocking the topology, named, with
// the topology it uses when that is another one.
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

namespace penalty {
namespace {

std::string cf_refusal(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}

Vec3Object& cf_state(const scene::Scene& s, const std::string& name) {
    for (const auto& r : s.states())
        if (r.state->state_name() == name) return dynamic_cast<Vec3Object&>(*r.state);
    ADD_FAILURE() << "no state " << name;
    return dynamic_cast<Vec3Object&>(*s.states().at(0).state);
}

/// The 2×2×2-cell tetrahedral cube (side 0.2 m) in node "body": `solver`, the container
/// "volume" with its modifier, the state "dofs" and `components`.
std::string cf_body(const std::string& components, const std::string& solver = "") {
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><DefaultAnimationLoop/><Node name="body">)" + solver +
           R"(
  <TetrahedronSetTopologyContainer name="volume" position=")" +
           test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  )" + components +
           "\n</Node></Node>\n";
}

// SOFA HEAD (2a278d8), `sofa-head SCENE 20 OUT --every 1`: the cube hanging from its x = 0 face,
// UniformMass totalMass 1 (1/27 kg a point), tetrahedra 0 and 4 removed at t = 0.02 (point 0
// goes), tetrahedron (1 3 9 13) added again at t = 0.04: every point keeps 1/27 kg, and the
// positions of every step are SOFA HEAD's bit for bit (three after step 20 here).
TEST(ComponentFollowers, UniformMassKeepsItsMassPerPointThroughChangesAsSofaHead) {
    const auto dir = std::filesystem::temp_directory_path() / "penalty_component_followers";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "changes.txt") << "T= 0.02\n  REMOVE= 2\n0 4\nT= 0.04\n  ADD= Tetrahedra 1\n1 3 9 13\n";
    auto s = test::build(cf_body(R"(<UniformMass name="mass" totalMass="1"/>
  <TetrahedronFEMForceField youngModulus="2000" poissonRatio="0.3" method="large"/>
  <FixedProjectiveConstraint indices="3 6 9 12 15 18 21 24"/>
  <TopologicalChangeProcessor filename=")" +
                                     (dir / "changes.txt").string() + R"("/>)",
                                 R"(
  <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
  <CGLinearSolver iterations="200" tolerance="1e-20" threshold="1e-20"/>)"));
    for (int k = 0; k < 20; ++k) s->step();
    const Vec3Object& x = cf_state(*s, "dofs");
    ASSERT_EQ(x.num_dofs(), 26u);
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 39u);
    EXPECT_DOUBLE_EQ(s->simulation().root().children()[0]->mass()->total_mass(), 26.0 / 27.0);
    EXPECT_EQ(x.position[0], Vec3(0.22483021249157858, 0.080571439090283151, 0.19259416491508111));
    EXPECT_EQ(x.position[13], Vec3(0.095119190359992556, 0.055290310798487535, 0.097689818440220802));
    EXPECT_EQ(x.position[25], Vec3(0.1239646251420312, 0.14452504725125567, 0.19495791953617297));

    // preserveTotalMass: no rule, the topology is blocked
    auto kept = test::build(cf_body(R"(<UniformMass name="mass" totalMass="1" preserveTotalMass="1"/>)"));
    EXPECT_EQ(cf_refusal([&] { kept->remove_elements("volume", ElementType::tetrahedron, {0}); }),
              "topology '/body/volume' cannot change: UniformMass 'mass' (test.scn:5) does not follow topological "
              "changes");
}

TEST(ComponentFollowers, ABarycentricMappingMapsItsPointsAgainOntoTheTetrahedraLeft) {
    // markers in tetrahedron 0's corner of the cube (removed with its corner point) and inside
    // the cube; after removals each is mapped onto a tetrahedron left (extrapolated for the first):
    // an affine motion x → A·x + b of the body moves every marker to A·x0 + b exactly
    auto s = test::build(cf_body(R"(<UniformMass totalMass="1"/>
  <Node name="inside">
    <MechanicalObject name="markers" position="0.01 0.01 0.01  0.15 0.1 0.05  0.05 0.17 0.13"/>
    <BarycentricMapping name="embed"/>
  </Node>)"));
    const std::vector<Vec3> rest{Vec3(0.01, 0.01, 0.01), Vec3(0.15, 0.1, 0.05), Vec3(0.05, 0.17, 0.13)};
    s->remove_elements("volume", ElementType::tetrahedron, {0, 4, 1, 2, 3});  // cell 0 is gone
    Vec3Object& x = cf_state(*s, "dofs");
    Vec3Object& markers = cf_state(*s, "markers");
    ASSERT_EQ(x.num_dofs(), 26u);
    Mat3 a;
    a << 1.1, 0.2, -0.1, 0.05, 0.9, 0.3, -0.2, 0.1, 1.2;
    const Vec3 b(0.3, -0.4, 0.5);
    for (std::size_t i = 0; i < x.num_dofs(); ++i) x.position[i] = a * x.rest_position[i] + b;
    s->simulation().root().children()[0]->children()[0]->mapping()->apply_position();
    for (std::size_t i = 0; i < rest.size(); ++i)
        EXPECT_LT((markers.position[i] - (a * rest[i] + b)).norm(), 1e-14) << i;
}

TEST(ComponentFollowers, AnIdentityMappingOntoTheSamePointsAndCollisionModelsFollow) {
    // an IdentityMapping into a child state on the body's topology follows the same points; the
    // line model on an edge container and the tetrahedron model take the elements left
    auto s = test::build(cf_body(R"(<UniformMass totalMass="1"/>
  <TetrahedronCollisionModel name="cells"/>
  <Node name="copy">
    <MechanicalObject name="copied"/>
    <IdentityMapping/>
  </Node>)"));
    s->remove_elements("volume", ElementType::tetrahedron, {0, 38});  // the corners 0 and 26 go
    EXPECT_EQ(cf_state(*s, "copied").num_dofs(), 25u);
    EXPECT_EQ(cf_state(*s, "dofs").num_dofs(), 25u);
    ASSERT_EQ(s->collision_models().size(), 1u);
    EXPECT_EQ(s->collision_models()[0].model->size(), 38u);

    auto wire = test::build(R"(<Node name="root"><Node name="wire">
  <EdgeSetTopologyContainer name="edges" position="0 0 0  1 0 0  2 0 0  3 0 0" edges="0 1  1 2  2 3"/>
  <EdgeSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="1"/>
  <LineCollisionModel name="lines"/>
</Node></Node>)");
    wire->remove_elements("edges", ElementType::edge, {1});
    ASSERT_EQ(wire->collision_models().size(), 1u);
    const auto* lines = dynamic_cast<const LineModel*>(wire->collision_models()[0].model.get());
    ASSERT_NE(lines, nullptr);
    EXPECT_EQ(lines->size(), 2u);
    EXPECT_EQ(cf_state(*wire, "dofs").num_dofs(), 4u);  // no point is left alone
}

TEST(ComponentFollowers, AFollowerOnAnotherTopologyOfTheStateBlocksNamingIt) {
    // a triangle container of its own in a child node (not a topological mapping's output), a
    // TriangularFEMForceField on it acting on the body's state: the body's removal would renumber
    // the points the triangles name
    auto s = test::build(cf_body(R"(<UniformMass totalMass="1"/>
  <Node name="skin">
    <TriangleSetTopologyContainer name="patch" triangles="0 1 3"/>
    <TriangleSetTopologyModifier/>
    <TriangularFEMForceField name="membrane" youngModulus="100" poissonRatio="0.3"/>
  </Node>)"));
    EXPECT_EQ(cf_refusal([&] { s->remove_elements("volume", ElementType::tetrahedron, {0}); }),
              "topology '/body/volume' cannot change: TriangularFEMForceField 'membrane' (test.scn:9) (its topology "
              "is /body/skin/patch) does not follow topological changes");
    // a MeshMatrixMass lumped on edges has no rule
    auto edges = test::build(R"(<Node name="root"><Node name="wire">
  <EdgeSetTopologyContainer name="edges" position="0 0 0  1 0 0  2 0 0" edges="0 1  1 2"/>
  <EdgeSetTopologyModifier/>
  <MechanicalObject/>
  <MeshMatrixMass name="m" massDensity="1"/>
</Node></Node>)");
    EXPECT_EQ(cf_refusal([&] { edges->remove_elements("edges", ElementType::edge, {0}); }),
              "topology '/wire/edges' cannot change: MeshMatrixMass 'm' (test.scn:5) does not follow topological "
              "changes");
}

}  // namespace
}  // namespace penalty
