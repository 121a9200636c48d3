#pragma once
// The component tables of the builder's family files: each family file declares the components
// it builds (ComponentSpec: type, attributes, build function) next to their build functions;
// src/scene/components.cpp assembles them into the registry.
#include "penalty/scene/components.hpp"

#include <span>

namespace penalty {
class HexahedronFEMForceField;
namespace scene {
struct NodeBuild;
}
}  // namespace penalty

namespace penalty::scene::builder {

std::span<const ComponentSpec> state_and_topology_components();    // states_and_topologies.cpp
std::span<const ComponentSpec> mass_and_force_field_components();  // masses_and_force_fields.cpp
std::span<const ComponentSpec> mapping_and_constraint_components(); // mappings_and_constraints.cpp
std::span<const ComponentSpec> solver_components();                // solvers.cpp
std::span<const ComponentSpec> collision_components();             // collision.cpp
std::span<const ComponentSpec> topology_container_components();     // topology_containers.cpp
std::span<const ComponentSpec> surface_force_field_components();   // surface_force_fields.cpp
std::span<const ComponentSpec> mass_and_region_components();        // masses_and_regions.cpp
std::span<const ComponentSpec> sparse_grid_components();           // sparse_grid.cpp
std::span<const ComponentSpec> pressure_load_components();          // pressure_loads.cpp
std::span<const ComponentSpec> region_of_interest_components();     // regions_of_interest.cpp
std::span<const ComponentSpec> external_load_components();         // external_loads.cpp
std::span<const ComponentSpec> hexahedra_and_subset_components();  // hexahedra_and_subsets.cpp
std::span<const ComponentSpec> bending_spring_components();        // bending_springs.cpp
std::span<const ComponentSpec> corotational_fem_components();      // corotational_fem.cpp
std::span<const ComponentSpec> topology_change_components();       // topology_changes.cpp

/// SOFA's SparseGridTopology::getStiffnessCoef on a HexahedronFEMForceField built on the node's
/// sparse grid (0.5 for boundary cells when fillWeighted) (sparse_grid.cpp).
void sparse_grid_stiffness_factors(HexahedronFEMForceField& ff, const NodeBuild& info);

}  // namespace penalty::scene::builder
