// DiagonalMass<Rigid3> (RigidDiagonalMass): M·dx against the assembled triplets, gravity and the
// kinetic energy in closed form, frames past the list without mass, bad masses refused.
#include "penalty/mechanics/rigid_diagonal_mass.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

Rigid3Object rigid_mass_frames(int n) {
    Rigid3Object s;
    for (int i = 0; i < n; ++i) s.position.push_back({Vec3(i, 2.0 * i, -1.0), Quat::Identity()});
    s.init();
    return s;
}

TEST(RigidDiagonalMass, ProductMatchesTheAssembledMatrixAndClosedForms) {
    Rigid3Object s = rigid_mass_frames(3);
    Mat3 j;
    j << 2, 0.5, 0, 0.5, 3, 0, 0, 0, 4;
    RigidDiagonalMass mass(s, {{15.0, Mat3::Identity() * 20.0}, {2.0, j}});  // frame 2: no mass
    // M·dx by add_mdx (factor 0.3) equals the triplets' matrix times dx
    for (std::size_t i = 0; i < 3; ++i) s.dx[i] = {Vec3(1.0 + i, -2.0, 0.5), Vec3(0.25, 1.0, -3.0 + i)};
    for (auto& d : s.df) d = {};
    mass.add_mdx(0.3);
    TripletList t;
    mass.add_mass_triplets(t, 0, 0.3);
    SparseMatrix m(18, 18);
    m.setFromTriplets(t.begin(), t.end());
    const Eigen::VectorXd expected = m * Eigen::VectorXd(s.dx_flat());
    EXPECT_TRUE(Eigen::VectorXd(s.df_flat()).isApprox(expected, 1e-14));
    EXPECT_DOUBLE_EQ(s.df[0].linear.x(), 0.3 * 15.0);         // m·dx
    EXPECT_DOUBLE_EQ(s.df[0].angular.x(), 0.3 * 300 * 0.25);  // (J·m)·dx, J = 20·I
    EXPECT_TRUE(s.df[2].linear.isZero(0));  // past the list: no mass (SOFA does not pad a Rigid3 list)
    // gravity: f = m·g, no torque; kinetic energy ½(m v² + ωᵀ(J·m)ω)
    for (auto& f : s.force) f = {};
    mass.add_gravity_force(Vec3(0, 0, -9.81));
    EXPECT_DOUBLE_EQ(s.force[1].linear.z(), -9.81 * 2.0);
    EXPECT_TRUE(s.force[1].angular.isZero(0));
    s.velocity[1] = {Vec3(1, 0, 0), Vec3(0, 1, 0)};
    EXPECT_DOUBLE_EQ(mass.kinetic_energy(), 0.5 * (2.0 * 1.0 + 3.0 * 2.0));
    EXPECT_DOUBLE_EQ(mass.total_mass(), 17.0);
    // M⁻¹·(M·x) = x on the frames with a mass
    Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(12, -1, 2), back(12);
    Rigid3Object two = rigid_mass_frames(2);
    RigidDiagonalMass m2(two, {{15.0, Mat3::Identity() * 20.0}, {2.0, j}});
    TripletList t2;
    m2.add_mass_triplets(t2, 0, 1.0);
    SparseMatrix mm(12, 12);
    mm.setFromTriplets(t2.begin(), t2.end());
    m2.apply_inverse(mm * x, back);
    EXPECT_TRUE(back.isApprox(x, 1e-13));
}

TEST(RigidDiagonalMass, RefusesBadMasses) {
    Rigid3Object s = rigid_mass_frames(2);
    EXPECT_THROW(RigidDiagonalMass(s, {{0.0, Mat3::Identity()}}), std::invalid_argument);
    EXPECT_THROW(RigidDiagonalMass(s, {{1.0, Mat3::Zero()}}), std::invalid_argument);
    Mat3 skew = Mat3::Identity();
    skew(0, 1) = 1;
    EXPECT_THROW(RigidDiagonalMass(s, {{1.0, skew}}), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
