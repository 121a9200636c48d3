// SparseGridTopology in a scene: a closed cube surface written here (an OBJ of quads) voxelised on
// SOFA's default box, its points taken by the MechanicalObject (even one given a single
// position, as SOFA's MechanicalObject::init), a HexahedronFEMForceField on its cells and a
// BarycentricMapping onto it.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/scene/scene.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {

using namespace penalty;

// A scene folder in the temporary directory, removed with the object.
struct CubeSceneFolder {
    std::filesystem::path dir;
    std::filesystem::path scene;
    CubeSceneFolder(std::filesystem::path d, std::filesystem::path s) : dir(std::move(d)), scene(std::move(s)) {}
    CubeSceneFolder(const CubeSceneFolder&) = delete;
    CubeSceneFolder& operator=(const CubeSceneFolder&) = delete;
    ~CubeSceneFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(dir, ignored);
    }
};

CubeSceneFolder write_cube_scene(const std::string& name, const std::string& grid_attributes) {
    const auto dir =
        std::filesystem::temp_directory_path() /
        ("penalty_sparse_grid_" + name + "_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "cube.obj") << "# unit cube, outward quads\n"
                                       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
                                       "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    std::ofstream(dir / "scene.scn") << R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <Node name="Cube">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    <SparseGridTopology fileTopology="cube.obj" )"
                                     << grid_attributes << R"(/>
    <MechanicalObject name="grid" position="0 0 0"/>
    <UniformMass totalMass="1"/>
    <HexahedronFEMForceField youngModulus="1000" poissonRatio="0.3"/>
    <Node name="Points">
      <MechanicalObject name="points" position="0.3 0.55 0.71  0.5 0.5 0.5  1.2 0.5 0.5"/>
      <BarycentricMapping/>
    </Node>
  </Node>
</Node>
)";
    return {dir, dir / "scene.scn"};
}

TEST(SparseGridComponents, CubeVoxelisedOnTheDefaultBoxFeedsStateFemAndMapping) {
    const CubeSceneFolder folder = write_cube_scene("default", "n=\"5 5 5\"");
    auto scene = scene::build_scene(io::parse_scene_file(folder.scene));
    const Node& cube = *scene->simulation().root().children().at(0);
    auto* grid = dynamic_cast<Vec3Object*>(cube.state());
    ASSERT_NE(grid, nullptr);
    // box [−0.01, 1.01]³, 4³ cells all kept, 5³ points x slowest
    ASSERT_EQ(grid->position.size(), 125u);
    const double step = 1.02 / 4;
    EXPECT_EQ(grid->position[0], Vec3::Constant(-0.01));
    EXPECT_EQ(grid->position[1], Vec3(-0.01, -0.01, -0.01 + step));
    EXPECT_EQ(grid->position[5], Vec3(-0.01, -0.01 + step, -0.01));
    EXPECT_EQ(grid->position[25], Vec3(-0.01 + step, -0.01, -0.01));
    const Node& points = *cube.children().at(0);
    auto* mapped = dynamic_cast<Vec3Object*>(points.state());
    ASSERT_NE(mapped, nullptr);
    const std::vector<Vec3> given{{0.3, 0.55, 0.71}, {0.5, 0.5, 0.5}, {1.2, 0.5, 0.5}};
    for (std::size_t i = 0; i < given.size(); ++i)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(mapped->position[i][k], given[i][k], 1e-12) << i;
    for (int i = 0; i < 20; ++i) scene->step();
    for (const Vec3& p : grid->position) EXPECT_TRUE(p.allFinite());
    EXPECT_LT(grid->position[0].y(), -0.01);  // falling
    EXPECT_THAT(scene::describe_scene(*scene), ::testing::HasSubstr("sparse grid 5 x 5 x 5"));
}

TEST(SparseGridComponents, MissingSurfaceFileIsAnErrorNamingTheComponent) {
    const CubeSceneFolder folder = write_cube_scene("missing", "n=\"5 5 5\"");
    std::filesystem::remove(folder.dir / "cube.obj");
    try {
        (void)scene::build_scene(io::parse_scene_file(folder.scene));
        ADD_FAILURE() << "no error";
    } catch (const std::exception& e) {
        EXPECT_THAT(e.what(), ::testing::HasSubstr("SparseGridTopology"));
    }
}

TEST(NodeContext, ChildNodeGravityAndDtAreTheParentsAsInSofa) {
    // SOFA's Node::updateContext copies the parent's gravity and dt over a child node's own
    auto scene = scene::build_scene(io::parse_scene_string(R"(<Node name="root" dt="0.02" gravity="0 0 -9.81">
  <Node name="Child" gravity="0 -9.81 0" dt="0.5"><MechanicalObject position="0 0 0"/></Node>
</Node>)",
                                                           "child_gravity.scn"));
    const Node& child = *scene->simulation().root().children().at(0);
    EXPECT_EQ(child.gravity(), Vec3(0, 0, -9.81));
    EXPECT_EQ(child.dt(), 0.02);
    EXPECT_THAT(
        scene::describe_scene(*scene),
        ::testing::HasSubstr("note: /Child: gravity of a child node is ignored (SOFA copies the parent's over it)"));
}

}  // namespace
