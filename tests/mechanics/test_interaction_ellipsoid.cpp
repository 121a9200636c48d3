// InteractionEllipsoidForceField (SOFA's InteractionEllipsoidForceField<Vec3d, Rigid3d>): the
// closed form of a sphere, the frame's transform, the stiffness against finite differences (the
// exact matrix) and SOFA's matrix as SOFA writes it, the frame's reaction, damping, bad values.
#include "penalty/mechanics/interaction_ellipsoid.hpp"

#include "penalty_test/finite_difference.hpp"
#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <random>

namespace penalty {
namespace {

struct EllipsoidRig {
    Vec3Object points;
    Rigid3Object frames{"frame"};
    EllipsoidRig(std::vector<Vec3> x, const RigidFrame& frame) {
        points.position = std::move(x);
        points.init();
        frames.position = {frame};
        frames.init();
    }
};

RigidFrame tilted_frame() { return {Vec3(0.5, -1, 2), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, -0.5).normalized()))}; }

TEST(InteractionEllipsoid, SphereClosedFormPushesOutByDepthTimesStiffness) {
    // sphere of radius r: f = k·(1 − d/r)·d̂ for a point at distance d < r from its center
    const RigidFrame frame = tilted_frame();
    const Vec3 local_center(0.3, 0, -0.2), direction = Vec3(1, -2, 2).normalized();
    const double r = 2.0, d = 1.5, k = 40.0;
    EllipsoidRig rig({frame.center + frame.orientation * (local_center + d * direction), Vec3(100, 0, 0)}, frame);
    InteractionEllipsoidForceField ff(
        rig.points, rig.frames, {.centers = {local_center}, .radii = {Vec3(r, r, r)}, .stiffness = k, .damping = 0});
    ff.init();
    ff.accumulate_force();
    const Vec3 expected = k * (1 - d / r) * (frame.orientation * direction);
    EXPECT_LT((rig.points.force[0] - expected).norm(), 1e-12 * k);
    EXPECT_EQ(rig.points.force[1], Vec3::Zero());  // outside: no force
    EXPECT_EQ(ff.contact_count(), 1u);
    // the frame takes the opposite linear force, no torque (SOFA's torque is commented out)
    EXPECT_LT((rig.frames.force[0].linear + expected).norm(), 1e-12 * k);
    EXPECT_EQ(rig.frames.force[0].angular, Vec3::Zero());
}

TEST(InteractionEllipsoid, NegativeStiffnessHoldsPointsInside) {
    EllipsoidRig rig({Vec3(3, 0, 0), Vec3(0.5, 0, 0)}, RigidFrame{});
    InteractionEllipsoidForceField ff(rig.points, rig.frames,
                                      {.radii = {Vec3(2, 1, 1)}, .stiffness = -10, .damping = 0});
    ff.init();
    ff.accumulate_force();
    // x = 3 on the x axis of radius 2: n = 1.5, g = (3/4, 0, 0): f = −10·0.5·x̂
    EXPECT_LT((rig.points.force[0] - Vec3(-5, 0, 0)).norm(), 1e-14);
    EXPECT_EQ(rig.points.force[1], Vec3::Zero());
}

TEST(InteractionEllipsoid, LeastNormalisedDistanceEllipsoidActsAndMissingRadiiRepeatTheLast) {
    // two centers, one radius: both ellipsoids have radii (1, 2, 1); the point is nearer the second
    EllipsoidRig rig({Vec3(0, -4.5, 0)}, RigidFrame{});
    InteractionEllipsoidForceField ff(
        rig.points, rig.frames,
        {.centers = {Vec3::Zero(), Vec3(0, -5, 0)}, .radii = {Vec3(1, 2, 1)}, .stiffness = 8, .damping = 0});
    ff.init();
    ff.accumulate_force();
    EXPECT_LT((rig.points.force[0] - Vec3(0, 8 * 0.75, 0)).norm(), 1e-14);  // v = 0.25 − 1, pushed toward +y
}

TEST(InteractionEllipsoid, DampingOpposesThePointVelocityTimesDepth) {
    EllipsoidRig rig({Vec3(0.5, 0, 0)}, RigidFrame{});
    rig.points.velocity = {Vec3(0, 2, 0)};
    InteractionEllipsoidForceField ff(rig.points, rig.frames,
                                      {.radii = {Vec3(1, 1, 1)}, .stiffness = 10, .damping = 3});
    ff.init();
    ff.accumulate_force();
    EXPECT_LT((rig.points.force[0] - Vec3(5, -3 * 0.5 * 2, 0)).norm(), 1e-14);
}

TEST(InteractionEllipsoid, InvertedFrameUsesTheInverseTransform) {
    RigidFrame frame = tilted_frame();
    const Quat inverse = frame.orientation.conjugate();
    const RigidFrame inverse_frame{-(inverse * frame.center), inverse};
    // local coordinates under the inverse frame: p = q·x + c; x chosen so that p = (0.5, 0.3, −0.2)
    const Vec3 x = inverse * (Vec3(0.5, 0.3, -0.2) - frame.center);
    EllipsoidRig direct({x}, inverse_frame), inverted({x}, frame);
    const InteractionEllipsoidParameters p{.radii = {Vec3(3, 2, 2.5)}, .stiffness = 7, .damping = 0};
    InteractionEllipsoidForceField a(direct.points, direct.frames, p);
    auto q = p;
    q.object2_invert = true;
    InteractionEllipsoidForceField b(inverted.points, inverted.frames, q);
    for (auto* ff : {&a, &b}) {
        ff->init();
        ff->accumulate_force();
    }
    ASSERT_EQ(a.contact_count(), 1u);
    EXPECT_LT((direct.points.force[0] - inverted.points.force[0]).norm(), 1e-12);
}

/// Points spread inside an ellipsoid on a tilted frame (fixed seed), the frame only read.
EllipsoidRig scattered_points(std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    const RigidFrame frame = tilted_frame();
    std::vector<Vec3> x;
    for (int i = 0; i < 12; ++i)
        x.push_back(frame.center + frame.orientation * Vec3(2.5 * u(rng), 1.5 * u(rng), 2 * u(rng)));
    return EllipsoidRig(x, frame);
}

const InteractionEllipsoidParameters kScattered{.centers = {Vec3(0.1, 0, -0.1)},
                                                .radii = {Vec3(3, 2, 2.5)},
                                                .stiffness = 50,
                                                .damping = 0,
                                                .object2_forces = false};

TEST(InteractionEllipsoid, ExactStiffnessMatchesFiniteDifferencesAndTheAssembledMatrix) {
    EllipsoidRig rig = scattered_points(3);
    InteractionEllipsoidForceField ff(rig.points, rig.frames, kScattered);
    ff.set_exact_stiffness(true);
    ff.init();
    const test::DerivativeTolerances tol{
        .dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt};
    const test::ForceFieldDerivatives d = test::check_force_field_derivatives(ff, rig.points, tol);
    EXPECT_GE(ff.contact_count(), 6u);  // most points are inside: the check is not vacuous
    EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 10.0);
}

TEST(InteractionEllipsoid, SofaStiffnessIsSofasMatrixNotTheDerivative) {
    // SOFA's addDForce: M = g gᵀ(α + β/r²ⱼ) + diag(γ/r²) with β = −|k|v/|g|²; the derivative has
    // β = +|k|v/|g|³: the two differ by g gᵀ diag(1/r²)·(β_sofa − β_exact), non-zero inside.
    EllipsoidRig rig({Vec3(0.6, -0.3, 0.2)}, RigidFrame{});
    const Vec3 r(1.5, 1, 1.2);
    InteractionEllipsoidForceField sofa(rig.points, rig.frames,
                                        {.radii = {r}, .stiffness = 20, .damping = 0, .object2_forces = false});
    sofa.init();
    sofa.accumulate_force();
    rig.points.dx = {Vec3(0.3, -0.7, 0.5)};
    rig.points.df = {Vec3::Zero()};
    sofa.accumulate_dforce(1.0, 0.0);
    const Vec3 p = rig.points.position[0];
    const Vec3 inv_r2(1 / (r[0] * r[0]), 1 / (r[1] * r[1]), 1 / (r[2] * r[2]));
    const Vec3 g = p.cwiseProduct(inv_r2);
    const double n = std::sqrt(p.cwiseProduct(p).dot(inv_r2)), v = n - 1, k = 20;
    const Mat3 m =
        g * g.transpose() *
            (Mat3::Identity() * (-k / (n * g.norm())) + (-k * v / g.squaredNorm()) * Mat3(inv_r2.asDiagonal())) +
        Mat3((-k * v / g.norm()) * inv_r2.asDiagonal());
    EXPECT_LT((rig.points.df[0] - m * rig.points.dx[0]).norm(), 1e-12);
}

TEST(InteractionEllipsoid, FrameReactionAndItsStiffnessAgainstFiniteDifferences) {
    EllipsoidRig rig = scattered_points(9);
    auto p = kScattered;
    p.object2_forces = true;
    InteractionEllipsoidForceField ff(rig.points, rig.frames, p);
    ff.set_exact_stiffness(true);
    ff.init();
    // f(x₁, c): the points' forces and the frame's linear force, by the frame's center
    const auto forces = [&](const Eigen::VectorXd& center) {
        rig.frames.position[0].center = center;
        std::fill(rig.points.force.begin(), rig.points.force.end(), Vec3::Zero());
        rig.frames.force[0] = RigidDeriv{};
        ff.accumulate_force();
        Eigen::VectorXd out(3 * rig.points.num_dofs() + 3);
        out << Vec3Object::flat(rig.points.force), rig.frames.force[0].linear;
        return out;
    };
    const Vec3 c0 = rig.frames.position[0].center;
    const Eigen::MatrixXd fd = test::finite_jacobian(c0, forces, 1e-6);
    forces(c0);
    ASSERT_GE(ff.contact_count(), 6u);
    // Σ f = 0 (action and reaction on the linear parts)
    EXPECT_LT((forces(c0).head(3 * rig.points.num_dofs()).reshaped(3, rig.points.num_dofs()).rowwise().sum() +
               forces(c0).tail<3>())
                  .norm(),
              1e-10);
    Eigen::MatrixXd product(fd.rows(), 3);
    for (int j = 0; j < 3; ++j) {
        std::fill(rig.points.dx.begin(), rig.points.dx.end(), Vec3::Zero());
        std::fill(rig.points.df.begin(), rig.points.df.end(), Vec3::Zero());
        rig.frames.dx[0] = RigidDeriv{};
        rig.frames.df[0] = RigidDeriv{};
        rig.frames.dx[0].linear[j] = 1.0;
        ff.accumulate_dforce(1.0, 0.0);
        product.col(j) << Vec3Object::flat(rig.points.df), rig.frames.df[0].linear;
    }
    EXPECT_TRUE(test::near_relative(product, fd, 1e-6)) << (product - fd).cwiseAbs().maxCoeff();
    // the assembled matrix (points then the frame's 6 rows) against the products
    TripletList t;
    const auto n1 = static_cast<Index>(3 * rig.points.num_dofs());
    ff.add_stiffness(
        t, [&](const BaseState* s) { return s == &rig.points ? Index{0} : n1; }, 1.0);
    SparseMatrix k(n1 + 6, n1 + 6);
    k.setFromTriplets(t.begin(), t.end());
    const Eigen::MatrixXd dense(k);
    Eigen::MatrixXd assembled(n1 + 3, 3);
    assembled << dense.block(0, n1, n1, 3), dense.block(n1, n1, 3, 3);
    EXPECT_TRUE(test::near_relative(assembled, product, 1e-12));
    EXPECT_EQ(dense.block(n1 + 3, 0, 3, n1 + 6).cwiseAbs().maxCoeff(), 0.0);  // no torque rows
}

TEST(InteractionEllipsoid, BadValuesAreRejected) {
    EllipsoidRig rig({Vec3::Zero()}, RigidFrame{});
    EXPECT_THROW(InteractionEllipsoidForceField(rig.points, rig.frames, {.radii = {Vec3(1, 0, 1)}}),
                 std::invalid_argument);
    EXPECT_THROW(InteractionEllipsoidForceField(rig.points, rig.frames, {.stiffness = std::nan("")}),
                 std::invalid_argument);
    InteractionEllipsoidForceField far(rig.points, rig.frames, {.frame_index = 3});
    EXPECT_THROW(far.init(), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
