/// @file
/// SOFA's static topological mappings (see topological_mapping.hpp).

#include "penalty/mechanics/topological_mapping.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>
#include <map>
#include <utility>

namespace penalty {

namespace {

/// An element's vertices sorted: the key SOFA's getTriangleIndex / getQuadIndex / getEdgeIndex
/// match whatever the orientation.
template <std::size_t N>
std::array<PointId, N> sorted(std::array<PointId, N> v) {
    std::sort(v.begin(), v.end());
    return v;
}

/// How many cells hold each face (sorted vertices), faces given by a local table.
template <std::size_t N, class Cell, std::size_t F>
std::map<std::array<PointId, N>, int> faces_count(const std::vector<Cell>& cells,
                                                  const std::array<std::array<int, N>, F>& faces) {
    std::map<std::array<PointId, N>, int> count;
    for (const Cell& cell : cells) {
        for (const auto& f : faces) {
            std::array<PointId, N> v{};
            for (std::size_t k = 0; k < N; ++k) v[k] = cell[std::size_t(f[k])];
            ++count[sorted(v)];
        }
    }
    return count;
}

template <class Element, std::size_t N>
int count_of(const std::map<std::array<PointId, N>, int>& count, const Element& e) {
    const auto it = count.find(sorted(e));
    return it == count.end() ? 0 : it->second;
}

}  // namespace

std::vector<Triangle> border_triangles(const MeshTopology& input, bool flip_normals) {
    const auto count = faces_count<3>(input.tetrahedra(), MeshTopology::kTetraFaces);
    std::vector<Triangle> out;
    for (const Triangle& t : input.triangles()) {
        if (count_of(count, t) != 1) continue;
        out.push_back(flip_normals ? Triangle{t[0], t[2], t[1]} : t);
    }
    return out;
}

std::vector<Quad> border_quads(const MeshTopology& input, bool flip_normals) {
    const auto count = faces_count<4>(input.hexahedra(), MeshTopology::kHexaFaces);
    std::vector<Quad> out;
    for (const Quad& q : input.quads()) {
        if (count_of(count, q) != 1) continue;
        out.push_back(flip_normals ? Quad{q[3], q[2], q[1], q[0]} : q);
    }
    return out;
}

std::vector<Edge> border_edges(const MeshTopology& input) {
    // edge j of a triangle: (t[j+1], t[j+2]) (TriangleSetTopologyContainer::createEdgesInTriangleArray)
    static constexpr std::array<std::array<int, 2>, 3> kTriangleEdges{{{1, 2}, {2, 0}, {0, 1}}};
    const auto count = faces_count<2>(input.triangles(), kTriangleEdges);
    std::vector<Edge> out;
    for (const Edge& e : input.edges())
        if (count_of(count, e) == 1) out.push_back(e);
    return out;
}

std::vector<Triangle> triangles_of_quads(const std::vector<Quad>& quads, bool swapping, int cells_x, int cells_y) {
    if (cells_x == 0 && cells_y == 0)
        throw_invalid_argument("Quad2TriangleTopologicalMapping: the input grid has no cell along x and y");
    const std::size_t scale = std::size_t(cells_x != 0 ? cells_x : cells_y);
    std::vector<Triangle> out;
    out.reserve(2 * quads.size());
    for (std::size_t i = 0; i < quads.size(); ++i) {
        const Quad& q = quads[i];
        if (swapping && (((i % scale) ^ (i / scale)) & 1u)) {
            out.push_back({q[0], q[1], q[3]});
            out.push_back({q[2], q[3], q[1]});
        } else {
            out.push_back({q[1], q[2], q[0]});
            out.push_back({q[3], q[0], q[2]});
        }
    }
    return out;
}

std::vector<Tetrahedron> tetrahedra_of_hexahedra(const std::vector<Hexahedron>& hexahedra, bool swapping, int cells_x,
                                                 int cells_y) {
    if (swapping && (cells_x <= 0 || cells_y <= 0))
        throw_invalid_argument("Hexa2TetraTopologicalMapping: swapping needs a grid with cells along x and y");
    // sofa::geometry::Hexahedron::xEdges, yEdges, zEdges: vertex pairs along each axis.
    static constexpr std::array<std::array<int, 2>, 4> kX{{{0, 1}, {4, 5}, {3, 2}, {7, 6}}};
    static constexpr std::array<std::array<int, 2>, 4> kY{{{4, 7}, {5, 6}, {1, 2}, {0, 3}}};
    static constexpr std::array<std::array<int, 2>, 4> kZ{{{4, 0}, {5, 1}, {6, 2}, {7, 3}}};
    static constexpr std::array<std::array<int, 4>, 6> kPattern{
        {{0, 5, 1, 6}, {0, 1, 3, 6}, {1, 3, 6, 2}, {6, 3, 0, 7}, {6, 7, 0, 5}, {7, 5, 4, 0}}};
    static constexpr std::array<std::array<int, 4>, 6> kSwappedPattern{
        {{0, 5, 6, 1}, {0, 1, 6, 3}, {1, 3, 2, 6}, {6, 3, 7, 0}, {6, 7, 5, 0}, {7, 5, 0, 4}}};
    std::vector<Tetrahedron> out;
    out.reserve(6 * hexahedra.size());
    for (std::size_t i = 0; i < hexahedra.size(); ++i) {
        Hexahedron c = hexahedra[i];
        bool swapped = false;
        const auto swap_edges = [&](const std::array<std::array<int, 2>, 4>& edges) {
            for (const auto& e : edges) std::swap(c[std::size_t(e[0])], c[std::size_t(e[1])]);
            swapped = !swapped;
        };
        if (swapping) {
            const std::size_t nx = std::size_t(cells_x), ny = std::size_t(cells_y);
            if (((i % nx) & 1u) == 0) swap_edges(kX);
            if (((i / nx) % ny) & 1u) swap_edges(kY);
            if ((i / (nx * ny)) & 1u) swap_edges(kZ);
        }
        for (const auto& t : swapped ? kSwappedPattern : kPattern)
            out.push_back({c[std::size_t(t[0])], c[std::size_t(t[1])], c[std::size_t(t[2])], c[std::size_t(t[3])]});
    }
    return out;
}

}  // namespace penalty
