// TopologicalChangeProcessor (scene/topology/topological_change_processor.cpp): a change file's
// changes apply at their times, bad lines are refused naming the line, removals past the end are
// skipped as SOFA.
#include "topological_change_scenes.hpp"

namespace penalty {
namespace {

using namespace test_topology_scenes;

TEST(TopologicalChanges, ProcessorFilesApplyAtTheirTimesAndBadOnesAreRefusedByLine) {
    const std::string good =
        tchg_change_file("good.txt", "T= 0.02\n  REMOVE= 2\n4 0\nT= 0.05\n  ADD= Tetrahedra 1\n0 1 2 3\n");
    auto s = build(tchg_processor_scene(R"(<TopologicalChangeProcessor filename=")" + good + R"("/>)"));
    const MeshTopology& m = s->topology_container("volume").mesh();
    for (int k = 0; k < 2; ++k) s->step();
    EXPECT_EQ(m.tetrahedra().size(), 5u);  // t = 0.01 at the start of the second step
    s->step();
    EXPECT_EQ(m.tetrahedra().size(), 3u);  // t = 0.02: removed
    for (int k = 0; k < 3; ++k) s->step();
    EXPECT_EQ(m.tetrahedra().size(), 4u);  // t = 0.05: added

    EXPECT_THAT(test::error_of(tchg_processor_scene(R"(<TopologicalChangeProcessor filename="/no/such/file.txt"/>)")),
                HasSubstr("attribute 'filename': cannot open /no/such/file.txt"));
    const std::string bad = tchg_change_file("bad.txt", "T= 0.01\n  REMOVE= 2\n1 x\n");
    EXPECT_THAT(test::error_of(tchg_processor_scene(R"(<TopologicalChangeProcessor filename=")" + bad + R"("/>)")),
                HasSubstr("bad.txt:3: 'x' is not an index"));
    const std::string keyword = tchg_change_file("keyword.txt", "T= 0.01\n  ADD= Prisms 1\n1 2 3 4 5 6\n");
    EXPECT_THAT(test::error_of(tchg_processor_scene(R"(<TopologicalChangeProcessor filename=")" + keyword + R"("/>)")),
                HasSubstr("keyword.txt:2: 'ADD= Prisms'"));

    // an element that does not exist (with the fix of SOFA's skipping, below), or one listed twice,
    // when the step comes: the error names the file and line, and nothing of the step is applied
    // (or a new element on a repeated vertex, or degenerate: four corners of the cube's bottom face)
    scene::BuildOptions refusing;
    refusing.sofa_quirk_fixes.fix_topology_removal_out_of_range = true;
    const std::pair<std::string, std::string> late_cases[] = {
        {"T= 0.01\n  REMOVE= 2\n0 9\n", "late.txt:3: tetrahedra 9 does not exist"},
        {"T= 0.01\n  REMOVE= 2\n1 1\n", "late.txt:3: tetrahedra 1 is listed twice"},
        {"T= 0.01\n  ADD= Tetrahedra 2\n0 1 2 7  0 1 2 2\n", "late.txt:3: new tetrahedra 1 uses vertex 2 twice"},
        {"T= 0.01\n  ADD= Tetrahedra 1\n0 1 2 3\n",
         "late.txt:3: the topology '/body/volume': new tetrahedron 0 (0 1 2 3) is degenerate"}};
    for (const auto& [text, expected] : late_cases) {
        const std::string late = tchg_change_file("late.txt", text);
        auto t = build(tchg_processor_scene(R"(<TopologicalChangeProcessor name="cuts" filename=")" + late + R"("/>)"),
                       refusing);
        t->step();
        try {
            t->step();
            ADD_FAILURE() << "no error";
        } catch (const io::SceneError& e) {
            EXPECT_THAT(e.what(), HasSubstr("TopologicalChangeProcessor 'cuts': "));
            EXPECT_THAT(e.what(), HasSubstr(expected));
        }
        EXPECT_EQ(t->topology_container("volume").mesh().tetrahedra().size(), 5u);
    }
}

TEST(TopologicalChanges, ProcessorSkipsRemovalsPastTheEndAsSofa) {
    // SOFA's TetrahedronSetTopologyModifier::removeTetrahedra skips an index past the end (a
    // warning) and removes the others: tetrahedron 9 of 5 is dropped, tetrahedron 0 removed
    const std::string late = tchg_change_file("past_end.txt", "T= 0.01\n  REMOVE= 3\n0 9 12\n");
    auto s = build(tchg_processor_scene(R"(<TopologicalChangeProcessor name="cuts" filename=")" + late + R"("/>)"));
    const MeshTopology& m = s->topology_container("volume").mesh();
    // the same mesh as a file removing tetrahedron 0 alone
    const std::string only = tchg_change_file("only_0.txt", "T= 0.01\n  REMOVE= 1\n0\n");
    auto reference = build(tchg_processor_scene(R"(<TopologicalChangeProcessor filename=")" + only + R"("/>)"));
    s->step();
    reference->step();
    testing::internal::CaptureStderr();
    s->step();
    const std::string warning = testing::internal::GetCapturedStderr();
    reference->step();
    ASSERT_EQ(m.tetrahedra().size(), 4u);
    EXPECT_EQ(m.tetrahedra(), reference->topology_container("volume").mesh().tetrahedra());
    EXPECT_EQ(m.num_points(), reference->topology_container("volume").mesh().num_points());
    EXPECT_THAT(
        warning,
        HasSubstr("past_end.txt:3: 2 tetrahedra index(es) past the end of '/body/volume' (5) not removed (9, 12)"));
    EXPECT_THAT(warning, HasSubstr("--fix-sofa-quirk topology_removal_out_of_range"));
}

}  // namespace
}  // namespace penalty
