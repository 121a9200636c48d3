// Outputs of a run with topological changes (docs/topological-changes.md): the VTK series, the
// exported states (SOFA's WriteState with the new sizes) and the browser viewer's layouts follow
// the cut frame by frame.
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace penalty {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

std::string read_all(const fs::path& file) {
    std::ifstream in(file);
    std::ostringstream out;
    out << in.rdbuf();
    return out.str();
}

/// A 6 × 6 sheet of 72 triangles falling under gravity; at t = 0.02 s a TopologicalChangeProcessor
/// removes its 8 middle triangles, and with them the middle point (the one only they used).
std::string cut_sheet_scene(const fs::path& dir) {
    const test::TriangleSheet sheet = test::triangle_sheet(6, 0.1);
    std::ofstream(dir / "cut.txt") << "T= 0.02\n  REMOVE= 8\n26 27 28 29 38 39 40 41\n";
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0"><Node name="Sheet">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
  <MechanicalObject name="dofs" position=")" +
           test::points_text(sheet.points) + R"("/>
  <TriangleSetTopologyContainer name="topo" triangles=")" +
           test::elements_text(sheet.triangles) + R"("/>
  <TriangleSetTopologyModifier/>
  <UniformMass totalMass="1"/>
  <TriangleCollisionModel name="sheet_triangles"/>
  <TopologicalChangeProcessor filename=")" +
           (dir / "cut.txt").string() + R"("/>
</Node></Node>
)";
}

TEST(TopologicalOutputs, VtkSeriesExportedStatesAndViewerFollowTheCut) {
    const fs::path dir = fs::temp_directory_path() / "penalty_topological_outputs";
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto scene = test::build(cut_sheet_scene(dir));
    scene::RunOptions options;
    options.steps = 5;
    options.vtk_directory = dir / "vtk";
    options.states_directory = dir / "states";
    options.view_directory = dir / "view";
    options.view_title = "cut";
    (void)scene::run_scene(*scene, options);

    // VTK: frames 0-2 before the change (t = 0, 0.01, 0.02: the change applies during the step
    // that starts at 0.02), frames 3-5 after
    const std::regex counts(R"re(NumberOfPoints="(\d+)" NumberOfCells="(\d+)")re");
    for (int frame = 0; frame <= 5; ++frame) {
        char name[64];
        std::snprintf(name, sizeof name, "0_dofs_%06d.vtu", frame);
        const std::string text = read_all(dir / "vtk" / name);
        std::smatch m;
        ASSERT_TRUE(std::regex_search(text, m, counts)) << name;
        EXPECT_EQ(m[1].str(), frame < 3 ? "49" : "48") << name;
        EXPECT_EQ(m[2].str(), frame < 3 ? "72" : "64") << name;
    }

    // exported states: one line per step, "X= " then 3 values per point of the state then
    std::ifstream states(dir / "states" / "0_dofs_mstate.txt");
    std::string line;
    std::vector<std::size_t> values;
    while (std::getline(states, line)) {
        std::istringstream in(line);
        std::string key;
        in >> key;
        if (key != "X=") continue;
        std::size_t n = 0;
        for (double v; in >> v;) ++n;
        values.push_back(n);
    }
    ASSERT_GE(values.size(), 5u);
    EXPECT_EQ(values.front(), 49u * 3);
    EXPECT_EQ(values.back(), 48u * 3);

    // viewer: a new layout from the first frame after the change
    const std::string manifest = read_all(dir / "view" / "run.json");
    EXPECT_THAT(manifest, HasSubstr("\"version\":2,"));
    EXPECT_THAT(manifest, HasSubstr("\"layout\":[0,0,0,1,1,1]"));
    EXPECT_THAT(manifest, HasSubstr("\"index_offset\":216,\"index_count\":192}"));
    fs::remove_all(dir);
}

}  // namespace
}  // namespace penalty
