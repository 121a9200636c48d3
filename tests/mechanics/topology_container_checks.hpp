#pragma once
// The checks of the topology container's tests (test_topology_container, test_topology_removal,
// test_topology_addition, test_topology_point_moves): an event recorder and the consistency of
// every cross table with the element lists.
#include "penalty/mechanics/state_topology.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

namespace penalty::test_topology {

using Ids = std::vector<ElementId>;

/// What a handler or listener saw: one string per event, "<tag>:<kind> <type> <indices>".
struct TcRecorder final : TopologyHandler, StateFollower {
    std::string tag;
    std::vector<std::string>* log;
    TcRecorder(std::string t, std::vector<std::string>& l) : tag(std::move(t)), log(&l) {}
    static std::string text(const TopologyChange& c) {
        static const char* kKind[] = {"added", "removed", "renumbered", "ending", "moved"};
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
inline void tc_expect_consistent(const TopologyContainer& c) {
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

}  // namespace penalty::test_topology
