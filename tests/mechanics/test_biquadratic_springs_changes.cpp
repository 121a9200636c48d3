// The triangular (bi)quadratic springs under topological changes (biquadratic_springs_changes.cpp,
// SOFA's edgeInfo / triangleInfo callbacks): a removed triangle takes its shares s_j from its
// edges' stiffness (a subtraction: an edge of that triangle alone goes to 0 exactly), an added
// triangle gives them back, added edges start at stiffness 0, removed edges leave by swap-and-pop.
// The square (0,0), (1,0), (1,1), (0,1) as triangles (0,1,2), (0,2,3) sharing the diagonal 0–2;
// the shares are each triangle's alone (the field over that triangle only).
#include "penalty/mechanics/topology_container.hpp"
#include "penalty/mechanics/triangular_biquadratic_springs.hpp"
#include "penalty/mechanics/triangular_quadratic_springs.hpp"

#include "penalty_test/element_products_on_threads.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace penalty {
namespace {

TopologyChange springs_change(TopologyChangeKind kind, ElementType element, std::vector<ElementId> indices) {
    TopologyChange c;
    c.kind = kind;
    c.element = element;
    c.indices = std::move(indices);
    return c;
}

/// A surface of `triangles` over the square's four points, its state and container.
struct SpringsSurface {
    MeshTopology mesh;
    Vec3Object state;
    std::unique_ptr<TopologyContainer> container;
    explicit SpringsSurface(std::vector<Triangle> triangles) {
        mesh.set_num_points(4);
        mesh.set_triangles(std::move(triangles));
        state.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
        state.init();
        container = std::make_unique<TopologyContainer>(mesh, ElementType::triangle, "square");
    }
    /// The value of `per_edge` at the edge (a, b).
    [[nodiscard]] double at(const std::vector<double>& per_edge, PointId a, PointId b) const {
        return per_edge[std::size_t(mesh.edge_index(a, b))];
    }
};

template <class Field, class Parameters>
void a_removed_triangle_takes_its_shares(const Parameters& parameters) {
    SpringsSurface both({{0, 1, 2}, {0, 2, 3}});
    SpringsSurface second({{0, 2, 3}});
    Field field(both.state, both.mesh, parameters);
    Field alone(second.state, second.mesh, parameters);
    field.init();
    alone.init();
    const std::vector<double> before = field.edge_stiffness();
    ASSERT_GT(second.at(alone.edge_stiffness(), 0, 2), 0.0);
    // TrianglesRemoved {1}, sent while the triangle is still there
    const std::vector<TopologyChange> removed{springs_change(TopologyChangeKind::removed, ElementType::triangle, {1})};
    field.handle_topology_changes(*both.container, removed);
    // its own edges 2–3 and 3–0: 0 exactly; the diagonal: (s₀ + s₁) − s₁; the others unchanged
    EXPECT_EQ(both.at(field.edge_stiffness(), 2, 3), 0.0);
    EXPECT_EQ(both.at(field.edge_stiffness(), 3, 0), 0.0);
    EXPECT_EQ(both.at(field.edge_stiffness(), 0, 2), both.at(before, 0, 2) - second.at(alone.edge_stiffness(), 0, 2));
    EXPECT_EQ(both.at(field.edge_stiffness(), 0, 1), both.at(before, 0, 1));
    EXPECT_EQ(both.at(field.edge_stiffness(), 1, 2), both.at(before, 1, 2));
    // TrianglesAdded {1}: its shares added back
    const std::vector<TopologyChange> added{springs_change(TopologyChangeKind::added, ElementType::triangle, {1})};
    field.handle_topology_changes(*both.container, added);
    EXPECT_EQ(both.at(field.edge_stiffness(), 2, 3), second.at(alone.edge_stiffness(), 2, 3));
    EXPECT_EQ(both.at(field.edge_stiffness(), 0, 2), (both.at(before, 0, 2) - second.at(alone.edge_stiffness(), 0, 2)) +
                                                         second.at(alone.edge_stiffness(), 0, 2));
    // EdgesRemoved {0}: the last edge's data in slot 0
    const std::size_t edges = field.edge_stiffness().size();
    const double last = field.edge_stiffness().back();
    const std::vector<TopologyChange> edge_removed{springs_change(TopologyChangeKind::removed, ElementType::edge, {0})};
    field.handle_topology_changes(*both.container, edge_removed);
    ASSERT_EQ(field.edge_stiffness().size(), edges - 1);
    EXPECT_EQ(field.edge_stiffness()[0], last);
}

TEST(BiquadraticSpringsChanges, ARemovedTriangleTakesItsSharesFromItsEdges) {
    a_removed_triangle_takes_its_shares<TriangularBiquadraticSpringsForceField>(
        BiquadraticSpringParameters{.young_modulus = 10.0, .poisson_ratio = 0.25});
}

TEST(BiquadraticSpringsChanges, TheQuadraticSpringsFollowTheSameRules) {
    a_removed_triangle_takes_its_shares<TriangularQuadraticSpringsForceField>(
        QuadraticSpringParameters{.young_modulus = 10.0, .poisson_ratio = 0.25});
}

/// Forwards a container's changes to a field (as the scene's wiring does).
template <class Field>
struct FieldFollower final : TopologyHandler {
    Field& field;
    const TopologyContainer& container;
    FieldFollower(Field& f, const TopologyContainer& c) : field(f), container(c) {}
    void handle_topology_changes(std::span<const TopologyChange> changes) override {
        field.handle_topology_changes(container, changes);
    }
};

template <class Field, class Parameters>
void threads_after_a_change_give_one_threads_bits(const Parameters& parameters) {
    // a sheet of 8 192 triangles on threads, then 64 of its triangles removed and added back:
    // as many triangles and edges as before, in another order, so the chunks and deferred terms
    // must be made again (a field's scatter is cleared by the change)
    test::TriangleSheet sheet(false);
    Vec3Object state;
    state.position = sheet.points;
    state.init();
    TopologyContainer container(sheet.topology, ElementType::triangle, "sheet");
    Field field(state, sheet.topology, parameters);
    field.init();
    FieldFollower<Field> follower(field, container);
    container.add_handler(follower, {ElementType::edge, ElementType::triangle});
    test::expect_threads_give_one_threads_bits(field, state, "before the change");
    const std::size_t edges = sheet.topology.edges().size();
    std::vector<ElementId> removed;
    std::vector<Triangle> again;
    for (ElementId t = 100; t < 8192; t += 127) {
        removed.push_back(t);
        again.push_back(sheet.topology.triangles()[std::size_t(t)]);
    }
    container.remove_triangles(removed, /*remove_isolated_edges=*/true, /*remove_isolated_points=*/false);
    container.add_triangles(again);
    ASSERT_EQ(sheet.topology.triangles().size(), 8192U);
    ASSERT_EQ(sheet.topology.edges().size(), edges);
    test::expect_threads_give_one_threads_bits(field, state, "after the change");
}

TEST(BiquadraticSpringsChanges, OnThreadsAfterAChangeTheBitsOfOneThread) {
    threads_after_a_change_give_one_threads_bits<TriangularBiquadraticSpringsForceField>(
        BiquadraticSpringParameters{.young_modulus = 500.0});
    threads_after_a_change_give_one_threads_bits<TriangularQuadraticSpringsForceField>(
        QuadraticSpringParameters{.young_modulus = 500.0});
}

}  // namespace
}  // namespace penalty
