// RestShapeSpringsForceField: finite differences of force and stiffness, SOFA's assembled
// matrix (buildStiffnessMatrix's indexing), rigid torques in closed form, external rest shapes,
// and a large field's springs on TBB's threads (the bits of one thread).
#include "penalty/mechanics/rest_shape_springs.hpp"

#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/point_state.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>
#include <type_traits>
#include <vector>

namespace penalty {
namespace {

using test::state_at;

/// Four points displaced from their rest positions.
Vec3Object displaced_points() {
    Vec3Object s = state_at({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)});
    s.position[0] += Vec3(0.1, -0.2, 0.05);
    s.position[2] += Vec3(-0.3, 0.1, 0.2);
    s.position[3] += Vec3(0.01, 0.02, -0.4);
    return s;
}

/// K from add_stiffness_triplets (dense).
template <class DataTypes>
Eigen::MatrixXd rest_spring_matrix(const RestShapeSpringsForceField<DataTypes>& ff, Eigen::Index n) {
    TripletList t;
    ff.add_stiffness_triplets(t, 0, 1.0);
    SparseMatrix k(n, n);
    k.setFromTriplets(t.begin(), t.end());
    return Eigen::MatrixXd(k);
}

TEST(RestShapeSprings, ForceIsMinusTheEnergyGradientAndStiffnessTheForceDerivative) {
    Vec3Object s = displaced_points();
    RestShapeSpringsForceField<Vec3Types> ff(s);
    ff.set_points({3, 0, 2});
    ff.set_stiffness({10.0, 200.0});  // spring 2 (point 2) takes the first value
    ff.set_active_directions({true, false, true});
    ff.set_sofa_assembly(false);
    ff.init();
    const auto d = test::check_force_field_derivatives(
        ff, s, {.dforce_vs_fd = 1e-8, .assembled_vs_dforce = 1e-15, .force_vs_energy = 1e-8});
    // closed form: f_p = −k (x_p − x0_p) in the active directions only
    EXPECT_NEAR(d.force[0], -200.0 * 0.1, 1e-12);   // point 0, x
    EXPECT_EQ(d.force[1], 0.0);                     // point 0, y inactive
    EXPECT_NEAR(d.force[11], -10.0 * -0.4, 1e-12);  // point 3, z
    EXPECT_NEAR(d.force[8], -10.0 * 0.2, 1e-12);    // point 2, z (first stiffness)
    EXPECT_EQ(d.force[3], 0.0);                     // point 1 is not held
}

TEST(RestShapeSprings, TheAssembledMatrixIsSofaHeadsBuildStiffnessMatrixByDefault) {
    // SOFA HEAD's buildStiffnessMatrix takes stiffness[point] (not stiffness[spring]) and keeps the
    // inactive translations; addDForce (the CG's product) does neither.
    Vec3Object s = displaced_points();
    RestShapeSpringsForceField<Vec3Types> ff(s);
    ff.set_points({3, 0});
    ff.set_stiffness({10.0, 200.0, 3000.0, 40000.0});
    ff.set_active_directions({true, false, true});
    ff.init();
    const Eigen::MatrixXd sofa = rest_spring_matrix(ff, 12);
    EXPECT_EQ(sofa(9, 9), -40000.0);    // point 3: stiffness[3], the spring's own is stiffness[0] = 10
    EXPECT_EQ(sofa(10, 10), -40000.0);  // inactive y kept
    EXPECT_EQ(sofa(0, 0), -10.0);       // point 0: stiffness[0], the spring's own is stiffness[1] = 200
    ff.set_sofa_assembly(false);
    const Eigen::MatrixXd fixed = rest_spring_matrix(ff, 12);
    EXPECT_EQ(fixed(9, 9), -10.0);
    EXPECT_EQ(fixed(10, 10), 0.0);
    EXPECT_EQ(fixed(0, 0), -200.0);
}

TEST(RestShapeSprings, ARigidFrameGetsTheAxisAngleTorque) {
    Rigid3Object s;
    s.position.resize(2);
    s.rest_position.resize(2);
    s.position[1].center = Vec3(1, 2, 3);
    s.init();
    s.rest_position = s.position;
    const double angle = 0.4;
    s.position[1].orientation = Quat(Eigen::AngleAxisd(angle, Vec3(0, 0.6, 0.8)));
    s.position[1].center += Vec3(0.1, 0, -0.2);
    RestShapeSpringsForceField<Rigid3Types> ff(s);
    ff.set_stiffness({5.0});
    ff.set_angular_stiffness({7.0, 9.0});  // cut to the stiffness count: 7 for every frame
    ff.init();
    s.force.assign(2, RigidDeriv{});
    ff.add_force(s.force, s.position, s.velocity);
    EXPECT_LT((s.force[1].linear - Vec3(-0.5, 0, 1.0)).norm(), 1e-14);
    EXPECT_LT((s.force[1].angular - (-7.0 * angle) * Vec3(0, 0.6, 0.8)).norm(), 1e-13);
    EXPECT_EQ(s.force[0].angular, Vec3::Zero());  // at rest: no torque (and no NaN)
    EXPECT_NEAR(ff.potential_energy(), 0.5 * 5 * 0.05 + 0.5 * 7 * angle * angle, 1e-13);
    // an inactive rotation direction removes that component of the axis
    ff.set_active_directions({true, true, true, true, false, true});
    s.force.assign(2, RigidDeriv{});
    ff.add_force(s.force, s.position, s.velocity);
    EXPECT_LT((s.force[1].angular - (-7.0 * angle) * Vec3(0, 0, 0.8)).norm(), 1e-13);
}

TEST(RestShapeSprings, TheRigidStiffnessIsTheTorquesDerivativeAtRest) {
    // K's angular block −ka·I is the derivative of −ka θ u at θ = 0 (SOFA's approximation away from it)
    Rigid3Object s;
    s.position.resize(1);
    s.init();
    RestShapeSpringsForceField<Rigid3Types> ff(s);
    ff.set_stiffness({3.0});
    ff.set_angular_stiffness({11.0});
    ff.init();
    const Eigen::MatrixXd k = rest_spring_matrix(ff, 6);
    const double h = 1e-6;
    for (int c = 0; c < 3; ++c) {
        RigidDeriv w;
        w.angular[c] = 1.0;
        std::array<Vec3, 2> torques;
        for (int side = 0; side < 2; ++side) {
            s.position[0] = rigid_add(RigidFrame{}, w, side == 0 ? h : -h);
            s.force.assign(1, RigidDeriv{});
            ff.add_force(s.force, s.position, s.velocity);
            torques[std::size_t(side)] = s.force[0].angular;
        }
        const Vec3 fd = (torques[0] - torques[1]) / (2 * h);
        for (int r = 0; r < 3; ++r) EXPECT_NEAR(fd[r], k(3 + r, 3 + c), 1e-6) << r << " " << c;
    }
    // add_dforce is the same matrix
    s.dx.assign(1, RigidDeriv{});
    s.df.assign(1, RigidDeriv{});
    s.dx[0].angular = Vec3(1, 2, 3);
    s.dx[0].linear = Vec3(-1, 0.5, 2);
    ff.add_dforce(s.df, s.dx, 1.0, 0.0);
    EXPECT_EQ(s.df[0].angular, Vec3(-11, -22, -33));
    EXPECT_EQ(s.df[0].linear, Vec3(3, -1.5, -6));
}

TEST(RestShapeSprings, AnExternalRestShapeAnchorsToItsCurrentPositions) {
    Vec3Object s = displaced_points();
    Vec3Object anchors = state_at({Vec3(5, 5, 5), Vec3(6, 6, 6)});
    RestShapeSpringsForceField<Vec3Types> ff(s);
    ff.set_points({2, 3});
    ff.set_stiffness({2.0});
    ff.set_external_rest_shape(&anchors, {1, 0});
    ff.init();
    anchors.position[1] = Vec3(1, 1, 1);  // the anchors move: the springs follow
    s.force.assign(4, Vec3::Zero());
    ff.add_force(s.force, s.position, s.velocity);
    EXPECT_LT((s.force[2] - (-2.0) * (s.position[2] - Vec3(1, 1, 1))).norm(), 1e-14);
    EXPECT_LT((s.force[3] - (-2.0) * (s.position[3] - Vec3(5, 5, 5))).norm(), 1e-14);
    std::vector<const BaseState*> read;
    ff.list_read_states(read);
    ASSERT_EQ(read.size(), 1u);
    EXPECT_EQ(read[0], &anchors);
    ff.set_external_rest_shape(&anchors, {});  // all external points: 2 anchors for 2 points
    EXPECT_NO_THROW(ff.init());
    ff.set_external_rest_shape(&anchors, {0});
    EXPECT_THROW(ff.init(), std::invalid_argument);  // 2 points, 1 anchor
    ff.set_external_rest_shape(&anchors, {0, 2});
    EXPECT_THROW(ff.init(), std::invalid_argument);  // out of the external state
}

TEST(RestShapeSprings, BadValuesAreRefused) {
    Vec3Object s = displaced_points();
    RestShapeSpringsForceField<Vec3Types> ff(s);
    EXPECT_THROW(ff.set_stiffness({1.0, -2.0}), std::invalid_argument);
    EXPECT_THROW(ff.set_stiffness({std::nan("")}), std::invalid_argument);
    ff.set_points({0, 4});
    EXPECT_THROW(ff.init(), std::invalid_argument);
}

/// add_force onto zero and add_dforce onto a fixed df of a field in an arena of `threads`:
/// the force, the energy and the product.
template <class DataTypes, class Deriv = typename DataTypes::Deriv>
struct SpringsRun {
    std::vector<Deriv> force, product;
    double energy = 0.0;
};
template <class DataTypes>
SpringsRun<DataTypes> run_springs(RestShapeSpringsForceField<DataTypes>& ff, MechanicalObject<DataTypes>& s,
                                  const std::vector<typename DataTypes::Deriv>& dx, int threads) {
    SpringsRun<DataTypes> out;
    tbb::task_arena(threads).execute([&] {
        if constexpr (std::is_same_v<DataTypes, Vec3Types>) out.force.assign(s.num_dofs(), Vec3::Zero());
        else out.force.assign(s.num_dofs(), RigidDeriv{});  // (zero: its members are)
        ff.add_force(out.force, s.position, s.velocity);
        out.energy = ff.potential_energy();
        out.product = dx;  // (any df: the product adds into it)
        ff.add_dforce(out.product, dx, -0.37, 0.0);
    });
    return out;
}
template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// 20 000 springs on points listed in a shuffled order, each its own stiffness, some directions
// off: on 2 and 8 threads (ranges of springs) the force, energy and product are one thread's
// bits; a point listed twice keeps the loop on one thread, with the same sums as before.
TEST(RestShapeSprings, ALargeFieldOnThreadsGivesTheBitsOfOneThread) {
    constexpr std::size_t n = 20'000;
    std::mt19937 random(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Index> points(n);
    std::iota(points.begin(), points.end(), Index{0});
    std::shuffle(points.begin(), points.end(), random);
    std::vector<double> stiffness(n);
    for (double& k : stiffness) k = 50.0 + 40.0 * u(random);
    {
        Vec3Object s;
        s.position.resize(n);
        for (Vec3& x : s.position) x = Vec3(u(random), u(random), u(random));
        s.init();
        for (Vec3& x : s.position) x += 0.05 * Vec3(u(random), u(random), u(random));
        std::vector<Vec3> dx(n);
        for (Vec3& d : dx) d = Vec3(u(random), u(random), u(random));
        for (const bool repeated : {false, true}) {
            std::vector<Index> listed = points;
            if (repeated) listed[n / 2] = listed[7];  // point listed[7] twice
            RestShapeSpringsForceField<Vec3Types> ff(s);
            ff.set_points(listed);
            ff.set_stiffness(stiffness);
            ff.set_active_directions({true, false, true});
            ff.init();
            const auto one = run_springs(ff, s, dx, 1);
            EXPECT_GT(one.energy, 0.0);
            EXPECT_EQ(one.force[static_cast<std::size_t>(points[1])][1], 0.0);  // y is off
            for (const int threads : {2, 8}) {
                const auto many = run_springs(ff, s, dx, threads);
                EXPECT_TRUE(same_bits(many.force, one.force)) << threads << " threads, repeated " << repeated;
                EXPECT_TRUE(same_bits(many.product, one.product)) << threads << " threads, repeated " << repeated;
                EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << threads << " threads";
            }
            if (repeated) {  // the twice-listed point gets both springs: twice the force in x
                const auto p = static_cast<std::size_t>(listed[7]);
                const double k7 = stiffness[7], kr = stiffness[n / 2];
                EXPECT_NEAR(one.force[p][0], -(k7 + kr) * (s.position[p][0] - s.rest_position[p][0]), 1e-9);
            }
        }
    }
    {
        Rigid3Object s;
        s.position.resize(n);
        for (auto& x : s.position) x.center = Vec3(u(random), u(random), u(random));
        s.init();
        s.rest_position = s.position;
        for (auto& x : s.position) {
            x.center += 0.05 * Vec3(u(random), u(random), u(random));
            x.orientation = Quat(Eigen::AngleAxisd(0.5 * u(random), Vec3(u(random), u(random), 1.0).normalized()));
        }
        std::vector<RigidDeriv> dx(n);
        for (auto& d : dx) {
            d.linear = Vec3(u(random), u(random), u(random));
            d.angular = Vec3(u(random), u(random), u(random));
        }
        RestShapeSpringsForceField<Rigid3Types> ff(s);
        ff.set_points(points);
        ff.set_stiffness(stiffness);
        ff.set_angular_stiffness(stiffness);
        ff.init();
        const auto one = run_springs(ff, s, dx, 1);
        EXPECT_GT(one.energy, 0.0);
        for (const int threads : {2, 8}) {
            const auto many = run_springs(ff, s, dx, threads);
            EXPECT_TRUE(same_bits(many.force, one.force)) << threads << " threads";
            EXPECT_TRUE(same_bits(many.product, one.product)) << threads << " threads";
            EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << threads << " threads";
        }
    }
}

}  // namespace
}  // namespace penalty
