// Whole files written by the output layer (file_io.cpp, write_output_file): the exact bytes, a
// longer old file truncated, a symbolic link at the name replaced (its target untouched), and the
// errors naming the file for a FIFO (no hang without a reader), a directory and a missing folder.
#include "output_test_support.hpp"
#include "penalty/output/output_file.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace penalty::output {
namespace {

using test::read_text;
using test::TempDir;

/// The message of the std::runtime_error that writing `content` into `file` raises.
std::string file_io_error(const std::filesystem::path& file) {
    try {
        write_output_file(file, "x");
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "no error";
}

TEST(FileIo, WritesTheExactBytesAndTruncatesALongerFile) {
    TempDir dir;
    const auto file = dir.path() / "summary.json";
    const std::string bytes("line 1\r\nnul \0 inside\n", 21);
    write_output_file(file, std::string(1000, 'o'));
    write_output_file(file, bytes);
    EXPECT_EQ(read_text(file), bytes);
    EXPECT_EQ(std::filesystem::file_size(file), 21u);
    write_output_file(file, "");
    EXPECT_EQ(std::filesystem::file_size(file), 0u);
}

TEST(FileIo, ALinkAtTheNameIsReplacedNeverWrittenThrough) {
    TempDir dir;
    const auto target = dir.path() / "precious.txt";
    write_output_file(target, "keep me");
    const auto file = dir.path() / "out.csv";
    std::filesystem::create_symlink(target, file);
    write_output_file(file, "a,b\n");
    EXPECT_FALSE(std::filesystem::is_symlink(file));
    EXPECT_EQ(read_text(file), "a,b\n");
    EXPECT_EQ(read_text(target), "keep me");
    // a dangling link likewise
    const auto dangling = dir.path() / "dangling";
    std::filesystem::create_symlink(dir.path() / "nowhere", dangling);
    write_output_file(dangling, "y");
    EXPECT_FALSE(std::filesystem::is_symlink(dangling));
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "nowhere"));
    EXPECT_EQ(read_text(dangling), "y");
}

TEST(FileIo, AFifoADirectoryAndAMissingFolderAreRefusedNamingTheFile) {
    TempDir dir;
    const auto fifo = dir.path() / "pipe";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
    // no reader: the non-blocking open fails at once instead of waiting for one
    EXPECT_EQ(file_io_error(fifo), "cannot open '" + fifo.string() + "' for writing: No such device or address");
    const auto folder = dir.path() / "folder";
    std::filesystem::create_directory(folder);
    EXPECT_EQ(file_io_error(folder), "cannot open '" + folder.string() + "' for writing: Is a directory");
    const auto missing = dir.path() / "missing" / "file.txt";
    EXPECT_EQ(file_io_error(missing), "cannot open '" + missing.string() + "' for writing: No such file or directory");
}

}  // namespace
}  // namespace penalty::output
