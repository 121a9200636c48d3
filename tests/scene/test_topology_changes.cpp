// The builder of the components that change a topology while the scene runs
// (scene/builder/topology_changes.cpp): TopologicalChangeProcessor, TopologyBoundingTrasher and
// CarvingManager are checked and described at the build, then act (a point falling from rest
// under g = 10 with dt = 0.01 is at y = −0.0005·n(n+1) after n steps: its triangle's barycentre
// leaves the trasher's box at step 48, not 47); the refusals name the file, line, component and
// attribute. What the changes do to the components that follow a topology is
// test_topological_changes.cpp's.
#include "builder_scenes.hpp"

#include "penalty/mechanics/state.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <filesystem>
#include <fstream>

namespace {

using namespace penalty::test_builder_scenes;

/// Three triangles over five points, four of them fixed, under g = 10, with `changer` in the node
/// (line 8).
std::string changing_cloth(const std::string& changer) {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Cloth">
    <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
    <TriangleSetTopologyContainer name="topo" position="0 0 0  1 0 0  0 1 0  1 1 0  2 0 0" triangles="0 1 2  1 3 2  1 4 3"/>
    <TriangleSetTopologyModifier/>
    <MechanicalObject name="cloth"/>
    )" + changer +
           R"(
    <UniformMass vertexMass="0.1"/>
    <FixedProjectiveConstraint indices="0 1 2 3"/>
  </Node>
</Node>
)";
}

const std::string& changer_role(const scene::Scene& s) {
    static std::string role;
    role = s.role(*s.file().root->children[0]->components[5]);
    return role;
}

TEST(TopologyChanges, TheTrasherRemovesTheTriangleWhoseBarycentreLeavesItsBox) {
    auto s = build(changing_cloth(R"(<TopologyBoundingTrasher box="-1 -0.05 -1 3 2 1"/>)"));
    EXPECT_EQ(changer_role(*s), "removes, at each step's end, the elements whose barycentre leaves its box");
    for (int k = 0; k < 47; ++k) s->step();
    // point 4 at y = −0.0005·47·48 = −1.128: the barycentre of (1, 4, 3) at y = −0.0427, inside
    EXPECT_EQ(s->topology_container("topo").mesh().triangles().size(), 3u);
    EXPECT_NEAR(dynamic_cast<const Vec3Object&>(*s->states()[0].state).position[4].y(), -1.128, 1e-12);
    s->step();  // y = −1.176: the barycentre at −0.0587, below the box's −0.05
    EXPECT_EQ(s->topology_container("topo").mesh().triangles().size(), 2u);
    EXPECT_EQ(s->states()[0].state->num_dofs(), 4u);  // the point no triangle uses any more goes too
}

TEST(TopologyChanges, TheProcessorRemovesItsListedElementsAfterTheirTime) {
    auto s = build(
        changing_cloth(R"(<TopologicalChangeProcessor useDataInputs="1" timeToRemove="0.02" trianglesToRemove="0"/>)"));
    EXPECT_EQ(changer_role(*s), "removes the listed elements of its topology after timeToRemove");
    s->step();
    EXPECT_EQ(s->topology_container("topo").mesh().triangles().size(), 3u);
    for (int k = 0; k < 4; ++k) s->step();
    EXPECT_EQ(s->topology_container("topo").mesh().triangles().size(), 2u);
    EXPECT_EQ(s->states()[0].state->num_dofs(), 4u);  // point 0 was in triangle 0 only
    // from a file of timed commands (SOFA's format)
    const auto dir = temp_dir("topology_changes");
    std::filesystem::create_directories(dir);
    const auto file = dir / "changes.txt";
    std::ofstream(file) << "T= 0.01\n  REMOVE= 1\n2\n";
    auto f = build(changing_cloth(R"(<TopologicalChangeProcessor filename=")" + file.string() + R"("/>)"));
    EXPECT_EQ(changer_role(*f), "changes its topology at the times of " + file.string());
    for (int k = 0; k < 3; ++k) f->step();
    EXPECT_EQ(f->topology_container("topo").mesh().triangles().size(), 2u);
    EXPECT_EQ(f->states()[0].state->num_dofs(), 4u);  // point 4 was in triangle 2 only
    std::filesystem::remove_all(dir);
}

TEST(TopologyChanges, TheCarvingManagerSaysWhetherItCarves) {
    auto off = build(changing_cloth(R"(<CarvingManager/>)"));
    EXPECT_EQ(changer_role(*off), "inactive (active=\"0\"; no key events headless)");
    EXPECT_EQ(error_of(changing_cloth(R"(<CarvingManager carvingDistance="near"/>)"))
                  .rfind("test.scn:8: CarvingManager: attribute 'carvingDistance'", 0),
              0u);
}

TEST(TopologyChanges, BadDataAreRefusedNamingTheAttribute) {
    EXPECT_EQ(error_of(changing_cloth("<TopologicalChangeProcessor/>")),
              "test.scn:8: TopologicalChangeProcessor: attribute 'filename': names the file of topological changes "
              "(or set useDataInputs)");
    EXPECT_EQ(error_of(changing_cloth(R"(<TopologicalChangeProcessor useDataInputs="1" interval="-1"/>)")),
              "test.scn:8: TopologicalChangeProcessor: attribute 'interval': must be >= 0, found '-1'");
    EXPECT_EQ(
        error_of(changing_cloth(R"(<TopologyBoundingTrasher box="0 0 0 1 1"/>)")),
        "test.scn:8: TopologyBoundingTrasher: attribute 'box': expected 6 numbers: xmin ymin zmin xmax ymax zmax");
    EXPECT_EQ(
        error_of(changing_cloth(R"(<TopologyBoundingTrasher box="0 0 0 1 1 1 1"/>)")),
        "test.scn:8: TopologyBoundingTrasher: attribute 'box': expected 6 numbers: xmin ymin zmin xmax ymax zmax");
}

TEST(TopologyChanges, AttributesTheyDoNotReadAreNoted) {
    auto s = build(changing_cloth(R"(<TopologyBoundingTrasher box="-1 -1 -1 3 2 1" colour="red"/>)"));
    bool noted = false;
    for (const std::string& w : s->warnings()) noted = noted || w.find("colour") != std::string::npos;
    EXPECT_TRUE(noted);
}

}  // namespace
