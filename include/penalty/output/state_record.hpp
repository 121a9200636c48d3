#pragma once
/// @file
/// The mechanical states of a scene as the output writers see them, and SOFA's selection of the
/// states its regression tests export.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/topology.hpp"

#include <span>
#include <string>
#include <vector>

namespace penalty {
class Node;
}

namespace penalty::output {

/// One MechanicalObject of a scene.
struct StateRecord {
    std::string name;                        ///< MechanicalObject name ("dofs", "rigid", ...)
    std::string node_path;                   ///< SOFA path of its node: "/" root, "/A/B"
    BaseState* state = nullptr;              ///< a Vec3Object, Rigid3Object or Vec1Object (dynamic_cast to read)
    const MeshTopology* topology = nullptr;  ///< elements for VTK cells; nullptr: vertices only
    bool mapped = false;                     ///< its node has a mapping whose output is this state
    bool in_solver_subtree = false;          ///< its node is in the subtree of a node with an ODE solver
    const BaseMass* mass = nullptr;          ///< the node's mass (for kinetic_energy); nullptr: none
    /// Sphere radius of each DOF (m) when a Sphere collision model covers the state, written as
    /// VTK point data `radius` (glyph scale in ParaView); empty: no sphere model.
    std::vector<double> radius;
};

/// SOFA's regression selection: the records with in_solver_subtree && (!mapped || include_mapped),
/// in the given order (callers pass depth-first scene order: parent before children, file order).
[[nodiscard]] std::vector<const StateRecord*> select_exported_states(std::span<const StateRecord> states,
                                                                     bool include_mapped);

/// Records for every node of `root`'s tree that has a state, depth-first (node before its
/// children, children in insertion order): name, node_path ("/" for root, "/A/B" below; the
/// root's own name is not part of paths), state, mapped (the node's mapping outputs its state),
/// in_solver_subtree (the node or an ancestor has an ODE solver), mass (the node's mass, if it is
/// a mass of this state). topology is left nullptr: the scene builder knows the topologies.
[[nodiscard]] std::vector<StateRecord> collect_state_records(const Node& root);

/// Scalars per DOF in the state file: 3 for a Vec3 state (x y z), 7 for a Rigid3 state
/// (x y z qx qy qz qw), 1 for a Vec1 state (SOFA's WriteState writes each Coord's values, for
/// every template). Throws std::invalid_argument for any other state type.
[[nodiscard]] int values_per_dof(const BaseState& state);

/// Whether the state's DOFs are points in space (Vec3d, Rigid3d): what VTK, the viewer and the
/// divergence bound show or watch. A Vec1d state (a distance, a temperature) is only in the
/// regression state files.
[[nodiscard]] bool has_points_in_space(const StateRecord& record);

/// "<node_path>/<name>" ("/dofs" for a root state): how messages name a state.
[[nodiscard]] std::string state_label(const StateRecord& record);

}  // namespace penalty::output
