// The generic topology followers (followers.cpp): RebuildFollower (a rebuild once per change that
// touched its types), SubsetIndicesFollower (SOFA's TopologySubsetIndices over the points),
// SpringPointsFollower (SOFA HEAD's SpringForceField applyRemovedPoints / applyRemovedEdges) and
// SOFA's TriangularBendingSprings and QuadularBendingSprings edge data (a spring across each edge
// shared by two faces, made when the edge first has two, dropped with a face, following the points).
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/mechanics/topology_container.hpp"
#include "penalty/mechanics/topology_followers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace penalty {
namespace {

TopologyChange follower_change(TopologyChangeKind kind, ElementType element, std::vector<ElementId> indices) {
    TopologyChange c;
    c.kind = kind;
    c.element = element;
    c.indices = std::move(indices);
    return c;
}

std::vector<std::array<Index, 2>> follower_ends(const std::vector<Spring>& springs) {
    std::vector<std::array<Index, 2>> out;
    for (const Spring& s : springs) out.push_back({s.a, s.b});
    return out;
}

TEST(Followers, RebuildOnceAfterAChangeOfItsTypes) {
    int rebuilds = 0;
    RebuildFollower f([&] { ++rebuilds; }, {ElementType::triangle, ElementType::edge});
    const std::vector<TopologyChange> others{follower_change(TopologyChangeKind::removed, ElementType::point, {0}),
                                             follower_change(TopologyChangeKind::ending, ElementType::triangle, {})};
    f.handle_topology_changes(others);
    f.topology_change_done();
    EXPECT_EQ(rebuilds, 0);  // a point change and an ending event are not its
    const std::vector<TopologyChange> mine{follower_change(TopologyChangeKind::added, ElementType::triangle, {3}),
                                           follower_change(TopologyChangeKind::removed, ElementType::edge, {1})};
    f.handle_topology_changes(mine);
    f.handle_topology_changes(mine);
    f.topology_change_done();
    EXPECT_EQ(rebuilds, 1);
    f.topology_change_done();
    EXPECT_EQ(rebuilds, 1);
}

/// The path 0-1-2-3-4 (five points) as an edge container.
struct FollowedPath {
    MeshTopology mesh;
    std::unique_ptr<TopologyContainer> container;
    FollowedPath() {
        mesh.set_edges({{0, 1}, {1, 2}, {2, 3}, {3, 4}});
        container = std::make_unique<TopologyContainer>(mesh, ElementType::edge, "path");
    }
};

TEST(Followers, SubsetIndicesEraseRemovedPointsAndRenameTheLast) {
    FollowedPath p;
    std::vector<Index> subset{0, 4, 2, 0};
    SubsetIndicesFollower f(
        *p.container, [&] { return subset; }, [&](std::vector<Index> v) { subset = std::move(v); });
    // PointsRemoved {0} of 5: both 0s erased, 4 (the last point) takes index 0
    const std::vector<TopologyChange> removed{follower_change(TopologyChangeKind::removed, ElementType::point, {0})};
    f.handle_topology_changes(removed);
    EXPECT_EQ(subset, (std::vector<Index>{0, 2}));
    // renumbered: entry i takes the entry at index[i]
    const std::vector<TopologyChange> renumbered{
        follower_change(TopologyChangeKind::renumbered, ElementType::point, {1, 0})};
    f.handle_topology_changes(renumbered);
    EXPECT_EQ(subset, (std::vector<Index>{2, 0}));
    // edges and added points change nothing
    const std::vector<TopologyChange> others{follower_change(TopologyChangeKind::removed, ElementType::edge, {0}),
                                             follower_change(TopologyChangeKind::added, ElementType::point, {5})};
    f.handle_topology_changes(others);
    EXPECT_EQ(subset, (std::vector<Index>{2, 0}));
}

TEST(Followers, SpringsOnARemovedPointLeaveAndTheLastPointsTakeItsIndex) {
    FollowedPath p;
    Vec3Object state;
    state.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0), Vec3(4, 0, 0)};
    state.init();
    SpringForceField springs(state);
    springs.add_spring({.a = 0, .b = 1, .ks = 10, .kd = 1, .rest_length = 1});
    springs.add_spring({.a = 1, .b = 4, .ks = 20, .kd = 2, .rest_length = 3});
    springs.add_spring({.a = 4, .b = 2, .ks = 30, .kd = 3, .rest_length = 2});
    springs.add_spring({.a = 3, .b = 4, .ks = 40, .kd = 4, .rest_length = 1});
    springs.init();
    SpringPointsFollower f(springs, *p.container);
    const std::vector<TopologyChange> removed{follower_change(TopologyChangeKind::removed, ElementType::point, {1})};
    f.handle_topology_changes(removed);
    EXPECT_EQ(springs.springs().size(), 4U);  // written back once the change is done
    f.topology_change_done();
    // first ends: (1,4) leaves, (4,2) becomes (1,2); second ends: (0,1) leaves, (3,4) becomes (3,1)
    EXPECT_EQ(follower_ends(springs.springs()), (std::vector<std::array<Index, 2>>{{1, 2}, {3, 1}}));
    EXPECT_EQ(springs.springs()[0].ks, 30.0);
    EXPECT_EQ(springs.springs()[1].rest_length, 1.0);
}

TEST(Followers, ARemovedEdgeTakesTheFirstSpringAlongItPerEnd) {
    FollowedPath p;
    Vec3Object state;
    state.position.assign(5, Vec3::Zero());
    state.init();
    SpringForceField springs(state);
    for (const auto& [a, b] : std::vector<std::pair<Index, Index>>{{0, 1}, {1, 0}, {0, 1}, {2, 3}})
        springs.add_spring({.a = a, .b = b, .ks = 1, .kd = 0, .rest_length = 1});
    springs.init();
    SpringPointsFollower f(springs, *p.container);
    const std::vector<TopologyChange> removed{follower_change(TopologyChangeKind::removed, ElementType::edge, {0})};
    f.handle_topology_changes(removed);
    f.topology_change_done();
    // the first (0 → 1) from the first ends, the first (1 → 0) from the second ends
    EXPECT_EQ(follower_ends(springs.springs()), (std::vector<std::array<Index, 2>>{{0, 1}, {2, 3}}));
}

/// The unit square as triangles (0,1,2), (0,2,3), the bending follower on its container.
struct BentSquare {
    MeshTopology mesh;
    Vec3Object state;
    std::unique_ptr<TopologyContainer> container;
    std::unique_ptr<SpringForceField> springs;
    std::unique_ptr<TriangularBendingSpringsFollower> follower;
    BentSquare() {
        mesh.set_triangles({{0, 1, 2}, {0, 2, 3}});
        state.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
        state.init();
        container = std::make_unique<TopologyContainer>(mesh, ElementType::triangle, "square");
        springs = std::make_unique<SpringForceField>(state);
        follower = std::make_unique<TriangularBendingSpringsFollower>(*springs, *container, state, 100, 0.5);
        container->add_handler(*follower, {ElementType::edge, ElementType::point, ElementType::triangle});
    }
};

TEST(Followers, TriangularBendingSpringsCrossTheSharedEdgeAndFollowItsTriangles) {
    BentSquare s;
    // the diagonal (0,2), first met by triangle 0 (reinit: every triangle in order, both there):
    // m1 opposite it in the other triangle (3), m2 in triangle 0 (1)
    const std::vector<Spring> initial = s.follower->springs();
    ASSERT_EQ(initial.size(), 1U);
    EXPECT_EQ(initial[0].a, 3);
    EXPECT_EQ(initial[0].b, 1);
    EXPECT_EQ(initial[0].ks, 100.0);
    EXPECT_EQ(initial[0].kd, 0.5);
    EXPECT_EQ(initial[0].rest_length, std::sqrt(2.0));
    s.container->remove_triangles({1});  // point 3 isolated, removed
    EXPECT_TRUE(s.follower->springs().empty());
    EXPECT_TRUE(s.springs->springs().empty());
    s.container->add_points(1);
    s.container->add_triangles({{0, 2, 3}});
    ASSERT_EQ(s.springs->springs().size(), 1U);  // the edge has two triangles again: m1 the old one's
    EXPECT_EQ(follower_ends(s.springs->springs()), (std::vector<std::array<Index, 2>>{{1, 3}}));
}

TEST(Followers, TriangularBendingSpringsFollowThePointsRenumbering) {
    BentSquare s;
    const std::vector<TopologyChange> renumbered{
        follower_change(TopologyChangeKind::renumbered, ElementType::point, {0, 3, 2, 1})};
    s.follower->handle_topology_changes(renumbered);
    s.follower->topology_change_done();
    EXPECT_EQ(follower_ends(s.springs->springs()), (std::vector<std::array<Index, 2>>{{1, 3}}));
}

// The fan (0,1,2), (0,2,3), (0,3,4): springs across (0,2) (3 → 1) and (0,3) (4 → 2). Removing the
// first triangle drops the first spring and point 1 (isolated); the last point, 4, takes index 1.
TEST(Followers, TriangularBendingSpringsFollowARemovedPoint) {
    MeshTopology mesh;
    mesh.set_triangles({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}});
    Vec3Object state;
    state.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(-1, 1, 0)};
    state.init();
    TopologyContainer container(mesh, ElementType::triangle, "fan");
    SpringForceField springs(state);
    TriangularBendingSpringsFollower follower(springs, container, state, 1, 0);
    container.add_handler(follower, {ElementType::edge, ElementType::point, ElementType::triangle});
    EXPECT_EQ(follower_ends(follower.springs()), (std::vector<std::array<Index, 2>>{{3, 1}, {4, 2}}));
    container.remove_triangles({0});
    EXPECT_EQ(container.num_points(), 4U);
    EXPECT_EQ(follower_ends(springs.springs()), (std::vector<std::array<Index, 2>>{{1, 2}}));
    EXPECT_EQ(springs.springs()[0].rest_length, 2.0);  // |x4 − x2| at the rest positions
}

TEST(Followers, QuadularBendingSpringsCrossTheSharedEdgeTwice) {
    MeshTopology mesh;
    mesh.set_quads({{0, 1, 2, 3}, {1, 4, 5, 2}});
    Vec3Object state;
    state.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(2, 1, 0)};
    state.init();
    TopologyContainer container(mesh, ElementType::quad, "strip");
    SpringForceField springs(state);
    QuadularBendingSpringsFollower follower(springs, container, state, 7, 0.25);
    container.add_handler(follower, {ElementType::edge, ElementType::point, ElementType::quad});
    // edge (1,2), first met by quad 0: t1 the other quad (1,4,5,2), the edge at i1 = 2 there, t2
    // quad 0 (i2 = 0): (t1[i1], t2[i2+3]) = (5, 3) and (t1[i1+3], t2[i2]) = (4, 0), both 2 long
    const std::vector<Spring> initial = follower.springs();
    EXPECT_EQ(follower_ends(initial), (std::vector<std::array<Index, 2>>{{5, 3}, {4, 0}}));
    for (const Spring& sp : initial) {
        EXPECT_EQ(sp.rest_length, 2.0);
        EXPECT_EQ(sp.ks, 7.0);
        EXPECT_EQ(sp.kd, 0.25);
    }
    // the first quad goes with points 0 and 3: the last points (5, 4) take their indices
    container.remove_quads({0});
    EXPECT_TRUE(springs.springs().empty());
    EXPECT_EQ(container.num_points(), 4U);
}

// Three quads in a strip: the springs across (4,5), between the second and third, are (7, 2) and
// (6, 1). Removing the first quad removes points 3 then 0 (decreasing): the last points, 7 then 6,
// take their indices.
TEST(Followers, QuadularBendingSpringsFollowRemovedPoints) {
    MeshTopology mesh;
    mesh.set_quads({{0, 1, 2, 3}, {1, 4, 5, 2}, {4, 6, 7, 5}});
    Vec3Object state;
    state.position.assign(8, Vec3::Zero());
    state.init();
    TopologyContainer container(mesh, ElementType::quad, "strip");
    SpringForceField springs(state);
    QuadularBendingSpringsFollower follower(springs, container, state, 1, 0);
    container.add_handler(follower, {ElementType::edge, ElementType::point, ElementType::quad});
    EXPECT_EQ(follower_ends(follower.springs()), (std::vector<std::array<Index, 2>>{{5, 3}, {4, 0}, {7, 2}, {6, 1}}));
    container.remove_quads({0});
    EXPECT_EQ(container.num_points(), 6U);
    EXPECT_EQ(follower_ends(springs.springs()), (std::vector<std::array<Index, 2>>{{3, 2}, {0, 1}}));
}

}  // namespace
}  // namespace penalty
