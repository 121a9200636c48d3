#include "penalty/io/rigid_mass_file.hpp"

#include "io/text.hpp"

#include <string>
#include <vector>

namespace penalty::io {

RigidMassFile load_rigid_mass_file(const std::filesystem::path& path) {
    return parse_rigid_mass_file(detail::read_file(path), path);
}

RigidMassFile parse_rigid_mass_file(std::string_view text, const std::filesystem::path& path) {
    text = detail::skip_byte_order_mark(text);
    RigidMassFile out;
    // tokens with their line, after the first line (UniformMass::loadFromFileRigidImpl skips it)
    std::vector<std::pair<std::string_view, int>> tokens;
    std::size_t pos = 0;
    int line = 0;
    while (pos < text.size()) {
        const std::size_t end = std::min(text.find('\n', pos), text.size());
        ++line;
        if (line > 1)
            for (const std::string_view t : detail::split_blanks(text.substr(pos, end - pos)))
                tokens.emplace_back(t, line);
        pos = end + 1;
    }
    std::size_t k = 0;
    const auto numbers = [&](std::string_view keyword, int count) {
        std::vector<double> values;
        const int keyword_line = tokens[k - 1].second;
        for (int i = 0; i < count; ++i) {
            const auto value = k < tokens.size() ? detail::parse_double(tokens[k].first) : std::nullopt;
            if (!value) {
                std::string what(keyword);  // built step by step: GCC 12 -Wrestrict misfires on a + chain here
                what += " needs ";
                what += std::to_string(count);
                what += " numbers";
                detail::fail(path, keyword_line, what);
            }
            if (const auto problem = detail::magnitude_problem(*value)) detail::fail(path, tokens[k].second, *problem);
            values.push_back(*value);
            ++k;
        }
        return values;
    };
    const auto skip_line = [&](int of_line) {
        while (k < tokens.size() && tokens[k].second == of_line) ++k;
    };
    while (k < tokens.size()) {
        const auto [keyword, keyword_line] = tokens[k++];
        if (keyword == "inrt") {
            const std::vector<double> j = numbers(keyword, 9);
            Mat3 inertia;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) inertia(r, c) = j[3 * std::size_t(r) + std::size_t(c)];
            out.inertia = inertia;
        } else if (keyword == "vertexMass") {
            out.vertex_mass = numbers(keyword, 1)[0];
        } else if (keyword == "center" || keyword == "cntr" || keyword == "grav") {
            (void)numbers(keyword, 3);
        } else if (keyword == "frme") {
            (void)numbers(keyword, 4);
        } else if (keyword == "volm" || keyword == "visc" || keyword == "stck" || keyword == "step" ||
                   keyword == "prec") {
            (void)numbers(keyword, 1);
        } else {  // '#' comment or an unknown keyword: the rest of its line
            skip_line(keyword_line);
        }
    }
    return out;
}

}  // namespace penalty::io
