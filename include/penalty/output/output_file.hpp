#pragma once
/// @file
/// Whole files written by the command line and the runner (a run's summary, a step's debug
/// export) as the output writers write theirs: never through a symbolic link at the name (the
/// link is replaced), never into a FIFO or a device.

#include <filesystem>
#include <string_view>

namespace penalty::output {

/// Writes `content` into `file`, truncating it; std::runtime_error naming the file on failure.
void write_output_file(const std::filesystem::path& file, std::string_view content);

}  // namespace penalty::output
