// TopologyRuntime (src/scene/topology/topology_runtime.cpp), through a built scene: the change
// sources run at the start and at the end of a step (a TopologicalChangeProcessor at the
// AnimateBeginEvent, then the components' doUpdateInternal; a TopologyBoundingTrasher at the
// AnimateEndEvent), the graph told when a topology changed, the dynamic topologies found by path,
// name or node path (ambiguous and unknown names refused with the candidates), a change refused
// before anything changes when a component cannot follow it (also through a topological mapping's
// output), when it would leave a BarycentricMapping no element, or when a new element is
// degenerate at rest.
#include "penalty/mechanics/diagonal_mass.hpp"
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

using ::testing::HasSubstr;

/// The 2×2×2-cell tetrahedral cube of side 0.2 m (27 points, 40 tetrahedra) in node `node`:
/// `head` (a solver), the container "volume", a modifier, a state and `components`.
std::string tr_body(const std::string& components, const std::string& node = "body", const std::string& head = "") {
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    return R"(<Node name=")" + node + R"(">)" + head + R"(
  <TetrahedronSetTopologyContainer name="volume" position=")" +
           test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  )" + components +
           "\n</Node>";
}

std::string tr_root(const std::string& nodes) {
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01">)" + nodes + "</Node>\n";
}

/// A file of `text` in a fresh folder (its path).
std::string tr_file(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "penalty_topology_runtime";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / name) << text;
    return (dir / name).string();
}

/// The message of the std::invalid_argument `f` raises ("no error" when none).
std::string tr_refusal(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}

Vec3Object& tr_state(scene::Scene& s) { return dynamic_cast<Vec3Object&>(*s.states().at(0).state); }

// SOFA HEAD (2a278d8), this scene with its change file, `sofa-head SCENE 30 OUT --every 1`: the
// processor removes tetrahedron 0 (its corner point 0 goes with it) at the start of the step from
// t = 0.02 and tetrahedra 5 and 7 (a point goes) at the start of the step from t = 0.04; the state
// has 27, 27, 27, 26, 26, 25 ... points after steps 0 to 5. DiagonalMass's density is taken
// again from its vertex masses after each point removal (its doUpdateInternal, which the runtime
// runs after the sources): without it the states part from SOFA's at step 5 (1.5e-13, 7.5e-12 at
// step 30). Every position at every step of 30 is SOFA HEAD's, bit for bit; three of step 30 here.
TEST(TopologyRuntime, AProcessorChangesAtTheStartOfItsStepAndTheMassTakesSofasDensityAsSofaHead) {
    const std::string file = tr_file("processor.txt", "T= 0.02\n  REMOVE= 1\n0\nT= 0.04\n  REMOVE= 2\n5 7\n");
    auto s = test::build(tr_root("<DefaultAnimationLoop/>" + tr_body(R"(
  <DiagonalMass massDensity="1000"/>
  <TetrahedronFEMForceField youngModulus="2000" poissonRatio="0.3" method="large"/>
  <FixedProjectiveConstraint indices="3 6 9 12 15 18 21 24"/>
  <TopologicalChangeProcessor filename=")" + file + R"("/>)",
                                                                     "body", R"(
  <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
  <CGLinearSolver iterations="200" tolerance="1e-20" threshold="1e-20"/>)")));
    Vec3Object& x = tr_state(*s);
    const std::uint64_t structure = s->simulation().root().structure_version();
    std::vector<std::size_t> sizes{x.num_dofs()};
    std::vector<std::uint64_t> revisions{s->topology_revision()};
    std::vector<std::uint64_t> structures{s->simulation().root().structure_version()};
    for (int k = 0; k < 30; ++k) {
        s->step();
        sizes.push_back(x.num_dofs());
        revisions.push_back(s->topology_revision());
        structures.push_back(s->simulation().root().structure_version());
    }
    EXPECT_EQ(std::vector<std::size_t>(sizes.begin(), sizes.begin() + 7),
              (std::vector<std::size_t>{27, 27, 27, 26, 26, 25, 25}));
    EXPECT_EQ(sizes.back(), 25u);
    // the revision moves at the steps of the changes only, and the graph is told then
    for (std::size_t k = 1; k < revisions.size(); ++k) {
        const bool change = k == 3 || k == 5;
        EXPECT_EQ(revisions[k] != revisions[k - 1], change) << "step " << k;
        EXPECT_EQ(structures[k] != structures[k - 1], change) << "step " << k;
    }
    EXPECT_NE(structures.back(), structure);
    EXPECT_EQ(x.position[5], Vec3(0.12341545454727484, -0.26411943868430593, 0.0078278684136142661));
    EXPECT_EQ(x.position[13], Vec3(0.073299177528194454, -0.13634302861150019, 0.096048753499582196));
    EXPECT_EQ(x.position[20], Vec3(0.051098907232188427, -0.32567285458782591, 0.18103243446837117));
}

// SOFA HEAD (2a278d8), this scene, `sofa-head SCENE 30 OUT --every 1`: a free fall (no force
// field: the body keeps its shape) through the box's floor y = −0.05; the trasher removes, at the
// end of each step (AnimateEndEvent), the tetrahedra whose centre is below it. The state has 27
// points after steps 0 to 11, 22 after 12 to 15, 18 after 16 to 18, 14 after 19 and 20, none from
// step 21: SOFA HEAD's sizes (its positions, a free fall, are penalty's bit for bit at every step:
// `penalty run --compare-trajectory`). A removal at the next step's start would be one step late.
TEST(TopologyRuntime, ATrasherRemovesAtTheEndOfTheStepTheElementsWhoseCentreLeftItsBoxAsSofaHead) {
    auto s = test::build(tr_root(tr_body(R"(<UniformMass vertexMass="1"/>
  <TopologyBoundingTrasher position="@dofs.position" box="-1 -0.05 -1 1 1 1"/>)",
                                         "body", R"(
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>)")));
    const TopologyContainer& c = s->topology_container("volume");
    const Vec3Object& x = tr_state(*s);
    std::vector<std::size_t> sizes;
    for (int k = 1; k <= 30; ++k) {
        s->step();
        sizes.push_back(x.num_dofs());
        for (const Tetrahedron& t : c.mesh().tetrahedra()) {
            double centre = 0;
            for (const PointId p : t) centre += x.position[std::size_t(p)].y() / 4;
            ASSERT_GE(centre, -0.05) << "step " << k;
        }
        if (k == 11) {
            // a free fall: y = y0 − g·h²·k(k+1)/2 (implicit Euler), the same for every point
            EXPECT_NEAR(x.position[0].y(), -9.81 * 0.01 * 0.01 * 66, 1e-15);
        }
    }
    std::vector<std::size_t> expected(30, 0);
    std::fill(expected.begin(), expected.begin() + 11, 27);
    std::fill(expected.begin() + 11, expected.begin() + 15, 22);
    std::fill(expected.begin() + 15, expected.begin() + 18, 18);
    std::fill(expected.begin() + 18, expected.begin() + 20, 14);
    EXPECT_EQ(sizes, expected);
    EXPECT_TRUE(c.mesh().tetrahedra().empty());
}

TEST(TopologyRuntime, TopologiesAreFoundByPathNameOrNodeAndAmbiguousOrUnknownNamesAreRefused) {
    auto s = test::build(tr_root(tr_body(R"(<UniformMass totalMass="1"/>
  <Node name="border">
    <TriangleSetTopologyContainer name="surface"/>
    <TriangleSetTopologyModifier/>
    <Tetra2TriangleTopologicalMapping input="@../volume" output="@surface"/>
  </Node>)") + tr_body(R"(<UniformMass totalMass="1"/>)", "other")));
    EXPECT_EQ(s->dynamic_topologies(),
              (std::vector<std::string>{"/body/volume", "/body/border/surface", "/other/volume"}));
    const TopologyContainer* surface = &s->topology_container("/body/border/surface");
    EXPECT_EQ(&s->topology_container("surface"), surface);
    EXPECT_EQ(&s->topology_container("/body/border"), surface);
    EXPECT_EQ(&s->topology_container("/body"), &s->topology_container("/body/volume"));
    EXPECT_EQ(&s->topology_container("/other"), &s->topology_container("/other/volume"));
    EXPECT_NE(&s->topology_container("/other"), &s->topology_container("/body"));
    EXPECT_EQ(surface->mesh().triangles().size(), 48u);  // 6 faces of 2×2 squares, 2 triangles each
    EXPECT_EQ(tr_refusal([&] { (void)s->topology_container("volume"); }),
              "topology 'volume' is ambiguous: '/body/volume' and '/other/volume' (give the path)");
    EXPECT_EQ(tr_refusal([&] { s->remove_elements("volume", ElementType::tetrahedron, {0}); }),
              "topology 'volume' is ambiguous: '/body/volume' and '/other/volume' (give the path)");
    EXPECT_EQ(tr_refusal([&] { (void)s->topology_container("nothing"); }),
              "no topology 'nothing' can change in this scene (those that can: /body/volume, "
              "/body/border/surface, /other/volume)");

    // a container of the root node: found by "/"
    const test::TetraCube cube = test::tetra_cube(1, 1.0);
    auto root =
        test::build(R"(<Node name="root"><TetrahedronSetTopologyContainer name="mesh" position=")" +
                    test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/>
  <TetrahedronSetTopologyModifier/><MechanicalObject/><UniformMass totalMass="1"/></Node>)");
    EXPECT_EQ(root->dynamic_topologies(), std::vector<std::string>{"/mesh"});
    EXPECT_EQ(&root->topology_container("/"), &root->topology_container("mesh"));

    // none can change: the refusal says so
    auto fixed =
        test::build(R"(<Node name="root"><MeshTopology name="mesh" position=")" + test::points_text(cube.points) +
                    R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/><MechanicalObject/></Node>)");
    EXPECT_TRUE(fixed->dynamic_topologies().empty());
    EXPECT_EQ(fixed->topology_revision(), 0u);
    EXPECT_EQ(tr_refusal([&] { fixed->remove_elements("mesh", ElementType::tetrahedron, {0}); }),
              "no topology 'mesh' can change in this scene (none has a topology modifier)");
}

TEST(TopologyRuntime, AChangeIsRefusedByTheFirstComponentThatCannotFollowItAlsoThroughAMappingsOutput) {
    // a PlaneForceField on the body's state blocks the body's volume; in the edge node below the
    // surface it also blocks the edges, which the surface's changes reach (Triangle2Edge)
    // the body's surface (Tetra2Triangle) and its edges (Triangle2Edge), `wire_extra` in the edge node
    const auto surface_and_edges = [](const std::string& wire_extra) {
        return tr_root(tr_body(R"(<UniformMass totalMass="1"/>
  <Node name="border">
    <TriangleSetTopologyContainer name="surface"/>
    <TriangleSetTopologyModifier/>
    <Tetra2TriangleTopologicalMapping input="@../volume" output="@surface"/>
    <Node name="wire">
      <EdgeSetTopologyContainer name="edges"/>
      <EdgeSetTopologyModifier/>
      <Triangle2EdgeTopologicalMapping input="@../surface" output="@edges"/>
      )" + wire_extra + R"(
    </Node>
  </Node>)"));
    };
    auto s = test::build(surface_and_edges(R"(<PlaneForceField name="floor"/>)"));
    const std::uint64_t revision = s->topology_revision();
    EXPECT_EQ(tr_refusal([&] { s->remove_elements("volume", ElementType::tetrahedron, {3}); }),
              "topology '/body/volume' cannot change: PlaneForceField 'floor' (test.scn:14) does not follow "
              "topological changes");
    EXPECT_EQ(tr_refusal([&] { s->remove_elements("surface", ElementType::triangle, {3}); }),
              "topology '/body/border/wire/edges' cannot change: PlaneForceField 'floor' (test.scn:14) does not "
              "follow topological changes");
    EXPECT_EQ(tr_refusal([&] {
                  s->add_elements("surface", ElementType::triangle, {0, 1, 4});
              }),
              "topology '/body/border/wire/edges' cannot change: PlaneForceField 'floor' (test.scn:14) does not "
              "follow topological changes");
    EXPECT_EQ(s->topology_revision(), revision);  // nothing changed
    EXPECT_EQ(s->topology_container("surface").mesh().triangles().size(), 48u);
    EXPECT_EQ(s->topology_container("edges").mesh().edges().size(), 0u);  // a closed surface has no border

    // without the plane: the surface's removal reaches the edges (the removed triangle's three
    // edges are border edges now)
    auto free = test::build(surface_and_edges(""));
    const std::uint64_t before = free->topology_revision();
    free->remove_elements("surface", ElementType::triangle, {3});
    EXPECT_EQ(free->topology_container("edges").mesh().edges().size(), 3u);
    EXPECT_GT(free->topology_revision(), before);
}

TEST(TopologyRuntime, ARemovalLeavingABarycentricMappingNoTetrahedronIsRefused) {
    auto s = test::build(tr_root(tr_body(R"(<UniformMass totalMass="1"/>
  <Node name="inside">
    <MechanicalObject name="marker" position="0.05 0.05 0.05  0.15 0.1 0.1"/>
    <BarycentricMapping name="embed"/>
  </Node>)")));
    std::vector<ElementId> all(40);
    for (std::size_t e = 0; e < all.size(); ++e) all[e] = ElementId(e);
    EXPECT_EQ(tr_refusal([&] { s->remove_elements("volume", ElementType::tetrahedron, all); }),
              "topology '/body/volume': the removal leaves no tetrahedra, and BarycentricMapping 'embed' "
              "(test.scn:8) maps its points onto them (refused; nothing changed)");
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 40u);
    EXPECT_EQ(tr_state(*s).num_dofs(), 27u);
    // one left: accepted
    all.pop_back();
    s->remove_elements("volume", ElementType::tetrahedron, all);
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 1u);
    EXPECT_EQ(tr_state(*s).num_dofs(), 4u);
}

TEST(TopologyRuntime, ANewElementDegenerateAtRestIsRefusedWithItsVolumeOrArea) {
    auto s = test::build(tr_root(tr_body(R"(<UniformMass totalMass="1"/>)")));
    // points 0, 1, 2 (x = 0, 0.1, 0.2 on the x axis) and 3 (0, 0.1, 0): a flat tetrahedron (0 1 3 4)
    // is fine, (0 1 2 3) has volume 0; the second of two is named by its rank
    const std::uint64_t revision = s->topology_revision();
    EXPECT_EQ(tr_refusal([&] {
                  s->add_elements("volume", ElementType::tetrahedron, {0, 1, 3, 9, 0, 1, 2, 3});
              }),
              "the topology '/body/volume': new tetrahedron 1 (0 1 2 3) is degenerate (volume 0)");
    // 1e-13 of the cell's volume: below 1e-12 × the longest edge³ (relative to its size)
    Vec3Object& x = tr_state(*s);
    const Vec3 moved = x.rest_position[13];
    x.rest_position[13] = Vec3(0.1, 0.1, 1e-13);
    const double volume = (x.rest_position[1] - x.rest_position[0])
                              .cross(x.rest_position[3] - x.rest_position[0])
                              .dot(x.rest_position[13] - x.rest_position[0]) /
                          6;
    EXPECT_DOUBLE_EQ(volume, 0.1 * 0.1 * 1e-13 / 6);
    EXPECT_EQ(tr_refusal([&] {
                  s->add_elements("volume", ElementType::tetrahedron, {0, 1, 3, 13});
              }),
              "the topology '/body/volume': new tetrahedron 0 (0 1 3 13) is degenerate (volume 1.666666666666667e-16)");
    x.rest_position[13] = moved;
    EXPECT_EQ(s->topology_revision(), revision);
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 40u);
    // the rest shape decides, not the current positions: flat now, a volume at rest
    x.position[9] = x.position[0];
    s->add_elements("volume", ElementType::tetrahedron, {0, 1, 3, 9});
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 41u);

    // a triangle of three points on a line (area 0); one of positive area is added
    const test::TriangleSheet sheet = test::triangle_sheet(2, 0.1);
    auto t = test::build(
        R"(<Node name="root"><Node name="sheet"><TriangleSetTopologyContainer name="surface" position=")" +
        test::points_text(sheet.points) + R"(" triangles=")" + test::elements_text(sheet.triangles) +
        R"("/><TriangleSetTopologyModifier/><MechanicalObject/><UniformMass totalMass="1"/></Node></Node>)");
    EXPECT_EQ(tr_refusal([&] {
                  t->add_elements("surface", ElementType::triangle, {0, 1, 2});
              }),
              "the topology '/sheet/surface': new triangle 0 (0 1 2) is degenerate (area 0)");
    t->add_elements("surface", ElementType::triangle, {0, 1, 4});
    EXPECT_EQ(t->topology_container("surface").mesh().triangles().size(), 9u);
}

}  // namespace
}  // namespace penalty
