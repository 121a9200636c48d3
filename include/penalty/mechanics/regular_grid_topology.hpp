#pragma once
/// @file
/// SOFA's RegularGridTopology: an axis-aligned grid of n = (nx, ny, nz) points between min and
/// max (spacing (max − min) / (n − 1) per axis with n > 1). Point (i, j, k) has index
/// i + nx (j + ny k); cell (i, j, k) has index i + (nx−1)(j + (ny−1) k) and SOFA's hexahedron
/// vertex order (i,j,k) (i+1,j,k) (i+1,j+1,k) (i,j+1,k) then the same at k+1.
/// A grid with one axis of 1 point is made of quads, with two such axes of edges.

#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>

namespace penalty {

class RegularGridTopology {
public:
    /// Throws std::invalid_argument if any n < 1, min/max not finite, or max < min on an axis
    /// with more than one point.
    RegularGridTopology(std::array<int, 3> n, const Vec3& min, const Vec3& max);

    [[nodiscard]] const std::array<int, 3>& n() const { return n_; }
    [[nodiscard]] const Vec3& min() const { return min_; }
    [[nodiscard]] const Vec3& max() const { return max_; }
    [[nodiscard]] Vec3 spacing() const { return dx_; }
    [[nodiscard]] std::size_t num_points() const { return static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]; }
    [[nodiscard]] PointId point_index(int i, int j, int k) const { return i + n_[0] * (j + n_[1] * k); }
    [[nodiscard]] Vec3 point(int i, int j, int k) const;
    /// All points, index order.
    [[nodiscard]] std::vector<Vec3> points() const;
    /// The grid as a MeshTopology (hexahedra, or quads, or edges; derived elements as SOFA).
    [[nodiscard]] MeshTopology mesh() const;
    /// Cell containing p (clamped to the grid for outside points) and the local coordinates
    /// (u, v, w) of p in it (in [0,1]³ inside the grid, extrapolated outside). 3-D grids only.
    [[nodiscard]] std::pair<std::array<int, 3>, Vec3> locate(const Vec3& p) const;

private:
    std::array<int, 3> n_;
    Vec3 min_, max_, dx_;
};

/// BarycentricMapping of points onto a 3-D regular grid: trilinear weights in the containing
/// (or nearest) cell, as SOFA's BarycentricMapperRegularGridTopology.
void map_on_regular_grid(BarycentricMapping& mapping, const RegularGridTopology& grid, std::span<const Vec3> points);

/// Springs of SOFA's RegularGridSpringForceField: grid edges (lines stiffness), face diagonals
/// (quads stiffness) and cell diagonals (cubes stiffness), ks = stiffness / L, kd = damping / L.
/// Same spring set as MeshSpringForceField on the grid (order: lines, quads, cubes).
std::vector<Spring> regular_grid_springs(const RegularGridTopology& grid, const MeshSpringParameters& parameters);

}  // namespace penalty
