// The folder the output writers write into (output_folder.cpp, OutputFolder): files made under a
// hidden temporary name and renamed onto theirs (no temporary left, a link at the name replaced,
// its target untouched), files created at once and appended to, removals of links and missing
// names, and the errors naming the folder or the file.
#include "output/output_folder.hpp"
#include "output_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace penalty::output {
namespace {

using detail::CreatedFile;
using detail::OutputFolder;
using test::read_text;
using test::TempDir;

/// The names in `folder`, sorted.
std::vector<std::string> folder_entries(const std::filesystem::path& folder) {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) names.push_back(entry.path().filename());
    std::sort(names.begin(), names.end());
    return names;
}

/// The message of the std::runtime_error `f` raises.
template <class F>
std::string output_folder_error(F&& f) {
    try {
        f();
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "no error";
}

TEST(OutputFolder, ReplacedFilesLeaveNoTemporaryAndReplaceALinkAtTheirName) {
    TempDir dir;
    const auto folder_path = dir.path() / "a" / "b";  // made with its parents
    const OutputFolder folder(folder_path);
    ASSERT_TRUE(std::filesystem::is_directory(folder_path));
    folder.replace_file("states.txt", "first");
    folder.replace_file("states.txt", "second, longer");
    EXPECT_EQ(read_text(folder_path / "states.txt"), "second, longer");
    // a link planted at the name: replaced by the file, the target keeps its bytes
    const auto target = dir.path() / "target.txt";
    test::write_text(target, "untouched");
    std::filesystem::create_symlink(target, folder_path / "linked.txt");
    folder.replace_file("linked.txt", "new");
    EXPECT_FALSE(std::filesystem::is_symlink(folder_path / "linked.txt"));
    EXPECT_EQ(read_text(folder_path / "linked.txt"), "new");
    EXPECT_EQ(read_text(target), "untouched");
    EXPECT_EQ(folder_entries(folder_path), (std::vector<std::string>{"linked.txt", "states.txt"}));
}

TEST(OutputFolder, ACreatedFileIsThereAtOnceAndTakesWhatIsAppended) {
    TempDir dir;
    const OutputFolder folder(dir.path());
    test::write_text(dir.path() / "run.csv", "an old run's rows\n");
    CreatedFile file = folder.create_file("run.csv");
    EXPECT_EQ(file.path(), dir.path() / "run.csv");
    EXPECT_EQ(read_text(dir.path() / "run.csv"), "");  // the old file is gone already
    file.write("step,time\n", 10);
    CreatedFile moved = std::move(file);
    moved.write("1,0.01\n", 7);
    EXPECT_EQ(read_text(dir.path() / "run.csv"), "step,time\n1,0.01\n");
    EXPECT_EQ(folder_entries(dir.path()), (std::vector<std::string>{"run.csv"}));
}

TEST(OutputFolder, RemovingTakesTheLinkNotItsTargetAndAMissingNameIsNoError) {
    TempDir dir;
    const auto folder_path = dir.path() / "out";
    const OutputFolder folder(folder_path);
    const auto target = dir.path() / "target.txt";
    test::write_text(target, "stays");
    std::filesystem::create_symlink(target, folder_path / "link");
    folder.remove("link");
    folder.remove("never-there");
    EXPECT_TRUE(folder_entries(folder_path).empty());
    EXPECT_EQ(read_text(target), "stays");
    std::filesystem::create_directory(folder_path / "sub");
    EXPECT_EQ(output_folder_error([&] { folder.remove("sub"); }),
              "cannot remove '" + (folder_path / "sub").string() + "': Is a directory");
}

TEST(OutputFolder, AFolderThatIsAFileAndANameThatIsAFolderAreRefused) {
    TempDir dir;
    const auto file = dir.path() / "plain";
    test::write_text(file, "");
    EXPECT_EQ(output_folder_error([&] { const OutputFolder folder(file); }),
              "cannot create directory '" + file.string() + "': Not a directory");
    // a directory at the name: the rename onto it fails and the temporary is removed
    const OutputFolder folder(dir.path());
    std::filesystem::create_directory(dir.path() / "taken");
    EXPECT_EQ(output_folder_error([&] { folder.replace_file("taken", "x"); }),
              "cannot write '" + (dir.path() / "taken").string() + "': Is a directory");
    EXPECT_EQ(folder_entries(dir.path()), (std::vector<std::string>{"plain", "taken"}));
}

}  // namespace
}  // namespace penalty::output
