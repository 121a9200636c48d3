// `--compare-trajectory`: SOFA's state files (plain or gzip) found by index and name, SOFA's
// criterion over the compared steps, the first step above the threshold with its DOF, the
// largest and last differences, and the verdict.
#include "penalty/output/state_file.hpp"

#include "output_test_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <string>

namespace penalty::output {
namespace {

using test::TempDir;
using test::write_text;
using ::testing::HasSubstr;

void write_gzip(const std::filesystem::path& file, const std::string& text) {
    gzFile out = gzopen(file.c_str(), "wb");
    ASSERT_NE(out, nullptr);
    ASSERT_EQ(gzwrite(out, text.data(), unsigned(text.size())), int(text.size()));
    gzclose(out);
}

// Two Vec3 DOFs, three steps (dt 0.1 written at full precision, as SOFA's trajectories).
const std::string kSofa =
    "T= 0\n  X= 0 0 0 1 1 1\n"
    "T= 0.10000000000000001\n  X= 0 -0.1 0 1 0.9 1\n"
    "T= 0.20000000000000001\n  X= 0 -0.3 0 1 0.7 1\n";

TEST(TrajectoryCompare, GzipFileFoundByIndexAndNameWithSpaces) {
    TempDir dir;
    write_gzip(dir.path() / "0_Particles Cube1_mstate.txt.gz", kSofa);
    write_text(dir.path() / "0_Particles_Cube1_mstate.txt", kSofa);  // ours: the space became '_'
    const std::vector<std::filesystem::path> ours{dir.path() / "0_Particles_Cube1_mstate.txt"};
    const std::vector<StateSample> read = read_state_file(dir.path() / "0_Particles Cube1_mstate.txt.gz");
    ASSERT_EQ(read.size(), 3u);
    EXPECT_DOUBLE_EQ(read[2].x[4], 0.7);
    const TrajectoryComparison c = compare_trajectories(dir.path(), ours, std::vector<int>{3}, 1e-12);
    ASSERT_EQ(c.states.size(), 1u);
    EXPECT_EQ(c.states[0].sofa_file.filename(), "0_Particles Cube1_mstate.txt.gz");
    EXPECT_EQ(c.states[0].steps_compared, 3u);
    EXPECT_EQ(c.states[0].criterion, 0.0);
    EXPECT_FALSE(c.states[0].first_over_threshold);
    EXPECT_TRUE(c.messages.empty());
    EXPECT_TRUE(c.passed());
}

TEST(TrajectoryCompare, FirstStepAboveThresholdDofAndCriterion) {
    TempDir dir;
    const auto sofa_dir = dir.path() / "sofa";
    std::filesystem::create_directories(sofa_dir);
    write_text(sofa_dir / "0_dofs_mstate.txt", kSofa);
    // Step 1: DOF 1 y off by 1e-13 (below 1e-12); step 2: DOF 0 z off by 3e-9, DOF 1 x by 1e-9.
    write_text(dir.path() / "0_dofs_mstate.txt",
               "T= 0\n  X= 0 0 0 1 1 1\n"
               "T= 0.1\n  X= 0 -0.1 0 1 0.9000000000001 1\n"
               "T= 0.2\n  X= 0 -0.3 3e-09 1.000000001 0.7 1\n");
    const std::vector<std::filesystem::path> ours{dir.path() / "0_dofs_mstate.txt"};
    const TrajectoryComparison c = compare_trajectories(sofa_dir, ours, std::vector<int>{3}, 1e-12);
    ASSERT_EQ(c.states.size(), 1u);
    const TrajectoryStateComparison& s = c.states[0];
    ASSERT_TRUE(s.first_over_threshold);
    EXPECT_EQ(s.first_over_threshold->step, 2u);
    EXPECT_EQ(s.first_over_threshold->dof, 0u);
    EXPECT_EQ(s.first_over_threshold->component, 2u);
    EXPECT_NEAR(s.first_over_threshold->max_difference, 3e-9, 1e-20);
    ASSERT_TRUE(s.last);
    EXPECT_EQ(s.last->step, 2u);
    // SOFA's error_s: (1e-13 + 3e-9 + 1e-9) / 2 DOFs.
    EXPECT_NEAR(s.criterion, (1e-13 + 3e-9 + 1e-9) / 2.0, 1e-15);  // decimal inputs: differences exact to ~1e-16
    EXPECT_FALSE(c.passed());
    // A looser threshold: within at every step, the criterion passes.
    const TrajectoryComparison loose = compare_trajectories(sofa_dir, ours, std::vector<int>{3}, 1e-8);
    EXPECT_FALSE(loose.states[0].first_over_threshold);
    EXPECT_TRUE(loose.passed());
    const std::string report = format_trajectory_comparison(c);
    EXPECT_THAT(report, HasSubstr("first step with |dx| > 1e-12: step 2 (t = 0.2 s) DOF 0 z: 3"));
    EXPECT_THAT(report, HasSubstr("FAIL"));
}

TEST(TrajectoryCompare, ShorterRunComparesItsStepsAndCountsTheRest) {
    TempDir dir;
    const auto sofa_dir = dir.path() / "sofa";
    std::filesystem::create_directories(sofa_dir);
    write_text(sofa_dir / "0_dofs_mstate.txt", kSofa);
    write_text(dir.path() / "0_dofs_mstate.txt", "T= 0\n  X= 0 0 0 1 1 1\nT= 0.1\n  X= 0 -0.1 0 1 0.9 1\n");
    const std::vector<std::filesystem::path> ours{dir.path() / "0_dofs_mstate.txt"};
    const TrajectoryComparison c = compare_trajectories(sofa_dir, ours, std::vector<int>{3});
    EXPECT_EQ(c.states[0].steps_compared, 2u);
    EXPECT_EQ(c.states[0].sofa_steps_not_compared, 1u);
    EXPECT_TRUE(c.passed());
}

TEST(TrajectoryCompare, MissingFileWrongWidthAndMissingDirectory) {
    TempDir dir;
    const auto sofa_dir = dir.path() / "sofa";
    std::filesystem::create_directories(sofa_dir);
    write_text(sofa_dir / "0_a_mstate.txt", kSofa);
    write_text(dir.path() / "0_a_mstate.txt", "T= 0\n  X= 0 0 0\n");
    write_text(dir.path() / "1_b_mstate.txt", "T= 0\n  X= 0 0 0\n");
    const std::vector<std::filesystem::path> ours{dir.path() / "0_a_mstate.txt", dir.path() / "1_b_mstate.txt"};
    const TrajectoryComparison c = compare_trajectories(sofa_dir, ours, std::vector<int>{3, 3});
    ASSERT_EQ(c.states.size(), 2u);
    EXPECT_THAT(c.states[0].problem, HasSubstr("X has 3 values, SOFA's 6"));
    EXPECT_TRUE(std::isinf(c.states[0].criterion));
    EXPECT_EQ(c.states[1].problem, "no SOFA file");
    ASSERT_EQ(c.messages.size(), 1u);
    EXPECT_THAT(c.messages[0], HasSubstr("no SOFA state file 1_*_mstate.txt"));
    EXPECT_FALSE(c.passed());
    EXPECT_THROW((void)compare_trajectories(dir.path() / "absent", ours, std::vector<int>{3, 3}), std::runtime_error);
}

}  // namespace
}  // namespace penalty::output
