#pragma once
// Private helpers of the output layer: directory creation, and files opened for writing without
// ever writing through a symbolic link at their name, reporting the path on failure.

#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>

namespace penalty::output::detail {

/// create_directories, throwing std::runtime_error "cannot create directory '<dir>': <reason>".
void create_directory(const std::filesystem::path& directory);

/// Opens `file` for writing, truncated: a symbolic link at that name is replaced by the new file
/// (unlinked, then the file created with O_EXCL | O_NOFOLLOW: never written through, even if the
/// link comes back meanwhile), and anything but a regular file there (a FIFO, a device, a
/// directory) is refused. std::runtime_error naming the file on failure.
[[nodiscard]] std::unique_ptr<std::ostream> open_output_file(const std::filesystem::path& file);

/// Writes `content` to `file` (open_output_file), throwing std::runtime_error naming the file.
void write_file(const std::filesystem::path& file, std::string_view content);

/// "'<path>'" for messages.
std::string quoted(const std::filesystem::path& path);

}  // namespace penalty::output::detail
