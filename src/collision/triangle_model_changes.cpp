// TriangleModel::refresh_triangles: a triangle collision model following its topology's
// changes (docs/topological-changes.md). SOFA's TriangleCollisionModel takes the whole topology
// again when its revision changes (updateFromTopology); the slots a change touches are refreshed
// here, the rest of the model is as it was, so the model equals one built on the changed topology.
#include "penalty/collision/models.hpp"
#include "penalty/core/error.hpp"

namespace penalty {

void TriangleModel::refresh_triangles(std::span<const std::size_t> touched) {
    const auto& tris = topology_->triangles();
    PENALTY_DEMAND(topology_->quads().empty());
    const auto full = [](std::uint32_t f) { return (f & (kPoints | kEdges)) == (kPoints | kEdges); };
    // slots past the new end leave; new slots start as partial until refreshed (they are touched)
    for (std::size_t t = tris.size(); t < triangles_.size(); ++t)
        if (!full(flags_[t])) --partial_feature_count_;
    const std::size_t old_size = triangles_.size();
    triangles_.resize(tris.size());
    flags_.resize(tris.size(), 0u);
    normals_.resize(tris.size(), Vec3::Zero());
    plane_normals_.resize(tris.size(), Vec3::Zero());
    for (std::size_t t = old_size; t < tris.size(); ++t) ++partial_feature_count_;
    for (const std::size_t t : touched) {
        if (t >= tris.size()) continue;
        triangles_[t] = tris[t];
        const std::uint32_t f = topology_flags(t);
        if (!full(flags_[t])) --partial_feature_count_;
        if (!full(f)) ++partial_feature_count_;
        flags_[t] = f;
    }
    num_topology_triangles_ = tris.size();
    owns_every_feature_ = partial_feature_count_ == 0;
    validated_state_size_ = kNotValidated;  // validate() again before the next detection
    planes_current_ = false;
}

}  // namespace penalty
