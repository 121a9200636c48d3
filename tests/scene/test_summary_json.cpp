// The run summary as JSON (summary_json.cpp; `penalty run --summary-json`, Python's Scene.run):
// every field under its name in order, numbers in the shortest form that reads back to the same
// double, inf and NaN as null, strings escaped (quotes, backslashes, newlines, control bytes),
// the tunnelling guard's totals as a nested object or null, and "text" as format_summary writes it.
#include "penalty/scene/runner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace {

using namespace penalty;

scene::RunSummary summary_with_numbers() {
    scene::RunSummary s;
    s.steps = 300;
    s.dt = 0.01;
    s.simulated_time = 3.0000000000000004;  // 300 sums of 0.01
    s.wall_seconds = 1.0 / 3.0;
    s.detection_seconds = 1e-300;
    s.response_seconds = std::numeric_limits<double>::infinity();
    s.solve_seconds = std::numeric_limits<double>::quiet_NaN();
    s.output_seconds = 0.0;
    s.mean_contacts = 2.5;
    s.max_contacts = 7;
    s.max_penetration = -0.0;
    s.kinetic_energy = 123456789.125;
    s.contact_energy = 5e-324;
    s.dissipated_energy = 0.1 + 0.2;
    s.cg = true;
    s.mean_cg_iterations = 12.25;
    s.max_cg_iterations = 25;
    s.cg_limit_steps = 3;
    return s;
}

TEST(SummaryJson, EveryFieldInOrderWithShortestNumbersAndNullForNonFinite) {
    const std::string json = scene::summary_json(summary_with_numbers());
    const std::string head = R"({
  "steps": 300,
  "dt": 0.01,
  "simulated_time": 3.0000000000000004,
  "wall_seconds": 0.3333333333333333,
  "detection_seconds": 1e-300,
  "response_seconds": null,
  "solve_seconds": null,
  "output_seconds": 0,
  "mean_contacts": 2.5,
  "max_contacts": 7,
  "max_penetration": -0,
  "kinetic_energy": 123456789.125,
  "contact_energy": 5e-324,
  "dissipated_energy": 0.30000000000000004,
  "cg": true,
  "mean_cg_iterations": 12.25,
  "max_cg_iterations": 25,
  "cg_limit_steps": 3,
  "newton": false,
  "mean_newton_iterations": 0,
  "max_newton_iterations": 0,
  "newton_unconverged_steps": 0,
  "state_files": [],
  "tunnelling": null,
  "text": ")";
    ASSERT_GE(json.size(), head.size());
    EXPECT_EQ(json.substr(0, head.size()), head);
    EXPECT_EQ(json.substr(json.size() - 4), "\"\n}\n");
}

TEST(SummaryJson, StringsAreEscapedAndTheTextIsFormatSummarys) {
    scene::RunSummary s = summary_with_numbers();
    s.state_files = {"out/0_\"dofs\".txt", "C:\\states\\1.txt", std::string("odd\x01\tname\n")};
    const std::string json = scene::summary_json(s);
    EXPECT_NE(json.find(R"("state_files": ["out/0_\"dofs\".txt", "C:\\states\\1.txt", "odd\u0001\u0009name\n"],)"),
              std::string::npos)
        << json;
    // the text: format_summary's lines, each newline as \n, nothing raw after the key
    const std::string text = scene::format_summary(s);
    ASSERT_NE(text.find('\n'), std::string::npos);
    std::string escaped;
    for (const char c : text) {
        if (c == '\n') escaped += "\\n";
        else if (c == '"' || c == '\\') escaped += std::string("\\") + c;
        else escaped += c;
    }
    EXPECT_NE(json.find("\"text\": \"" + escaped + "\"\n}\n"), std::string::npos);
}

TEST(SummaryJson, TheTunnellingGuardsTotalsAreANestedObject) {
    scene::RunSummary s = summary_with_numbers();
    s.tunnelling.mode = "substep";
    s.tunnelling.crossings = 2;
    s.tunnelling.crossing_steps = 1;
    s.tunnelling.prevented = 4;
    s.tunnelling.undone_solves = 3;
    s.tunnelling.extra_solves = 6;
    s.tunnelling.deepest_halving = 2;
    s.tunnelling.max_depth = 0.0025;
    s.tunnelling.first_crossing = "step 7: vertex 3 of 'ball' through triangle 1 of 'floor'";
    s.tunnelling.stiffened_contacts = 0;
    s.tunnelling.max_stiffening = 1.0;
    s.tunnelling.stiffening_energy = 0.0;
    s.tunnelling.guard_seconds = 0.5;
    const std::string json = scene::summary_json(s);
    const std::string nested = R"(  "tunnelling": {
  "mode": "substep",
  "crossings": 2,
  "crossing_steps": 1,
  "prevented": 4,
  "undone_solves": 3,
  "extra_solves": 6,
  "deepest_halving": 2,
  "max_depth": 0.0025,
  "first_crossing": "step 7: vertex 3 of 'ball' through triangle 1 of 'floor'",
  "stiffened_contacts": 0,
  "max_stiffening": 1,
  "stiffening_energy": 0,
  "guard_seconds": 0.5
},
  "text": ")";
    EXPECT_NE(json.find(nested), std::string::npos) << json;
}

}  // namespace
