#include "output/file_io.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
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

void write_file(const std::filesystem::path& file, std::string_view content) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot open " + quoted(file) + " for writing: " + std::strerror(errno));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.close();
    if (!out) throw std::runtime_error("cannot write " + quoted(file));
}

}  // namespace penalty::output::detail
