#include "scene/display.hpp"

#include <array>
#include <cstdio>
#include <utility>

namespace penalty::scene::display {

std::string number(double value) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", value);
    return buf;
}

std::string vector(const Vec3& v) {
    std::string out = "(";
    out += number(v.x());
    out += ", ";
    out += number(v.y());
    out += ", ";
    out += number(v.z());
    out += ")";
    return out;
}

std::string node_path(const Node& node) {
    if (node.parent() == nullptr) return "/";
    std::string out;
    for (const Node* x = &node; x->parent() != nullptr; x = x->parent()) out.insert(0, "/" + x->name());
    return out;
}

std::string node_path(const io::SceneNode& node) { return node.parent ? node.path() : std::string("/"); }

std::string counted(std::size_t n, std::string_view singular, std::string_view plural) {
    return std::to_string(n) + " " + std::string(n == 1 ? singular : plural);
}

namespace {
std::string element_counts(std::size_t points, std::size_t edges, std::size_t triangles, std::size_t quads,
                           std::size_t tetrahedra, std::size_t hexahedra) {
    std::string out = counted(points, "point", "points");
    const std::array<std::pair<std::size_t, std::array<const char*, 2>>, 5> parts{
        {{edges, {"edge", "edges"}},
         {triangles, {"triangle", "triangles"}},
         {quads, {"quad", "quads"}},
         {tetrahedra, {"tetrahedron", "tetrahedra"}},
         {hexahedra, {"hexahedron", "hexahedra"}}}};
    for (const auto& [n, words] : parts)
        if (n > 0) out += ", " + counted(n, words[0], words[1]);
    return out;
}
}  // namespace

std::string element_counts(std::size_t points, const MeshTopology& t) {
    return element_counts(points, t.edges().size(), t.triangles().size(), t.quads().size(), t.tetrahedra().size(),
                          t.hexahedra().size());
}
std::string mesh_counts(const io::MeshData& m) {
    return element_counts(m.positions.size(), m.edges.size(), m.triangles.size(), m.quads.size(), m.tetrahedra.size(),
                          m.hexahedra.size());
}

}  // namespace penalty::scene::display
