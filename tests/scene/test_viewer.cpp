// The viewer's shapes of a built scene (viewer.hpp): one per collision model, with the right
// state, indices, radii and cylinder data; a Tetrahedron model's boundary is a closed surface.
#include "penalty/io/scene_file.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/viewer.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "penalty_test/paths.hpp"

#include <algorithm>
#include <filesystem>
#include <map>

namespace penalty::scene {
namespace {

using output::ViewerShapeKind;
using ::testing::ElementsAre;

const std::filesystem::path kScenes = penalty::test::source_dir() / "scenes";

TEST(ViewerBodies, BuiltInSceneHasTheFloorTheCubeAndTheBall) {
    auto scene = build_scene(io::parse_scene_string(default_scene_xml(), "<built-in scene>"));
    const ViewerBodies bodies = viewer_bodies(*scene);
    ASSERT_EQ(bodies.states.size(), 3u);
    EXPECT_EQ(output::state_label(*bodies.states[0]), "/Floor/floor");
    EXPECT_EQ(output::state_label(*bodies.states[1]), "/SoftCube/cube");
    EXPECT_EQ(output::state_label(*bodies.states[2]), "/Ball/ball");
    ASSERT_EQ(bodies.shapes.size(), 3u);
    const auto& floor = bodies.shapes[0];
    EXPECT_EQ(floor.name, "floor_triangles");
    EXPECT_EQ(floor.kind, ViewerShapeKind::triangles);
    EXPECT_EQ(floor.state, 0u);
    EXPECT_THAT(floor.indices, ElementsAre(0, 2, 1, 0, 3, 2));  // the scene's triangles
    const auto& cube = bodies.shapes[1];
    EXPECT_EQ(cube.kind, ViewerShapeKind::points);
    EXPECT_EQ(cube.state, 1u);
    EXPECT_EQ(cube.indices.size(), 125u);  // 5 x 5 x 5 grid
    EXPECT_EQ(cube.indices.back(), 124u);
    const auto& ball = bodies.shapes[2];
    EXPECT_EQ(ball.type, "RigidSphere");
    EXPECT_EQ(ball.kind, ViewerShapeKind::spheres);
    EXPECT_EQ(ball.state, 2u);
    EXPECT_THAT(ball.indices, ElementsAre(0));
    EXPECT_THAT(ball.radius, ElementsAre(0.15));
}

TEST(ViewerBodies, TetrahedronModelShowsItsBoundaryAsAClosedOutwardSurface) {
    auto scene = load_scene(kScenes / "tetra_point.scn");
    const ViewerBodies bodies = viewer_bodies(*scene);
    const auto it = std::find_if(bodies.shapes.begin(), bodies.shapes.end(),
                                 [](const output::ViewerShape& s) { return s.name == "block_tetrahedra"; });
    ASSERT_NE(it, bodies.shapes.end());
    EXPECT_EQ(it->kind, ViewerShapeKind::triangles);
    const auto* block = dynamic_cast<const Vec3Object*>(bodies.states[it->state]->state);
    ASSERT_NE(block, nullptr);
    // Closed: every edge of the boundary belongs to exactly two of its triangles, once in each
    // direction (consistent orientation).
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    double volume = 0.0;  // divergence theorem: V = Σ a·(b × c) / 6 over the outward triangles
    const auto& x = block->position;
    for (std::size_t t = 0; t < it->indices.size(); t += 3) {
        const std::uint32_t a = it->indices[t], b = it->indices[t + 1], c = it->indices[t + 2];
        ++directed[{a, b}];
        ++directed[{b, c}];
        ++directed[{c, a}];
        volume += x[a].dot(x[b].cross(x[c])) / 6.0;
    }
    for (const auto& [edge, count] : directed) {
        EXPECT_EQ(count, 1) << edge.first << "-" << edge.second;
        EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << edge.first << "-" << edge.second;
    }
    EXPECT_NEAR(volume, 0.6 * 0.2 * 0.6, 1e-9);  // the block, 0.6 x 0.2 x 0.6 m
}

TEST(ViewerBodies, CylindersCarryRadiusHeightAndAxis) {
    auto scene = load_scene(kScenes / "cylinders.scn");
    const ViewerBodies bodies = viewer_bodies(*scene);
    const auto it = std::find_if(bodies.shapes.begin(), bodies.shapes.end(),
                                 [](const output::ViewerShape& s) { return s.name == "log_cylinder"; });
    ASSERT_NE(it, bodies.shapes.end());
    EXPECT_EQ(it->kind, ViewerShapeKind::cylinders);
    EXPECT_THAT(it->radius, ElementsAre(0.1));
    EXPECT_THAT(it->height, ElementsAre(0.6));
    ASSERT_EQ(it->axis.size(), 1u);
    EXPECT_EQ(it->axis[0], Vec3::UnitX());
    EXPECT_EQ(bodies.shapes.size(), scene->collision_models().size());
}

TEST(ViewerBodies, SceneWithoutCollisionModelsShowsItsStatesAsPoints) {
    auto scene = build_scene(io::parse_scene_string(R"(<Node name="root">
        <Node name="A"><MechanicalObject name="p" position="0 0 0  1 0 0  2 0 0"/></Node>
        <Node name="B"><MechanicalObject name="r" template="Rigid3d" position="0 0 0  0 0 0 1"/></Node>
    </Node>)",
                                                    "bare.scn"));
    const ViewerBodies bodies = viewer_bodies(*scene);
    ASSERT_EQ(bodies.shapes.size(), 1u);  // the Vec3 state; the Rigid3 one has no size to draw
    EXPECT_EQ(bodies.shapes[0].type, "state");
    EXPECT_EQ(bodies.shapes[0].kind, ViewerShapeKind::points);
    EXPECT_THAT(bodies.shapes[0].indices, ElementsAre(0, 1, 2));
    EXPECT_EQ(output::state_label(*bodies.states[bodies.shapes[0].state]), "/A/p");
}

}  // namespace
}  // namespace penalty::scene
