// SOFA's data path (io/data_path.cpp): the scene's folder, then the data folders, then the environment.
#include "io_test_util.hpp"

#include "penalty/io/data_path.hpp"
#include "penalty/io/scene_file.hpp"
#include "penalty/io/scene_mesh.hpp"
#include "penalty/scene/components.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>

namespace penalty::io {
namespace {

using test::data_dir;
using test::message_of;

TEST(DataPath, SceneFolderThenDataDirsThenEnvironment) {
    const auto scene_dir = data_dir() / "scenes";
    EXPECT_EQ(resolve_data_file("tiny.scn", scene_dir, {}), scene_dir / "tiny.scn");
    EXPECT_EQ(resolve_data_file("mesh/tetra.obj", scene_dir, {"/nonexistent", data_dir()}),
              data_dir() / "mesh" / "tetra.obj");
    ::setenv(kDataPathEnvironmentVariable, ("/nonexistent2::" + data_dir().string()).c_str(), 1);
    EXPECT_EQ(resolve_data_file("mesh/tetra.obj", scene_dir, {}), data_dir() / "mesh" / "tetra.obj");
    EXPECT_EQ(message_of<LoadError>([&] { (void)resolve_data_file("mesh/none.obj", scene_dir, {"/nonexistent"}); }),
              "cannot find data file 'mesh/none.obj'; looked in: " + scene_dir.string() +
                  ", /nonexistent, /nonexistent2, " + data_dir().string());
    ::unsetenv(kDataPathEnvironmentVariable);
    EXPECT_EQ(message_of<LoadError>([&] { (void)resolve_data_file("/no/such/file.obj", scene_dir, {}); }),
              "cannot find data file '/no/such/file.obj'");
}

}  // namespace
}  // namespace penalty::io
