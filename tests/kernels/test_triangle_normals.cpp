// Triangle normals (triangle_normals.hpp): both paths against Eigen's normalize((p1 − p0) ×
// (p2 − p0)) bit for bit, zeros' signs included, on random meshes with degenerate, tiny, huge and
// non-finite triangles; and TriangleModel::update() computing them once per call.
#include "fixtures.hpp"
#include "kernels/collision/triangle_normals.hpp"
#include "penalty/collision/models.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace penalty {
namespace {

using test::same_bits;

// The reference, written with Eigen as SOFA writes it; the zero vector where |n| is not > 0.
Vec3 reference_normal(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    const Vec3 n = (p1 - p0).cross(p2 - p0);
    const double len = n.norm();
    return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
}

// Points of every kind: ordinary, on a coarse grid (so that triangles are exactly collinear or
// repeat a vertex), scaled so far down that the cross product underflows or so far up that its
// squared norm overflows, −0, NaN and infinite coordinates.
std::vector<Vec3> random_points(std::mt19937& g, std::size_t n) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> pick(0, 59);
    std::vector<Vec3> x(n);
    for (Vec3& p : x) {
        p = Vec3(u(g), u(g), u(g));
        const int kind = pick(g);
        if (kind < 10) p = (p * 2.0).array().round() / 2.0;  // grid of step 0.5
        else if (kind < 13) p *= 1e-160;
        else if (kind < 16) p *= 1e160;
        else if (kind == 16) p[1] = -0.0;
        else if (kind == 17) p[2] = std::numeric_limits<double>::quiet_NaN();
        else if (kind == 18) p[0] = std::numeric_limits<double>::infinity();
    }
    return x;
}

TEST(TriangleNormals, EveryPathEqualsEigensNormalizedCrossProduct) {
    std::mt19937 g(4242);
    const bool avx = kernel_path_supported(KernelPath::avx);
    std::size_t normals = 0, zeros = 0, nonfinite = 0;
    for (const std::size_t count : {0, 1, 2, 3, 4, 5, 7, 8, 13, 64, 203, 1000}) {
        const std::vector<Vec3> x = random_points(g, 40);
        std::uniform_int_distribution<PointId> vertex(0, 39);
        std::vector<Triangle> t(count);
        for (Triangle& tri : t) tri = {vertex(g), vertex(g), vertex(g)};
        for (const KernelPath path : {KernelPath::scalar, KernelPath::avx}) {
            if (path == KernelPath::avx && !avx) continue;
            std::vector<Vec3> n(count, Vec3::Constant(7.0));
            detail::triangle_normals(x, t, n, path);
            for (std::size_t i = 0; i < count; ++i) {
                const Vec3 expected =
                    reference_normal(x[std::size_t(t[i][0])], x[std::size_t(t[i][1])], x[std::size_t(t[i][2])]);
                ASSERT_TRUE(same_bits(n[i], expected))
                    << to_string(path) << ", " << count << " triangles, triangle " << i << ": " << n[i].transpose()
                    << " instead of " << expected.transpose();
                if (path == KernelPath::scalar) {
                    ++normals;
                    if (expected == Vec3::Zero()) ++zeros;
                    else if (!expected.allFinite()) ++nonfinite;
                }
            }
        }
    }
    // the cases the reference treats apart all occur, and most normals are ordinary unit vectors
    EXPECT_EQ(normals, 1310u);
    EXPECT_GT(zeros, 200u);     // repeated vertices, collinear grid points, underflow, NaN, n / inf
    EXPECT_GT(nonfinite, 20u);  // an infinite coordinate in the cross product (inf − inf = NaN)
    EXPECT_LT(zeros + nonfinite, normals / 2);
}

TEST(TriangleNormals, ModelUpdateStoresTheNormalsOfTheCurrentPositions) {
    // a unit square of two triangles, (0,1,2) counter-clockwise seen from +z, (0,2,3) likewise
    auto mesh = test::triangle_mesh({{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}}, {{0, 1, 2}, {0, 2, 3}, {0, 0, 1}});
    TriangleModel model(mesh->state, mesh->topo);
    model.update();
    EXPECT_EQ(model.normal(0), Vec3(0, 0, 1));
    EXPECT_EQ(model.normal(1), Vec3(0, 0, 1));
    EXPECT_EQ(model.normal(2), Vec3::Zero());  // a repeated vertex: no normal
    // tilted about x by 90°: the normals follow at the next update (the model is moving)
    for (Vec3& p : mesh->state.position) p = Vec3(p.x(), 0.0, p.y());
    EXPECT_EQ(model.normal(0), Vec3(0, 0, 1));
    model.update();
    EXPECT_EQ(model.normal(0), Vec3(0, -1, 0));
    EXPECT_EQ(model.normal(1), Vec3(0, -1, 0));
}

}  // namespace
}  // namespace penalty
