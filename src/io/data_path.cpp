#include "penalty/io/data_path.hpp"

#include "io/text.hpp"

#include <cstdlib>
#include <string>

namespace penalty::io {

std::vector<std::filesystem::path> data_search_dirs(const std::filesystem::path& scene_dir,
                                                    const std::vector<std::filesystem::path>& data_dirs) {
    std::vector<std::filesystem::path> dirs;
    dirs.push_back(scene_dir.empty() ? std::filesystem::path(".") : scene_dir);
    for (const auto& d : data_dirs) dirs.push_back(d);
    if (const char* env = std::getenv(kDataPathEnvironmentVariable)) {
        const std::string_view list(env);
        std::size_t start = 0;
        while (start <= list.size()) {
            const std::size_t end = std::min(list.find(':', start), list.size());
            if (end > start) dirs.emplace_back(std::string(list.substr(start, end - start)));
            start = end + 1;
        }
    }
    return dirs;
}

std::filesystem::path resolve_data_file(std::string_view name, const std::filesystem::path& scene_dir,
                                        const std::vector<std::filesystem::path>& data_dirs) {
    if (name.empty()) throw LoadError("empty data file name");
    std::filesystem::path file{std::string(name)};
    if (file.is_absolute()) {
        const auto why = detail::unreadable_reason(file);
        if (!why) return file;
        if (*why == "does not exist") throw LoadError("cannot find data file '" + std::string(name) + "'");
        throw LoadError("data file '" + std::string(name) + "' " + *why);
    }
    // The first directory where the name exists decides: a directory, a device or a link loop
    // found there is reported as such rather than as "cannot find".
    std::string looked;
    for (const auto& dir : data_search_dirs(scene_dir, data_dirs)) {
        std::filesystem::path candidate = dir / file;
        const auto why = detail::unreadable_reason(candidate);
        if (!why) return candidate;
        if (*why != "does not exist")
            throw LoadError("data file '" + std::string(name) + "' found as " + candidate.string() + ", which " + *why);
        looked += (looked.empty() ? "" : ", ") + dir.string();
    }
    throw LoadError("cannot find data file '" + std::string(name) + "'; looked in: " + looked);
}

}  // namespace penalty::io
