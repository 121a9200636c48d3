#include "output/output_folder.hpp"

#include "output/file_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace penalty::output::detail {

namespace {

std::string reason() { return std::strerror(errno); }

}  // namespace

CreatedFile::CreatedFile(CreatedFile&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), path_(std::move(other.path_)) {}

CreatedFile& CreatedFile::operator=(CreatedFile&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = std::exchange(other.fd_, -1);
        path_ = std::move(other.path_);
    }
    return *this;
}

CreatedFile::~CreatedFile() {
    if (fd_ >= 0) ::close(fd_);
}

void CreatedFile::write(const void* data, std::size_t size) {
    const char* bytes = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd_, bytes, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw std::runtime_error("cannot write " + quoted(path_) + ": " + reason());
        bytes += n;
        size -= std::size_t(n);
    }
}

OutputFolder::OutputFolder(const std::filesystem::path& path) : path_(path) {
    detail::create_directory(path_);  // (qualified: std::filesystem::create_directory is found by ADL)
    fd_ = ::open(path_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd_ < 0) throw std::runtime_error("cannot open directory " + quoted(path_) + ": " + reason());
}

OutputFolder::~OutputFolder() {
    if (fd_ >= 0) ::close(fd_);
}

int OutputFolder::create_temporary(std::string_view name, std::string& temporary) const {
    static std::atomic<unsigned> counter{0};
    for (int attempt = 0; attempt < 100; ++attempt) {
        temporary.assign(1, '.');  // appended piece by piece: GCC 12 warns (-Wrestrict, wrongly) on "." + string
        temporary.append(name)
            .append(".tmp-")
            .append(std::to_string(::getpid()))
            .append("-")
            .append(std::to_string(counter++));
        const int fd = ::openat(fd_, temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd >= 0) return fd;
        if (errno != EEXIST) break;  // EEXIST: an entry (perhaps a planted link) has that name: another one
    }
    throw std::runtime_error("cannot create a temporary file for " + quoted(path_ / std::string(name)) + " in " +
                             quoted(path_) + ": " + reason());
}

void OutputFolder::rename_onto(const std::string& temporary, std::string_view name) const {
    if (::renameat(fd_, temporary.c_str(), fd_, std::string(name).c_str()) != 0) {
        const std::string why = reason();
        ::unlinkat(fd_, temporary.c_str(), 0);
        throw std::runtime_error("cannot write " + quoted(path_ / std::string(name)) + ": " + why);
    }
}

void OutputFolder::replace_file(std::string_view name, std::string_view content) const {
    std::string temporary;
    CreatedFile file(create_temporary(name, temporary), path_ / std::string(name));
    try {
        file.write(content.data(), content.size());
    } catch (...) {
        ::unlinkat(fd_, temporary.c_str(), 0);
        throw;
    }
    rename_onto(temporary, name);
}

CreatedFile OutputFolder::create_file(std::string_view name) const {
    std::string temporary;
    CreatedFile file(create_temporary(name, temporary), path_ / std::string(name));
    rename_onto(temporary, name);
    return file;
}

void OutputFolder::remove(std::string_view name) const {
    if (::unlinkat(fd_, std::string(name).c_str(), 0) != 0 && errno != ENOENT)
        throw std::runtime_error("cannot remove " + quoted(path_ / std::string(name)) + ": " + reason());
}

}  // namespace penalty::output::detail
