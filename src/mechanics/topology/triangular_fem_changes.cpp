// TriangularFEMForceField's topological changes (docs/topological-changes.md). SOFA's
// TriangularFEMForceField keeps its triangleInfo in a TopologyData whose creation callback
// (TriangularFEMForceField::createTriangleInformation → initLarge / initSmall,
// computeMaterialStiffness) runs when the triangles' addition event reaches it
// (TopologyData::add), reading the state's rest positions at that moment; a removal swaps each
// removed triangle's data with the last one and pops it (TopologyData::remove); a renumbering
// permutes it; moved points (TriangleSetTopologyModifier::movePointsProcess) change nothing
// (TopologyDataHandler ignores the moved events). So a triangle's data is that of its rest shape
// when it was created: after an incision snapped a vertex onto its path, the triangles around it
// keep their rest shape from before the move (SOFA's), which a rebuild from the moved rest
// positions would not. vertexInfo (TriangularFEMForceField's other TopologyData) only serves the
// drawing and the principal stresses: no force depends on it.
#include "penalty/core/error.hpp"
#include "penalty/mechanics/topology_container.hpp"
#include "penalty/mechanics/topology_data.hpp"
#include "penalty/mechanics/triangular_fem.hpp"

namespace penalty {

void TriangularFEMForceField::handle_topology_changes(const TopologyContainer& container,
                                                      std::span<const TopologyChange> changes) {
    blocks_current_ = false;
    pending_.container = &container;
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::removed, ElementType::triangle)) {
            // TopologyData::remove, indices in decreasing order (no destruction callback)
            topology_data_remove(triangles_, c.indices);
            for_each_element_array([&c](auto& v) { topology_data_remove(v, c.indices); });
            for (const ElementId id : c.indices) pending_.slots.push_back(std::size_t(id));
        } else if (c.is(TopologyChangeKind::added, ElementType::triangle)) {
            // TopologyData::add: appended, then createTriangleInformation for each, in order
            PENALTY_DEMAND(c.indices.empty() || std::size_t(c.indices.front()) == triangles_.size());
            for (std::size_t k = 0; k < c.indices.size(); ++k) {
                triangles_.push_back(c.added_element<3>(k));
                const std::size_t n = triangles_.size();
                for_each_element_array([n](auto& v) { v.resize(n); });
                init_element(n - 1);
            }
        } else if (c.is(TopologyChangeKind::renumbered, ElementType::triangle)) {
            topology_data_renumber(triangles_, c.indices);
            for_each_element_array([&c](auto& v) { topology_data_renumber(v, c.indices); });
        } else if (c.is(TopologyChangeKind::removed, ElementType::point)) {
            // the last points take the removed indices: their triangles are renamed
            pending_.renamed_points.insert(pending_.renamed_points.end(), c.indices.begin(), c.indices.end());
        } else if (c.is(TopologyChangeKind::renumbered, ElementType::point)) {
            pending_.all = true;
        }
    }
}

void TriangularFEMForceField::topology_change_done() {
    blocks_current_ = false;
    if (pending_.container == nullptr) return;
    const MeshTopology& mesh = pending_.container->mesh();
    PendingTopologyChange pending = std::move(pending_);
    pending_ = {};
    scatter_.clear();  // the triangles change in place: the split is made again
    const auto& triangles = mesh.triangles();
    PENALTY_DEMAND(triangles.size() == triangles_.size());
    if (pending.all) {
        triangles_ = triangles;
        return;
    }
    // the vertices of the triangles on a renamed point, and of the slots a swap filled
    const auto& around = mesh.triangles_around_vertex();
    for (const PointId p : pending.renamed_points)
        if (std::size_t(p) < around.size())
            for (const auto t : around[std::size_t(p)]) triangles_[std::size_t(t)] = triangles[std::size_t(t)];
    for (const std::size_t slot : pending.slots)
        if (slot < triangles_.size()) triangles_[slot] = triangles[slot];
}

std::size_t TriangularFEMForceField::take_triangles_keeping_slot_data(const std::vector<Triangle>& triangles) {
    blocks_current_ = false;
    // TriangleFEMForceField's loops run over the topology's triangles with init's vectors, which
    // never shrink: rest_local_, area_, material_ keep their slots; j_ and rotation_ are made by
    // add_force for the slots in use
    triangles_ = triangles;
    scatter_.clear();
    const std::size_t kept = rest_local_.size();
    if (triangles_.size() <= kept) return 0;
    for_each_element_array([n = triangles_.size()](auto& v) { v.resize(n); });
    for (std::size_t e = kept; e < triangles_.size(); ++e) init_element(e);
    return triangles_.size() - kept;
}

}  // namespace penalty
