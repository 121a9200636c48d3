// SOFA's Data of every registered component type, read from the catalog scripts/sofa-data-catalog.py
// wrote from SOFA itself (src/scene/sofa_data_catalog.tsv, embedded at build time): one line per
// (type, template, Data or link) with SOFA's value type, how SofaPython3 presents the value, and
// the default.
#include "penalty/scene/live_data.hpp"

#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

namespace penalty::scene {

std::string_view sofa_data_catalog_text();  // generated (cmake/PenaltyEmbedText.cmake)

namespace {

/// `\t`, `\n` and `\\` of a default, as the script escaped them.
std::string unescape(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '\\' || i + 1 == text.size()) {
            out += text[i];
            continue;
        }
        const char next = text[++i];
        out += next == 't' ? '\t' : next == 'n' ? '\n' : next;
    }
    return out;
}

struct Catalog {
    /// "type|template" → rows, template "" (nodes, Python classes), "Vec3d" or "Rigid3d".
    std::map<std::string, std::vector<CatalogEntry>, std::less<>> rows;
};

const Catalog& catalog() {
    static const Catalog parsed = [] {
        Catalog c;
        const std::string_view text = sofa_data_catalog_text();
        std::size_t begin = 0;
        while (begin < text.size()) {
            std::size_t end = text.find('\n', begin);
            if (end == std::string_view::npos) end = text.size();
            const std::string_view line = text.substr(begin, end - begin);
            begin = end + 1;
            if (line.empty()) continue;
            std::vector<std::string_view> fields;
            std::size_t from = 0;
            for (int k = 0; k < 6; ++k) {
                const std::size_t tab = line.find('\t', from);
                if (tab == std::string_view::npos) throw std::logic_error("penalty: malformed SOFA data catalog line");
                fields.push_back(line.substr(from, tab - from));
                from = tab + 1;
            }
            fields.push_back(line.substr(from));
            CatalogEntry e;
            e.link = fields[2] == "link";
            e.name = std::string(fields[3]);
            e.sofa_type = std::string(fields[4]);
            e.python_form = std::string(fields[5]);
            e.default_text = unescape(fields[6]);
            c.rows[std::string(fields[0]) + "|" + std::string(fields[1])].push_back(std::move(e));
        }
        return c;
    }();
    return parsed;
}

}  // namespace

const std::vector<CatalogEntry>& sofa_data_catalog(std::string_view type, bool rigid) {
    static const std::vector<CatalogEntry> none;
    const Catalog& c = catalog();
    const std::string name(type);
    for (const std::string& key : {name + (rigid ? "|Rigid3d" : "|Vec3d"), name + "|Vec3d", name + "|"}) {
        const auto it = c.rows.find(key);
        if (it != c.rows.end()) return it->second;
    }
    return none;
}

std::size_t sofa_type_columns(std::string_view t) {
    static const std::map<std::string_view, std::size_t, std::less<>> rows = {
        {"vector<Vec3d>", 3},
        {"vector<Vec2d>", 2},
        {"vector<Vec6d>", 6},
        {"vector<Vec10d>", 10},
        {"vector<Vec2f>", 2},
        {"vector<Edge>", 2},
        {"vector<Triangle>", 3},
        {"vector<Quad>", 4},
        {"vector<Tetrahedron>", 4},
        {"vector<Hexahedron>", 8},
        {"vector<Pyramid>", 5},
        {"vector<Prism>", 6},
        {"vector<RigidCoord3d>", 7},
        {"vector<RigidDeriv3d>", 6},
        {"vector<Quatd>", 4},
        {"vector<RGBAColor>", 4},
        {"BoundingBox", 3},
        {"vector<fixed_array<I,4>>", 4},
        {"vector<fixed_array<I,5>>", 5},
        {"vector<fixed_array<I,6>>", 6},
        {"vector<fixed_array<I,8>>", 8},
        {"vector<fixed_array<i,3>>", 3},
        {"Mat4x4d", 4},
        {"vector<Mat3x3d>", 9},
    };
    const auto it = rows.find(t);
    return it == rows.end() ? 0 : it->second;
}

std::string_view live_write_name(LiveWrite live) {
    switch (live) {
        case LiveWrite::state:
            return "state";
        case LiveWrite::next_step:
            return "next step";
        case LiveWrite::reinit:
            return "at reinit";
        case LiveWrite::no_effect:
            return "no effect";
        case LiveWrite::refused:
            return "refused";
        case LiveWrite::read_only:
            return "read-only";
    }
    return "?";
}

}  // namespace penalty::scene
