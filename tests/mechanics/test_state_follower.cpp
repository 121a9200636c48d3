// A state following its topology's point changes (state_follower.cpp, SOFA's MechanicalObject::
// handleStateChange): every vector grown by the added points' weighted values (a Rigid3 frame's
// orientation the normalised weighted sum of its ancestors' quaternions), a point placed in a
// triangle off its plane along the unit normal, removals by swap-and-pop leaving an unset vector
// alone, renumbering, moves, and the refusals naming the state.
#include "penalty/mechanics/state_topology.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace penalty {
namespace {

TopologyChange point_change(TopologyChangeKind kind, std::vector<ElementId> indices,
                            std::vector<std::vector<ElementId>> ancestors = {},
                            std::vector<std::vector<double>> coefficients = {}) {
    TopologyChange c;
    c.kind = kind;
    c.element = ElementType::point;
    c.indices = std::move(indices);
    c.ancestors = std::move(ancestors);
    c.coefficients = std::move(coefficients);
    return c;
}

TEST(StateFollower, ARigidFramesOrientationIsTheNormalisedWeightedQuaternion) {
    // frames at (0,0,0), unrotated, and (2,0,0), turned by 90° about z: halfway, (1,0,0) turned
    // by 45° (q₀ + q₁ normalised); its velocity the mean of theirs
    Rigid3Object frames;
    frames.position = {RigidFrame{Vec3(0, 0, 0), Quat::Identity()},
                       RigidFrame{Vec3(2, 0, 0), Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()))}};
    frames.init();
    frames.velocity[0].linear = Vec3(1, 0, 0);
    frames.velocity[1].angular = Vec3(0, 0, 4);
    StateTopologyFollower<Rigid3Types> follower(frames);
    follower.handle_state_change(point_change(TopologyChangeKind::added, {2}, {{0, 1}}, {{0.5, 0.5}}));
    ASSERT_EQ(frames.position.size(), 3u);
    EXPECT_EQ(frames.position[2].center, Vec3(1, 0, 0));
    const Quat expected(Eigen::AngleAxisd(std::numbers::pi / 4, Vec3::UnitZ()));
    EXPECT_NEAR((frames.position[2].orientation.coeffs() - expected.coeffs()).norm(), 0.0, 1e-15);
    EXPECT_EQ(frames.velocity[2].linear, Vec3(0.5, 0, 0));
    EXPECT_EQ(frames.velocity[2].angular, Vec3(0, 0, 2));
    EXPECT_EQ(frames.rest_position.size(), 3u);
    EXPECT_EQ(frames.dx.size(), 3u);
}

TEST(StateFollower, WithoutCoefficientsTheAncestorsWeighAlike) {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(0, 6, 0)};
    s.init();
    StateTopologyFollower<Vec3Types> follower(s);
    follower.handle_state_change(point_change(TopologyChangeKind::added, {3}, {{0, 1, 2}}));
    EXPECT_EQ(s.position[3], Vec3(1, 2, 0));
}

TEST(StateFollower, APointInATriangleIsPlacedOffItsPlaneAlongTheUnitNormal) {
    // SOFA's initPointAdded: p0 + (p1 − p0)·l0 + (p2 − p0)·l1 + n·l2, n = (p1 − p0) × (p2 − p0) / |…|
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 2, 0)};
    s.init();
    StateTopologyFollower<Vec3Types> follower(s);
    TopologyChange c = point_change(TopologyChangeKind::added, {3}, {{0, 1, 2}}, {{0.25, 0.5, 0.25}});
    c.ancestor_elements = {PointAncestorElement{ElementType::triangle, {0, 1, 2}, {0.5, 0.25, 0.75}}};
    follower.handle_state_change(c);
    EXPECT_EQ(s.position[3], Vec3(2, 0.5, 0.75));
    EXPECT_EQ(s.rest_position[3], Vec3(2, 0.5, 0.75));
}

TEST(StateFollower, RemovalsSwapThePastPointsInAndLeaveAnUnsetVectorAlone) {
    Vec3Object s;
    for (int i = 0; i < 5; ++i) s.position.emplace_back(i, 0, 0);
    s.init();
    s.external_force.clear();  // unset: another size, left alone
    for (int i = 0; i < 5; ++i) s.velocity[std::size_t(i)] = Vec3(0, i, 0);
    StateTopologyFollower<Vec3Types> follower(s);
    // SOFA's order: the indices as given; 3 takes 4, then 0 takes 3 (the new last)
    follower.handle_state_change(point_change(TopologyChangeKind::removed, {3, 0}));
    ASSERT_EQ(s.position.size(), 3u);
    EXPECT_EQ(s.position, (std::vector<Vec3>{Vec3(4, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)}));
    EXPECT_EQ(s.velocity[0], Vec3(0, 4, 0));
    EXPECT_EQ(s.dx.size(), 3u);
    EXPECT_TRUE(s.external_force.empty());
    // renumbered: new point k is old point indices[k]
    follower.handle_state_change(point_change(TopologyChangeKind::renumbered, {2, 0, 1}));
    EXPECT_EQ(s.position, (std::vector<Vec3>{Vec3(2, 0, 0), Vec3(4, 0, 0), Vec3(1, 0, 0)}));
    // moved: point 1 to the weighted value of points 0 and 2
    follower.handle_state_change(point_change(TopologyChangeKind::moved, {1}, {{0, 2}}, {{0.5, 0.5}}));
    EXPECT_EQ(s.position[1], Vec3(1.5, 0, 0));
}

TEST(StateFollower, PointsOutsideTheStateAreRefusedNamingIt) {
    Vec3Object s("cloth");
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
    s.init();
    StateTopologyFollower<Vec3Types> follower(s);
    const auto message = [&](const TopologyChange& c) {
        try {
            follower.handle_state_change(c);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(message(point_change(TopologyChangeKind::removed, {5})), "state 'cloth': cannot remove point 5 of 3");
    EXPECT_EQ(message(point_change(TopologyChangeKind::moved, {-1}, {{0}}, {{1.0}})),
              "state 'cloth': cannot move point -1 of 3");
    EXPECT_EQ(s.position.size(), 3u);
    // a change of another element type is not the state's
    follower.handle_state_change([] {
        TopologyChange c;
        c.kind = TopologyChangeKind::removed;
        c.element = ElementType::edge;
        c.indices = {0};
        return c;
    }());
    EXPECT_EQ(s.position.size(), 3u);
}

}  // namespace
}  // namespace penalty
