// Triangle collision models follow topological changes (collision/triangle_model_changes.cpp): the
// same triangles, flags and counts as models built afresh on the changed topology.
#include "topological_change_scenes.hpp"

namespace penalty {
namespace {

using namespace test_topology_scenes;

TEST(TopologicalChanges, TriangleCollisionModelsFollowAsIfBuiltAfresh) {
    std::mt19937 rng(51);
    // a body's border through Tetra2Triangle: removals of tetrahedra uncover inner triangles,
    // remove border ones and renumber points
    const test::TetraCube cube = test::tetra_cube(4, 0.4);
    auto body = build(tchg_body(cube.points, cube.tetrahedra, R"(<DiagonalMass massDensity="1000"/>
  <Node name="border">
    <TriangleSetTopologyContainer name="surface"/>
    <TriangleSetTopologyModifier/>
    <Tetra2TriangleTopologicalMapping input="@../volume" output="@surface"/>
    <TriangleCollisionModel/>
  </Node>)"));
    tchg_expect_triangle_models_fresh(*body, "built");
    for (int round = 0; round < 12; ++round) {
        const std::size_t n = body->topology_container("volume").mesh().tetrahedra().size();
        std::set<ElementId> picked;
        while (picked.size() < std::min<std::size_t>(n, 1 + round % 4))
            picked.insert(ElementId(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng)));
        body->remove_elements("volume", ElementType::tetrahedron, {picked.begin(), picked.end()});
        tchg_expect_triangle_models_fresh(*body, "body, round " + std::to_string(round));
    }
    // a sheet: triangles removed, and removed ones added again on their points (found by position:
    // a removal may renumber them, or remove them with their last triangle)
    const test::TriangleSheet sheet = test::triangle_sheet(5, 0.1);
    auto s = build(tchg_ball_over_sheet(sheet, 0.05, Vec3(0.21, 0.3, 0.27)));
    const Vec3Object& sheet_dofs = tchg_state(*s, 0);
    ASSERT_EQ(sheet_dofs.num_dofs(), sheet.points.size());
    std::vector<std::array<Vec3, 3>> removed;
    std::size_t added = 0;
    for (int round = 0; round < 12; ++round) {
        const MeshTopology& mesh = s->topology_container("surface").mesh();
        const std::size_t n = mesh.triangles().size();
        if (round % 3 == 2) {
            std::vector<PointId> again;
            for (const auto& corners : removed) {
                std::vector<PointId> t;
                for (const Vec3& p : corners) {
                    const auto& x0 = sheet_dofs.rest_position;
                    const auto it = std::find(x0.begin(), x0.end(), p);
                    if (it != x0.end()) t.push_back(PointId(it - x0.begin()));
                }
                if (t.size() == 3) again.insert(again.end(), t.begin(), t.end());
            }
            removed.clear();
            if (again.empty()) continue;
            added += again.size() / 3;
            s->add_elements("surface", ElementType::triangle, again);
        } else {
            std::set<ElementId> picked;
            while (picked.size() < std::min<std::size_t>(n, 3))
                picked.insert(ElementId(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng)));
            for (const ElementId t : picked) {
                std::array<Vec3, 3> corners;
                for (std::size_t j = 0; j < 3; ++j)
                    corners[j] = sheet_dofs.rest_position[std::size_t(mesh.triangles()[std::size_t(t)][j])];
                removed.push_back(corners);
            }
            s->remove_elements("surface", ElementType::triangle, {picked.begin(), picked.end()});
        }
        tchg_expect_triangle_models_fresh(*s, "sheet, round " + std::to_string(round));
        s->step();
    }
    EXPECT_GT(added, 3u);  // the additions ran
}

}  // namespace
}  // namespace penalty
