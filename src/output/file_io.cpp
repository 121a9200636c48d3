#include "output/file_io.hpp"

#include "penalty/output/output_file.hpp"

#include <ext/stdio_filebuf.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace penalty::output::detail {

std::string quoted(const std::filesystem::path& path) {
    std::string out(1, '\'');
    out += path.string();
    out += '\'';
    return out;
}

void create_directory(const std::filesystem::path& directory) {
    std::error_code ec;
    std::filesystem::create_directories(directory, ec);
    if (ec) throw std::runtime_error("cannot create directory " + quoted(directory) + ": " + ec.message());
    if (!std::filesystem::is_directory(directory, ec))
        throw std::runtime_error("cannot create directory " + quoted(directory) + ": not a directory");
}

namespace {
/// An ostream over a file descriptor it owns (libstdc++'s stdio_filebuf closes it).
class DescriptorStream final : public std::ostream {
public:
    explicit DescriptorStream(int fd) : std::ostream(nullptr), buffer_(fd, std::ios::out | std::ios::binary) {
        rdbuf(&buffer_);
    }

private:
    __gnu_cxx::stdio_filebuf<char> buffer_;
};

[[noreturn]] void fail_open(const std::filesystem::path& file, const std::string& why) {
    throw std::runtime_error("cannot open " + quoted(file) + " for writing: " + why);
}
}  // namespace

std::unique_ptr<std::ostream> open_output_file(const std::filesystem::path& file) {
    // O_NONBLOCK: opening a FIFO without a reader fails (ENXIO) instead of hanging
    constexpr int kFlags = O_WRONLY | O_CREAT | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK;
    int fd = ::open(file.c_str(), kFlags | O_TRUNC, 0644);
    if (fd < 0 && errno == ELOOP) {
        // a link at the name: replaced by the file, never written through
        if (::unlink(file.c_str()) != 0 && errno != ENOENT)
            fail_open(file, "a symbolic link that cannot be removed: " + std::string(std::strerror(errno)));
        fd = ::open(file.c_str(), kFlags | O_EXCL, 0644);
    }
    if (fd < 0) fail_open(file, std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        fail_open(file, "not a regular file");
    }
    if (::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK) != 0) {
        ::close(fd);
        fail_open(file, std::strerror(errno));
    }
    return std::make_unique<DescriptorStream>(fd);
}

void write_file(const std::filesystem::path& file, std::string_view content) {
    const std::unique_ptr<std::ostream> out = open_output_file(file);
    out->write(content.data(), static_cast<std::streamsize>(content.size()));
    out->flush();
    if (!*out) throw std::runtime_error("cannot write " + quoted(file));
}

}  // namespace penalty::output::detail

namespace penalty::output {

void write_output_file(const std::filesystem::path& file, std::string_view content) {
    detail::write_file(file, content);
}

}  // namespace penalty::output
