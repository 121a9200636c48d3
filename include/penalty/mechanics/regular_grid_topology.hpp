#pragma once
/// @file
/// SOFA's RegularGridTopology: an axis-aligned grid of n = (nx, ny, nz) points, point (i, j, k) at
/// p0 + i·dx + j·dy + k·dz (RegularGridTopology::getPointInGrid). As RegularGridTopology::setPos:
/// the cell vector of an axis is (max − min) / (n − 1), or max − min when n = 1; p0, when not
/// given, is min, except on an axis of one point: the middle (max + min) / 2 for x and y, min for
/// z. max may be below min (the grid runs backwards) or equal to it (its points coincide), as in
/// SOFA. Point (i, j, k) has index i + nx (j + ny k); cell (i, j, k) has index
/// i + (nx−1)(j + (ny−1) k) and SOFA's hexahedron
/// vertex order (i,j,k) (i+1,j,k) (i+1,j+1,k) (i,j+1,k) then the same at k+1.
/// Elements as SOFA's GridTopology builds them (not derived by MeshTopology): hexahedra (x fastest),
/// quads of every face (XY planes for each z, then XZ, then YZ, interior faces included), edges
/// (lines along X, then Y, then Z). SOFA's GridTopology also builds two triangles per quad
/// (computeTriangleList, default true in recent versions), and then derives the edges from them:
/// mesh(true) reproduces that variant.

#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/mechanics/topology.hpp"

#include <algorithm>
#include <array>
#include <optional>

namespace penalty {

/// Index of cell (or point) (i, j, k) of a grid of cx × cy × … cells (points): i + cx (j + cy k),
/// computed in std::size_t. i, j, k, cx, cy ≥ 0.
[[nodiscard]] constexpr std::size_t grid_cell_index(int i, int j, int k, int cx, int cy) {
    return std::size_t(i) + std::size_t(cx) * (std::size_t(j) + std::size_t(cy) * std::size_t(k));
}

class RegularGridTopology {
public:
    /// Throws std::invalid_argument if any n < 1 or min, max or p0 is not finite. `p0`: SOFA's
    /// `p0` attribute (the first point), when the scene sets it.
    RegularGridTopology(std::array<int, 3> n, const Vec3& min, const Vec3& max, std::optional<Vec3> p0 = {});

    [[nodiscard]] const std::array<int, 3>& n() const { return n_; }
    [[nodiscard]] const Vec3& min() const { return min_; }
    [[nodiscard]] const Vec3& max() const { return max_; }
    /// p0: point (0, 0, 0).
    [[nodiscard]] const Vec3& origin() const { return origin_; }
    /// The cell vectors' non-zero components (dx_x, dy_y, dz_z); on an axis of one point, max − min.
    [[nodiscard]] Vec3 spacing() const { return dx_; }
    [[nodiscard]] std::size_t num_points() const { return static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]; }
    [[nodiscard]] PointId point_index(int i, int j, int k) const { return i + n_[0] * (j + n_[1] * k); }
    [[nodiscard]] Vec3 point(int i, int j, int k) const;
    /// All points, index order.
    [[nodiscard]] std::vector<Vec3> points() const;
    /// The grid as a MeshTopology with SOFA's GridTopology element lists (see the file comment);
    /// without hexahedra when !with_hexahedra (SOFA's computeHexaList = 0).
    [[nodiscard]] MeshTopology mesh(bool with_triangles = false, bool with_hexahedra = true) const;
    /// Hexahedra per row (nx − 1) and per layer row (ny − 1), for tetrahedra_from_hexahedra.
    [[nodiscard]] int cells_x() const { return std::max(1, n_[0] - 1); }
    [[nodiscard]] int cells_y() const { return std::max(1, n_[1] - 1); }
    /// Cell containing p (clamped to the grid for outside points) and the local coordinates
    /// (u, v, w) of p in it (in [0,1]³ inside the grid, extrapolated outside). 3-D grids only,
    /// with a non-zero cell vector on each axis (std::invalid_argument otherwise).
    [[nodiscard]] std::pair<std::array<int, 3>, Vec3> locate(const Vec3& p) const;

private:
    std::array<int, 3> n_;
    Vec3 min_, max_, origin_, dx_;
};

/// SOFA's TetrahedronFEMForceField split of hexahedra (when its topology has no tetrahedra): 6
/// tetrahedra per hexahedron, mirrored on alternate cells so the diagonals match; nx, ny = number
/// of cells along x and y for a grid (SOFA uses 2 and 1 for a non-grid topology).
std::vector<Tetrahedron> tetrahedra_from_hexahedra(const std::vector<Hexahedron>& hexas, int nx = 2, int ny = 1);

/// BarycentricMapping of points onto a 3-D regular grid: trilinear weights in the containing
/// (or nearest) cell, as SOFA's BarycentricMapperRegularGridTopology.
void map_on_regular_grid(BarycentricMapping& mapping, const RegularGridTopology& grid, std::span<const Vec3> points);

/// Springs of SOFA's RegularGridSpringForceField, in the order its addForce visits them: grid
/// edges along x, y, z (lines stiffness), face diagonals of the xy, xz, yz planes, two per face
/// (quads stiffness), the four cell diagonals (cubes stiffness); ks = stiffness / L,
/// kd = damping / L, with L the length of the grid's cell vectors (dx, dx + dy, ...), not of the
/// state's rest positions (which a MechanicalObject rotation may have moved by rounding). The
/// second yz diagonal takes ks, kd from the first one's length, as SOFA.
std::vector<Spring> regular_grid_springs(const RegularGridTopology& grid, const MeshSpringParameters& parameters);

}  // namespace penalty
