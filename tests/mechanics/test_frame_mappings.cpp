// SkinningMapping, DeformableOnRigidFrameMapping and DistanceFromTargetMapping: J against finite
// differences of apply, Jᵀ as the adjoint of J (⟨J dx, y⟩ = ⟨dx, Jᵀ y⟩), the triplets against
// apply_j, the geometric stiffness against finite differences of Jᵀ·f, and closed forms.
#include "penalty/mechanics/frame_mappings.hpp"

#include "penalty_test/finite_difference.hpp"

#include <gtest/gtest.h>

#include <random>

namespace penalty {
namespace {

std::mt19937 frame_rng(11);
double frame_uni() { return std::uniform_real_distribution<double>(-1, 1)(frame_rng); }
Vec3 frame_vec() { return Vec3(frame_uni(), frame_uni(), frame_uni()); }
Quat frame_rotation() { return Quat(Eigen::AngleAxisd(2 * frame_uni(), frame_vec().normalized())); }

/// Moves scalar c of a Rigid3 state by h: the centre, or a world rotation about an axis.
void move_frame(Rigid3Object& s, double h, Eigen::Index c) {
    RigidFrame& f = s.position[std::size_t(c / 6)];
    if (c % 6 < 3) f.center[c % 6] += h;
    else f.orientation = Quat(Eigen::AngleAxisd(h, Vec3::Unit(c % 6 - 3))) * f.orientation;
}
void move_point(Vec3Object& s, double h, Eigen::Index c) { s.position[std::size_t(c / 3)][c % 3] += h; }

Eigen::VectorXd positions_of(const Vec3Object& s) {
    return ConstFlatVector(reinterpret_cast<const double*>(s.position.data()), Eigen::Index(s.scalar_size()));
}

/// J (columns: the inputs' scalars in order) by apply_dx on unit vectors, and by central finite
/// differences of apply_position; both returned.
std::pair<Eigen::MatrixXd, Eigen::MatrixXd> jacobians(
    BaseMapping& map, std::vector<BaseState*> inputs, Vec3Object& out,
    const std::function<void(std::size_t, double, Eigen::Index)>& move) {
    Eigen::Index columns = 0;
    for (BaseState* s : inputs) columns += Eigen::Index(s->scalar_size());
    const auto rows = Eigen::Index(out.scalar_size());
    Eigen::MatrixXd j(rows, columns), fd(rows, columns);
    Eigen::Index col = 0;
    const double h = 1e-6;
    for (std::size_t k = 0; k < inputs.size(); ++k) {
        for (Eigen::Index c = 0; c < Eigen::Index(inputs[k]->scalar_size()); ++c, ++col) {
            for (BaseState* s : inputs) s->dx_flat().setZero();
            inputs[k]->dx_flat()[c] = 1.0;
            map.apply_position();
            map.apply_dx();
            j.col(col) = out.dx_flat();
            move(k, h, c);
            map.apply_position();
            const Eigen::VectorXd plus = positions_of(out);
            move(k, -2 * h, c);
            map.apply_position();
            const Eigen::VectorXd minus = positions_of(out);
            move(k, h, c);
            fd.col(col) = (plus - minus) / (2 * h);
        }
    }
    map.apply_position();
    return {j, fd};
}

/// ⟨J dx, y⟩ = ⟨dx, Jᵀ y⟩ over random dx (every input) and y.
void expect_adjoint(BaseMapping& map, std::vector<BaseState*> inputs, BaseState& out) {
    for (int trial = 0; trial < 4; ++trial) {
        double rhs = 0;
        std::vector<Eigen::VectorXd> dx;
        for (BaseState* s : inputs) {
            dx.push_back(Eigen::VectorXd::NullaryExpr(Eigen::Index(s->scalar_size()), [] { return frame_uni(); }));
            s->dx_flat() = dx.back();
            s->df_flat().setZero();
        }
        map.apply_dx();
        const Eigen::VectorXd y =
            Eigen::VectorXd::NullaryExpr(Eigen::Index(out.scalar_size()), [] { return frame_uni(); });
        const double lhs = out.dx_flat().dot(y);
        out.df_flat() = y;
        map.apply_jt_df();
        for (std::size_t k = 0; k < inputs.size(); ++k) rhs += dx[k].dot(inputs[k]->df_flat());
        EXPECT_NEAR(lhs, rhs, 1e-12 * std::max(1.0, std::abs(lhs)));
        EXPECT_GT(std::abs(lhs), 1e-6);
    }
}

TEST(SkinningMapping, JacobianAdjointAndFiniteDifferences) {
    Rigid3Object frames;
    Vec3Object points;
    for (int i = 0; i < 4; ++i) frames.position.push_back({frame_vec() * 2, frame_rotation()});
    frames.init();
    for (int i = 0; i < 6; ++i) points.position.push_back(frame_vec() * 2);
    points.init();
    const std::vector<Vec3> initial = points.position;
    SkinningMapping map(frames, points);
    map.set_nb_ref({3});
    map.init();
    // the weights: three frames per point, the nearest first, summing to 1
    for (const auto& inf : map.influences()) {
        ASSERT_EQ(inf.weights.size(), 3u);
        EXPECT_NEAR(inf.weights[0] + inf.weights[1] + inf.weights[2], 1.0, 1e-15);
        EXPECT_GE(inf.weights[0], inf.weights[1]);
        EXPECT_GE(inf.weights[1], inf.weights[2]);
    }
    // at rest the skinned points are the initial ones
    for (std::size_t i = 0; i < points.position.size(); ++i)
        EXPECT_TRUE(points.position[i].isApprox(initial[i], 1e-13));
    for (auto& f : frames.position) f = {f.center + frame_vec(), frame_rotation() * f.orientation};
    const auto [j, fd] =
        jacobians(map, {&frames}, points, [&](std::size_t, double h, Eigen::Index c) { move_frame(frames, h, c); });
    EXPECT_TRUE(test::near_relative(j, fd, 1e-7)) << j << "\n--\n" << fd;
    expect_adjoint(map, {&frames}, points);
    TripletList t;
    map.add_jacobian_triplets(t, 0, 0);
    SparseMatrix js(j.rows(), j.cols());
    js.setFromTriplets(t.begin(), t.end());
    EXPECT_TRUE(test::near_relative(Eigen::MatrixXd(js), j, 1e-14));
}

TEST(SkinningMapping, OneInfluenceIsARigidAttachment) {
    // nbRef = 1: each point follows its nearest frame rigidly, x = c + R·R0ᵀ(x0 − c0)
    Rigid3Object frames;
    Vec3Object points;
    frames.position = {{Vec3(0, 0, 0), Quat::Identity()}, {Vec3(10, 0, 0), Quat::Identity()}};
    frames.init();
    points.position = {Vec3(1, 0.5, 0), Vec3(9, -1, 2), Vec3(10, 0, 0)};
    points.init();
    SkinningMapping map(frames, points);
    map.set_nb_ref({1});
    map.init();
    EXPECT_EQ(map.influences()[0].frames[0], 0);
    EXPECT_EQ(map.influences()[1].frames[0], 1);
    const Quat q(Eigen::AngleAxisd(0.7, Vec3(0, 0, 1)));
    frames.position[1] = {Vec3(10, 3, 0), q};
    map.apply_position();
    EXPECT_TRUE(points.position[1].isApprox(Vec3(10, 3, 0) + q * Vec3(-1, -1, 2), 1e-14));
    EXPECT_EQ(points.position[2], Vec3(10, 3, 0));   // on the frame's centre (weight: the largest double)
    EXPECT_EQ(points.position[0], Vec3(1, 0.5, 0));  // frame 0 did not move
}

TEST(DeformableOnRigidFrameMapping, BothInputsJacobianAdjointAndClosedForm) {
    Vec3Object local;
    Rigid3Object frames;
    Vec3Object out;
    for (int i = 0; i < 5; ++i) local.position.push_back(frame_vec());
    local.init();
    frames.position = {{frame_vec(), frame_rotation()}, {frame_vec(), frame_rotation()}};
    frames.init();
    DeformableOnRigidFrameMapping map(local, frames, out, 1);
    map.init();
    EXPECT_EQ(map.second_from(), &frames);
    for (std::size_t i = 0; i < 5; ++i)
        EXPECT_TRUE(out.position[i].isApprox(
            frames.position[1].center + frames.position[1].orientation * local.position[i], 1e-14));
    const auto [j, fd] = jacobians(map, {&local, &frames}, out, [&](std::size_t k, double h, Eigen::Index c) {
        if (k == 0) move_point(local, h, c);
        else move_frame(frames, h, c);
    });
    EXPECT_TRUE(test::near_relative(j, fd, 1e-7)) << j << "\n--\n" << fd;
    EXPECT_TRUE(j.block(0, 15, 15, 6).isZero(0));  // frame 0 is not used
    expect_adjoint(map, {&local, &frames}, out);
    TripletList t1, t2;
    map.add_jacobian_triplets(t1, 0, 0);
    map.add_second_input_jacobian_triplets(t2, 0, 15);
    t1.insert(t1.end(), t2.begin(), t2.end());
    SparseMatrix js(j.rows(), j.cols());
    js.setFromTriplets(t1.begin(), t1.end());
    EXPECT_TRUE(test::near_relative(Eigen::MatrixXd(js), j, 1e-14));
    // a bad frame index is refused at init
    Vec3Object out2;
    DeformableOnRigidFrameMapping bad(local, frames, out2, 2);
    EXPECT_THROW(bad.init(), std::invalid_argument);
}

TEST(DistanceFromTargetMapping, DistancesJacobianAndGeometricStiffness) {
    Vec3Object points;
    Vec1Object distances;
    for (int i = 0; i < 4; ++i) points.position.push_back(frame_vec() * 3);
    points.init();
    const std::vector<Vec3> targets = {Vec3(0, 0, 0), Vec3(1, 2, 3), frame_vec()};
    DistanceFromTargetMapping map(points, distances, {2, 0, 3}, targets, {0.5}, /*exact*/ 1);
    map.init();
    ASSERT_EQ(distances.position.size(), 3u);
    EXPECT_DOUBLE_EQ(distances.position[0], (points.position[2] - targets[0]).norm() - 0.5);
    EXPECT_DOUBLE_EQ(distances.position[1], (points.position[0] - targets[1]).norm());  // rest length padded with 0
    // J: rows u_iᵀ; adjoint; finite differences
    const double h = 1e-6;
    Eigen::MatrixXd j(3, 12), fd(3, 12);
    for (Eigen::Index c = 0; c < 12; ++c) {
        points.dx_flat().setZero();
        points.dx_flat()[c] = 1.0;
        map.apply_dx();
        j.col(c) = distances.dx_flat();
        move_point(points, h, c);
        map.apply_position();
        const Eigen::Vector3d plus(distances.position[0], distances.position[1], distances.position[2]);
        move_point(points, -2 * h, c);
        map.apply_position();
        const Eigen::Vector3d minus(distances.position[0], distances.position[1], distances.position[2]);
        move_point(points, h, c);
        map.apply_position();
        fd.col(c) = (plus - minus) / (2 * h);
    }
    EXPECT_TRUE(test::near_relative(j, fd, 1e-7)) << j << "\n--\n" << fd;
    expect_adjoint(map, {&points}, distances);
    // geometric stiffness = ∂(Jᵀ f)/∂x for a fixed output force f (exact mode)
    const std::vector<double> f = {-2.0, 1.5, -0.7};
    const auto jt_f = [&] {
        std::vector<Vec3> in(points.position.size(), Vec3::Zero());
        map.apply_position();
        map.apply_jt(in, f);
        return ConstFlatVector(reinterpret_cast<const double*>(in.data()), 12).eval();
    };
    Eigen::MatrixXd k(12, 12), k_fd(12, 12);
    for (Eigen::Index c = 0; c < 12; ++c) {
        std::vector<Vec3> dx(4, Vec3::Zero()), df(4, Vec3::Zero());
        dx[std::size_t(c / 3)][c % 3] = 1.0;
        map.apply_position();
        map.add_geometric_stiffness(df, dx, f, 1.0);
        k.col(c) = ConstFlatVector(reinterpret_cast<const double*>(df.data()), 12);
        move_point(points, h, c);
        const Eigen::VectorXd plus = jt_f();
        move_point(points, -2 * h, c);
        const Eigen::VectorXd minus = jt_f();
        move_point(points, h, c);
        k_fd.col(c) = (plus - minus) / (2 * h);
    }
    map.apply_position();
    EXPECT_TRUE(test::near_relative(k, k_fd, 1e-6)) << k << "\n--\n" << k_fd;
    // stabilized (SOFA's default): only the outputs pulled apart (f < 0) count
    Vec1Object d2;
    DistanceFromTargetMapping stabilized(points, d2, {2, 0, 3}, targets, {}, 2);
    stabilized.init();
    std::vector<Vec3> dx(4, Vec3(1, -2, 0.5)), df(4, Vec3::Zero()), df_exact(4, Vec3::Zero());
    stabilized.add_geometric_stiffness(df, dx, std::vector<double>{0.0, 1.5, 0.0}, 1.0);
    for (const Vec3& v : df) EXPECT_EQ(v, Vec3::Zero());
}

}  // namespace
}  // namespace penalty
