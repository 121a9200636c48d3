// place_loaded_points: SOFA's loader transform, to the bit.
#include "penalty/mechanics/loader_placement.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace penalty {
namespace {

Vec3 placed(const Vec3& p, const Vec3& t, const Vec3& r, const Vec3& s, LoaderKind kind) {
    std::vector<Vec3> points{p};
    place_loaded_points(points, t, r, s, kind);
    return points[0];
}

// SOFA HEAD's initial states (sofa-head, `../shared/sofa/examples`): PointSplatModel.scn's
// MeshOBJLoader (scale3d 0.2) puts the file's x = -10.087340 at -2.0174680000000005, and
// TriangleSurfaceCutting.scn's (scale 10) its y = 0.303030 at 3.030300000000001: T(T⁻¹(T(p))),
// one or two units in the last place from T(p) (-2.017468, 3.0303000000000004).
TEST(LoaderPlacement, MeshLoaderRunsItsTransformTwiceAsSofaHead) {
    const Vec3 dragon = placed(Vec3(-10.087340, 2.557804, -0.081764), Vec3::Zero(), Vec3::Zero(), Vec3::Constant(0.2),
                               LoaderKind::mesh_loader);
    EXPECT_EQ(dragon.x(), -2.0174680000000005);
    EXPECT_NE(dragon.x(), -10.087340 * 0.2);
    const Vec3 square =
        placed(Vec3(0.0, 0.303030, 0.0), Vec3::Zero(), Vec3::Zero(), Vec3::Constant(10.0), LoaderKind::mesh_loader);
    EXPECT_EQ(square.y(), 3.030300000000001);
    EXPECT_EQ(square.x(), 0.0);
}

TEST(LoaderPlacement, SphereLoaderAppliesItOnce) {
    const Vec3 p =
        placed(Vec3(-10.087340, 0, 0), Vec3::Zero(), Vec3::Zero(), Vec3::Constant(0.2), LoaderKind::sphere_loader);
    EXPECT_EQ(p.x(), -10.087340 * 0.2);
}

TEST(LoaderPlacement, ScaleRotateTranslateAndIdentity) {
    // (1,1,1) -scale-> (2,3,4) -Rz(90)-> (-3,2,4) -translate-> (-2,3,5)
    for (const LoaderKind kind : {LoaderKind::mesh_loader, LoaderKind::sphere_loader}) {
        EXPECT_LT((placed(Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(0, 0, 90), Vec3(2, 3, 4), kind) - Vec3(-2, 3, 5)).norm(),
                  1e-15);
        EXPECT_EQ(placed(Vec3(0.1, 0.2, 0.3), Vec3::Zero(), Vec3::Zero(), Vec3::Ones(), kind), Vec3(0.1, 0.2, 0.3));
    }
    // a scale of 0 (a singular T): no round trip, finite points
    const Vec3 flat = placed(Vec3(1, 2, 3), Vec3(0, 0, 1), Vec3::Zero(), Vec3(1, 1, 0), LoaderKind::mesh_loader);
    EXPECT_EQ(flat, Vec3(1, 2, 1));
}

}  // namespace
}  // namespace penalty
