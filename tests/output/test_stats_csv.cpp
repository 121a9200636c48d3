// Per-step statistics: CSV header and rows, contact summary over penalty force fields.
#include "penalty/output/format.hpp"
#include "penalty/output/stats_csv.hpp"

#include "output_test_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

namespace penalty::output {
namespace {

using test::read_text;
using test::TempDir;
using ::testing::HasSubstr;

TEST(StatsCsv, HeaderAndRowsExactly) {
    TempDir dir;
    const auto file = dir.path() / "sub" / "stats.csv";
    StatsCsvWriter writer(file);
    EXPECT_EQ(read_text(file),
              "step,time,contacts,active_contacts,max_penetration,contact_energy,kinetic_energy,dissipated_energy,"
              "detection_seconds,response_seconds,solve_seconds,output_seconds,cg_iterations,newton_iterations\n");
    StepStats stats;
    stats.step = 3;
    stats.time = 0.03;
    stats.contacts = 12;
    stats.active_contacts = 7;
    stats.max_penetration = 0.0015;
    stats.contact_energy = 1e-300;
    stats.kinetic_energy = 2.5;
    stats.dissipated_energy = 0.0;
    stats.detection_seconds = 0.25;
    stats.response_seconds = 0.125;
    stats.solve_seconds = 1.5;
    stats.output_seconds = 0.001;
    stats.cg_iterations = 41;
    stats.newton_iterations = 3;
    writer.write(stats);
    EXPECT_EQ(read_text(file),
              std::string(stats_csv_header()) + "\n3,0.03,12,7,0.0015,1e-300,2.5,0,0.25,0.125,1.5,0.001,41,3\n");
}

TEST(StatsCsv, NonFiniteThrowsNamingColumnAndStep) {
    TempDir dir;
    StatsCsvWriter writer(dir.path() / "stats.csv");
    StepStats stats;
    stats.step = 41;
    stats.kinetic_energy = std::numeric_limits<double>::infinity();
    try {
        writer.write(stats);
        FAIL();
    } catch (const NonFiniteValueError& error) {
        EXPECT_THAT(error.what(), HasSubstr("kinetic_energy"));
        EXPECT_THAT(error.what(), HasSubstr("step 41"));
    }
    EXPECT_EQ(read_text(dir.path() / "stats.csv"), std::string(stats_csv_header()) + "\n");
}

TEST(StatsCsv, UnwritablePathThrowsNamingIt) {
    TempDir dir;
    test::write_text(dir.path() / "blocker", "x");
    try {
        StatsCsvWriter writer(dir.path() / "blocker" / "stats.csv");
        FAIL();
    } catch (const std::runtime_error& error) {
        EXPECT_THAT(error.what(), HasSubstr("blocker"));
    }
}

TEST(SummarizeContacts, SumsFieldsAndTakesMaxPenetration) {
    // field 1: two contacts between a 2-point state and a 2-point state along +y (ks = 100 N/m)
    Vec3Object a("a");
    a.position = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
    a.init();
    Vec3Object b("b");
    b.position = {Vec3(0, -0.1, 0), Vec3(1, 0.5, 0)};
    b.init();
    PenaltyForceField field1;
    field1.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitY(), 0.0,
                       100.0);  // pen = 0 − (−0.1) = 0.1
    field1.add_contact(DofIndex(1), DofIndex(1), ElementIndex(1), ElementIndex(1), Vec3::UnitY(), 0.0,
                       100.0);  // pen = −0.5: inactive
    Vec3List f1(2, Vec3::Zero()), f2(2, Vec3::Zero());
    const Vec3List v(2, Vec3::Zero());
    field1.add_force(f1, f2, a.position, b.position, v, v);
    // field 2: one contact with dist 0.05 (m): pen = 0.05 − (−0.1) = 0.15
    PenaltyForceField field2;
    field2.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitY(), 0.05, 10.0);
    field2.add_force(f1, f2, a.position, b.position, v, v);
    const std::vector<ContactRecord> contacts{{"c1", &field1, &a, &b}, {"c2", &field2, &a, &b}};
    const ContactSummary summary = summarize_contacts(contacts);
    EXPECT_EQ(summary.contacts, 3u);
    EXPECT_EQ(summary.active_contacts, 2u);
    EXPECT_DOUBLE_EQ(summary.max_penetration, 0.15);
    // ½·100·0.1² + ½·10·0.15² = 0.5 + 0.1125
    EXPECT_DOUBLE_EQ(summary.contact_energy, 0.6125);
    EXPECT_EQ(summary.dissipated_energy, 0.0);

    EXPECT_EQ(summarize_contacts({}).max_penetration, 0.0);
    const std::vector<ContactRecord> broken{{"broken", nullptr, &a, &b}};
    EXPECT_THROW((void)summarize_contacts(broken), std::invalid_argument);
}

}  // namespace
}  // namespace penalty::output
