#pragma once
// Private helpers of the output layer: writing into a folder without ever following a symbolic
// link that is (or appears) in it. The folder is opened once; each file is created under a fresh
// hidden temporary name with O_CREAT | O_EXCL | O_NOFOLLOW (which refuses any existing entry,
// a link included) and renamed onto its name: rename(2) replaces a link by the file, never writes
// through it. A reader sees the old file or the new one, never half of one.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>

namespace penalty::output::detail {

/// A file created by OutputFolder::create_file, open for appending; closed by the destructor.
class CreatedFile {
public:
    CreatedFile(int fd, std::filesystem::path path) : fd_(fd), path_(std::move(path)) {}
    CreatedFile(CreatedFile&& other) noexcept;
    CreatedFile& operator=(CreatedFile&& other) noexcept;
    CreatedFile(const CreatedFile&) = delete;
    CreatedFile& operator=(const CreatedFile&) = delete;
    ~CreatedFile();

    /// Appends `size` bytes, throwing std::runtime_error naming the file on failure.
    void write(const void* data, std::size_t size);
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

private:
    int fd_ = -1;
    std::filesystem::path path_;
};

/// A folder the output layer writes into (created when missing; the folder itself may be a link,
/// as the user named it). Names are single path components.
class OutputFolder {
public:
    /// Creates `path` (create_directories) and opens it; std::runtime_error naming it on failure.
    explicit OutputFolder(const std::filesystem::path& path);
    OutputFolder(const OutputFolder&) = delete;
    OutputFolder& operator=(const OutputFolder&) = delete;
    ~OutputFolder();

    /// Writes `content` to a temporary file and renames it onto `name` (atomic for readers).
    void replace_file(std::string_view name, std::string_view content) const;

    /// A new empty file `name` (created as a temporary and renamed onto `name` at once), open for
    /// appending: for data written while a run goes.
    [[nodiscard]] CreatedFile create_file(std::string_view name) const;

    /// Removes the entry `name` (a link is removed, not its target); missing is not an error.
    void remove(std::string_view name) const;

    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

private:
    /// A fresh hidden file ".<name>.tmp-<pid>-<n>" (O_EXCL | O_NOFOLLOW); returns its descriptor.
    int create_temporary(std::string_view name, std::string& temporary) const;
    void rename_onto(const std::string& temporary, std::string_view name) const;

    std::filesystem::path path_;
    int fd_ = -1;
};

}  // namespace penalty::output::detail
