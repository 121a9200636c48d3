// TopologicalChangeProcessor INCISE= lines in a built scene (tests/scene/data/incision_sheet.scn: a
// 3 x 2 sheet with DiagonalMass, TriangularFEMForceField and TriangularBendingSprings, cut twice):
// the states' sizes SOFA HEAD gives the same scene, a cut separating the sheet, SOFA HEAD's
// positions after the cuts (TriangularFEMForceField's triangle data kept from each triangle's
// creation, DiagonalMass's density kept when its callbacks cleaned its data tracker), and bad
// lines refused by file and line with nothing changed.
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/triangle_incision.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/paths.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace penalty {
namespace {

using ::testing::HasSubstr;

const std::filesystem::path kIncisionData = penalty::test::source_dir() / "tests/scene/data";

/// incision_sheet.scn with its change file replaced by `changes` (a file written for the test),
/// `attributes` added to the processor.
std::string incision_scene(const std::string& changes, const std::string& attributes = "") {
    std::ifstream in(kIncisionData / "incision_sheet.scn");
    std::ostringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    const std::string from = R"(filename="incision_sheet.txt")";
    // one folder a process: CTest runs this file's tests side by side, each with its own changes
    const auto dir = std::filesystem::temp_directory_path() / ("penalty_incision_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto file = dir / "changes.txt";
    std::ofstream(file) << changes;
    s.replace(s.find(from), from.size(), "filename=\"" + file.string() + "\" " + attributes);
    return s;
}

std::size_t incision_points(scene::Scene& s) { return s.topology_container("surface").num_points(); }

const std::vector<Vec3>& incision_positions(scene::Scene& s) {
    const auto* x = dynamic_cast<const Vec3Object*>(s.states().at(0).state);
    if (x == nullptr) throw std::logic_error("incision_sheet.scn: no Vec3 state");
    return x->position;
}

// SOFA HEAD on incision_sheet.scn (sofa-head, --every 1): 12 points, 18 after the step at
// t = 0.05, 32 after the one at t = 0.1.
TEST(IncisionScene, SheetIsCutAtTheFilesTimesWithSofasPointCounts) {
    auto s = scene::load_scene(kIncisionData / "incision_sheet.scn");
    const MeshTopology& m = s->topology_container("surface").mesh();
    for (int k = 0; k < 5; ++k) s->step();
    EXPECT_EQ(incision_points(*s), 12U);
    EXPECT_EQ(count_connected_components(m.triangles(), incision_points(*s)), 1U);
    s->step();  // t = 0.05: across the sheet, the left column falls off
    EXPECT_EQ(incision_points(*s), 18U);
    EXPECT_EQ(m.triangles().size(), 16U);
    EXPECT_EQ(count_connected_components(m.triangles(), incision_points(*s)), 2U);
    for (int k = 0; k < 5; ++k) s->step();  // t = 0.1: a cut of two segments inside the right part
    EXPECT_EQ(incision_points(*s), 32U);
    EXPECT_EQ(count_connected_components(m.triangles(), incision_points(*s)), 2U);
    for (const auto& st : s->states()) EXPECT_EQ(st.state->num_dofs(), 32U);
}

// SOFA HEAD (2a278d8, `sofa-head incision_sheet.scn 30 OUT --every 1`, %.17g) after 15 steps,
// the second cut (t = 0.1) included: bit for bit. The cuts add points and then triangles, whose
// DiagonalMass callbacks end with cleanTracker(): the step's doUpdateInternal finds nothing
// changed and ρ stays 1 (a density recomputed from the summed masses moved DOF 27 by 1.2e-5).
TEST(IncisionScene, SheetCutTwiceFollowsSofaHeadToTheBit) {
    auto s = scene::load_scene(kIncisionData / "incision_sheet.scn");
    for (int k = 0; k < 15; ++k) s->step();
    const std::vector<Vec3>& x = incision_positions(*s);
    ASSERT_EQ(x.size(), 32U);
    EXPECT_EQ(x[19], Vec3(2.4577670610778659, 0.45125791254318809, -0.1162362992918082));
    EXPECT_EQ(x[27], Vec3(2.7063560012749912, 0.59767392006662512, -0.10336198261653128));
    EXPECT_EQ(x[28], Vec3(2.6772380119135475, 0.67148857593221589, -0.11530291107832207));
}

// A cut passing 0.01 from the inner vertex 5 = (1, 1): SplitAlongPath snaps the path onto it and
// moves it (movePointsProcess, rest position included). SOFA's TriangularFEMForceField keeps the
// data of the triangles made before the move (createTriangleInformation at their addition), so
// those around vertex 5 keep their rest shape; a rebuild from the moved rest positions parted
// from SOFA HEAD by 3e-4 at the next step. SOFA HEAD, the same scene and change file, after 10
// steps: bit for bit.
TEST(IncisionScene, SnappedVertexKeepsTheTrianglesRestShapeAsSofaHead) {
    auto s = test::build(incision_scene("T= 0.05\n  INCISE= 2\n0.97 0.05 0 1.05 1.95 0\n"));
    for (int k = 0; k < 10; ++k) s->step();
    const std::vector<Vec3>& x = incision_positions(*s);
    ASSERT_EQ(x.size(), 15U);
    EXPECT_EQ(x[1], Vec3(1.0009999590538736, -0.00022229495194418727, -0.053732938148742901));
    EXPECT_EQ(x[5], Vec3(1.0009397831138789, 1.0030681501739613, -0.05374117716110316));
    EXPECT_EQ(x[9], Vec3(1.0009586177635641, 1.9998550779198119, -0.053724132464347749));
}

TEST(IncisionScene, BadLinesAreRefusedByFileAndLineAndChangeNothing) {
    // read at build
    EXPECT_THAT(test::error_of(incision_scene("T= 0.01\n  INCISE= 2\n1.15 0.05 0 1.15 1.95\n")),
                HasSubstr("changes.txt:3: 5 values for 'INCISE= 2': expected 6 (x y z per point) or 8"));
    EXPECT_THAT(test::error_of(incision_scene("T= 0.01\n  INCISE= 1\n1.15 0.05 0\n")),
                HasSubstr("changes.txt:2: 'INCISE=' needs the count of the cut's points (2 or more)"));
    EXPECT_THAT(test::error_of(incision_scene("T= 0.01\n  INCISE= 2\n1.15 0.05 0 1.15 x 0\n")),
                HasSubstr("changes.txt:3: 'x' is not a number"));
    EXPECT_THAT(test::error_of(incision_scene("T= 0.01\n  INCISE= 2\n1.15 0.05 0 1.15 1.95 0\n  REMOVE= 1\n0\n")),
                HasSubstr("mixes INCISE= with REMOVE=/ADD= lines"));
    EXPECT_THAT(test::error_of(incision_scene("T= 0.01\n  INCISE= 2\n1.15 0.05 0 1.15 1e200 0\n")),
                HasSubstr("changes.txt:3: '1e200': magnitude above 1e100"));
    // saveIndicesAtInit pairs an INCISE= line with the T= line right before it (SOFA's saveIndices)
    const std::string two_cuts = "T= 0.01\n  INCISE= 2\n1.15 0.05 0 1.15 1.95 0\n  INCISE= 2\n2.1 0.1 0 2.1 1.9 0\n";
    EXPECT_THAT(test::error_of(incision_scene(two_cuts, R"(saveIndicesAtInit="1")")),
                HasSubstr("changes.txt:4: with saveIndicesAtInit an INCISE= line must follow its T= line"));
    EXPECT_NO_THROW(test::build(incision_scene(two_cuts)));
    EXPECT_NO_THROW(
        test::build(incision_scene("T= 0.01\n\n  INCISE= 2\n1.15 0.05 0 1.15 1.95 0\n", R"(saveIndicesAtInit="1")")));
    // when the step comes: a point in no triangle (the second segment's end), nothing cut
    const std::string outside = incision_scene("T= 0.01\n  INCISE= 3\n1.15 0.05 0 1.15 1.95 0 5 1 0\n");
    auto s = test::build(outside);
    s->step();
    try {
        s->step();
        ADD_FAILURE() << "no error";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(), HasSubstr("TopologicalChangeProcessor"));
        EXPECT_THAT(e.what(), HasSubstr("changes.txt:3: INCISE=: point 3 (5 1 0) is in no triangle"));
    }
    EXPECT_EQ(incision_points(*s), 12U);
    EXPECT_EQ(s->topology_container("surface").mesh().triangles().size(), 12U);
}

// A segment that stays inside one triangle: SOFA's "Invalid path" skips the rest of its line (a
// warning), and the next line cuts; with the fix, an error and nothing cut.
TEST(IncisionScene, InvalidPathIsSkippedAsSofaOrRefusedWithTheFix) {
    const std::string text =
        incision_scene("T= 0.01\n  INCISE= 2\n0.6 0.2 0 0.8 0.3 0\nT= 0.02\n  INCISE= 2\n1.15 0.05 0 1.15 1.95 0\n");
    auto s = test::build(text);
    for (int k = 0; k < 2; ++k) s->step();
    EXPECT_EQ(incision_points(*s), 12U);  // skipped
    s->step();
    EXPECT_EQ(incision_points(*s), 18U);  // the next line cuts
    scene::BuildOptions fixed;
    fixed.sofa_quirk_fixes.fix_incision_invalid_path = true;
    auto t = test::build(text, fixed);
    t->step();
    EXPECT_THROW(t->step(), io::SceneError);
    EXPECT_EQ(incision_points(*t), 12U);
}

}  // namespace
}  // namespace penalty
