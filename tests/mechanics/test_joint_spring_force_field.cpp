// JointSpringForceField: SOFA's spring text (one object read in turn, the REST_T quirk), the
// restoring force and torque of a clamped joint in closed form, the pivot and limit cases, and
// its stiffness against finite differences (exact for translations anywhere and for every DOF at
// rest, SOFA's K) and against the assembled matrix.
#include "penalty/mechanics/joint_spring_force_field.hpp"

#include "penalty_test/rigid_derivatives.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace penalty {
namespace {

TEST(JointSpringParsing, SpringsAreReadIntoOneObjectInTurn) {
    const auto springs = parse_joint_springs(
        "BEGIN_SPRING  0 1  FREE_AXIS 0 0 0 0 1 0  KS_T 0 30000  KS_R 0 200000  KD 1  R_LIM_X -0.8 0.8  "
        "R_LIM_Y -1.57 1.57  R_LIM_Z 0 0  END_SPRING\n BEGIN_SPRING  2 3  END_SPRING\n");
    ASSERT_EQ(springs.size(), 2u);
    const JointSpring& a = springs[0];
    EXPECT_EQ(a.m1, 0);
    EXPECT_EQ(a.m2, 1);
    EXPECT_EQ(a.free_movements, (std::array<bool, 6>{false, false, false, false, true, false}));
    EXPECT_EQ(a.hard_translation, 30000);
    EXPECT_EQ(a.hard_rotation, 200000);
    EXPECT_EQ(a.bloc_rotation, 2000) << "KS_B absent: hard rotation / 100";
    EXPECT_EQ(a.kd, 1);
    EXPECT_EQ(a.limit_angles[4], 0);
    EXPECT_FALSE(a.init_from_positions);
    // the second spring keeps the first one's KS_T, KS_R and KD (type::vector::read reuses the
    // object) but gets the default axes and limits back
    const JointSpring& b = springs[1];
    EXPECT_EQ(b.m1, 2);
    EXPECT_EQ(b.hard_translation, 30000);
    EXPECT_EQ(b.hard_rotation, 200000);
    EXPECT_EQ(b.kd, 1);
    EXPECT_EQ(b.free_movements, (std::array<bool, 6>{false, false, false, true, true, true}));
    EXPECT_EQ(b.limit_angles[0], -100000.);
}

TEST(JointSpringParsing, RestTranslationMakesSofaTakeTheRestFromThePositions) {
    const auto springs = parse_joint_springs("BEGIN_SPRING 0 1 REST_T 1 2 3 REST_R 0 0 0 1 END_SPRING");
    ASSERT_EQ(springs.size(), 1u);
    EXPECT_TRUE(springs[0].init_from_positions);
    EXPECT_THROW(static_cast<void>(parse_joint_springs("BEGIN_SPRING 0 1 KS_X 1 END_SPRING")), std::invalid_argument);
    EXPECT_THROW(static_cast<void>(parse_joint_springs("BEGIN_SPRING 0 1 KS_T 1 2")), std::invalid_argument);
    EXPECT_THROW(static_cast<void>(parse_joint_springs("BEGIN_SPRING -1 1 END_SPRING")), std::invalid_argument);
    EXPECT_THROW(static_cast<void>(parse_joint_springs("BEGIN_SPRING 0 1 FREE_AXIS 0 2 0 0 0 0 END_SPRING")),
                 std::invalid_argument);
    EXPECT_THROW(static_cast<void>(parse_joint_springs("0 1 END_SPRING")), std::invalid_argument);
}

/// Two frames: 0 at the origin, 1 at `c1` turned by `angle` about `axis`.
Rigid3Object two_frames(const Vec3& c1, double angle, const Vec3& axis) {
    Rigid3Object s;
    s.position = {RigidFrame{}, RigidFrame{c1, Quat(Eigen::AngleAxisd(angle, axis.normalized()))}};
    s.init();
    return s;
}

TEST(JointSpringForceField, ClampedJointRestoringForceAndTorqueInClosedForm) {
    Rigid3Object s = two_frames(Vec3(0.2, 0, 0), 0.3, Vec3::UnitZ());
    const double kt = 500, kr = 40;
    JointSpringForceField ff(
        s, s, parse_joint_springs("BEGIN_SPRING 0 1 FREE_AXIS 0 0 0 0 0 0 KS_T 0 500 KS_R 0 40 END_SPRING"));
    ff.init();
    ff.accumulate_force();
    // no REST_T: rest offset 0, rest rotation identity; frame 0's axes are the world's
    EXPECT_NEAR((s.force[0].linear - Vec3(kt * 0.2, 0, 0)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((s.force[1].linear + Vec3(kt * 0.2, 0, 0)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((s.force[0].angular - Vec3(0, 0, kr * 0.3)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((s.force[1].angular + Vec3(0, 0, kr * 0.3)).norm(), 0.0, 1e-12) << "torque turning frame 1 back";
    EXPECT_NEAR(ff.potential_energy(), 0.5 * kt * 0.04 + 0.5 * kr * 0.09, 1e-12);
}

TEST(JointSpringForceField, FreeAxisInsideItsLimitsIsAPivot) {
    // rotation about z free inside ±1 rad with a soft stiffness 0: a turn of 0.5 about z gives no torque
    Rigid3Object s = two_frames(Vec3::Zero(), 0.5, Vec3::UnitZ());
    JointSpringForceField ff(
        s, s, parse_joint_springs("BEGIN_SPRING 0 1 FREE_AXIS 0 0 0 0 0 1 KS_R 0 100 R_LIM_Z -1 1 END_SPRING"));
    ff.init();
    ff.accumulate_force();
    EXPECT_NEAR(s.force[0].angular.norm(), 0.0, 1e-12);
    // past the limit: the bloc stiffness (100/100 = 1) times the rotation beyond it (1.3 − 1)
    Rigid3Object far = two_frames(Vec3::Zero(), 1.3, Vec3::UnitZ());
    JointSpringForceField beyond(
        far, far, parse_joint_springs("BEGIN_SPRING 0 1 FREE_AXIS 0 0 0 0 0 1 KS_R 0 100 R_LIM_Z -1 1 END_SPRING"));
    beyond.init();
    beyond.accumulate_force();
    EXPECT_NEAR(far.force[0].angular.z(), 1.0 * 0.3, 1e-12);
}

TEST(JointSpringForceField, StiffnessExactAtRestAndForTranslations) {
    // rest taken from the positions (REST_T): every DOF's derivative is SOFA's K at rest. SOFA's
    // bwdInit takes initRot = q2·q1⁻¹, which is the rest rotation only when q1 = q2 (kept: see
    // docs/components/rigid_force_fields.md), so both frames share their orientation here.
    const Quat q(Eigen::AngleAxisd(0.4, Vec3(1, 2, 0).normalized()));
    Rigid3Object s;
    s.position = {RigidFrame{Vec3(0.1, -0.3, 0.2), q}, RigidFrame{Vec3(1.0, 0.2, -0.1), q}};
    s.init();
    JointSpringForceField ff(
        s, s,
        parse_joint_springs("BEGIN_SPRING 0 1 FREE_AXIS 0 1 0 0 0 0 KS_T 30 500 KS_R 7 40 REST_T 0 0 0 END_SPRING"));
    ff.init();
    const Eigen::MatrixXd fd = test::rigid_force_jacobian(ff, s);
    const Eigen::MatrixXd k = test::rigid_dforce_matrix(ff, s);
    EXPECT_TRUE(test::near_relative(k, fd, 1e-6)) << "max diff " << (k - fd).cwiseAbs().maxCoeff();
    EXPECT_TRUE(test::near_relative(test::assembled_stiffness(ff, 12), k, 1e-14));
    // deformed: the translation columns stay exact (the force is linear in the centres)
    s.position[1].center += Vec3(0.05, -0.02, 0.03);
    s.position[1].orientation = (Quat(Eigen::AngleAxisd(0.2, Vec3::UnitX())) * s.position[1].orientation).normalized();
    const Eigen::MatrixXd fd2 = test::rigid_force_jacobian(ff, s);
    const Eigen::MatrixXd k2 = test::rigid_dforce_matrix(ff, s);
    for (int c : {0, 1, 2, 6, 7, 8}) EXPECT_TRUE(test::near_relative(k2.col(c), fd2.col(c), 1e-6)) << "column " << c;
    EXPECT_TRUE(test::near_relative(test::assembled_stiffness(ff, 12), k2, 1e-14));
}

TEST(JointSpringForceField, ForceIsMinusTheEnergyGradientInTheCentres) {
    Rigid3Object s = two_frames(Vec3(0.3, 0.1, -0.2), 0.25, Vec3(1, 1, 1));
    JointSpringForceField ff(
        s, s, parse_joint_springs("BEGIN_SPRING 0 1 FREE_AXIS 0 0 0 0 0 0 KS_T 0 800 KS_R 0 50 END_SPRING"));
    ff.init();
    const std::vector<RigidFrame> x0 = s.position;
    const Eigen::VectorXd f = test::rigid_force_at(ff, s, x0, Eigen::VectorXd::Zero(12));
    const auto energy = [&](const Eigen::VectorXd& centres) {
        Eigen::VectorXd d = Eigen::VectorXd::Zero(12);
        d.segment<3>(0) = centres.segment<3>(0);
        d.segment<3>(6) = centres.segment<3>(3);
        test::rigid_force_at(ff, s, x0, d);
        return ff.potential_energy();
    };
    const Eigen::VectorXd g = test::finite_gradient(Eigen::VectorXd::Zero(6), energy, 1e-6);
    Eigen::VectorXd f_centres(6);
    f_centres << f.segment<3>(0), f.segment<3>(6);
    EXPECT_TRUE(test::near_relative(Eigen::VectorXd(-g), f_centres, 1e-7));
}

TEST(JointSpringForceField, RestRotationFromThePositionsIsSofasProduct) {
    // frame 1 turned by 0.3 about z, REST_T given: SOFA's initRot = q2·q1⁻¹ = q2, and the relative
    // rotation at rest is q1⁻¹·q2·initRot, a turn of 0.6: the rest pose is not torque-free (kept)
    Rigid3Object s = two_frames(Vec3(1, 0, 0), 0.3, Vec3::UnitZ());
    JointSpringForceField ff(
        s, s, parse_joint_springs("BEGIN_SPRING 0 1 FREE_AXIS 0 0 0 0 0 0 KS_R 0 10 REST_T 0 0 0 END_SPRING"));
    ff.init();
    ff.accumulate_force();
    EXPECT_NEAR(s.force[0].angular.z(), 10 * 0.6, 1e-12);
    EXPECT_NEAR(s.force[0].linear.norm(), 0.0, 1e-12) << "initTrans = c2 - c1";
}

TEST(JointSpringForceField, RefusesSpringsOutsideTheStates) {
    Rigid3Object s = two_frames(Vec3::Zero(), 0, Vec3::UnitZ());
    JointSpringForceField ff(s, s, parse_joint_springs("BEGIN_SPRING 0 2 END_SPRING"));
    EXPECT_THROW(ff.init(), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
