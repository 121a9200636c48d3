#pragma once
/// @file
/// The fidelity defaults, in one place: the library (ContactPipeline, CollisionPipeline,
/// CollisionResponse, the ODE solvers), the scene builder (scene::BuildOptions), the command line
/// and Python all start from these values.

namespace penalty {

struct FidelityDefaults {
    /// SOFA HEAD's two orders (docs/sofa-compatibility.md, "SOFA HEAD's orders"): the ODE
    /// solvers sum computeForce and addMBKv through SOFA's MappingGraph
    /// (OdeSolver::sofa_mapping_graph_order) and the contacts follow SOFA's stable-id maps
    /// (CollisionResponse::sofa_stable_id_order). On: the bits of SOFA HEAD.
    bool sofa_head_orders = true;
    /// SOFA's exhaustive element-pair loop instead of the BVH narrow phase (ContactDetection):
    /// both give the same outputs in the same order; the BVH is faster beyond a few elements.
    bool exhaustive_detection = false;
};

inline constexpr FidelityDefaults kFidelityDefaults{};

}  // namespace penalty
