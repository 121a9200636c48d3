#pragma once
// The component tables of the builder's family files: each family file declares the components
// it builds (ComponentSpec: type, attributes, build function) next to their build functions;
// src/scene/components.cpp assembles them into the registry.
#include "penalty/scene/components.hpp"

#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace penalty {
class CGLinearSolver;
class DirectLinearSolver;
class HexahedronFEMForceField;
class Node;
namespace scene {
struct NodeBuild;
}
}  // namespace penalty

namespace penalty::scene::builder {

std::span<const ComponentSpec> state_and_topology_components();           // states_and_topologies.cpp
std::span<const ComponentSpec> mass_and_force_field_components();         // masses_and_force_fields.cpp
std::span<const ComponentSpec> mapping_and_constraint_components();       // mappings_and_constraints.cpp
std::span<const ComponentSpec> solver_components();                       // solvers.cpp
std::span<const ComponentSpec> collision_components();                    // collision.cpp
std::span<const ComponentSpec> topology_container_components();           // topology_containers.cpp
std::span<const ComponentSpec> surface_force_field_components();          // surface_force_fields.cpp
std::span<const ComponentSpec> mass_and_region_components();              // masses_and_regions.cpp
std::span<const ComponentSpec> sparse_grid_components();                  // sparse_grid.cpp
std::span<const ComponentSpec> pressure_load_components();                // pressure_loads.cpp
std::span<const ComponentSpec> region_of_interest_components();           // regions_of_interest.cpp
std::span<const ComponentSpec> external_load_components();                // external_loads.cpp
std::span<const ComponentSpec> hexahedra_and_subset_components();         // hexahedra_and_subsets.cpp
std::span<const ComponentSpec> bending_spring_components();               // bending_springs.cpp
std::span<const ComponentSpec> corotational_fem_components();             // corotational_fem.cpp
std::span<const ComponentSpec> topology_change_components();              // topology_changes.cpp
std::span<const ComponentSpec> direct_solver_components();                // direct_solvers.cpp
std::span<const ComponentSpec> integrator_components();                   // integrators.cpp
std::span<const ComponentSpec> matrix_mass_and_rest_spring_components();  // matrix_mass_and_rest_springs.cpp

/// "N DOFs in K states": the independent DOFs of a solver's subtree (mapped states not counted).
[[nodiscard]] std::string subtree_dofs(const Node& n);

/// The node's linear solver read by its ODE solver: CGLinearSolver's limits into `cg`
/// (solvers.cpp), or a direct solver (direct_solvers.cpp: the solver with its linear system and
/// ordering method).
void read_conjugate_gradient(SceneBuilder& b, const io::SceneComponent& linear, CGLinearSolver& cg);
[[nodiscard]] bool is_direct_linear_solver(std::string_view type);
[[nodiscard]] std::shared_ptr<DirectLinearSolver> read_direct_linear_solver(SceneBuilder& b,
                                                                            const io::SceneComponent& linear);
std::span<const ComponentSpec> transform_engine_components();         // transform_engines.cpp
std::span<const ComponentSpec> selection_engine_components();         // selection_engines.cpp
std::span<const ComponentSpec> frame_mapping_components();            // frame_mappings.cpp
std::span<const ComponentSpec> python_components();                   // python_components.cpp
std::span<const ComponentSpec> projective_constraint_components();    // projective_constraints.cpp
std::span<const ComponentSpec> rigid_force_field_components();        // rigid_force_fields.cpp
std::span<const ComponentSpec> interaction_force_field_components();  // interaction_force_fields.cpp
std::span<const ComponentSpec> hyperelasticity_components();          // hyperelasticity.cpp
std::span<const ComponentSpec> shell_force_field_components();        // shell_force_fields.cpp
std::span<const ComponentSpec> nonuniform_hexahedra_components();     // nonuniform_hexahedra.cpp
std::span<const ComponentSpec> tait_pressure_components();            // tait_pressure.cpp
std::span<const ComponentSpec> multi_mapping_components();            // multi_mappings.cpp
std::span<const ComponentSpec> drawing_components();                  // drawing_components.cpp
std::span<const ComponentSpec> shape_matching_components();           // shape_matching.cpp
std::span<const ComponentSpec> diffusion_components();                // diffusion.cpp

/// SOFA's SparseGridTopology::getStiffnessCoef on a HexahedronFEMForceField built on the node's
/// sparse grid (0.5 for boundary cells when fillWeighted) (sparse_grid.cpp).
void sparse_grid_stiffness_factors(HexahedronFEMForceField& ff, const NodeBuild& info);
/// SOFA's SparseGridTopology::getMassCoef of each cell of the node's sparse grid (sparse_grid.cpp).
std::vector<double> sparse_grid_mass_factors(const NodeBuild& info);

}  // namespace penalty::scene::builder
