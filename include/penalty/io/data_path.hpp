#pragma once
/// @file
/// Where relative data file names (`mesh/torus.obj`) are looked for.

#include "penalty/io/error.hpp"

#include <filesystem>
#include <string_view>
#include <vector>

namespace penalty::io {

/// Name of the environment variable holding extra data directories, separated by ':'.
inline constexpr const char* kDataPathEnvironmentVariable = "PENALTY_DATA_PATH";

/// The directories searched for a relative data file name, in order: the scene's folder,
/// each of `data_dirs` (the command line's `--data-dir`, in the order given), then each
/// non-empty entry of the PENALTY_DATA_PATH environment variable.
[[nodiscard]] std::vector<std::filesystem::path> data_search_dirs(const std::filesystem::path& scene_dir,
                                                                  const std::vector<std::filesystem::path>& data_dirs);

/// Resolves a data file name. An absolute name is returned as is when the file exists;
/// a relative name is tried in each directory of data_search_dirs(), the first existing
/// regular file wins.
/// @throws LoadError `cannot find data file 'NAME'; looked in: DIR1, DIR2, ...`
///         (for an absolute name: `cannot find data file 'NAME'`)
[[nodiscard]] std::filesystem::path resolve_data_file(std::string_view name, const std::filesystem::path& scene_dir,
                                                      const std::vector<std::filesystem::path>& data_dirs);

}  // namespace penalty::io
