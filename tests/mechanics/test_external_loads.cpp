// PlaneForceField, ConstantForceField, ConicalForceField (SOFA's MechanicalLoad): closed forms of
// their forces, SOFA's quirks (unnormalised plane normal, depth-scaled damping, the cone's
// normal-only stiffness), and finite-difference checks of f = −∂E/∂x and df = K·dx.
#include "penalty/mechanics/external_loads.hpp"

#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/point_state.hpp"
#include "penalty_test/rigid_derivatives.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace penalty {
namespace {

using test::force_of;
using test::state_at;

/// df = K·dx through add_dforce (k_factor `k`), for one displacement.
std::vector<Vec3> dforce_of(BaseForceField& ff, Vec3Object& s, const std::vector<Vec3>& dx, double k = 1.0) {
    s.dx = dx;
    std::fill(s.df.begin(), s.df.end(), Vec3::Zero());
    ff.accumulate_dforce(k, 0.0);
    return s.df;
}

void expect_vec_near(const Vec3& actual, const Vec3& expected, double tol) {
    EXPECT_NEAR((actual - expected).norm(), 0.0, tol)
        << "actual " << actual.transpose() << ", expected " << expected.transpose();
}

// ---- PlaneForceField ----------------------------------------------------------------------------

TEST(PlaneForceField, PointBelowThePlaneGetsStiffnessTimesDepthAlongTheNormal) {
    // plane y = −1 (n = (0, 1, 0), d = −1), k = 1000: a point 0.5 below gets 500 N up, one above nothing
    Vec3Object s = state_at({Vec3(0.3, -1.5, 2.0), Vec3(0.0, 0.2, 0.0), Vec3(4.0, -1.25, -3.0)});
    PlaneForceFieldParameters p;
    p.offset = -1.0;
    p.stiffness = 1000.0;
    p.damping = 7.0;  // no velocity: no damping force
    PlaneForceField ff(s, p);
    const std::vector<Vec3> f = force_of(ff, s);
    EXPECT_EQ(f[0], Vec3(0.0, 500.0, 0.0));
    EXPECT_EQ(f[1], Vec3::Zero());
    EXPECT_EQ(f[2], Vec3(0.0, 250.0, 0.0));
    EXPECT_EQ(ff.active_points(), (std::vector<Index>{0, 2}));
    EXPECT_DOUBLE_EQ(ff.potential_energy(), 0.5 * 1000.0 * (0.25 + 0.0625));
    // K = −k n nᵀ on the active points only
    const std::vector<Vec3> df = dforce_of(ff, s, {Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(-1, -1, 0)}, 0.5);
    EXPECT_EQ(df[0], Vec3(0.0, -1000.0, 0.0));
    EXPECT_EQ(df[1], Vec3::Zero());
    EXPECT_EQ(df[2], Vec3(0.0, 500.0, 0.0));
}

TEST(PlaneForceField, RigidFramesGetTheForceOnTheirCentreAndNoTorque) {
    // PlaneForceField<Rigid3>: the centres below the plane y = −1 (n = (0, 1, 0), d = −1), k = 1000,
    // c = 7; frame 0 is 0.5 below and moves (1, −2, 0.5): f = n·500 − v·(7·0.5) on the linear part
    const Quat q(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
    Rigid3Object s;
    s.position = {RigidFrame{Vec3(0.3, -1.5, 2.0), q}, RigidFrame{Vec3(0.0, 0.2, 0.0), q}};
    s.init();
    s.velocity[0].linear = Vec3(1, -2, 0.5);
    s.velocity[0].angular = Vec3(9, 9, 9);  // no effect
    PlaneForceFieldParameters p;
    p.offset = -1.0;
    p.stiffness = 1000.0;
    p.damping = 7.0;
    RigidPlaneForceField ff(s, p);
    ff.accumulate_force();
    EXPECT_EQ(s.force[0].linear, Vec3(0.0, 500.0, 0.0) - Vec3(1, -2, 0.5) * 3.5);
    EXPECT_EQ(s.force[0].angular, Vec3::Zero());
    EXPECT_EQ(s.force[1].linear, Vec3::Zero());
    EXPECT_EQ(ff.active_points(), (std::vector<Index>{0}));
    // df = K·dx against central differences of f (no velocity: the damping term is not in K, as
    // SOFA), and the assembled matrix against add_dforce
    std::fill(s.velocity.begin(), s.velocity.end(), RigidDeriv{});
    const Eigen::MatrixXd fd = test::rigid_force_jacobian(ff, s);
    const Eigen::MatrixXd k = test::rigid_dforce_matrix(ff, s);
    EXPECT_TRUE(test::near_relative(k, fd, 1e-6)) << "max diff " << (k - fd).cwiseAbs().maxCoeff();
    EXPECT_EQ(k(1, 1), -1000.0);
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

TEST(PlaneForceField, NormalIsUsedAsGivenNotNormalised) {
    // SOFA's scenes write normal="0 0.2 1": depth d = x·n − offset and f = −k d n with the raw n
    Vec3Object s = state_at({Vec3(1.0, -2.0, -3.0)});
    PlaneForceFieldParameters p;
    p.normal = Vec3(0.0, 0.2, 1.0);
    p.offset = -1.0;
    p.stiffness = 100.0;
    p.damping = 1.0;
    PlaneForceField ff(s, p);
    const double depth = -0.4 - 3.0 + 1.0;  // x·n − d = −2.4
    expect_vec_near(force_of(ff, s)[0], -100.0 * depth * p.normal, 1e-12);
}

TEST(PlaneForceField, DampingScalesWithDepthAndActsAlongTheWholeVelocity) {
    // PlaneForceField::addForce: f = n (−k d) − v (−c d)
    Vec3Object s = state_at({Vec3(0.0, -0.5, 0.0)});
    s.velocity[0] = Vec3(1.0, -2.0, 3.0);
    PlaneForceFieldParameters p;
    p.stiffness = 200.0;
    p.damping = 10.0;
    PlaneForceField ff(s, p);
    const double d = -0.5;
    expect_vec_near(force_of(ff, s)[0], Vec3(0.0, 100.0, 0.0) + 10.0 * d * Vec3(1.0, -2.0, 3.0), 1e-12);
}

TEST(PlaneForceField, MaxForceClampsTheMagnitudeAndKeepsTheDirection) {
    Vec3Object s = state_at({Vec3(0.0, -2.0, 0.0), Vec3(0.0, -0.01, 0.0)});
    s.velocity[0] = Vec3(3.0, 0.0, 0.0);
    PlaneForceFieldParameters p;
    p.stiffness = 100.0;
    p.damping = 20.0;
    p.max_force = 50.0;
    PlaneForceField ff(s, p);
    const std::vector<Vec3> f = force_of(ff, s);
    const Vec3 unclamped = Vec3(0.0, 200.0, 0.0) + 20.0 * -2.0 * Vec3(3.0, 0.0, 0.0);
    EXPECT_NEAR(f[0].norm(), 50.0, 1e-12);
    expect_vec_near(f[0], unclamped.normalized() * 50.0, 1e-12);
    EXPECT_EQ(f[1], Vec3(0.0, 1.0, 0.0));  // 1 N < 50 N: unchanged
}

TEST(PlaneForceField, BilateralPullsPointsAboveBackToThePlane) {
    Vec3Object s = state_at({Vec3(0.0, 0.25, 0.0), Vec3(0.0, -0.5, 0.0)});
    PlaneForceFieldParameters p;
    p.stiffness = 100.0;
    p.bilateral = true;
    PlaneForceField ff(s, p);
    const std::vector<Vec3> f = force_of(ff, s);
    EXPECT_EQ(f[0], Vec3(0.0, -25.0, 0.0));
    EXPECT_EQ(f[1], Vec3(0.0, 50.0, 0.0));
    EXPECT_EQ(ff.active_points(), (std::vector<Index>{0, 1}));
}

TEST(PlaneForceField, LocalRangeLimitsThePointsConsidered) {
    Vec3Object s = state_at({Vec3(0, -1, 0), Vec3(0, -1, 0), Vec3(0, -1, 0), Vec3(0, -1, 0)});
    PlaneForceFieldParameters p;
    p.stiffness = 10.0;
    p.local_range = {1, 2};
    PlaneForceField ff(s, p);
    const std::vector<Vec3> f = force_of(ff, s);
    EXPECT_EQ(f[0], Vec3::Zero());
    EXPECT_EQ(f[1], Vec3(0, 10, 0));
    EXPECT_EQ(f[2], Vec3(0, 10, 0));
    EXPECT_EQ(f[3], Vec3::Zero());
    // a last index past the end is clipped to the points
    p.local_range = {2, 99};
    PlaneForceField clipped(s, p);
    EXPECT_EQ(force_of(clipped, s)[3], Vec3(0, 10, 0));
    EXPECT_EQ(clipped.active_points(), (std::vector<Index>{2, 3}));
}

TEST(PlaneForceField, ForceStiffnessAndEnergyMatchFiniteDifferences) {
    // a tilted, unnormalised plane; points well below and above (no crossing within the FD step)
    Vec3Object s = state_at({Vec3(0.1, -1.0, 0.3), Vec3(0.5, 2.0, -0.2), Vec3(-0.7, -0.4, -0.9), Vec3(0.2, 0.1, 0.0)});
    PlaneForceFieldParameters p;
    p.normal = Vec3(0.3, 1.2, -0.4);
    p.offset = 0.2;
    p.stiffness = 750.0;
    p.damping = 3.0;  // zero velocities: the damping term and its x-derivative vanish
    PlaneForceField ff(s, p);
    const auto d = test::check_force_field_derivatives(ff, s, {1e-6, 1e-12, 1e-6});
    EXPECT_EQ(ff.active_points(), (std::vector<Index>{0, 2, 3}));
    EXPECT_GT(d.force.norm(), 100.0);
    EXPECT_TRUE(d.k_fd.isApprox(d.k_fd.transpose(), 1e-6));
    // the stiffness follows the active set of the last add_force: point 1 (above) has none
    EXPECT_EQ(d.k_dforce.block(3, 3, 3, 3), Eigen::Matrix3d::Zero());
}

TEST(PlaneForceField, RefusesNegativeCoefficients) {
    Vec3Object s = state_at({Vec3::Zero()});
    PlaneForceFieldParameters p;
    p.stiffness = -1.0;
    EXPECT_THROW(PlaneForceField(s, p), std::invalid_argument);
    p.stiffness = 1.0;
    p.max_force = -2.0;
    EXPECT_THROW(PlaneForceField(s, p), std::invalid_argument);
}

// ---- ConstantForceField -------------------------------------------------------------------------

TEST(ConstantForceField, OneForcePerIndex) {
    Vec3Object s = state_at({Vec3(1, 0, 0), Vec3(0, 2, 0), Vec3(0, 0, 3)});
    ConstantForceFieldParameters p;
    p.indices = {2, 0};
    p.forces = {Vec3(1, 2, 3), Vec3(-4, 0, 0.5)};
    ConstantForceField ff(s, p);
    ff.init();
    const std::vector<Vec3> f = force_of(ff, s);
    EXPECT_EQ(f[0], Vec3(-4, 0, 0.5));
    EXPECT_EQ(f[1], Vec3::Zero());
    EXPECT_EQ(f[2], Vec3(1, 2, 3));
    EXPECT_EQ(ff.total_force(), Vec3(-3, 2, 3.5));
    // E = −Σ F·x
    EXPECT_DOUBLE_EQ(ff.potential_energy(), -(3.0 * 3.0) - (-4.0 * 1.0));
}

TEST(ConstantForceField, OneForceIsRepeatedOnEveryIndex) {
    // the example scenes' indices="0" forces="1 0 0", and forces without indices: every point
    Vec3Object s = state_at({Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
    ConstantForceFieldParameters p;
    p.forces = {Vec3(1, 0, 0)};
    ConstantForceField all(s, p);
    all.init();
    EXPECT_EQ(all.points(), (std::vector<Index>{0, 1, 2}));
    for (const Vec3& f : force_of(all, s)) EXPECT_EQ(f, Vec3(1, 0, 0));
    EXPECT_EQ(all.total_force(), Vec3(3, 0, 0));
    p.indices = {0};
    ConstantForceField one(s, p);
    one.init();
    const std::vector<Vec3> f = force_of(one, s);
    EXPECT_EQ(f[0], Vec3(1, 0, 0));
    EXPECT_EQ(f[1], Vec3::Zero());
}

TEST(ConstantForceField, TotalForceIsSplitEvenlyOverTheIndices) {
    // SOFA HEAD (computeForceFromTotalForce): F_j = T / n, so Σ F_j = T
    Vec3Object s = state_at(std::vector<Vec3>(5, Vec3::Zero()));
    ConstantForceFieldParameters p;
    p.indices = {0, 1, 4};
    p.total_force = Vec3(0.05, 0.0, -0.2);
    ConstantForceField ff(s, p);
    ff.init();
    const std::vector<Vec3> f = force_of(ff, s);
    for (const Index i : {0, 1, 4}) EXPECT_EQ(f[static_cast<std::size_t>(i)], Vec3(0.05 / 3.0, 0.0, -0.2 / 3.0));
    EXPECT_EQ(f[2], Vec3::Zero());
    expect_vec_near(ff.total_force(), Vec3(0.05, 0.0, -0.2), 1e-15);
    // forces win over totalForce (SOFA's init warns and uses forces)
    p.forces = {Vec3(1, 1, 1)};
    ConstantForceField both(s, p);
    both.init();
    EXPECT_EQ(both.total_force(), Vec3(3, 3, 3));
}

TEST(ConstantForceField, IndicesFromTheEnd) {
    Vec3Object s = state_at(std::vector<Vec3>(4, Vec3::Zero()));
    ConstantForceFieldParameters p;
    p.indices = {0, 2};
    p.forces = {Vec3(1, 0, 0), Vec3(0, 1, 0)};
    p.index_from_end = true;
    ConstantForceField ff(s, p);
    ff.init();
    EXPECT_EQ(ff.points(), (std::vector<Index>{3, 1}));
    const std::vector<Vec3> f = force_of(ff, s);
    EXPECT_EQ(f[3], Vec3(1, 0, 0));
    EXPECT_EQ(f[1], Vec3(0, 1, 0));
}

TEST(ConstantForceField, ForceIsMinusTheGradientOfItsEnergyAndHasNoStiffness) {
    Vec3Object s = state_at({Vec3(0.3, -1.0, 2.0), Vec3(1.0, 0.5, -0.7)});
    ConstantForceFieldParameters p;
    p.forces = {Vec3(2.0, -1.0, 0.5), Vec3(-0.3, 4.0, 1.0)};
    ConstantForceField ff(s, p);
    ff.init();
    const Eigen::VectorXd x0 = Vec3Object::flat(s.position);
    const Eigen::VectorXd grad = test::finite_gradient(x0, [&](const Eigen::VectorXd& x) {
        Vec3Object::flat(s.position) = x;
        force_of(ff, s);
        return ff.potential_energy();
    });
    Vec3Object::flat(s.position) = x0;
    const std::vector<Vec3> f = force_of(ff, s);
    EXPECT_TRUE(test::near_relative(Eigen::VectorXd(-grad), Eigen::VectorXd(Vec3Object::flat(f)), 1e-8));
    for (const Vec3& df : dforce_of(ff, s, {Vec3(1, 1, 1), Vec3(1, 1, 1)})) EXPECT_EQ(df, Vec3::Zero());
    TripletList t;
    ff.add_stiffness(
        t, [](const BaseState*) { return Index{0}; }, 1.0);
    EXPECT_TRUE(t.empty());
}

TEST(ConstantForceField, RefusesBadInput) {
    Vec3Object s = state_at(std::vector<Vec3>(3, Vec3::Zero()));
    EXPECT_THROW(ConstantForceField(s, ConstantForceFieldParameters{}), std::invalid_argument);  // no force at all
    ConstantForceFieldParameters p;
    p.indices = {0, 1, 2};
    p.forces = {Vec3(1, 0, 0), Vec3(1, 0, 0)};  // 2 forces for 3 indices
    ConstantForceField mismatch(s, p);
    mismatch.init();  // SOFA's computeForceFromForcesVector: Invalid, no force
    EXPECT_FALSE(mismatch.valid());
    std::vector<Vec3> f(3, Vec3::Zero());
    const std::vector<Vec3> x(3, Vec3::Zero());
    mismatch.add_force(f, x, x);
    for (const Vec3& fi : f) EXPECT_EQ(fi, Vec3::Zero());
    p.indices = {3};
    p.forces = {Vec3(1, 0, 0)};
    ConstantForceField out_of_range(s, p);
    EXPECT_THROW(out_of_range.init(), std::invalid_argument);
}

// ---- ConicalForceField --------------------------------------------------------------------------

/// The example scene's cone: apex (0, −10, 0), axis (0, 20, 0), half-angle 40°.
ConicalForceFieldParameters example_cone() {
    ConicalForceFieldParameters p;
    p.center = Vec3(0.0, -10.0, 0.0);
    p.height = Vec3(0.0, 20.0, 0.0);
    p.angle_deg = 40.0;
    return p;
}

TEST(ConicalForceField, InsideTestFollowsTheConeAndItsSphericalCap) {
    Vec3Object s = state_at({Vec3::Zero()});
    const ConicalForceField ff(s, example_cone());
    EXPECT_TRUE(ff.is_inside(Vec3(0.0, 5.0, 0.0)));     // on the axis
    EXPECT_TRUE(ff.is_inside(Vec3(0.0, -10.0, 0.0)));   // the apex
    EXPECT_TRUE(ff.is_inside(Vec3(5.0, 0.0, 0.0)));     // 26.6° off the axis
    EXPECT_FALSE(ff.is_inside(Vec3(9.0, 0.0, 0.0)));    // 42° off the axis
    EXPECT_FALSE(ff.is_inside(Vec3(0.0, 10.5, 0.0)));   // beyond the cap |u| = 20.5 > 20
    EXPECT_TRUE(ff.is_inside(Vec3(12.0, 5.0, 0.0)));    // |u| = 19.2, 38.7°
    EXPECT_FALSE(ff.is_inside(Vec3(0.0, -11.0, 0.0)));  // behind the apex
}

TEST(ConicalForceField, ClosedFormForcesInTheThreeRegions) {
    ConicalForceFieldParameters p;
    p.center = Vec3(1.0, 2.0, 3.0);
    p.height = Vec3(0.0, 4.0, 0.0);  // h = 4, axis +y
    p.angle_deg = 45.0;
    p.stiffness = 100.0;
    p.damping = 0.0;
    Vec3Object s = state_at({p.center + Vec3(0.0, 5.0, 0.0),    // beyond the cap: |u| = 5, d = 1
                             p.center + Vec3(1.0, 0.5, 0.0),    // beside: 63° > 45°
                             p.center + Vec3(0.0, -0.5, 0.3),   // behind the apex
                             p.center + Vec3(0.5, 2.0, 0.0)});  // inside
    ConicalForceField ff(s, p);
    const std::vector<Vec3> f = force_of(ff, s);
    expect_vec_near(f[0], Vec3(0.0, -100.0, 0.0), 1e-12);
    // beside: the generatrix (1, 1, 0)/√2; the projection of u = (1, 0.5, 0) on it is (0.75, 0.75, 0)
    expect_vec_near(f[1], 100.0 * Vec3(-0.25, 0.25, 0.0), 1e-12);
    expect_vec_near(f[2], -100.0 * Vec3(0.0, -0.5, 0.3), 1e-12);
    EXPECT_EQ(f[3], Vec3::Zero());
    ASSERT_EQ(ff.contacts().size(), 3u);
    expect_vec_near(ff.contacts()[1].normal, Vec3(-1.0, 1.0, 0.0).normalized(), 1e-14);
    EXPECT_NEAR(ff.potential_energy(), 0.5 * 100.0 * (1.0 + 0.125 + 0.34), 1e-12);
}

TEST(ConicalForceField, DampingAsSofaWritesIt) {
    // beyond the cap: f = −k d û − v (−c d) (d > 0: along v); elsewhere f = k d n − c (n·v) n
    ConicalForceFieldParameters p;
    p.height = Vec3(0.0, 0.0, 2.0);
    p.angle_deg = 30.0;
    p.stiffness = 10.0;
    p.damping = 4.0;
    Vec3Object s = state_at({Vec3(0.0, 0.0, 3.0), Vec3(0.0, 0.0, -1.0)});
    s.velocity[0] = Vec3(1.0, 0.0, -1.0);
    s.velocity[1] = Vec3(2.0, 0.0, -3.0);
    ConicalForceField ff(s, p);
    const std::vector<Vec3> f = force_of(ff, s);
    expect_vec_near(f[0], Vec3(0.0, 0.0, -10.0) + 4.0 * 1.0 * Vec3(1.0, 0.0, -1.0), 1e-12);
    // behind the apex: n = (0, 0, 1), d = 1, n·v = −3
    expect_vec_near(f[1], Vec3(0.0, 0.0, 10.0) + Vec3(0.0, 0.0, 12.0), 1e-12);
}

TEST(ConicalForceField, ForceIsMinusTheGradientOfItsEnergyAndStiffnessIsItsNormalPart) {
    // SOFA keeps K = −k n nᵀ per contact: the part along n of the exact ∂f/∂x (whose other terms
    // come from the curvature of the cone and of the cap). Checked: f = −∂E/∂x, the assembled
    // triplets equal add_dforce, and add_dforce = P·(FD ∂f/∂x) with P = n nᵀ per contact.
    ConicalForceFieldParameters p = example_cone();
    p.stiffness = 300.0;
    p.damping = 2.0;                                  // zero velocities
    Vec3Object s = state_at({Vec3(1.0, 11.0, 2.0),    // beyond the cap
                             Vec3(9.0, 0.0, 1.0),     // beside the cone
                             Vec3(0.5, -10.5, -0.5),  // behind the apex
                             Vec3(0.0, 0.0, 1.0)});   // inside
    ConicalForceField ff(s, p);
    const Eigen::VectorXd x0 = Vec3Object::flat(s.position);
    const auto force = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
        Vec3Object::flat(s.position) = x;
        return Vec3Object::flat(force_of(ff, s));
    };
    const Eigen::VectorXd grad = test::finite_gradient(x0, [&](const Eigen::VectorXd& x) {
        force(x);
        return ff.potential_energy();
    });
    const Eigen::MatrixXd jacobian_fd = test::finite_jacobian(x0, force, 1e-6);
    const Eigen::VectorXd f0 = force(x0);  // linearise at x0
    ASSERT_EQ(ff.contacts().size(), 3u);
    EXPECT_GT(f0.norm(), 100.0);
    EXPECT_TRUE(test::near_relative(Eigen::VectorXd(-grad), f0, 1e-6)) << "f = -dE/dx";

    Eigen::MatrixXd k_dforce(12, 12);
    for (Eigen::Index j = 0; j < 12; ++j) {
        std::vector<Vec3> dx(4, Vec3::Zero());
        Vec3Object::flat(dx)[j] = 1.0;
        k_dforce.col(j) = Vec3Object::flat(dforce_of(ff, s, dx));
    }
    Eigen::MatrixXd projection = Eigen::MatrixXd::Zero(12, 12);
    for (const ConicalForceField::Contact& c : ff.contacts())
        projection.block<3, 3>(3 * c.index, 3 * c.index) = c.normal * c.normal.transpose();
    EXPECT_TRUE(test::near_relative(k_dforce, Eigen::MatrixXd(projection * jacobian_fd), 1e-6))
        << "max diff " << (k_dforce - projection * jacobian_fd).cwiseAbs().maxCoeff();
    // the exact Jacobian has more than its normal part beside the cone and beyond the cap
    EXPECT_GT((jacobian_fd - k_dforce).cwiseAbs().maxCoeff(), 1.0);

    TripletList t;
    ff.add_stiffness(
        t, [](const BaseState*) { return Index{0}; }, 1.0);
    SparseMatrix k_sparse(12, 12);
    k_sparse.setFromTriplets(t.begin(), t.end());
    EXPECT_TRUE(test::near_relative(Eigen::MatrixXd(k_sparse), k_dforce, 1e-14));
}

}  // namespace
}  // namespace penalty
