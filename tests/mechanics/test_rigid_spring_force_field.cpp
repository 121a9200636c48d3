// SpringForceField<Rigid3> (RigidSpringForceField): the spring law on the frames' centres in closed
// form (no torque, linear velocities only), and its stiffness against finite differences and the
// assembled matrix.
#include "penalty/mechanics/rigid_spring_force_field.hpp"

#include "penalty_test/rigid_derivatives.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

Rigid3Object two_rigid_frames() {
    Rigid3Object s;
    const Quat q1(Eigen::AngleAxisd(0.3, Vec3(1, 0, 2).normalized()));
    const Quat q2(Eigen::AngleAxisd(-1.1, Vec3(0, 1, 1).normalized()));
    s.position = {RigidFrame{Vec3(0, 0, 0), q1}, RigidFrame{Vec3(3, 4, 0), q2}};
    s.init();
    return s;
}

TEST(RigidSpringForceField, CentresPullEachOtherAlongTheSpringWithoutTorque) {
    Rigid3Object s = two_rigid_frames();
    s.velocity[1].linear = Vec3(0.6, 0.8, 1.0);  // elongation speed (0.6, 0.8, 1)·(0.6, 0.8, 0) = 1
    s.velocity[1].angular = Vec3(5, 5, 5);       // not read
    RigidSpringForceField ff(s, s, {Spring{.a = 0, .b = 1, .ks = 10, .kd = 2, .rest_length = 4}});
    ff.init();
    ff.accumulate_force();
    // d = 5, û = (0.6, 0.8, 0): F = 10·(5 − 4) + 2·1 = 12
    EXPECT_TRUE(s.force[0].linear.isApprox(Vec3(7.2, 9.6, 0), 1e-15));
    EXPECT_TRUE(s.force[1].linear.isApprox(Vec3(-7.2, -9.6, 0), 1e-15));
    EXPECT_EQ(s.force[0].angular, Vec3::Zero());
    EXPECT_EQ(s.force[1].angular, Vec3::Zero());
    EXPECT_DOUBLE_EQ(ff.potential_energy(), 5.0);
}

TEST(RigidSpringForceField, StiffnessMatchesFiniteDifferencesAndTheAssembledMatrix) {
    Rigid3Object s = two_rigid_frames();
    RigidSpringForceField ff(s, s, {Spring{.a = 0, .b = 1, .ks = 30, .kd = 0, .rest_length = 2.5}});
    ff.init();
    const Eigen::MatrixXd fd = test::rigid_force_jacobian(ff, s);
    const Eigen::MatrixXd k = test::rigid_dforce_matrix(ff, s);
    EXPECT_TRUE(test::near_relative(k, fd, 1e-6)) << "max diff " << (k - fd).cwiseAbs().maxCoeff();
    EXPECT_GT(k.cwiseAbs().maxCoeff(), 1.0);
    EXPECT_TRUE(test::near_relative(test::assembled_stiffness(ff, 12), k, 1e-14));
    // f = −∂E/∂x in the centres
    const std::vector<RigidFrame> x0 = s.position;
    const auto energy = [&](const Eigen::VectorXd& centres) {
        Eigen::VectorXd d = Eigen::VectorXd::Zero(12);
        d.segment<3>(0) = centres.segment<3>(0);
        d.segment<3>(6) = centres.segment<3>(3);
        test::rigid_force_at(ff, s, x0, d);
        return ff.potential_energy();
    };
    const Eigen::VectorXd g = test::finite_gradient(Eigen::VectorXd::Zero(6), energy, 1e-6);
    const Eigen::VectorXd f = test::rigid_force_at(ff, s, x0, Eigen::VectorXd::Zero(12));
    Eigen::VectorXd f_centres(6);
    f_centres << f.segment<3>(0), f.segment<3>(6);
    EXPECT_TRUE(test::near_relative(Eigen::VectorXd(-g), f_centres, 1e-7));
}

TEST(RigidSpringForceField, RefusesFramesOutsideTheStates) {
    Rigid3Object s = two_rigid_frames();
    RigidSpringForceField ff(s, s, {Spring{.a = 0, .b = 2, .ks = 1, .kd = 0, .rest_length = 1}});
    EXPECT_THROW(ff.init(), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
