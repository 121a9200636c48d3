// MeshTetraStuffing (SOFA's isosurface stuffing engine) on surfaces made here: a closed box and an
// icosphere. Every tetrahedron has a positive volume, no oriented face is used twice (SOFA's own
// check), the volumes add up to the enclosed volume within the stated tolerance, and the points lie
// inside the surface when the tetrahedra are cut (outside by at most a cell diagonal when not).
#include "penalty/mechanics/mesh_tetra_stuffing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

namespace penalty {
namespace {

struct StuffingSurface {
    std::vector<Vec3> points;
    std::vector<Triangle> triangles;
    /// Enclosed volume: Σ p0·(p1 × p2)/6 over the outward triangles.
    [[nodiscard]] double volume() const {
        double v = 0;
        for (const Triangle& t : triangles)
            v += points[std::size_t(t[0])].dot(points[std::size_t(t[1])].cross(points[std::size_t(t[2])])) / 6;
        return v;
    }
};

/// The box [lo, hi] as 12 outward triangles.
StuffingSurface closed_box(const Vec3& lo, const Vec3& hi) {
    StuffingSurface s;
    for (int k = 0; k < 8; ++k)
        s.points.emplace_back((k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]);
    const std::array<std::array<int, 4>, 6> faces{
        {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};
    for (const auto& f : faces) {
        s.triangles.push_back({f[0], f[1], f[2]});
        s.triangles.push_back({f[0], f[2], f[3]});
    }
    return s;
}

/// An icosahedron subdivided `levels` times, its points on the sphere of radius r at `centre`.
StuffingSurface icosphere(double r, int levels, const Vec3& centre) {
    const double g = (1 + std::sqrt(5.0)) / 2;
    StuffingSurface s;
    for (const Vec3& p :
         {Vec3(-1, g, 0), Vec3(1, g, 0), Vec3(-1, -g, 0), Vec3(1, -g, 0), Vec3(0, -1, g), Vec3(0, 1, g),
          Vec3(0, -1, -g), Vec3(0, 1, -g), Vec3(g, 0, -1), Vec3(g, 0, 1), Vec3(-g, 0, -1), Vec3(-g, 0, 1)})
        s.points.push_back(p.normalized() * r);
    s.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                   {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                   {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<PointId, PointId>, PointId> middle;
        const auto mid = [&](PointId a, PointId b) {
            const auto key = std::minmax(a, b);
            if (auto it = middle.find(key); it != middle.end()) return it->second;
            s.points.push_back((s.points[std::size_t(a)] + s.points[std::size_t(b)]).normalized() * r);
            return middle[key] = PointId(s.points.size() - 1);
        };
        std::vector<Triangle> finer;
        for (const Triangle& t : s.triangles) {
            const PointId a = mid(t[0], t[1]), b = mid(t[1], t[2]), c = mid(t[2], t[0]);
            finer.insert(finer.end(), {{t[0], a, c}, {t[1], b, a}, {t[2], c, b}, {a, b, c}});
        }
        s.triangles = std::move(finer);
    }
    for (Vec3& p : s.points) p += centre;
    return s;
}

double volume6(const StuffedVolume& v, const Tetrahedron& t) {
    const Vec3& p0 = v.points[std::size_t(t[0])];
    return (v.points[std::size_t(t[1])] - p0)
        .dot((v.points[std::size_t(t[2])] - p0).cross(v.points[std::size_t(t[3])] - p0));
}

/// Total volume, after checking every tetrahedron is positive and no oriented face is repeated.
double checked_volume(const StuffedVolume& v) {
    double total = 0;
    std::set<std::array<PointId, 3>> faces;
    std::size_t repeated = 0;
    for (const Tetrahedron& t : v.tetrahedra) {
        const double v6 = volume6(v, t);
        EXPECT_GT(v6, 0.0);
        total += v6 / 6;
        for (const auto& f : MeshTopology::kTetraFaces) {
            std::array<PointId, 3> face{t[std::size_t(f[0])], t[std::size_t(f[1])], t[std::size_t(f[2])]};
            std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
            repeated += faces.insert(face).second ? 0 : 1;
        }
    }
    EXPECT_EQ(repeated, 0u) << "an oriented face used by two tetrahedra";
    return total;
}

// The surfaces are placed off the lattice (no lattice line through a vertex or along a face):
// SOFA's ray votes are not robust there, and neither are penalty's, which are SOFA's.
TEST(MeshTetraStuffing, CutAndSnappedBoxFillsTheBoxFromInside) {
    const Vec3 lo(0.013, 0.021, 0.017), hi(1.007, 0.811, 0.613);
    const StuffingSurface box = closed_box(lo, hi);
    MeshTetraStuffingParameters p;
    p.size = 0.1;
    p.snap_points = true;
    p.split_tetrahedra = true;
    const StuffedVolume v = mesh_tetra_stuffing(box.points, box.triangles, {}, p);
    ASSERT_GT(v.tetrahedra.size(), 1000u);
    EXPECT_EQ(v.invalid_splits, 0u);
    const double volume = checked_volume(v);
    // the boundary triangles chamfer the box's edges: a little less than the box
    EXPECT_LE(volume, box.volume() * (1 + 1e-12));
    EXPECT_GT(volume, box.volume() * 0.99);
    for (const Vec3& x : v.points)
        for (int c = 0; c < 3; ++c) {
            EXPECT_GE(x[c], lo[c] - 1e-12);
            EXPECT_LE(x[c], hi[c] + 1e-12);
        }
}

TEST(MeshTetraStuffing, UncutLatticeCoversTheSurface) {
    // without cutting, every lattice tetrahedron with an inside vertex is kept whole: more volume,
    // points at most a lattice edge (one cell) outside
    const StuffingSurface box = closed_box(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5));
    MeshTetraStuffingParameters p;
    p.box = std::array<Vec3, 2>{Vec3(-0.513, -0.527, -0.509), Vec3(0.531, 0.522, 0.517)};
    p.size = -10;  // ten cells along the longest side of vbbox (1.049 m)
    const StuffedVolume v = mesh_tetra_stuffing(box.points, box.triangles, {}, p);
    const double volume = checked_volume(v);
    EXPECT_GT(volume, 1.0);
    EXPECT_LT(volume, 1.8);
    const double cell = 1.049 / 10;
    for (const Vec3& x : v.points) EXPECT_LE(x.cwiseAbs().maxCoeff(), 0.5 + cell + 1e-12);
}

TEST(MeshTetraStuffing, SphereVolumeWithinTwoPercent) {
    const Vec3 centre(0.0123, -0.0234, 0.0311);
    const StuffingSurface sphere = icosphere(1.0, 2, centre);  // 320 triangles
    MeshTetraStuffingParameters p;
    p.size = 0.2;
    p.alpha_long = 0.3;
    p.alpha_short = 0.4;
    p.snap_points = true;
    p.split_tetrahedra = true;
    const StuffedVolume v = mesh_tetra_stuffing(sphere.points, sphere.triangles, {}, p);
    const double volume = checked_volume(v);
    EXPECT_NEAR(volume / sphere.volume(), 1.0, 0.02);
    for (const Vec3& x : v.points) EXPECT_LE((x - centre).norm(), 1.0 + 1e-9);  // inside (the polyhedron is)
    EXPECT_EQ(v.invalid_splits, 0u);
    // snapping moves the inside points near the surface onto it: fewer cut points (without it,
    // cuts near a lattice point make slivers, of zero volume at worst, as in SOFA)
    p.snap_points = false;
    const StuffedVolume unsnapped = mesh_tetra_stuffing(sphere.points, sphere.triangles, {}, p);
    EXPECT_GT(unsnapped.points.size(), v.points.size());
    p.snap_points = true;
    // quads give the same output as their two triangles
    StuffingSurface box = closed_box(Vec3(0.013, 0.021, 0.017), Vec3(1.007, 0.811, 0.613));
    std::vector<Quad> quads;
    for (std::size_t i = 0; i < box.triangles.size(); i += 2)
        quads.push_back({box.triangles[i][0], box.triangles[i][1], box.triangles[i][2], box.triangles[i + 1][2]});
    p.size = 0.25;
    const StuffedVolume from_triangles = mesh_tetra_stuffing(box.points, box.triangles, {}, p);
    const StuffedVolume from_quads = mesh_tetra_stuffing(box.points, {}, quads, p);
    EXPECT_EQ(from_triangles.points, from_quads.points);
    EXPECT_EQ(from_triangles.tetrahedra, from_quads.tetrahedra);
}

TEST(MeshTetraStuffing, BadInputIsRefused) {
    const StuffingSurface box = closed_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
    EXPECT_THROW((void)mesh_tetra_stuffing({}, box.triangles, {}, {}), std::invalid_argument);
    EXPECT_THROW((void)mesh_tetra_stuffing(box.points, {}, {}, {}), std::invalid_argument);
    std::vector<Triangle> bad = box.triangles;
    bad[3][1] = 8;
    EXPECT_THROW((void)mesh_tetra_stuffing(box.points, bad, {}, {}), std::invalid_argument);
    MeshTetraStuffingParameters tiny;
    tiny.size = 1e-5;
    EXPECT_THROW((void)mesh_tetra_stuffing(box.points, box.triangles, {}, tiny, 1'000'000), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
