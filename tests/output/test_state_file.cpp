// SOFA's regression state files: names, exact text, reader round trip and errors, and the
// regression criterion on hand-computed numbers.
#include "penalty/output/format.hpp"
#include "penalty/output/state_file.hpp"

#include "output_test_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "penalty_test/paths.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace penalty::output {
namespace {

using test::read_text;
using test::TempDir;
using test::write_text;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

struct TwoStates {
    Vec3Object points{"dofs"};
    Rigid3Object rigid{"rigid"};
    std::vector<StateRecord> records;

    TwoStates() {
        points.position = {Vec3(-5, 0, 0.1), Vec3(1e-300, 2.5, -0.0)};
        points.init();
        rigid.position.resize(1);
        rigid.position[0].center = Vec3(5, 10, 0);
        rigid.position[0].orientation = Quat(0.5, 0.5, -0.5, 0.5);  // w x y z
        rigid.init();
        records.push_back({"dofs", "/A", &points, nullptr, false, true, nullptr, {}});
        records.push_back({"rigid", "/B", &rigid, nullptr, false, true, nullptr, {}});
    }
    std::vector<const StateRecord*> pointers() const { return {&records[0], &records[1]}; }
};

TEST(StateExporter, FileNamesFollowSofa) {
    TempDir dir;
    TwoStates s;
    StateExporter exporter(dir.path() / "nested" / "out", s.pointers());
    ASSERT_EQ(exporter.files().size(), 2u);
    EXPECT_EQ(exporter.files()[0], dir.path() / "nested" / "out" / "0_dofs_mstate.txt");
    EXPECT_EQ(exporter.files()[1], dir.path() / "nested" / "out" / "1_rigid_mstate.txt");
    EXPECT_TRUE(std::filesystem::exists(exporter.files()[0]));
    EXPECT_THAT(exporter.values_per_dof(), ElementsAre(3, 7));
}

TEST(StateExporter, ExactTextVec3AndRigid3) {
    TempDir dir;
    TwoStates s;
    StateExporter exporter(dir.path(), s.pointers());
    exporter.write(0.0);
    s.points.position[0] = Vec3(0.1, -5, 3);
    s.rigid.position[0].center.y() = 9.5;
    exporter.write(1.99);
    EXPECT_EQ(read_text(exporter.files()[0]),
              "T= 0\n  X= -5 0 0.1 1e-300 2.5 -0\n"
              "T= 1.99\n  X= 0.1 -5 3 1e-300 2.5 -0\n");
    EXPECT_EQ(read_text(exporter.files()[1]),
              "T= 0\n  X= 5 10 0 0.5 -0.5 0.5 0.5\n"
              "T= 1.99\n  X= 5 9.5 0 0.5 -0.5 0.5 0.5\n");
}

TEST(StateExporter, Vec1StateOneValuePerDofAsSofaWriteState) {
    // SOFA's WriteState writes a Vec1 MechanicalObject's values, one per DOF (examples-states'
    // TextureInterpolation: 0_ElecObj_mstate.txt)
    TempDir dir;
    Vec1Object potential("ElecObj");
    potential.position = {0.0, 9.0, 100.0, -0.25};
    potential.init();
    const StateRecord record{"ElecObj", "/MecaNode/ElecNode", &potential, nullptr, false, true, nullptr, {}};
    EXPECT_FALSE(has_points_in_space(record));
    StateExporter exporter(dir.path(), {&record});
    EXPECT_THAT(exporter.values_per_dof(), ElementsAre(1));
    exporter.write(0.0);
    potential.position[3] = 1e-300;
    exporter.write(2.0000000000000013);
    EXPECT_EQ(read_text(exporter.files()[0]), "T= 0\n  X= 0 9 100 -0.25\nT= 2.0000000000000013\n  X= 0 9 100 1e-300\n");
    const auto samples = read_state_file(exporter.files()[0]);
    ASSERT_EQ(samples.size(), 2u);
    EXPECT_EQ(samples[1].x, (std::vector<double>{0.0, 9.0, 100.0, 1e-300}));
    potential.position[1] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(exporter.write(3.0), NonFiniteValueError);
}

TEST(StateExporter, EmptyStateWritesEmptyXLine) {
    TempDir dir;
    Vec3Object empty("empty");
    const StateRecord record{"empty", "/", &empty, nullptr, false, true, nullptr, {}};
    StateExporter exporter(dir.path(), {&record});
    exporter.write(0.5);
    EXPECT_EQ(read_text(exporter.files()[0]), "T= 0.5\n  X= \n");
    const auto samples = read_state_file(exporter.files()[0]);
    ASSERT_EQ(samples.size(), 1u);
    EXPECT_TRUE(samples[0].x.empty());
}

TEST(StateExporter, NonFiniteThrowsNamingStateDofAndTimeAndWritesNothing) {
    TempDir dir;
    TwoStates s;
    StateExporter exporter(dir.path(), s.pointers());
    exporter.write(0.0);
    s.rigid.position[0].center.x() = std::numeric_limits<double>::quiet_NaN();
    try {
        exporter.write(0.01);
        FAIL() << "expected NonFiniteValueError";
    } catch (const NonFiniteValueError& error) {
        EXPECT_THAT(error.what(), HasSubstr("/B/rigid"));
        EXPECT_THAT(error.what(), HasSubstr("DOF 0"));
        EXPECT_THAT(error.what(), HasSubstr("0.01"));
    }
    // the Vec3 state (checked first, finite) got nothing either
    EXPECT_EQ(read_text(exporter.files()[0]), "T= 0\n  X= -5 0 0.1 1e-300 2.5 -0\n");
}

TEST(StateExporter, UnwritableDirectoryThrowsNamingPath) {
    TempDir dir;
    write_text(dir.path() / "file", "x");
    TwoStates s;
    try {
        StateExporter exporter(dir.path() / "file" / "sub", s.pointers());
        FAIL() << "expected std::runtime_error";
    } catch (const std::runtime_error& error) {
        EXPECT_THAT(error.what(), HasSubstr((dir.path() / "file" / "sub").string()));
    }
}

TEST(StateExporter, NullStateIsInvalidArgument) {
    TempDir dir;
    const StateRecord record{"x", "/", nullptr, nullptr, false, true, nullptr, {}};
    EXPECT_THROW(StateExporter(dir.path(), {&record}), std::invalid_argument);
}

TEST(ReadStateFile, RoundTripIsExact) {
    TempDir dir;
    TwoStates s;
    s.points.position[1] = Vec3(1.0 / 3.0, -1e-300, 123456789.123456789);
    StateExporter exporter(dir.path(), s.pointers());
    exporter.write(0.0);
    exporter.write(0.1);
    const auto samples = read_state_file(exporter.files()[0]);
    ASSERT_EQ(samples.size(), 2u);
    EXPECT_EQ(samples[1].time, 0.1);
    EXPECT_THAT(samples[0].x, ElementsAre(-5.0, 0.0, 0.1, 1.0 / 3.0, -1e-300, 123456789.123456789));
    const auto rigid = read_state_file(exporter.files()[1]);
    ASSERT_EQ(rigid.size(), 2u);
    EXPECT_THAT(rigid[0].x, ElementsAre(5.0, 10.0, 0.0, 0.5, -0.5, 0.5, 0.5));
}

TEST(ReadStateFile, ReadsSofaLayoutWithVLinesAndBlankLines) {
    TempDir dir;
    write_text(
        dir.path() / "sofa.txt",
        "T= 0\n  X= -5 10 0 0 0 0 1\n  V= 0 0 0 0 0 0\n\nT= 1.99\n  X= -4.99544 -2.30941 -0.000787169 0 0 0 1\n");
    const auto samples = read_state_file(dir.path() / "sofa.txt");
    ASSERT_EQ(samples.size(), 2u);
    EXPECT_EQ(samples[0].time, 0.0);
    EXPECT_EQ(samples[1].time, 1.99);
    EXPECT_THAT(samples[1].x, ElementsAre(-4.99544, -2.30941, -0.000787169, 0, 0, 0, 1));
}

TEST(ReadStateFile, ReadsSofaReferenceFiles) {
    // SOFA's own regression reference (in the shared area, not in the repository).
    const std::filesystem::path file = penalty::test::shared_dir() / "sofa" / "reference" /
                                       "CompositeCollisionPipeline_none.scn.reference_0_rigid_mstate.txt";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " not available";
    const auto samples = read_state_file(file);
    ASSERT_EQ(samples.size(), 2u);
    EXPECT_EQ(samples[0].time, 0.0);
    EXPECT_THAT(samples[0].x, ElementsAre(-5, 10, 0, 0, 0, 0, 1));
    EXPECT_EQ(samples[1].time, 1.99);
    EXPECT_EQ(samples[1].x.size(), 7u);
    // Through the criterion, against runs written from the samples: an exact copy (error 0) and
    // one whose last sample is moved by 3e-4 along x (error 3e-4 per DOF: above SOFA's 1e-4).
    TempDir dir;
    const auto write_run = [&](const std::string& name, double shift) {
        std::ostringstream text;
        text.precision(17);
        for (std::size_t k = 0; k < samples.size(); ++k) {
            text << "T= " << samples[k].time << "\n  X=";
            for (std::size_t i = 0; i < samples[k].x.size(); ++i)
                text << ' ' << samples[k].x[i] + (k + 1 == samples.size() && i == 0 ? shift : 0.0);
            text << "\n";
        }
        write_text(dir.path() / name, text.str());
        return std::vector<std::filesystem::path>{dir.path() / name};
    };
    const std::vector<std::filesystem::path> refs{file};
    const std::vector<int> widths{7};
    const auto same = compare_with_reference(refs, write_run("copy.txt", 0.0), widths);
    EXPECT_TRUE(same.passed());
    EXPECT_EQ(same.mean_error, 0.0);
    const auto moved = compare_with_reference(refs, write_run("moved.txt", 3e-4), widths);
    EXPECT_FALSE(moved.passed());
    EXPECT_NEAR(moved.mean_error, 3e-4, 1e-12);
}

struct MalformedCase {
    const char* text;
    const char* expected;  // message after "<file>:"
};

void PrintTo(const MalformedCase& c, std::ostream* out) { *out << '"' << c.text << '"'; }

class ReadStateFileMalformed : public ::testing::TestWithParam<MalformedCase> {};

TEST_P(ReadStateFileMalformed, ThrowsNamingFileAndLine) {
    TempDir dir;
    const auto file = dir.path() / "bad.txt";
    write_text(file, GetParam().text);
    try {
        (void)read_state_file(file);
        FAIL() << "expected std::runtime_error";
    } catch (const std::runtime_error& error) {
        EXPECT_EQ(std::string(error.what()), file.string() + ":" + GetParam().expected);
    }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ReadStateFileMalformed,
    ::testing::Values(MalformedCase{"T= 0\n  X= 1 2 x3\n", "2: 'x3' is not a number"},
                      MalformedCase{"  X= 1 2 3\n", "1: X line before any T line"},
                      MalformedCase{"T= 0\n  X= 1\n  X= 2\n", "3: second X line for T= 0"},
                      MalformedCase{"T= 0\n  X= 1\nT= 0.5\nT= 1\n  X= 1\n", "3: sample T= 0.5 has no X line"},
                      MalformedCase{"T= 0\n  X= 1\nT= 2\n", "3: sample T= 2 has no X line"},
                      MalformedCase{"T= 0 1\n", "1: expected 'T= <time>'"},
                      MalformedCase{"T=\n", "1: expected 'T= <time>'"},
                      MalformedCase{"T= 0\n  Y= 1\n", "2: unknown keyword 'Y=' (expected T=, X= or V=)"},
                      MalformedCase{"T= 1e\n", "1: '1e' is not a number"}),
    [](const ::testing::TestParamInfo<MalformedCase>& param) { return "Case" + std::to_string(param.index); });

TEST(ReadStateFile, MissingFileThrowsNamingIt) {
    TempDir dir;
    try {
        (void)read_state_file(dir.path() / "missing.txt");
        FAIL();
    } catch (const std::runtime_error& error) {
        EXPECT_THAT(error.what(), HasSubstr("missing.txt"));
    }
}

// --- regression criterion -----------------------------------------------------------------------

TEST(Regression, HandComputedErrorTwoStates) {
    TempDir dir;
    const auto d = dir.path();
    // state 0: Vec3, 2 DOFs, 2 reference times; ours has an extra time (ignored).
    write_text(d / "ref0.txt", "T= 0\n  X= 0 0 0 1 1 1\nT= 1\n  X= 1 2 3 4 5 6\n");
    write_text(d / "our0.txt", "T= 0\n  X= 0 0 0 1 1 1.5\nT= 0.5\n  X= 9 9 9 9 9 9\nT= 1\n  X= 1 2 3.25 4 5 5\n");
    // Σ|Δ| = 0.5 (T=0) + 0.25 + 1 (T=1) = 1.75; 2 DOFs -> 0.875
    // state 1: Rigid3, 1 DOF; Σ|Δ| = 0.5 + 0.125 = 0.625 at the only time -> 0.625
    write_text(d / "ref1.txt", "T= 0\n  X= 5 10 0 0 0 0 1\n");
    write_text(d / "our1.txt", "T= 0\n  X= 5.5 10 0 0 0 0.125 1\n");
    const std::vector<std::filesystem::path> refs{d / "ref0.txt", d / "ref1.txt"};
    const std::vector<std::filesystem::path> ours{d / "our0.txt", d / "our1.txt"};
    const std::vector<int> widths{3, 7};
    const RegressionResult result = compare_with_reference(refs, ours, widths);
    EXPECT_TRUE(result.messages.empty());
    EXPECT_THAT(result.per_state_error, ElementsAre(0.875, 0.625));
    EXPECT_EQ(result.mean_error, 0.75);
    EXPECT_FALSE(result.passed());
    EXPECT_TRUE(result.passed(0.75));
}

TEST(Regression, IdenticalFilesPassAndTimeToleranceIsRelative) {
    TempDir dir;
    const auto d = dir.path();
    write_text(d / "ref.txt", "T= 0\n  X= 1 2 3\nT= 1000\n  X= 4 5 6\n");
    write_text(d / "our.txt", "T= 0\n  X= 1 2 3\nT= 1000.0000005\n  X= 4 5 6\n");  // |Δt| = 5e-7 ≤ 1e-9·1000
    const std::vector<std::filesystem::path> refs{d / "ref.txt"};
    const std::vector<std::filesystem::path> ours{d / "our.txt"};
    const std::vector<int> widths{3};
    const RegressionResult result = compare_with_reference(refs, ours, widths);
    EXPECT_TRUE(result.messages.empty());
    EXPECT_EQ(result.mean_error, 0.0);
    EXPECT_TRUE(result.passed());
}

TEST(Regression, ReferenceTimesRoundedToSixDigitsMatchTheClosestSample) {
    TempDir dir;
    const auto d = dir.path();
    // SOFA wrote 123.4567 and 123.4572 as 123.457 (6 significant digits; half a unit = 5e-4).
    write_text(d / "ref.txt", "T= 123.457\n  X= 1 2 3\n");
    write_text(d / "our.txt", "T= 123.4567\n  X= 9 9 9\nT= 123.4572\n  X= 1 2 4\nT= 123.4576\n  X= 9 9 9\n");
    const std::vector<std::filesystem::path> refs{d / "ref.txt"};
    const std::vector<std::filesystem::path> ours{d / "our.txt"};
    const std::vector<int> widths{3};
    const RegressionResult result = compare_with_reference(refs, ours, widths);
    EXPECT_TRUE(result.messages.empty());
    EXPECT_EQ(result.mean_error, 1.0);  // the closest sample (123.4572) is compared: |4 − 3| / 1 DOF
    write_text(d / "far.txt", "T= 123.4564\n  X= 1 2 3\n");  // 6e-4 away: not the same time
    const std::vector<std::filesystem::path> far{d / "far.txt"};
    EXPECT_EQ(compare_with_reference(refs, far, widths).messages.size(), 1u);
}

TEST(Regression, MismatchesAreMessagesWithInfiniteError) {
    TempDir dir;
    const auto d = dir.path();
    write_text(d / "ref.txt", "T= 0\n  X= 1 2 3\nT= 0.5\n  X= 1 2 3\n");
    write_text(d / "missing_time.txt", "T= 0\n  X= 1 2 3\nT= 0.50001\n  X= 1 2 3\n");
    write_text(d / "short.txt", "T= 0\n  X= 1 2\nT= 0.5\n  X= 1 2 3\n");
    write_text(d / "nan.txt", "T= 0\n  X= 1 nan 3\nT= 0.5\n  X= 1 2 3\n");
    write_text(d / "bad_width.txt", "T= 0\n  X= 1 2 3 4\n");
    write_text(d / "empty.txt", "");
    const auto inf = std::numeric_limits<double>::infinity();

    const auto compare_one = [&](const std::string& ref, const std::string& ours) {
        const std::vector<std::filesystem::path> r{d / ref};
        const std::vector<std::filesystem::path> o{d / ours};
        const std::vector<int> widths{3};
        return compare_with_reference(r, o, widths);
    };
    {
        const auto result = compare_one("ref.txt", "missing_time.txt");
        EXPECT_THAT(result.per_state_error, ElementsAre(inf));
        EXPECT_EQ(result.mean_error, inf);
        ASSERT_EQ(result.messages.size(), 1u);
        EXPECT_THAT(result.messages[0], HasSubstr("no sample at reference time T= 0.5"));
        EXPECT_THAT(result.messages[0], HasSubstr("missing_time.txt"));
        EXPECT_FALSE(result.passed());
    }
    {
        const auto result = compare_one("ref.txt", "short.txt");
        ASSERT_EQ(result.messages.size(), 1u);
        EXPECT_THAT(result.messages[0], HasSubstr("at T= 0 X has 2 values, the reference has 3"));
    }
    {
        const auto result = compare_one("ref.txt", "nan.txt");
        ASSERT_EQ(result.messages.size(), 1u);
        EXPECT_THAT(result.messages[0], HasSubstr("non-finite value 1 at T= 0"));
        EXPECT_EQ(result.mean_error, inf);
    }
    {
        const auto result = compare_one("bad_width.txt", "bad_width.txt");
        ASSERT_EQ(result.messages.size(), 1u);
        EXPECT_THAT(result.messages[0], HasSubstr("has 4 values, not a multiple of 3 values per DOF"));
    }
    {
        const auto result = compare_one("empty.txt", "ref.txt");
        ASSERT_EQ(result.messages.size(), 1u);
        EXPECT_THAT(result.messages[0], HasSubstr("the reference has no sample"));
    }
    {
        const auto result = compare_one("ref.txt", "does_not_exist.txt");
        ASSERT_EQ(result.messages.size(), 1u);
        EXPECT_THAT(result.messages[0], HasSubstr("does_not_exist.txt"));
        EXPECT_EQ(result.mean_error, inf);
    }
}

TEST(Regression, DifferentFileCountsAreAnError) {
    TempDir dir;
    const auto d = dir.path();
    write_text(d / "a.txt", "T= 0\n  X= 1 2 3\n");
    const std::vector<std::filesystem::path> refs{d / "a.txt", d / "a.txt"};
    const std::vector<std::filesystem::path> ours{d / "a.txt"};
    const std::vector<int> widths{3, 3};
    const auto result = compare_with_reference(refs, ours, widths);
    ASSERT_EQ(result.messages.size(), 1u);
    EXPECT_EQ(result.messages[0], "2 reference files but 1 files of ours");
    EXPECT_THAT(result.per_state_error, ElementsAre(0.0));
    EXPECT_EQ(result.mean_error, std::numeric_limits<double>::infinity());
    const std::vector<int> one_width{3};
    EXPECT_THROW((void)compare_with_reference(refs, ours, one_width), std::invalid_argument);
}

TEST(Regression, OurExportMatchesItselfAndSofaLayoutReference) {
    // Our writer against a SOFA-precision (6 digits) reference of the same motion.
    TempDir dir;
    Rigid3Object rigid("rigid");
    rigid.position.resize(1);
    rigid.position[0].center = Vec3(-4.995441234, -2.309412, -0.000787169);
    rigid.init();
    const StateRecord record{"rigid", "/", &rigid, nullptr, false, true, nullptr, {}};
    StateExporter exporter(dir.path() / "ours", {&record});
    exporter.write(1.99);
    write_text(dir.path() / "ref.txt", "T= 1.99\n  X= -4.99544 -2.30941 -0.000787169 0 0 0 1\n");
    const std::vector<std::filesystem::path> refs{dir.path() / "ref.txt"};
    const auto result = compare_with_reference(refs, exporter.files(), exporter.values_per_dof());
    EXPECT_TRUE(result.messages.empty());
    EXPECT_NEAR(result.mean_error, 0.000001234 + 0.000002, 1e-12);
    EXPECT_TRUE(result.passed());
}

}  // namespace
}  // namespace penalty::output
