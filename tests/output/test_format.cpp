// The number and file-name formats of the outputs (output/format.cpp): shortest round-trip numbers,
// sanitized file names.
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

TEST(Format, NumbersAreShortestRoundTrip) {
    EXPECT_EQ(format_number(-5.0), "-5");
    EXPECT_EQ(format_number(0.0), "0");
    EXPECT_EQ(format_number(0.1), "0.1");
    EXPECT_EQ(format_number(1e-300), "1e-300");
    EXPECT_EQ(format_number(-4.99544), "-4.99544");
    EXPECT_EQ(format_number(1.0 / 3.0), "0.3333333333333333");
    EXPECT_EQ(std::stod(format_number(1.0 / 3.0)), 1.0 / 3.0);
}

TEST(Format, SanitizeFileName) {
    EXPECT_EQ(sanitize_file_name("dofs"), "dofs");
    EXPECT_EQ(sanitize_file_name("my dofs/1:a"), "my_dofs_1_a");
    EXPECT_EQ(sanitize_file_name("a-b.c_d"), "a-b.c_d");
    EXPECT_EQ(sanitize_file_name(""), "state");
}

}  // namespace
}  // namespace penalty::output
