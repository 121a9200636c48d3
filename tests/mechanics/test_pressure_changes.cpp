// The pressure loads under topological changes (pressure_changes.cpp, SOFA's TopologySubsetData
// remove/add on trianglePressureMap, quadPressureMap and edgePressureMap): a removed element's entry
// erased with its area or length and force, the entries naming the subset's last element renamed
// to the removed one, SOFA's stale last index (raised by additions, never lowered by removals)
// against SofaQuirkFixes' current last index, the entries past the topology's end dropped, and the
// edges' forces recomputed once the change is done. Disjoint elements of distinct sizes, so each
// entry's area (length) names the element it holds.
#include "penalty/mechanics/pressure_loads.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace penalty {
namespace {

TopologyChange pressure_change(TopologyChangeKind kind, ElementType element, std::vector<ElementId> indices) {
    TopologyChange c;
    c.kind = kind;
    c.element = element;
    c.indices = std::move(indices);
    return c;
}

/// Triangle k (k = 0..3): (0,0,0), (k+1,0,0), (0,1,0) shifted by 10·k in y: area (k+1)/2.
std::vector<Triangle> pressure_triangles() { return {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {9, 10, 11}}; }

/// Four disjoint triangles of areas 0.5, 1, 1.5, 2 under P = (0, 0, 6): forces 3, 6, 9, 12.
struct PressedTriangles {
    MeshTopology mesh;
    Vec3Object state;
    std::unique_ptr<TopologyContainer> container;
    std::unique_ptr<TrianglePressureForceField> field;
    explicit PressedTriangles(std::vector<Index> selected) {
        mesh.set_triangles(pressure_triangles());
        for (int k = 0; k < 4; ++k) {
            const double y = 10.0 * k;
            state.position.emplace_back(0, y, 0);
            state.position.emplace_back(k + 1, y, 0);
            state.position.emplace_back(0, y + 1, 0);
        }
        state.init();
        container = std::make_unique<TopologyContainer>(mesh, ElementType::triangle, "triangles");
        field = std::make_unique<TrianglePressureForceField>(state, mesh, std::move(selected), Vec3(0, 0, 6));
        field->init();
    }
    /// The z forces at the 12 points.
    std::vector<double> forces_z() {
        std::vector<Vec3> f(12, Vec3::Zero());
        const std::vector<Vec3> v(12, Vec3::Zero());
        field->add_force(f, state.position, v);
        std::vector<double> z;
        for (const Vec3& fk : f) z.push_back(fk.z());
        return z;
    }
};

// TrianglesRemoved {0} then {1} of the selection {1, 2, 3}: the topology becomes [t3, t1, t2], then
// [t3, t2]. SOFA's last index stays 3: the first removal renames 3 to 0, the second renames nothing,
// and entry 2 (t2, now at 1) is left past the end.
TEST(PressureChanges, TrianglesFollowSofasStaleLastIndex) {
    PressedTriangles s({1, 2, 3});
    EXPECT_EQ(s.field->total_rest_area(), 4.5);
    const std::vector<TopologyChange> removed{pressure_change(TopologyChangeKind::removed, ElementType::triangle, {0}),
                                              pressure_change(TopologyChangeKind::removed, ElementType::triangle, {1})};
    s.field->handle_topology_changes(*s.container, removed);
    EXPECT_EQ(s.field->triangles(), (std::vector<Index>{2, 0}));
    EXPECT_EQ(s.field->total_rest_area(), 3.5);  // t2's 1.5 and t3's 2 kept with their entries
    const std::vector<Triangle> all = pressure_triangles();
    s.mesh.set_triangles({all[3], all[2]});
    EXPECT_EQ(s.field->drop_entries_past_end(), 1U);
    EXPECT_EQ(s.field->triangles(), (std::vector<Index>{0}));
    EXPECT_EQ(s.field->total_rest_area(), 2.0);
    // t3's force 12 on its three corners, nothing elsewhere
    EXPECT_EQ(s.forces_z(), (std::vector<double>{0, 0, 0, 0, 0, 0, 0, 0, 0, 4, 4, 4}));
}

TEST(PressureChanges, TrianglesFollowTheCurrentLastIndexWhenFixed) {
    PressedTriangles s({1, 2, 3});
    s.field->set_current_last_index(true);
    const std::vector<TopologyChange> removed{pressure_change(TopologyChangeKind::removed, ElementType::triangle, {0}),
                                              pressure_change(TopologyChangeKind::removed, ElementType::triangle, {1})};
    s.field->handle_topology_changes(*s.container, removed);
    EXPECT_EQ(s.field->triangles(), (std::vector<Index>{1, 0}));
    const std::vector<Triangle> all = pressure_triangles();
    s.mesh.set_triangles({all[3], all[2]});
    EXPECT_EQ(s.field->drop_entries_past_end(), 0U);
    EXPECT_EQ(s.field->total_rest_area(), 3.5);
    EXPECT_EQ(s.forces_z(), (std::vector<double>{0, 0, 0, 0, 0, 0, 3, 3, 3, 4, 4, 4}));
}

// TrianglesAdded raises the last index: a removal then renames the new last element, not the old one.
TEST(PressureChanges, AddedTrianglesRaiseTheLastIndexButJoinNoEntry) {
    for (const bool current : {false, true}) {
        PressedTriangles renamed({0, 3});
        renamed.field->set_current_last_index(current);
        const std::vector<TopologyChange> remove0{
            pressure_change(TopologyChangeKind::removed, ElementType::triangle, {0})};
        renamed.field->handle_topology_changes(*renamed.container, remove0);
        EXPECT_EQ(renamed.field->triangles(), (std::vector<Index>{0})) << current;  // 3 took 0's place

        PressedTriangles kept({0, 3});
        kept.field->set_current_last_index(current);
        const std::vector<TopologyChange> add_then_remove{
            pressure_change(TopologyChangeKind::added, ElementType::triangle, {4}),
            pressure_change(TopologyChangeKind::removed, ElementType::triangle, {0})};
        kept.field->handle_topology_changes(*kept.container, add_then_remove);
        EXPECT_EQ(kept.field->triangles(), (std::vector<Index>{3})) << current;  // 4 took 0's place
        EXPECT_EQ(kept.field->total_rest_area(), 2.0) << current;
    }
}

/// Edge k (k = 0..3): (0, 10·k, 0) to (k+1, 10·k, 0), length k+1, under P = (0, 2, 0): forces 2·(k+1).
struct PressedEdges {
    MeshTopology mesh;
    Vec3Object state;
    std::unique_ptr<TopologyContainer> container;
    std::unique_ptr<EdgePressureForceField> field;
    explicit PressedEdges(std::vector<Index> selected) {
        mesh.set_edges({{0, 1}, {2, 3}, {4, 5}, {6, 7}});
        for (int k = 0; k < 4; ++k) {
            state.position.emplace_back(0, 10.0 * k, 0);
            state.position.emplace_back(k + 1, 10.0 * k, 0);
        }
        state.init();
        container = std::make_unique<TopologyContainer>(mesh, ElementType::edge, "edges");
        field = std::make_unique<EdgePressureForceField>(state, mesh, std::move(selected), Vec3(0, 2, 0));
        field->init();
    }
    std::vector<double> forces_y() {
        std::vector<Vec3> f(8, Vec3::Zero());
        const std::vector<Vec3> v(8, Vec3::Zero());
        field->add_force(f, state.position, v);
        std::vector<double> y;
        for (const Vec3& fk : f) y.push_back(fk.y());
        return y;
    }
};

// EdgesRemoved {0}, then (in a later change, the topology now [e3, e1, e2]) EdgesRemoved {1}: the
// selection {2, 3} becomes {2, 0} after the first; SOFA's last index (3, read from the container at
// the first change) renames nothing in the second, the current one (2) renames e2's entry to 1.
TEST(PressureChanges, EdgesRenameTheLastEdgeAndRecomputeTheirForcesWhenDone) {
    MeshTopology after_first;
    after_first.set_edges({{6, 7}, {2, 3}, {4, 5}});
    for (const bool current : {false, true}) {
        PressedEdges s({2, 3});
        s.field->set_current_last_index(current);
        EXPECT_EQ(s.field->total_rest_length(), 7.0);
        const std::vector<TopologyChange> remove0{pressure_change(TopologyChangeKind::removed, ElementType::edge, {0})};
        s.field->handle_topology_changes(*s.container, remove0);
        EXPECT_EQ(s.field->edges(), (std::vector<Index>{2, 0})) << current;
        TopologyContainer second(after_first, ElementType::edge, "edges after the first change");
        const std::vector<TopologyChange> remove1{pressure_change(TopologyChangeKind::removed, ElementType::edge, {1})};
        s.field->handle_topology_changes(second, remove1);
        EXPECT_EQ(s.field->edges(), (current ? std::vector<Index>{1, 0} : std::vector<Index>{2, 0})) << current;
        EXPECT_EQ(s.field->total_rest_length(), 7.0) << current;  // the lengths kept with their entries
        s.mesh.set_edges({{6, 7}, {4, 5}});
        EXPECT_EQ(s.field->drop_entries_past_end(), current ? 0U : 1U);
        s.field->topology_change_done();  // the forces and lengths of the edges now listed
        EXPECT_EQ(s.field->total_rest_length(), current ? 7.0 : 4.0);
        const std::vector<double> expected =
            current ? std::vector<double>{0, 0, 0, 0, 3, 3, 4, 4} : std::vector<double>{0, 0, 0, 0, 0, 0, 4, 4};
        EXPECT_EQ(s.forces_y(), expected) << current;
    }
}

// The forces are P·L₀ of the edges an entry names, recomputed from the rest positions once the change
// is done (SOFA's addForce reads initEdgeInformation's at every step), not at each event.
TEST(PressureChanges, EdgeForcesAreRecomputedOnceTheChangeIsDone) {
    PressedEdges s({3});
    const std::vector<TopologyChange> remove0{pressure_change(TopologyChangeKind::removed, ElementType::edge, {0})};
    s.field->handle_topology_changes(*s.container, remove0);
    EXPECT_EQ(s.field->edges(), (std::vector<Index>{0}));
    EXPECT_EQ(s.forces_y(), (std::vector<double>{4, 4, 0, 0, 0, 0, 0, 0}));  // e3's 8 at e0's points still
    s.mesh.set_edges({{6, 7}, {2, 3}, {4, 5}});
    s.state.rest_position[7] = Vec3(8, 30, 0);  // e3's rest length now 8: P·L₀ = 16
    s.field->topology_change_done();
    EXPECT_EQ(s.field->total_rest_length(), 8.0);
    EXPECT_EQ(s.forces_y(), (std::vector<double>{0, 0, 0, 0, 0, 0, 8, 8}));
    s.state.rest_position[7] = Vec3(2, 30, 0);
    s.field->topology_change_done();  // nothing pending: unchanged
    EXPECT_EQ(s.field->total_rest_length(), 8.0);
}

// One EdgesRemoved {0, 1}: the last edge is one lower for each index of the event (3, then 2).
TEST(PressureChanges, OneEventRemovingTwoEdgesLowersTheLastEdge) {
    PressedEdges s({3, 2});
    const std::vector<TopologyChange> removed{pressure_change(TopologyChangeKind::removed, ElementType::edge, {0, 1})};
    s.field->handle_topology_changes(*s.container, removed);
    EXPECT_EQ(s.field->edges(), (std::vector<Index>{0, 1}));  // the topology is now [e3, e2]
    EXPECT_EQ(s.field->total_rest_length(), 7.0);
}

// QuadsRemoved on the quadPressureMap: the same subset rule (unit squares scaled by k+1: areas 1, 4, 9).
TEST(PressureChanges, QuadsFollowTheSubsetRule) {
    MeshTopology mesh;
    mesh.set_quads({{0, 1, 2, 3}, {4, 5, 6, 7}, {8, 9, 10, 11}});
    Vec3Object state;
    for (int k = 0; k < 3; ++k) {
        const double a = k + 1;
        const double z = 10.0 * k;
        state.position.insert(state.position.end(), {Vec3(0, 0, z), Vec3(a, 0, z), Vec3(a, a, z), Vec3(0, a, z)});
    }
    state.init();
    TopologyContainer container(mesh, ElementType::quad, "quads");
    QuadPressureForceField field(state, mesh, {0, 2}, Vec3(0, 0, 4));
    field.init();
    EXPECT_EQ(field.total_rest_area(), 10.0);
    const std::vector<TopologyChange> remove0{pressure_change(TopologyChangeKind::removed, ElementType::quad, {0})};
    field.handle_topology_changes(container, remove0);
    EXPECT_EQ(field.quads(), (std::vector<Index>{0}));  // q2 took q0's place
    EXPECT_EQ(field.total_rest_area(), 9.0);
    mesh.set_quads({{8, 9, 10, 11}, {4, 5, 6, 7}});
    std::vector<Vec3> f(12, Vec3::Zero());
    const std::vector<Vec3> v(12, Vec3::Zero());
    field.add_force(f, state.position, v);
    for (std::size_t p = 0; p < 12; ++p) EXPECT_EQ(f[p].z(), p >= 8 ? 9.0 : 0.0) << p;  // 4·9/4 a corner
}

}  // namespace
}  // namespace penalty
