// EdgePressureForceField::handle_topology_changes and TrianglePressureForceField::
// handle_topology_changes: SOFA's EdgeSubsetData and TriangleSubsetData rules for their
// edgePressureMap and trianglePressureMap (TopologySubsetData::remove: erase, keeping the order,
// then the entries of the last element renamed; add with supportNewTopologyElements false).
#include "penalty/mechanics/pressure_loads.hpp"

#include "penalty/core/error.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <algorithm>

namespace penalty {

void EdgePressureForceField::handle_topology_changes(const TopologyContainer& container, std::span<const TopologyChange> changes) {
    // BaseTopologyData::setDataSetArraySize at the data's link: the last edge of the topology then
    if (subset_last_ == -2) subset_last_ = Index(container.count(ElementType::edge)) - 1;
    bool changed = false;
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::added, ElementType::edge)) {
            subset_last_ += Index(c.indices.size());  // new edges are not added to the subset
        } else if (c.is(TopologyChangeKind::removed, ElementType::edge)) {
            Index last = subset_last_;  // a copy: SOFA does not store it back
            for (const ElementId removed : c.indices) {
                if (edges_.empty()) break;
                for (std::size_t k = edges_.size(); k-- > 0;) {
                    if (edges_[k] != removed) continue;
                    edges_.erase(edges_.begin() + std::ptrdiff_t(k));
                    rest_lengths_.erase(rest_lengths_.begin() + std::ptrdiff_t(k));
                    forces_.erase(forces_.begin() + std::ptrdiff_t(k));
                }
                std::replace(edges_.begin(), edges_.end(), last, Index(removed));
                --last;
            }
            changed = true;
        }
    }
    if (changed) pending_init_ = true;
}

// SOFA's addForce recomputes every entry's P·L₀ from the topology's current edge (initEdgeInformation).
void EdgePressureForceField::topology_change_done() {
    if (!pending_init_) return;
    pending_init_ = false;
    init();
}

void TrianglePressureForceField::handle_topology_changes(const TopologyContainer&, std::span<const TopologyChange> changes) {
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::added, ElementType::triangle)) {
            subset_last_ += Index(c.indices.size());  // new triangles are not added to the subset
        } else if (c.is(TopologyChangeKind::removed, ElementType::triangle)) {
            Index last = subset_last_;  // a copy: SOFA does not store it back
            for (const ElementId removed : c.indices) {
                if (triangles_.empty()) break;
                for (std::size_t k = triangles_.size(); k-- > 0;) {
                    if (triangles_[k] != removed) continue;
                    triangles_.erase(triangles_.begin() + std::ptrdiff_t(k));
                    rest_areas_.erase(rest_areas_.begin() + std::ptrdiff_t(k));
                    forces_.erase(forces_.begin() + std::ptrdiff_t(k));
                }
                std::replace(triangles_.begin(), triangles_.end(), last, Index(removed));
                --last;
            }
        }
    }
}

}  // namespace penalty
