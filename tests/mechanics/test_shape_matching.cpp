// ClusteringEngine, ShapeMatching and PositionBasedDynamicsProjectiveConstraint (shape_matching.hpp):
// clusters derived by hand from SOFA's rules (ClusteringEngine::doUpdate, farthestPointSampling,
// dijkstra, AddNeighborhoodFromNeighborhood), shape matching against closed forms (a rigid motion
// is reproduced exactly) and against an SVD (Kabsch) best rigid fit, SOFA's polar factor against
// the SVD's, and one PBD projection against SOFA's projectPosition/projectVelocity formulas.
#include "penalty/mechanics/shape_matching.hpp"

#include <gtest/gtest.h>
#include <Eigen/SVD>

#include <random>

namespace penalty {
namespace {

using ClusterLists = std::vector<std::vector<PointId>>;

// A U-shaped chain 0-1-2-3-4-5 in the z = 0 plane: geodesic and Euclidean farthest points differ.
const std::vector<Vec3> kChainPoints{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {0, 1, 0}};
const std::vector<std::vector<PointId>> kChainNeighbours{{1}, {0, 2}, {1, 3}, {2, 4}, {3, 5}, {4}};

TEST(ClusteringEngine, EuclideanSeedsRadiusAndTheNearestSeedRule) {
    // points on the x axis 0..5; seeds 0 then the farthest, 5. Radius 1.5: 1 joins 0's cluster and
    // 4 joins 5's; 2 and 3 are in no radius and join the nearest seed's; each seed, in no other
    // radius, joins the nearest other seed's cluster (SOFA's loop skips only j == seed).
    std::vector<Vec3> x;
    for (int i = 0; i < 6; ++i) x.emplace_back(i, 0, 0);
    ClusteringParameters p;
    p.use_topology = false;
    p.radius = 1.5;
    p.number = 2;
    p.fixed_radius = 1.0;
    const ClusterLists c = clustering_engine(x, nullptr, p, {Vec3(5.5, 0, 0), Vec3(2.5, 3, 0)});
    EXPECT_EQ(c, (ClusterLists{{0, 1, 2, 5}, {5, 0, 3, 4, 6}}));  // fixed point 0 is index 6
}

TEST(ClusteringEngine, MinusOneMakesEveryPointASeed) {
    ClusteringParameters p;
    p.use_topology = false;
    p.radius = 1.1;
    const ClusterLists c = clustering_engine(kChainPoints, nullptr, p);
    ASSERT_EQ(c.size(), 6u);
    EXPECT_EQ(c[0], (std::vector<PointId>{0, 1, 5}));  // |0-1| = |0-5| = 1 < 1.1
    EXPECT_EQ(c[2], (std::vector<PointId>{2, 1, 3}));
}

TEST(ClusteringEngine, GeodesicSeedsVoronoiRegionsAndOneRing) {
    ClusteringParameters p;
    p.radius = 0.5;  // no point within it: membership is the Voronoi region plus one ring
    p.number = 2;
    // along the chain the farthest point from 0 is 5; the Voronoi regions are {0,1,2} and {3,4,5}
    const ClusterLists geodesic = clustering_engine(kChainPoints, &kChainNeighbours, p);
    EXPECT_EQ(geodesic, (ClusterLists{{0, 1, 2, 3}, {5, 4, 3, 2}}));
    // without the topology the farthest point from 0 is 3 (√5)
    p.use_topology = false;
    EXPECT_EQ(clustering_engine(kChainPoints, &kChainNeighbours, p).at(1).front(), 3);
    // radius 1.2: point 5 is within it of seed 0 but is reached only through 4 (√2 away): left out
    p.use_topology = true;
    p.radius = 1.2;
    EXPECT_EQ(clustering_engine(kChainPoints, &kChainNeighbours, p).at(0), (std::vector<PointId>{0, 1, 2, 3}));
    // radius 1.5: 4 joins (√2 < 1.5), and through it 5
    p.radius = 1.5;
    EXPECT_EQ(clustering_engine(kChainPoints, &kChainNeighbours, p).at(0), (std::vector<PointId>{0, 1, 2, 3, 4, 5}));
}

Mat3 rotation_about(const Vec3& axis, double angle) {
    return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

std::vector<Vec3> shape_points() { return {{0, 0, 0}, {1, 0, 0}, {0, 1.5, 0}, {0, 0, 2}, {1, 1, 1}, {-0.5, 0.3, 0.7}}; }

TEST(ShapeMatching, ARigidMotionIsReproduced) {
    const std::vector<Vec3> rest = shape_points();
    const Mat3 r = rotation_about(Vec3(1, 2, -0.5), 0.8);
    const Vec3 t(3, -1, 2);
    std::vector<Vec3> moved;
    for (const Vec3& p : rest) moved.push_back(r * p + t);
    const ShapeMatching sm({{0, 1, 2, 3, 4}, {4, 5, 2, 3}}, rest, {});
    std::vector<Vec3> target;
    sm.targets(moved, target);
    ASSERT_EQ(target.size(), rest.size());
    for (std::size_t i = 0; i < rest.size(); ++i) EXPECT_NEAR((target[i] - moved[i]).norm(), 0, 1e-12) << i;
}

/// The best rigid fit (Kabsch) of a cluster: the target of each member.
std::vector<Vec3> kabsch_fit(const std::vector<Vec3>& rest, const std::vector<Vec3>& x,
                             const std::vector<PointId>& ids) {
    Vec3 c0 = Vec3::Zero(), c = Vec3::Zero();
    for (PointId i : ids) {
        c0 += rest[static_cast<std::size_t>(i)];
        c += x[static_cast<std::size_t>(i)];
    }
    c0 /= static_cast<double>(ids.size());
    c /= static_cast<double>(ids.size());
    Mat3 h = Mat3::Zero();
    for (PointId i : ids)
        h += (x[static_cast<std::size_t>(i)] - c) * (rest[static_cast<std::size_t>(i)] - c0).transpose();
    Eigen::JacobiSVD<Mat3> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 d = Mat3::Identity();
    d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() > 0 ? 1 : -1;
    const Mat3 r = svd.matrixU() * d * svd.matrixV().transpose();
    std::vector<Vec3> out;
    for (PointId i : ids) out.push_back(c + r * (rest[static_cast<std::size_t>(i)] - c0));
    return out;
}

TEST(ShapeMatching, ADeformedClusterGetsTheBestRigidFitAndSharedPointsTheMean) {
    const std::vector<Vec3> rest = shape_points();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    const Mat3 r = rotation_about(Vec3(0, 1, 1), -1.1);
    std::vector<Vec3> x;
    for (const Vec3& p : rest) x.push_back(r * p + Vec3(1, 2, 3) + Vec3(u(rng), u(rng), u(rng)));
    const std::vector<PointId> a{0, 1, 2, 3, 4}, b{4, 5, 2, 3};
    const ShapeMatching sm({a, b}, rest, {});
    std::vector<Vec3> target;
    sm.targets(x, target);
    const std::vector<Vec3> fa = kabsch_fit(rest, x, a), fb = kabsch_fit(rest, x, b);
    EXPECT_NEAR((target[0] - fa[0]).norm(), 0, 1e-10);
    EXPECT_NEAR((target[1] - fa[1]).norm(), 0, 1e-10);
    EXPECT_NEAR((target[5] - fb[1]).norm(), 0, 1e-10);
    EXPECT_NEAR((target[2] - 0.5 * (fa[2] + fb[2])).norm(), 0, 1e-10);  // point 2: in both clusters
    EXPECT_NEAR((target[4] - 0.5 * (fa[4] + fb[0])).norm(), 0, 1e-10);
    EXPECT_NEAR((target[3] - 0.5 * (fa[3] + fb[3])).norm(), 0, 1e-10);
    EXPECT_GT((target[0] - x[0]).norm(), 1e-3);  // the fit moved the points
}

TEST(ShapeMatching, PolarFactorIsTheSvdRotation) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int k = 0; k < 20; ++k) {
        Mat3 m;
        for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = u(rng);
        Eigen::JacobiSVD<Mat3> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
        const Mat3 expected = svd.matrixU() * svd.matrixV().transpose();  // M = (UVᵀ)(VΣVᵀ)
        EXPECT_NEAR((sofa_polar_rotation(m) - expected).norm(), 0, 1e-7) << k;
    }
    // a zero determinant stops SOFA's iteration at once: the (transposed back) input is returned
    Mat3 flat = Mat3::Zero();
    flat(0, 0) = 2;
    flat(1, 1) = 3;
    EXPECT_EQ(sofa_polar_rotation(flat), flat);
}

TEST(PositionBasedDynamics, OneProjectionGivesSofasPositionAndVelocity) {
    Vec3Object s;
    s.position = {Vec3(1, 2, 3)};
    s.init();
    const Vec3 target(2, 2, 5);
    PositionBasedDynamicsConstraint pbd(
        s, [&](const std::vector<Vec3>&, std::vector<Vec3>& out) { out = {target}; }, 0.5, [] { return 0.1; });
    pbd.project_position();  // x_old = x before the move; x ← x + ½(target − x); v = (x − x_old)/dt
    pbd.project_velocity();
    EXPECT_NEAR((s.position[0] - Vec3(1.5, 2, 4)).norm(), 0, 1e-15);
    EXPECT_NEAR((s.velocity[0] - Vec3(5, 0, 10)).norm(), 0, 1e-13);
    s.position[0] = Vec3(1.6, 2, 4);  // the solver moved it; x_old is the last projected position
    pbd.project_position();
    pbd.project_velocity();
    EXPECT_NEAR((s.position[0] - Vec3(1.8, 2, 4.5)).norm(), 0, 1e-15);
    EXPECT_NEAR((s.velocity[0] - Vec3(3, 0, 5)).norm(), 0, 1e-13);
}

TEST(PositionBasedDynamics, ZeroTimeStepLeavesThePositions) {
    Vec3Object s;
    s.position = {Vec3(1, 2, 3)};
    s.init();
    s.velocity[0] = Vec3(7, 7, 7);
    PositionBasedDynamicsConstraint pbd(
        s, [](const std::vector<Vec3>&, std::vector<Vec3>& out) { out = {Vec3::Zero()}; }, 1.0, [] { return 0.0; });
    pbd.project_position();
    pbd.project_velocity();  // no velocities computed yet: left (SOFA reports a size error)
    EXPECT_EQ(s.position[0], Vec3(1, 2, 3));
    EXPECT_EQ(s.velocity[0], Vec3(7, 7, 7));
}

}  // namespace
}  // namespace penalty
