// The io layer's text helpers (io/text.cpp): numbers parsed from whole tokens only, finite and
// within the magnitudes a scene may hold; blanks, trimming and the byte-order mark; the tokenizer's
// line numbers and its messages naming file and line; files that cannot be read, refused before
// reading.
#include "io/text.hpp"
#include "io_test_util.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>

namespace penalty::io {
namespace {

using detail::parse_double;
using detail::parse_int;
using test::message_of;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(Text, NumbersAreWholeFiniteTokens) {
    EXPECT_EQ(parse_double("2.5"), 2.5);
    EXPECT_EQ(parse_double("+2.5e-3"), 2.5e-3);
    EXPECT_EQ(parse_double("-0"), -0.0);
    EXPECT_TRUE(std::signbit(*parse_double("-0")));
    for (const char* bad : {"", "+", "++1", "1.0x", " 1", "1 ", "nan", "inf", "-inf", "1e400", "0x10", "1,5"})
        EXPECT_FALSE(parse_double(bad).has_value()) << "'" << bad << "'";
    EXPECT_EQ(parse_int("+42"), 42);
    EXPECT_EQ(parse_int("-9223372036854775808"), std::numeric_limits<std::int64_t>::min());
    for (const char* bad : {"", "+", "1.0", "9223372036854775808", "12a", "1e3"})
        EXPECT_FALSE(parse_int(bad).has_value()) << "'" << bad << "'";
}

TEST(Text, MagnitudesOutsideTheScenesRangeAreNamed) {
    EXPECT_FALSE(detail::magnitude_problem(0.0).has_value());
    EXPECT_FALSE(detail::magnitude_problem(1e100).has_value());
    EXPECT_FALSE(detail::magnitude_problem(-1e-100).has_value());
    EXPECT_THAT(*detail::magnitude_problem(-1.5e100), HasSubstr("magnitude above 1e100"));
    EXPECT_THAT(*detail::magnitude_problem(5e-101), HasSubstr("magnitude below 1e-100"));
    EXPECT_THAT(*detail::magnitude_problem(std::numeric_limits<double>::denorm_min()), HasSubstr("below 1e-100"));
}

TEST(Text, BlanksTrimAndTheByteOrderMark) {
    EXPECT_THAT(detail::split_blanks(" a\tb\r\nc \v\fd  "), ElementsAre("a", "b", "c", "d"));
    EXPECT_TRUE(detail::split_blanks(" \t\n").empty());
    EXPECT_EQ(detail::trim("\t x y \r\n"), "x y");
    EXPECT_EQ(detail::skip_byte_order_mark("\xEF\xBB\xBFsph 1.0"), "sph 1.0");
    EXPECT_EQ(detail::skip_byte_order_mark("\xEF\xBBsph"), "\xEF\xBBsph");  // not a whole mark
    EXPECT_EQ(detail::quoted("a b"), "'a b'");
}

TEST(Text, TokenizerCountsLinesAndNamesThemInItsErrors) {
    detail::Tokenizer t(
        "\xEF\xBB\xBF"
        "first 1\n\n  2.5 rest of  line \n7 x",
        "f.txt");
    EXPECT_EQ(t.expect("a word").text, "first");
    EXPECT_EQ(t.expect_int("a count"), 1);
    EXPECT_EQ(t.expect_double("a length"), 2.5);
    EXPECT_EQ(t.line(), 3);
    EXPECT_EQ(t.rest_of_line(), "rest of  line");
    EXPECT_EQ(t.expect_int("a count"), 7);
    EXPECT_EQ(message_of<LoadError>([&] { (void)t.expect_double("a radius"); }),
              "f.txt:4: expected a radius (a number), found 'x'");
    EXPECT_EQ(message_of<LoadError>([&] { (void)t.expect("a name"); }),
              "f.txt:4: unexpected end of file (expected a name)");
    detail::Tokenizer big("1e101", "g.txt");
    EXPECT_THAT(message_of<LoadError>([&] { (void)big.expect_double("a mass"); }),
                HasSubstr("g.txt:1: a mass '1e101': magnitude above 1e100"));
}

TEST(Text, CountsAFileCannotHoldAreRefused) {
    detail::Tokenizer t("n 3\n1 2 3", "c.txt");
    (void)t.expect("n");
    (void)t.expect_int("a count");
    EXPECT_NO_THROW(t.check_count(3, 1, "point"));  // "\n1 2 3": 6 bytes, at most 4 tokens
    EXPECT_EQ(message_of<LoadError>([&] { t.check_count(5, 1, "point"); }),
              "c.txt:1: point count 5 exceeds what the file can hold");
    EXPECT_EQ(message_of<LoadError>([&] { t.check_count(-1, 1, "point"); }), "c.txt:1: point count -1 is negative");
    EXPECT_EQ(message_of<LoadError>([] { detail::fail("p.txt", 0, "bad"); }), "p.txt: bad");
}

TEST(Text, FilesThatCannotBeReadAreRefusedBeforeReading) {
    const auto dir = std::filesystem::path(::testing::TempDir());
    EXPECT_THAT(*detail::unreadable_reason(dir / "no_such_file.txt"), HasSubstr("does not exist"));
    EXPECT_THAT(*detail::unreadable_reason(dir), HasSubstr("directory"));
    if (std::filesystem::exists("/dev/zero")) {  // a character device: never read (it has no end)
        EXPECT_THAT(*detail::unreadable_reason("/dev/zero"), HasSubstr("not a regular file"));
    }
    const auto file = test::write_temp("text_ok.txt",
                                       "\xEF\xBB\xBF"
                                       "a b\n");
    EXPECT_FALSE(detail::unreadable_reason(file).has_value());
    EXPECT_EQ(detail::read_file(file),
              "\xEF\xBB\xBF"
              "a b\n");
    EXPECT_THAT(message_of<LoadError>([&] { (void)detail::read_file(dir / "no_such_file.txt"); }),
                HasSubstr("no_such_file.txt: cannot read: the path does not exist"));
}

}  // namespace
}  // namespace penalty::io
