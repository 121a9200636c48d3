// SOFA's `.rigid` mass files (io/rigid_mass_file.cpp): the first line skipped, vertexMass and the
// inertia read row by row, the other keywords' numbers consumed, comments and unknown keywords
// skipped to the end of their line, and a keyword short of numbers named with its file and line.
#include "io_test_util.hpp"
#include "penalty/io/rigid_mass_file.hpp"

#include <gtest/gtest.h>

namespace penalty::io {
namespace {

using test::message_of;

TEST(RigidMassFile, ReadsVertexMassAndInertiaRowByRow) {
    const RigidMassFile f = parse_rigid_mass_file(
        "Xsp 3.0 mass (this line is skipped: vertexMass 99)\n"
        "volm 1.5\n"
        "inrt 1 2 3\n"
        "     4 5 6\n"
        "     7 8 9\n"
        "cntr 0 0 0 # a comment: vertexMass 7\n"
        "frme 0 0 0 1\n"
        "grav 0 -9.81 0\n"
        "visc 0 stck 0 step 0.01 prec 1e-6\n"
        "colour red green  (unknown keyword: its line is skipped)\n"
        "vertexMass 2.5\n",
        "cube.rigid");
    ASSERT_TRUE(f.vertex_mass.has_value());
    EXPECT_EQ(*f.vertex_mass, 2.5);
    ASSERT_TRUE(f.inertia.has_value());
    EXPECT_EQ((*f.inertia)(0, 1), 2.0);
    EXPECT_EQ((*f.inertia)(1, 0), 4.0);
    EXPECT_EQ((*f.inertia)(2, 2), 9.0);
}

TEST(RigidMassFile, AFileWithoutTheKeywordsLeavesThemUnset) {
    const RigidMassFile f = parse_rigid_mass_file("header\nvolm 2\ncenter 1 2 3\n", "plain.rigid");
    EXPECT_FALSE(f.vertex_mass.has_value());
    EXPECT_FALSE(f.inertia.has_value());
    EXPECT_FALSE(parse_rigid_mass_file("", "empty.rigid").vertex_mass.has_value());
}

TEST(RigidMassFile, AKeywordShortOfNumbersNamesFileAndLine) {
    EXPECT_EQ(message_of<LoadError>([] { (void)parse_rigid_mass_file("h\nvolm 1\ninrt 1 2 3 4\n", "short.rigid"); }),
              "short.rigid:3: inrt needs 9 numbers");
    EXPECT_EQ(message_of<LoadError>([] { (void)parse_rigid_mass_file("h\nvertexMass heavy\n", "word.rigid"); }),
              "word.rigid:2: vertexMass needs 1 numbers");
}

TEST(RigidMassFile, ReadsAFileFromDisk) {
    const auto path = test::write_temp("disk.rigid", "Xsp 3.0\nvertexMass 0.75\n");
    EXPECT_EQ(load_rigid_mass_file(path).vertex_mass, 0.75);
    EXPECT_THROW((void)load_rigid_mass_file(path.string() + ".missing"), LoadError);
}

}  // namespace
}  // namespace penalty::io
