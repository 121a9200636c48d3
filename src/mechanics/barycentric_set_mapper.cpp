// BarycentricMapping onto the tetrahedra or hexahedra of a dynamic container (a
// *SetTopologyContainer): SOFA's BarycentricMapperTetrahedronSetTopology and
// BarycentricMapperHexahedronSetTopology, whose init (BarycentricMapperTopologyContainer::init)
// looks for each point's element in a spatial hash grid before any exhaustive search. Inside a
// tetrahedron it finds the element the exhaustive search of map_on_tetrahedra finds; outside every
// element (a point whose element was removed) it may keep another, which this reproduces. A
// hexahedron is mapped as the parallelepiped of its three edges from vertex 0 (affine
// coordinates, trilinear weights), not by the inverse trilinear map of map_on_hexahedra.
#include "barycentric_tetrahedra.hpp"
#include "penalty/core/error.hpp"
#include "penalty/mechanics/mapping.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

namespace penalty {
namespace {

using Cell = std::array<int, 3>;

/// The spatial hash of BarycentricMapperTopologyContainer: cells of the mean edge length,
/// each listing the elements whose bounding box touches it, in element order.
struct TetrahedronHashGrid {
    double cell_size = 0.0;   ///< m: mean edge length (computeHashingCellSize)
    double per_length = 0.0;  ///< 1/m (m_convFactor)
    std::map<Cell, std::vector<std::size_t>> cells;

    /// getGridIndices: ⌊p·(1/m)⌋ per axis (std::invalid_argument for a point whose cell an int
    /// cannot name: not finite, or farther than 2³¹ cells from the origin).
    [[nodiscard]] Cell cell_of(const Vec3& p) const {
        Cell c{};
        for (std::size_t a = 0; a < 3; ++a) {
            const double v = std::floor(p[Eigen::Index(a)] * per_length);
            if (!(std::abs(v) < double(std::numeric_limits<int>::max())))
                throw_invalid_argument("BarycentricMapping: a point at (", p[0], ", ", p[1], ", ", p[2],
                                       ") has no cell in SOFA's hash grid of cell ", cell_size, " m");
            c[a] = int(v);
        }
        return c;
    }
};

/// The grid of `elements` (each an array of vertex indices) with the positions `x`.
template <class Element>
TetrahedronHashGrid hash_elements(const MeshTopology& topo, const std::vector<Element>& elements,
                                  std::span<const Vec3> x) {
    TetrahedronHashGrid g;
    // computeHashingCellSize: the mean length of the topology's edges (of the elements' first
    // edges when it lists none), summed in edge order
    double sum = 0.0;
    if (!topo.edges().empty()) {
        for (const Edge& e : topo.edges()) sum += (x[std::size_t(e[0])] - x[std::size_t(e[1])]).norm();
        sum /= double(topo.edges().size());
    } else {
        for (const Element& t : elements) sum += (x[std::size_t(t[0])] - x[std::size_t(t[1])]).norm();
        sum /= double(elements.size());
    }
    g.cell_size = sum;
    g.per_length = 1.0 / sum;
    if (!std::isfinite(g.per_length) || !(g.cell_size > 0))
        throw_invalid_argument("BarycentricMapping: the elements' mean edge length is ", g.cell_size,
                               " (SOFA's hash grid needs a positive one)");
    // computeHashTable: every cell of each element's bounding box
    for (std::size_t t = 0; t < elements.size(); ++t) {
        Vec3 lo = x[std::size_t(elements[t][0])], hi = lo;
        for (const PointId p : elements[t]) {
            lo = lo.cwiseMin(x[std::size_t(p)]);
            hi = hi.cwiseMax(x[std::size_t(p)]);
        }
        const Cell a = g.cell_of(lo), b = g.cell_of(hi);
        for (int i = a[0]; i <= b[0]; ++i)
            for (int j = a[1]; j <= b[1]; ++j)
                for (int k = a[2]; k <= b[2]; ++k) g.cells[{i, j, k}].push_back(t);
    }
    return g;
}

/// BarycentricMapperHexahedronSetTopology::computeBase and computeCenter: B = (x1 − x0, x3 − x0,
/// x4 − x0)⁻¹ (the parallelepiped of the hexahedron's three edges from vertex 0) and
/// c = (x0 + ... + x7)·0.125; the score of a point (computeDistance): with b = B·(p − x0),
/// max(−b0, −b1, −b2, b0 − 1, b1 − 1, b2 − 1), replaced, when positive (outside), by |p − c|².
struct HexahedronFrames {
    std::vector<Mat3> bases;
    std::vector<Vec3> centres;

    HexahedronFrames(const std::vector<Hexahedron>& hexas, std::span<const Vec3> x)
        : bases(hexas.size()), centres(hexas.size()) {
        for (std::size_t h = 0; h < hexas.size(); ++h) {
            for (const PointId p : hexas[h])
                if (std::size_t(p) >= x.size())
                    throw_invalid_argument("BarycentricMapping: hexahedron ", h, " vertex out of range");
            const auto at = [&](std::size_t k) -> const Vec3& { return x[std::size_t(hexas[h][k])]; };
            Mat3 edges;  // columns x1 − x0, x3 − x0, x4 − x0 (SOFA: the transpose of the rows)
            edges.col(0) = at(1) - at(0);
            edges.col(1) = at(3) - at(0);
            edges.col(2) = at(4) - at(0);
            if (std::abs(sofa_vec::determinant(edges)) < 1e-300)
                throw_invalid_argument("BarycentricMapping: hexahedron ", h,
                                       " is degenerate (its edges from vertex 0 are coplanar)");
            bases[h] = sofa_vec::inverse(edges);
            Vec3 sum = at(0);
            for (std::size_t k = 1; k < 8; ++k) sum = sum + at(k);
            centres[h] = sofa_vec::scaled(sum, 0.125);
        }
    }

    [[nodiscard]] double score(std::size_t h, const Vec3& x0, const Vec3& p, Vec3& coefs) const {
        coefs = sofa_vec::times(bases[h], p - x0);
        const Vec3& v = coefs;
        const double d =
            std::max(std::max(-v[0], -v[1]), std::max(std::max(-v[2], v[0] - 1), std::max(v[1] - 1, v[2] - 1)));
        if (d <= 0) return d;
        const Vec3 r = p - centres[h];
        return sofa_vec::dot3(r, r);
    }
};

/// getBarycentricCoefficients of the hexahedron mapper (trilinear in b, SOFA's products).
void push_hexahedron_weights(BarycentricRow& row, const Hexahedron& h, const Vec3& f) {
    const double w[8] = {(1 - f[0]) * (1 - f[1]) * (1 - f[2]),
                         (f[0]) * (1 - f[1]) * (1 - f[2]),
                         (f[0]) * (f[1]) * (1 - f[2]),
                         (1 - f[0]) * (f[1]) * (1 - f[2]),
                         (1 - f[0]) * (1 - f[1]) * (f[2]),
                         (f[0]) * (1 - f[1]) * (f[2]),
                         (f[0]) * (f[1]) * (f[2]),
                         (1 - f[0]) * (f[1]) * (f[2])};
    for (std::size_t k = 0; k < 8; ++k) row.push(h[k], w[k]);
}

/// BarycentricMapperTopologyContainer::init over `elements` with their `frames`: each point's
/// element from its hash-grid cell, all elements when the cell has none, the 27 cells around when
/// the best is farther than half a cell; `push` writes its weights.
template <class Element, class Frames, class Push>
std::vector<BarycentricRow> map_on_set_elements(const MeshTopology& topo, const std::vector<Element>& elements,
                                                const Frames& frames, std::span<const Vec3> x,
                                                std::span<const Vec3> points, Push&& push) {
    for (const Edge& e : topo.edges())
        if (std::size_t(e[0]) >= x.size() || std::size_t(e[1]) >= x.size())
            throw_invalid_argument("BarycentricMapping: an edge's vertex is out of range");
    const TetrahedronHashGrid grid = hash_elements(topo, elements, x);
    // checkDistanceFromElement: the first element of strictly least score wins
    struct Nearest {
        double distance = std::numeric_limits<double>::max();
        std::size_t element = std::numeric_limits<std::size_t>::max();
        Vec3 coefs = Vec3::Zero();
    };
    const auto check = [&](std::size_t t, const Vec3& p, Nearest& n) {
        Vec3 v;
        const double d = frames.score(t, x[std::size_t(elements[t][0])], p, v);
        if (d < n.distance) n = {d, t, v};
    };
    const auto check_cell = [&](const Cell& c, const Vec3& p, Nearest& n) {
        const auto it = grid.cells.find(c);
        if (it != grid.cells.end())
            for (const std::size_t t : it->second) check(t, p, n);
    };
    std::vector<BarycentricRow> rows(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3& p = points[i];
        Nearest n;
        const Cell home = grid.cell_of(p);
        check_cell(home, p, n);
        if (n.element == std::numeric_limits<std::size_t>::max()) {
            // no element in the point's cell: every element
            for (std::size_t t = 0; t < elements.size(); ++t) check(t, p, n);
        } else if (std::abs(n.distance) > grid.cell_size / 2) {
            // SOFA compares the squared distance with half a cell's length: the 27 cells around
            for (int a = -1; a <= 1; ++a)
                for (int b = -1; b <= 1; ++b)
                    for (int c = -1; c <= 1; ++c) check_cell({home[0] + a, home[1] + b, home[2] + c}, p, n);
        }
        if (n.element == std::numeric_limits<std::size_t>::max())
            throw_invalid_argument("BarycentricMapping: point ", i, " is not finite");
        push(rows[i], elements[n.element], n.coefs);
    }
    return rows;
}

}  // namespace

void BarycentricMapping::map_on_set_tetrahedra(const MeshTopology& topo, std::span<const Vec3> x,
                                               std::span<const Vec3> points) {
    const auto& tetras = topo.tetrahedra();
    if (tetras.empty()) throw_invalid_argument("BarycentricMapping: topology has no tetrahedron");
    const detail::TetrahedronFrames frames(tetras, x);  // computeBasesAndCenters (checks every vertex)
    set_rows(map_on_set_elements(topo, tetras, frames, x, points, detail::push_tetrahedron_weights));
}

void BarycentricMapping::map_on_set_hexahedra(const MeshTopology& topo, std::span<const Vec3> x,
                                              std::span<const Vec3> points) {
    const auto& hexas = topo.hexahedra();
    if (hexas.empty()) throw_invalid_argument("BarycentricMapping: topology has no hexahedron");
    const HexahedronFrames frames(hexas, x);
    set_rows(map_on_set_elements(topo, hexas, frames, x, points, push_hexahedron_weights));
}

}  // namespace penalty
