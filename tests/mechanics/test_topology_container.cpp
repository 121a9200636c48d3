// TopologyContainer: SOFA's swap-and-pop removals, isolated items, additions, the event lists and
// their order, element by element against hand-derived expectations (SOFA's
// ...SetTopologyModifier::remove...Process / add...Process), and the cross tables' consistency
// over random removals.
#include "penalty/mechanics/state_topology.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <stdexcept>
#include <string>

namespace penalty {
namespace {

using Ids = std::vector<ElementId>;

/// What a handler or listener saw: one string per event, "<tag>:<kind> <type> <indices>".
struct TcRecorder final : TopologyHandler, StateFollower {
    std::string tag;
    std::vector<std::string>* log;
    TcRecorder(std::string t, std::vector<std::string>& l) : tag(std::move(t)), log(&l) {}
    static std::string text(const TopologyChange& c) {
        static const char* kKind[] = {"added", "removed", "renumbered", "ending"};
        std::string s = kKind[int(c.kind)];
        if (c.kind == TopologyChangeKind::ending) return s;
        s += ' ';
        s += element_type_name(c.element);
        for (const ElementId i : c.indices) {
            s += ' ';
            s += std::to_string(i);
        }
        return s;
    }
    void handle_topology_changes(std::span<const TopologyChange> changes) override {
        for (const auto& c : changes) log->push_back(tag + ":" + text(c));
    }
    void handle_state_change(const TopologyChange& c) override { log->push_back(tag + ":" + text(c)); }
};

/// Every cross table agrees with the element lists (each shell holds exactly the elements using
/// the vertex, edge or face; each element's edges and faces have its vertices).
void tc_expect_consistent(const TopologyContainer& c) {
    const MeshTopology& m = c.mesh();
    const std::size_t n = m.num_points();
    auto check_around = [&](const auto& elements, const std::vector<std::vector<std::int32_t>>& around,
                            const char* what) {
        ASSERT_EQ(around.size(), n) << what;
        std::vector<std::multiset<std::int32_t>> expected(n);
        for (std::size_t e = 0; e < elements.size(); ++e)
            for (const PointId p : elements[e]) {
                ASSERT_LT(std::size_t(p), n) << what << " " << e;
                expected[std::size_t(p)].insert(std::int32_t(e));
            }
        for (std::size_t v = 0; v < n; ++v)
            EXPECT_EQ(std::multiset<std::int32_t>(around[v].begin(), around[v].end()), expected[v])
                << what << " vertex " << v;
    };
    check_around(m.edges(), m.edges_around_vertex(), "edges");
    check_around(m.triangles(), m.triangles_around_vertex(), "triangles");
    check_around(m.tetrahedra(), m.tetrahedra_around_vertex(), "tetrahedra");
    auto same_edge = [&](ElementId e, PointId a, PointId b) {
        const Edge& x = m.edges()[std::size_t(e)];
        return (x[0] == a && x[1] == b) || (x[0] == b && x[1] == a);
    };
    ASSERT_EQ(m.edges_in_triangle().size(), m.triangles().size());
    for (std::size_t t = 0; t < m.triangles().size(); ++t)
        for (std::size_t j = 0; j < 3; ++j) {
            const Triangle& tri = m.triangles()[t];
            const ElementId e = m.edges_in_triangle()[t][j];
            EXPECT_TRUE(same_edge(e, tri[(j + 1) % 3], tri[(j + 2) % 3])) << "triangle " << t << " edge " << j;
            const auto& s = m.triangles_around_edge()[std::size_t(e)];
            EXPECT_EQ(std::count(s.begin(), s.end(), std::int32_t(t)), 1);
        }
    ASSERT_EQ(m.triangles_around_edge().size(), m.edges().size());
    for (std::size_t e = 0; e < m.edges().size(); ++e)
        for (const auto t : m.triangles_around_edge()[e]) {
            const auto& eit = m.edges_in_triangle()[std::size_t(t)];
            EXPECT_NE(std::find(eit.begin(), eit.end(), std::int32_t(e)), eit.end());
        }
    if (c.level() != ElementType::tetrahedron) return;
    ASSERT_EQ(c.tetrahedra_around_edge().size(), m.edges().size());
    ASSERT_EQ(c.tetrahedra_around_triangle().size(), m.triangles().size());
    for (std::size_t t = 0; t < m.tetrahedra().size(); ++t) {
        const Tetrahedron& tet = m.tetrahedra()[t];
        for (std::size_t j = 0; j < 6; ++j) {
            const ElementId e = c.edges_in_tetrahedron()[t][j];
            const auto& le = MeshTopology::kTetraEdges[j];
            EXPECT_TRUE(same_edge(e, tet[std::size_t(le[0])], tet[std::size_t(le[1])]));
            const auto& s = c.tetrahedra_around_edge()[std::size_t(e)];
            EXPECT_EQ(std::count(s.begin(), s.end(), ElementId(t)), 1);
        }
        for (std::size_t j = 0; j < 4; ++j) {
            const ElementId f = c.triangles_in_tetrahedron()[t][j];
            Triangle face = m.triangles()[std::size_t(f)];
            const auto& lf = MeshTopology::kTetraFaces[j];
            Triangle want{tet[std::size_t(lf[0])], tet[std::size_t(lf[1])], tet[std::size_t(lf[2])]};
            std::sort(face.begin(), face.end());
            std::sort(want.begin(), want.end());
            EXPECT_EQ(face, want);
            const auto& s = c.tetrahedra_around_triangle()[std::size_t(f)];
            EXPECT_EQ(std::count(s.begin(), s.end(), ElementId(t)), 1);
        }
    }
    // every face and edge is used (the container's own removals leave none isolated)
    for (std::size_t f = 0; f < m.triangles().size(); ++f) EXPECT_FALSE(c.tetrahedra_around_triangle()[f].empty()) << f;
    for (std::size_t e = 0; e < m.edges().size(); ++e) EXPECT_FALSE(c.tetrahedra_around_edge()[e].empty()) << e;
}

TEST(TopologyContainer, RemovingATriangleSwapsTheLastInAndRemovesItsIsolatedEdgesAndPoint) {
    MeshTopology mesh;
    mesh.set_triangles({{0, 1, 2}, {1, 3, 2}});
    // derived edges (first occurrence, triangle orientation): (1,2) (2,0) (0,1) (3,2) (1,3)
    ASSERT_EQ(mesh.edges(), (std::vector<Edge>{{1, 2}, {2, 0}, {0, 1}, {3, 2}, {1, 3}}));
    TopologyContainer c(mesh, ElementType::triangle, "surface");
    std::vector<std::string> log;
    TcRecorder handler("h", log), listener("l", log), state("s", log);
    c.add_handler(handler, {ElementType::triangle, ElementType::point});
    c.add_listener(listener);
    c.add_state_follower(state);
    const auto revision = mesh.revision();

    c.remove_triangles({0});

    // triangle 1 moved into slot 0; edges (0,1) and (2,0) lost their only triangle (removed in
    // decreasing order: edge 2 takes the last edge (1,3), then edge 1 takes (3,2)); point 0 lost its
    // only triangle and takes point 3.
    EXPECT_EQ(mesh.num_points(), 3u);
    EXPECT_EQ(mesh.triangles(), (std::vector<Triangle>{{1, 0, 2}}));
    EXPECT_EQ(mesh.edges(), (std::vector<Edge>{{1, 2}, {0, 2}, {1, 0}}));
    EXPECT_EQ(mesh.edges_in_triangle()[0], (std::array<std::int32_t, 3>{1, 0, 2}));
    EXPECT_EQ(mesh.edges_around_vertex()[0], (Ids{1, 2}));
    EXPECT_EQ(mesh.edges_around_vertex()[1], (Ids{0, 2}));
    EXPECT_EQ(mesh.edges_around_vertex()[2], (Ids{0, 1}));
    EXPECT_EQ(mesh.vertices_around_vertex()[0], (std::vector<PointId>{2, 1}));
    EXPECT_GT(mesh.revision(), revision);
    tc_expect_consistent(c);
    // Three propagations: triangles (handler on its triangle phase), edges (not registered: only
    // the listener), points (handler on its point phase, then the listener, then the state).
    EXPECT_EQ(log, (std::vector<std::string>{"h:removed triangles 0", "h:ending", "l:removed triangles 0", "l:ending",
                                             "l:removed edges 2 1", "l:ending", "h:removed points 0", "h:ending",
                                             "l:removed points 0", "l:ending", "s:removed points 0"}));
}

TEST(TopologyContainer, RemovingOneOfTwoTetrahedraRemovesItsOwnFacesEdgesAndApex) {
    MeshTopology mesh;
    mesh.set_tetrahedra({{0, 1, 2, 3}, {1, 2, 3, 4}});
    ASSERT_EQ(mesh.triangles().size(), 7u);
    ASSERT_EQ(mesh.edges().size(), 9u);
    TopologyContainer c(mesh, ElementType::tetrahedron, "volume");
    tc_expect_consistent(c);
    std::vector<std::string> log;
    TcRecorder listener("l", log);
    c.add_listener(listener);

    c.remove_tetrahedra({0});

    EXPECT_EQ(mesh.tetrahedra(), (std::vector<Tetrahedron>{{1, 2, 3, 0}}));  // point 4 took point 0's slot
    EXPECT_EQ(mesh.num_points(), 4u);
    EXPECT_EQ(mesh.triangles().size(), 4u);
    EXPECT_EQ(mesh.edges().size(), 6u);
    tc_expect_consistent(c);
    // one propagation for the tetrahedron, one for its 3 own faces and 3 own edges, one for point 0
    ASSERT_EQ(log.size(), 7u);
    EXPECT_EQ(log[0], "l:removed tetrahedra 0");
    EXPECT_EQ(log[2].rfind("l:removed triangles", 0), 0u);
    EXPECT_EQ(log[3].rfind("l:removed edges", 0), 0u);
    EXPECT_EQ(log[5], "l:removed points 0");
}

TEST(TopologyContainer, RemovalChecksEveryIndexBeforeChangingAnything) {
    MeshTopology mesh;
    mesh.set_tetrahedra({{0, 1, 2, 3}, {1, 2, 3, 4}});
    TopologyContainer c(mesh, ElementType::tetrahedron, "volume");
    EXPECT_THROW(c.remove_tetrahedra({1, 2}), std::invalid_argument);
    EXPECT_THROW(c.remove_tetrahedra({1, 1}), std::invalid_argument);
    EXPECT_THROW(c.remove_tetrahedra({-1}), std::invalid_argument);
    EXPECT_THROW(c.remove_quads({0}), std::invalid_argument);  // a tetrahedron container has no quads
    EXPECT_EQ(mesh.tetrahedra().size(), 2u);
    EXPECT_EQ(mesh.revision(), 0u);
    try {
        c.remove_tetrahedra({0, 7});
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("tetrahedra 7"), std::string::npos) << e.what();
    }
}

TEST(TopologyContainer, AddingATetrahedronCreatesItsFacesAndEdgesEachWithItsEventFirst) {
    MeshTopology mesh;
    mesh.set_tetrahedra({{0, 1, 2, 3}});
    mesh.set_num_points(5);
    TopologyContainer c(mesh, ElementType::tetrahedron, "volume");
    std::vector<std::string> log;
    TcRecorder handler("h", log);
    c.add_handler(handler, {ElementType::tetrahedron});
    c.add_tetrahedra({{1, 2, 3, 4}});
    EXPECT_EQ(mesh.tetrahedra().size(), 2u);
    EXPECT_EQ(mesh.triangles().size(), 7u);
    EXPECT_EQ(mesh.edges().size(), 9u);
    tc_expect_consistent(c);
    // face 0 (2,3,4) of the new tetrahedron first: its edges (3,4), (4,2) then the face; face 1
    // (1,4,3): edge (1,4) then the face; face 2 (2,4,1) (face 3 (1,3,2) exists); the tetrahedron.
    EXPECT_EQ(log, (std::vector<std::string>{"h:added edges 6", "h:added edges 7", "h:added triangles 4",
                                             "h:added edges 8", "h:added triangles 5", "h:added triangles 6",
                                             "h:added tetrahedra 1", "h:ending"}));
    EXPECT_EQ(mesh.edges()[6], (Edge{3, 4}));
    EXPECT_EQ(mesh.triangles()[4], (Triangle{2, 3, 4}));
}

TEST(TopologyContainer, AddedPointsGrowTheStatesWithWeightedAncestorsBeforeTheEvent) {
    MeshTopology mesh;
    mesh.set_triangles({{0, 1, 2}});
    TopologyContainer c(mesh, ElementType::triangle, "surface");
    Vec3Object state;
    state.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 2, 0)};
    state.init();
    StateTopologyFollower<Vec3Types> follower(state);
    c.add_state_follower(follower);
    std::vector<std::string> log;
    TcRecorder handler("h", log);
    c.add_handler(handler, {ElementType::point});
    c.add_points(2, {{0, 1}, {1, 2}}, {{0.25, 0.75}, {0.5, 0.5}});
    ASSERT_EQ(state.position.size(), 5u);
    EXPECT_EQ(state.rest_position.size(), 5u);
    EXPECT_EQ(state.position[3], Vec3(0.75, 0, 0));
    EXPECT_EQ(state.position[4], Vec3(0.5, 1, 0));
    EXPECT_EQ(mesh.num_points(), 5u);
    EXPECT_EQ(mesh.triangles_around_vertex().size(), 5u);
    EXPECT_EQ(log, (std::vector<std::string>{"h:added points 3 4", "h:ending"}));
    EXPECT_THROW(c.add_triangles({{0, 1, 9}}), std::invalid_argument);
    EXPECT_THROW(c.add_triangles({{0, 1, 1}}), std::invalid_argument);
    c.add_triangles({{1, 3, 4}});
    tc_expect_consistent(c);
}

TEST(TopologyContainer, StatesFollowPointRemovalBySwapAndPop) {
    MeshTopology mesh;
    mesh.set_edges({{0, 1}, {2, 3}, {3, 4}});
    TopologyContainer c(mesh, ElementType::edge, "wire");
    Vec3Object state;
    for (int i = 0; i < 5; ++i) state.position.push_back(Vec3(i, 0, 0));
    state.init();
    for (int i = 0; i < 5; ++i) state.velocity[std::size_t(i)] = Vec3(0, i, 0);
    StateTopologyFollower<Vec3Types> follower(state);
    c.add_state_follower(follower);
    c.remove_edges({0});  // points 0 and 1 are isolated: removed as {1, 0}
    // point 1 takes point 4, then point 0 takes point 3
    ASSERT_EQ(state.position.size(), 3u);
    EXPECT_EQ(state.position[0], Vec3(3, 0, 0));
    EXPECT_EQ(state.position[1], Vec3(4, 0, 0));
    EXPECT_EQ(state.position[2], Vec3(2, 0, 0));
    EXPECT_EQ(state.velocity[1], Vec3(0, 4, 0));
    EXPECT_EQ(state.dx.size(), 3u);
    EXPECT_EQ(mesh.edges(), (std::vector<Edge>{{0, 1}, {2, 0}}));  // (3,4) moved into slot 0, renamed
}

/// A cube of 5·n³ tetrahedra made of n³ cells (each cell 5 tetrahedra; neighbouring cells
/// mirrored so that faces match).
MeshTopology tc_tetrahedral_cube(int n) {
    auto id = [n](int x, int y, int z) { return PointId(x + (n + 1) * (y + (n + 1) * z)); };
    std::vector<Tetrahedron> tets;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                PointId v[8] = {id(x, y, z),     id(x + 1, y, z),     id(x + 1, y + 1, z),     id(x, y + 1, z),
                                id(x, y, z + 1), id(x + 1, y, z + 1), id(x + 1, y + 1, z + 1), id(x, y + 1, z + 1)};
                if ((x + y + z) % 2 == 0) {
                    tets.push_back({v[0], v[1], v[3], v[4]});
                    tets.push_back({v[1], v[2], v[3], v[6]});
                    tets.push_back({v[1], v[4], v[5], v[6]});
                    tets.push_back({v[3], v[4], v[6], v[7]});
                    tets.push_back({v[1], v[3], v[4], v[6]});
                } else {
                    tets.push_back({v[0], v[1], v[2], v[5]});
                    tets.push_back({v[0], v[2], v[3], v[7]});
                    tets.push_back({v[0], v[4], v[5], v[7]});
                    tets.push_back({v[2], v[5], v[6], v[7]});
                    tets.push_back({v[0], v[2], v[5], v[7]});
                }
            }
    // positively oriented (a face shared by two tetrahedra then runs both ways, as SOFA's meshes)
    const auto at = [n](PointId p) {
        const int k = int(p);
        return Vec3(k % (n + 1), (k / (n + 1)) % (n + 1), k / ((n + 1) * (n + 1)));
    };
    for (Tetrahedron& t : tets)
        if ((at(t[1]) - at(t[0])).cross(at(t[2]) - at(t[0])).dot(at(t[3]) - at(t[0])) < 0) std::swap(t[2], t[3]);
    MeshTopology m;
    m.set_tetrahedra(std::move(tets));
    return m;
}

TEST(TopologyContainer, RandomRemovalsAndAdditionsKeepEveryCrossTableConsistent) {
    MeshTopology mesh = tc_tetrahedral_cube(3);
    TopologyContainer c(mesh, ElementType::tetrahedron, "cube");
    tc_expect_consistent(c);
    std::mt19937 rng(51);
    std::vector<Tetrahedron> removed;
    int steps = 0;
    while (mesh.tetrahedra().size() > 3) {
        const std::size_t n = mesh.tetrahedra().size();
        std::vector<ElementId> pick;
        std::uniform_int_distribution<int> count(1, 4);
        for (int k = count(rng); k > 0; --k) {
            const auto i = ElementId(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng));
            if (std::find(pick.begin(), pick.end(), i) == pick.end()) pick.push_back(i);
        }
        // expected element list: SOFA's swap-and-pop, in decreasing order, of the tetrahedra alone
        std::vector<Tetrahedron> expected = mesh.tetrahedra();
        std::vector<ElementId> sorted = pick;
        std::sort(sorted.rbegin(), sorted.rend());
        for (const ElementId i : sorted) {
            expected[std::size_t(i)] = expected.back();
            expected.pop_back();
        }
        const std::size_t points_before = mesh.num_points();
        c.remove_tetrahedra(pick);
        if (mesh.num_points() == points_before) {
            EXPECT_EQ(mesh.tetrahedra(), expected);  // no point renamed
        }
        EXPECT_EQ(mesh.tetrahedra().size(), expected.size());
        tc_expect_consistent(c);
        if (++steps % 5 == 0 && mesh.num_points() >= 4) {  // add one back between existing points
            const auto p = PointId(mesh.num_points());
            c.add_points(1);
            c.add_tetrahedra({{0, 1, 2, PointId(p)}});
            tc_expect_consistent(c);
        }
    }
    EXPECT_GT(steps, 20);
}

}  // namespace
}  // namespace penalty
