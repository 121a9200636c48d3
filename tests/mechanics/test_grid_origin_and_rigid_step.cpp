// RegularGridTopology's p0 and its axes of one point (RegularGridTopology::setPos), and the Rigid3
// position update of SOFA HEAD (RigidCoord::operator+=, exponential integration).
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace penalty {
namespace {

TEST(RegularGridOrigin, P0OffsetsEveryPointAndOnePointAxesTakeTheMiddle) {
    // p0 given: the first point, whatever min is; the spacing still (max − min)/(n − 1)
    const RegularGridTopology moved({6, 1, 1}, Vec3(-10, -10, -10), Vec3(10, 10, 10), Vec3(18, 10, -10));
    EXPECT_EQ(moved.point(0, 0, 0), Vec3(18, 10, -10));
    EXPECT_EQ(moved.point(5, 0, 0), Vec3(38, 10, -10));
    // no p0: min, except on an axis of one point: the middle for x and y, min for z
    const RegularGridTopology line({6, 1, 1}, Vec3(0, 0, 6), Vec3(5, 1, 6));
    EXPECT_EQ(line.origin(), Vec3(0, 0.5, 6));
    EXPECT_EQ(line.point(3, 0, 0), Vec3(3, 0.5, 6));
    const RegularGridTopology column({1, 1, 4}, Vec3(-1, 2, 0), Vec3(3, 4, 3));
    EXPECT_EQ(column.point(0, 0, 2), Vec3(1, 3, 2));
    // max below min runs backwards; max = min with several points: coincident points (SOFA)
    const RegularGridTopology backwards({3, 1, 3}, Vec3(0, 0, -20), Vec3(10, 0, -30), Vec3(0, 0, -1));
    EXPECT_EQ(backwards.point(2, 0, 2), Vec3(10, 0, -11));
    const RegularGridTopology flat({3, 3, 2}, Vec3(0, 0, 0), Vec3(2, 2, 0));
    EXPECT_EQ(flat.point(1, 1, 0), flat.point(1, 1, 1));
    EXPECT_THROW((void)flat.locate(Vec3(1, 1, 0)), std::invalid_argument);  // no cell of non-zero size
    EXPECT_THROW(
        RegularGridTopology({2, 2, 2}, Vec3::Zero(), Vec3::Ones(), Vec3(0, std::numeric_limits<double>::infinity(), 0)),
        std::invalid_argument);
}

TEST(RigidStep, ExponentialIntegrationOfTheAngularVelocity) {
    // q ← exp(½ ω h) ⊗ q: a rotation by the angle |ω| h about ω, exactly (to rounding)
    const RigidFrame start{Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(0.3, Vec3(0, 1, 0)))};
    const RigidDeriv v{Vec3(0.5, -1, 2), Vec3(0.4, -1.2, 2.0)};
    const double h = 0.02;
    const RigidFrame end = rigid_add(start, v, h);
    EXPECT_EQ(end.center, Vec3(1 + 0.5 * h, 2 - 1 * h, 3 + 2 * h));
    const Quat exact = Quat(Eigen::AngleAxisd(v.angular.norm() * h, v.angular.normalized())) * start.orientation;
    EXPECT_NEAR(end.orientation.angularDistance(exact), 0.0, 1e-15);
    EXPECT_NEAR(end.orientation.norm(), 1.0, 1e-15);
    // the first-order update SOFA used before (q + ½ (ω h ⊗ q), normalised) differs by ~θ³: a
    // test that the exponential is what runs
    const Vec3 w = h * v.angular;
    Quat first = Quat(0, w.x(), w.y(), w.z()) * start.orientation;
    first = Quat(start.orientation.w() + 0.5 * first.w(), start.orientation.x() + 0.5 * first.x(),
                 start.orientation.y() + 0.5 * first.y(), start.orientation.z() + 0.5 * first.z())
                .normalized();
    EXPECT_GT(end.orientation.angularDistance(first), 1e-7);
    // a zero angular velocity keeps the orientation bit for bit
    EXPECT_EQ(rigid_add(start, RigidDeriv{Vec3::Zero(), Vec3::Zero()}, h).orientation.coeffs(),
              start.orientation.coeffs());
}

}  // namespace
}  // namespace penalty
