// BarycentricMapping onto the tetrahedra of a dynamic container (a *SetTopologyContainer): SOFA's
// BarycentricMapperTetrahedronSetTopology, whose init (BarycentricMapperTopologyContainer::init)
// looks for each point's element in a spatial hash grid before any exhaustive search. Inside an
// element it finds the element the exhaustive search of map_on_tetrahedra finds; outside every
// element (a point whose tetrahedron was removed) it may keep another, which this reproduces.
#include "penalty/core/error.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "barycentric_tetrahedra.hpp"

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
    double cell_size = 0.0;        ///< m: mean edge length (computeHashingCellSize)
    double per_length = 0.0;       ///< 1/m (m_convFactor)
    std::map<Cell, std::vector<std::size_t>> cells;

    /// getGridIndices: ⌊p·(1/m)⌋ per axis.
    [[nodiscard]] Cell cell_of(const Vec3& p) const {
        return {int(std::floor(p[0] * per_length)), int(std::floor(p[1] * per_length)), int(std::floor(p[2] * per_length))};
    }
};

TetrahedronHashGrid hash_tetrahedra(const MeshTopology& topo, std::span<const Vec3> x) {
    TetrahedronHashGrid g;
    const auto& tetras = topo.tetrahedra();
    // computeHashingCellSize: the mean length of the topology's edges (of the elements' first
    // edges when it lists none), summed in edge order
    double sum = 0.0;
    if (!topo.edges().empty()) {
        for (const Edge& e : topo.edges()) sum += (x[std::size_t(e[0])] - x[std::size_t(e[1])]).norm();
        sum /= double(topo.edges().size());
    } else {
        for (const Tetrahedron& t : tetras) sum += (x[std::size_t(t[0])] - x[std::size_t(t[1])]).norm();
        sum /= double(tetras.size());
    }
    g.cell_size = sum;
    g.per_length = 1.0 / sum;
    // computeHashTable: every cell of each element's bounding box
    for (std::size_t t = 0; t < tetras.size(); ++t) {
        Vec3 lo = x[std::size_t(tetras[t][0])], hi = lo;
        for (const PointId p : tetras[t]) {
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

}  // namespace

void BarycentricMapping::map_on_set_tetrahedra(const MeshTopology& topo, std::span<const Vec3> x, std::span<const Vec3> points) {
    const auto& tetras = topo.tetrahedra();
    if (tetras.empty()) throw_invalid_argument("BarycentricMapping: topology has no tetrahedron");
    const detail::TetrahedronFrames frames(tetras, x);  // computeBasesAndCenters (checks every vertex)
    for (const Edge& e : topo.edges())
        if (std::size_t(e[0]) >= x.size() || std::size_t(e[1]) >= x.size())
            throw_invalid_argument("BarycentricMapping: an edge's vertex is out of range");
    const TetrahedronHashGrid grid = hash_tetrahedra(topo, x);
    if (!std::isfinite(grid.per_length) || grid.cell_size <= 0)
        throw_invalid_argument("BarycentricMapping: the tetrahedra's mean edge length is ", grid.cell_size,
                               " (SOFA's hash grid needs a positive one)");
    // checkDistanceFromElement (barycentric_tetrahedra.hpp): the first element of strictly least
    // score wins
    struct Nearest {
        double distance = std::numeric_limits<double>::max();
        std::size_t element = std::numeric_limits<std::size_t>::max();
        Vec3 coefs = Vec3::Zero();
    };
    const auto check = [&](std::size_t t, const Vec3& p, Nearest& n) {
        Vec3 v;
        const double d = frames.score(t, x[std::size_t(tetras[t][0])], p, v);
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
            for (std::size_t t = 0; t < tetras.size(); ++t) check(t, p, n);
        } else if (std::abs(n.distance) > grid.cell_size / 2) {
            // SOFA compares the squared distance with half a cell's length: the 27 cells around
            for (int a = -1; a <= 1; ++a)
                for (int b = -1; b <= 1; ++b)
                    for (int c = -1; c <= 1; ++c) check_cell({home[0] + a, home[1] + b, home[2] + c}, p, n);
        }
        if (n.element == std::numeric_limits<std::size_t>::max())
            throw_invalid_argument("BarycentricMapping: point ", i, " is not finite");
        detail::push_tetrahedron_weights(rows[i], tetras[n.element], n.coefs);
    }
    set_rows(std::move(rows));
}

}  // namespace penalty
