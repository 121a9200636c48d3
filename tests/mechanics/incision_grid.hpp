#pragma once
// The grid of the incision tests (test_triangle_incision, test_triangle_path,
// test_triangle_snapping, test_incision_line): 3 x 2 unit squares, two triangles each (12
// points, 12 triangles), its container and a state following it.
#include "penalty/mechanics/state_topology.hpp"
#include "penalty/mechanics/triangle_incision.hpp"

#include <memory>
#include <set>
#include <vector>

namespace penalty::test_incision {

/// Point (i, j) of the grid: index 4 j + i, at (i, j, 0).
constexpr PointId grid_point(int i, int j) { return PointId(4 * j + i); }

/// The grid, its container and a state following it.
struct IncisionGrid {
    MeshTopology mesh;
    Vec3Object state{"grid"};
    std::unique_ptr<TopologyContainer> container;
    std::unique_ptr<StateTopologyFollower<Vec3Types>> follower;
    IncisionGrid() {
        std::vector<Triangle> triangles;
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) {
                const PointId a = grid_point(i, j), b = grid_point(i + 1, j), c = grid_point(i + 1, j + 1),
                              d = grid_point(i, j + 1);
                triangles.push_back({a, b, c});  // below the diagonal a-c
                triangles.push_back({a, c, d});  // above it
            }
        mesh.set_num_points(12);
        mesh.set_triangles(triangles);
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i) state.position.emplace_back(double(i), double(j), 0.0);
        state.rest_position = state.position;
        container = std::make_unique<TopologyContainer>(mesh, ElementType::triangle, "grid");
        follower = std::make_unique<StateTopologyFollower<Vec3Types>>(state);
        container->add_state_follower(*follower);
    }
    /// The triangles as vertex sets.
    [[nodiscard]] std::set<std::set<PointId>> triangle_sets() const {
        std::set<std::set<PointId>> out;
        for (const Triangle& t : mesh.triangles()) out.insert({t[0], t[1], t[2]});
        return out;
    }
    [[nodiscard]] double signed_area_sum() const {
        double sum = 0;
        for (const Triangle& t : mesh.triangles()) {
            const Vec3 &a = state.position[std::size_t(t[0])], &b = state.position[std::size_t(t[1])],
                       &c = state.position[std::size_t(t[2])];
            sum += 0.5 * (b - a).cross(c - a)[2];
        }
        return sum;
    }
};

}  // namespace penalty::test_incision
