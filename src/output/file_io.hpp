#pragma once
// Private helpers of the output layer: directory creation and whole-file writes that report the
// path on failure.

#include <filesystem>
#include <string>
#include <string_view>

namespace penalty::output::detail {

/// create_directories, throwing std::runtime_error "cannot create directory '<dir>': <reason>".
void create_directory(const std::filesystem::path& directory);

/// Writes `content` to `file` (truncating), throwing std::runtime_error naming the file.
void write_file(const std::filesystem::path& file, std::string_view content);

/// "'<path>'" for messages.
std::string quoted(const std::filesystem::path& path);

}  // namespace penalty::output::detail
