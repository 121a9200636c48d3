#pragma once
// A static two-triangle floor at y = 0 (normal +y, |x|, |z| ≤ 10 m) in its own child node: the
// ground of SOFA's worked example E and of most contact tests. Header-only; include it only from
// suites that link penalty::collision and penalty::simulation.
#include "penalty/collision/models.hpp"
#include "penalty/simulation/node.hpp"

#include <memory>
#include <string>

namespace penalty::test {

/// Floor model parameters: name "floor", contact stiffness k, not moving, simulated as asked.
inline CollisionModelParams floor_params(double contact_stiffness = 10.0, bool simulated = false) {
    CollisionModelParams p;
    p.name = "floor";
    p.contact_stiffness = contact_stiffness;
    p.simulated = simulated;
    p.moving = false;
    return p;
}

struct StaticFloor {
    Node* node;
    Vec3Object* state;
    MeshTopology topology;
    std::unique_ptr<TriangleModel> model;

    StaticFloor(Node& parent, const CollisionModelParams& params, const std::string& node_name = "floor") {
        node = &parent.add_child(node_name);
        state = &node->add_state<Vec3Types>("floor");
        state->position = {Vec3(-10, 0, -10), Vec3(-10, 0, 10), Vec3(10, 0, 10), Vec3(10, 0, -10)};
        topology.set_num_points(4);
        topology.set_triangles({Triangle{0, 1, 2}, Triangle{0, 2, 3}});
        model = std::make_unique<TriangleModel>(*state, topology, params);
    }
    StaticFloor(const StaticFloor&) = delete;  // the model points at `topology`
    StaticFloor& operator=(const StaticFloor&) = delete;
};

}  // namespace penalty::test
