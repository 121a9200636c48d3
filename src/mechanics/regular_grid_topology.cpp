#include "penalty/mechanics/regular_grid_topology.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

RegularGridTopology::RegularGridTopology(std::array<int, 3> n, const Vec3& min, const Vec3& max, std::optional<Vec3> p0)
    : n_(n), min_(min), max_(max), origin_(min), dx_(Vec3::Zero()) {
    if (!min.allFinite() || !max.allFinite()) throw_invalid_argument("RegularGridTopology: min/max must be finite");
    if (p0 && !p0->allFinite()) throw_invalid_argument("RegularGridTopology: p0 must be finite");
    for (int a = 0; a < 3; ++a) {
        const int count = n[static_cast<std::size_t>(a)];
        if (count < 1) throw_invalid_argument("RegularGridTopology: n[", a, "] must be >= 1, got ", count);
        // RegularGridTopology::setPos: (max − min) / (n − 1), or max − min for one point, whose
        // p0 is then the middle on x and y (min on z)
        if (count > 1) {
            dx_[a] = (max[a] - min[a]) / (count - 1);
        } else {
            dx_[a] = max[a] - min[a];
            if (a < 2) origin_[a] = (max[a] + min[a]) / 2;
        }
    }
    if (p0) origin_ = *p0;
}

Vec3 RegularGridTopology::point(int i, int j, int k) const {
    return origin_ + Vec3(i * dx_.x(), j * dx_.y(), k * dx_.z());
}

std::vector<Vec3> RegularGridTopology::points() const {
    std::vector<Vec3> p;
    p.reserve(num_points());
    for (int k = 0; k < n_[2]; ++k)
        for (int j = 0; j < n_[1]; ++j)
            for (int i = 0; i < n_[0]; ++i) p.push_back(point(i, j, k));
    return p;
}

MeshTopology RegularGridTopology::mesh(bool with_triangles, bool with_hexahedra) const {
    MeshTopology topo;
    topo.set_num_points(num_points());
    const int nx = n_[0], ny = n_[1], nz = n_[2];
    auto p = [this](int i, int j, int k) { return point_index(i, j, k); };
    std::vector<Hexahedron> hexas;
    for (int z = 0; z + 1 < nz; ++z)
        for (int y = 0; y + 1 < ny; ++y)
            for (int x = 0; x + 1 < nx; ++x)
                hexas.push_back({p(x, y, z), p(x + 1, y, z), p(x + 1, y + 1, z), p(x, y + 1, z), p(x, y, z + 1),
                                 p(x + 1, y, z + 1), p(x + 1, y + 1, z + 1), p(x, y + 1, z + 1)});
    std::vector<Quad> quads;  // XY planes, then XZ, then YZ (every face, interior ones included)
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y + 1 < ny; ++y)
            for (int x = 0; x + 1 < nx; ++x)
                quads.push_back({p(x, y, z), p(x + 1, y, z), p(x + 1, y + 1, z), p(x, y + 1, z)});
    for (int z = 0; z + 1 < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x + 1 < nx; ++x)
                quads.push_back({p(x, y, z), p(x + 1, y, z), p(x + 1, y, z + 1), p(x, y, z + 1)});
    for (int z = 0; z + 1 < nz; ++z)
        for (int y = 0; y + 1 < ny; ++y)
            for (int x = 0; x < nx; ++x)
                quads.push_back({p(x, y, z), p(x, y + 1, z), p(x, y + 1, z + 1), p(x, y, z + 1)});
    // GridUpdate::updateEdges: edges from the triangles when there are some, else along the axes
    // (a grid of one row or column has no quad, hence no triangle: its segments are its edges)
    if (with_triangles && !quads.empty()) {
        // Triangles from quads; edges then derived from the triangles (oriented, first occurrence).
        std::vector<Triangle> tris;
        for (const Quad& q : quads) {
            tris.push_back({q[0], q[1], q[2]});
            tris.push_back({q[0], q[2], q[3]});
        }
        MeshTopology surface;
        surface.set_triangles(tris);
        topo.set_edges(surface.edges());
        topo.set_triangles(std::move(tris));
    } else {
        std::vector<Edge> edges;  // lines along X, then Y, then Z
        for (int z = 0; z < nz; ++z)
            for (int y = 0; y < ny; ++y)
                for (int x = 0; x + 1 < nx; ++x) edges.push_back({p(x, y, z), p(x + 1, y, z)});
        for (int z = 0; z < nz; ++z)
            for (int y = 0; y + 1 < ny; ++y)
                for (int x = 0; x < nx; ++x) edges.push_back({p(x, y, z), p(x, y + 1, z)});
        for (int z = 0; z + 1 < nz; ++z)
            for (int y = 0; y < ny; ++y)
                for (int x = 0; x < nx; ++x) edges.push_back({p(x, y, z), p(x, y, z + 1)});
        topo.set_edges(std::move(edges));
    }
    topo.set_quads(std::move(quads));
    if (with_hexahedra) topo.set_hexahedra(std::move(hexas));
    return topo;
}

std::vector<Tetrahedron> tetrahedra_from_hexahedra(const std::vector<Hexahedron>& hexas, int nx, int ny) {
    if (nx < 1 || ny < 1) throw_invalid_argument("tetrahedra_from_hexahedra: nx and ny must be >= 1");
    std::vector<Tetrahedron> tetras;
    tetras.reserve(6 * hexas.size());
    for (std::size_t i = 0; i < hexas.size(); ++i) {
        Hexahedron c = hexas[i];
        const auto si = static_cast<long>(i);
        if (((si % nx) & 1) == 0) {  // mirror along x
            std::swap(c[0], c[1]);
            std::swap(c[3], c[2]);
            std::swap(c[4], c[5]);
            std::swap(c[7], c[6]);
        }
        if (((si / nx) % ny) & 1) {  // mirror along y
            std::swap(c[0], c[3]);
            std::swap(c[1], c[2]);
            std::swap(c[4], c[7]);
            std::swap(c[5], c[6]);
        }
        if ((si / (static_cast<long>(nx) * ny)) & 1) {  // mirror along z
            std::swap(c[0], c[4]);
            std::swap(c[1], c[5]);
            std::swap(c[2], c[6]);
            std::swap(c[3], c[7]);
        }
        tetras.push_back({c[0], c[5], c[1], c[6]});
        tetras.push_back({c[0], c[1], c[3], c[6]});
        tetras.push_back({c[1], c[3], c[6], c[2]});
        tetras.push_back({c[6], c[3], c[0], c[7]});
        tetras.push_back({c[6], c[7], c[0], c[5]});
        tetras.push_back({c[7], c[5], c[4], c[0]});
    }
    return tetras;
}

std::pair<std::array<int, 3>, Vec3> RegularGridTopology::locate(const Vec3& p) const {
    std::array<int, 3> cell{};
    Vec3 uvw;
    for (int a = 0; a < 3; ++a) {
        const auto ua = static_cast<std::size_t>(a);
        if (n_[ua] < 2) throw_invalid_argument("RegularGridTopology: locate needs a 3-D grid");
        if (dx_[a] == 0.0)
            throw_invalid_argument("RegularGridTopology: locate needs cells of non-zero size (max[", a, "] = min[", a,
                                   "])");
        // SOFA's RegularGridTopology::findCube: x = ((pos − p0)·dx)·inv_dx2, inv_dx2 = 1/(dx·dx),
        // with dx the cell vector (one non-zero component, so the dot product is one product).
        const double inverse_squared = 1 / (dx_[a] * dx_[a]);
        const double t = ((p[a] - origin_[a]) * dx_[a]) * inverse_squared;
        // SOFA's findCube / findNearestCube: the cell index is clamped, the fraction is not
        const int c = static_cast<int>(std::clamp(std::floor(t), 0.0, static_cast<double>(n_[ua] - 2)));
        cell[ua] = c;
        uvw[a] = t - c;
    }
    return {cell, uvw};
}

void map_on_regular_grid(BarycentricMapping& mapping, const RegularGridTopology& grid, std::span<const Vec3> points) {
    std::vector<std::vector<BarycentricMapping::Entry>> rows(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!points[i].allFinite()) throw_invalid_argument("BarycentricMapping: point ", i, " is not finite");
        const auto [c, uvw] = grid.locate(points[i]);
        // SOFA's BarycentricMapperRegularGridTopology::apply sums the cube's corners in the order
        // cube[0], [1], [3], [2], [4], [5], [7], [6] (x fastest, then y, then z), each weight
        // ((1−fx)·(1−fy))·(1−fz) etc.; the rounding of the mapped points depends on that order.
        const double fx = uvw.x(), fy = uvw.y(), fz = uvw.z();
        for (int k = 0; k < 8; ++k) {
            const int dx = k & 1, dy = (k >> 1) & 1, dz = (k >> 2) & 1;
            const double weight = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz);
            rows[i].push_back({grid.point_index(c[0] + dx, c[1] + dy, c[2] + dz), weight});
        }
    }
    mapping.set_weights(std::move(rows));
}

std::vector<Spring> regular_grid_springs(const RegularGridTopology& grid, const MeshSpringParameters& p) {
    // SOFA's RegularGridSpringForceField::addForce builds its springs on the fly from the grid,
    // in this order, with rest lengths from the grid's cell vectors (getDx/getDy/getDz, i.e. the
    // written min/max, not the state's possibly moved rest positions).
    const Vec3 spacing = grid.spacing();
    const Vec3 dx(spacing.x(), 0, 0), dy(0, spacing.y(), 0), dz(0, 0, spacing.z());
    const auto length = [](const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
    const int nx = grid.n()[0], ny = grid.n()[1], nz = grid.n()[2];
    std::vector<Spring> out;
    auto add = [&](int x1, int y1, int z1, int x2, int y2, int z2, double rest, double ks, double kd) {
        out.push_back(Spring{grid.point_index(x1, y1, z1), grid.point_index(x2, y2, z2), ks, kd, rest});
    };
    if (p.lines_stiffness != 0.0 || p.lines_damping != 0.0) {
        double l = length(dx);
        for (int z = 0; z < nz; ++z)
            for (int y = 0; y < ny; ++y)
                for (int x = 0; x < nx - 1; ++x)
                    add(x, y, z, x + 1, y, z, l, p.lines_stiffness / l, p.lines_damping / l);
        l = length(dy);
        for (int z = 0; z < nz; ++z)
            for (int y = 0; y < ny - 1; ++y)
                for (int x = 0; x < nx; ++x) add(x, y, z, x, y + 1, z, l, p.lines_stiffness / l, p.lines_damping / l);
        l = length(dz);
        for (int z = 0; z < nz - 1; ++z)
            for (int y = 0; y < ny; ++y)
                for (int x = 0; x < nx; ++x) add(x, y, z, x, y, z + 1, l, p.lines_stiffness / l, p.lines_damping / l);
    }
    if (p.quads_stiffness != 0.0 || p.quads_damping != 0.0) {
        const double ks = p.quads_stiffness, kd = p.quads_damping;
        double l1 = length(dx + dy), l2 = length(dx - dy);
        for (int z = 0; z < nz; ++z)
            for (int y = 0; y < ny - 1; ++y)
                for (int x = 0; x < nx - 1; ++x) {
                    add(x, y, z, x + 1, y + 1, z, l1, ks / l1, kd / l1);
                    add(x + 1, y, z, x, y + 1, z, l2, ks / l2, kd / l2);
                }
        l1 = length(dx + dz);
        l2 = length(dx - dz);
        for (int z = 0; z < nz - 1; ++z)
            for (int y = 0; y < ny; ++y)
                for (int x = 0; x < nx - 1; ++x) {
                    add(x, y, z, x + 1, y, z + 1, l1, ks / l1, kd / l1);
                    add(x + 1, y, z, x, y, z + 1, l2, ks / l2, kd / l2);
                }
        l1 = length(dy + dz);
        l2 = length(dy - dz);
        for (int z = 0; z < nz - 1; ++z)
            for (int y = 0; y < ny - 1; ++y)
                for (int x = 0; x < nx; ++x) {
                    add(x, y, z, x, y + 1, z + 1, l1, ks / l1, kd / l1);
                    // As SOFA (RegularGridSpringForceField::addForce, YZ plane): the second
                    // diagonal's ks and kd are divided by the first diagonal's length. Harmless:
                    // dy and dz are axis-aligned, so |dy − dz| and |dy + dz| are the same double.
                    add(x, y + 1, z, x, y, z + 1, l2, ks / l1, kd / l1);
                }
    }
    if (p.cubes_stiffness != 0.0 || p.cubes_damping != 0.0) {
        const double ks = p.cubes_stiffness, kd = p.cubes_damping;
        const double l1 = length(dx + dy + dz), l2 = length(-dx + dy + dz), l3 = length(dx - dy + dz),
                     l4 = length(dx + dy - dz);
        for (int z = 0; z < nz - 1; ++z)
            for (int y = 0; y < ny - 1; ++y)
                for (int x = 0; x < nx - 1; ++x) {
                    add(x, y, z, x + 1, y + 1, z + 1, l1, ks / l1, kd / l1);
                    add(x + 1, y, z, x, y + 1, z + 1, l2, ks / l2, kd / l2);
                    add(x, y + 1, z, x + 1, y, z + 1, l3, ks / l3, kd / l3);
                    add(x, y, z + 1, x + 1, y + 1, z, l4, ks / l4, kd / l4);
                }
    }
    return out;
}

}  // namespace penalty
