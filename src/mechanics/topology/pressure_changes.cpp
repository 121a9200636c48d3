// EdgePressureForceField::handle_topology_changes, TrianglePressureForceField:: and
// QuadPressureForceField::handle_topology_changes: SOFA's EdgeSubsetData, TriangleSubsetData and
// QuadSubsetData rules for their edgePressureMap, trianglePressureMap and quadPressureMap (TopologySubsetData::remove:
// erase, keeping the order, then the entries of the last element renamed; add with supportNewTopologyElements false).
#include "penalty/mechanics/pressure_loads.hpp"

#include "penalty/core/error.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <algorithm>

namespace penalty {

void EdgePressureForceField::handle_topology_changes(const TopologyContainer& container,
                                                     std::span<const TopologyChange> changes) {
    // BaseTopologyData::setDataSetArraySize at the data's link: the last edge of the topology then
    if (subset_last_ == -2) subset_last_ = Index(container.count(ElementType::edge)) - 1;
    bool changed = false;
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::added, ElementType::edge)) {
            subset_last_ += Index(c.indices.size());  // new edges are not added to the subset
        } else if (c.is(TopologyChangeKind::removed, ElementType::edge)) {
            // a copy: SOFA does not store it back
            Index last = current_last_index_ ? Index(container.count(ElementType::edge)) - 1 : subset_last_;
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

namespace {

/// TopologySubsetData::add and ::remove on a pressure map over elements of `type`: `ids` the
/// map's elements, `columns` the per-entry data (erased with their entry). `subset_last` is the
/// subset data's last element index: raised by the added elements (which the subset does not
/// take), read but not lowered by a removal (SOFA keeps a local copy). With `current` (the fix
/// of that quirk) the last element is the container's (its count before the events).
template <class... Columns>
void follow_subset_data(Index& subset_last, const TopologyContainer* current, ElementType type, std::vector<Index>& ids,
                        std::span<const TopologyChange> changes, std::vector<Columns>&... columns) {
    Index current_last = current != nullptr ? Index(current->count(type)) - 1 : -1;
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::added, type)) {
            subset_last += Index(c.indices.size());
            current_last += Index(c.indices.size());
        } else if (c.is(TopologyChangeKind::removed, type)) {
            Index last = current != nullptr ? current_last : subset_last;
            current_last -= Index(c.indices.size());
            for (const ElementId removed : c.indices) {
                if (ids.empty()) break;
                for (std::size_t k = ids.size(); k-- > 0;) {
                    if (ids[k] != removed) continue;
                    ids.erase(ids.begin() + std::ptrdiff_t(k));
                    (columns.erase(columns.begin() + std::ptrdiff_t(k)), ...);
                }
                std::replace(ids.begin(), ids.end(), last, Index(removed));
                --last;
            }
        }
    }
}

/// Erases the entries of `ids` naming an element at or past `count`, with their columns.
template <class... Columns>
std::size_t drop_past_end(std::vector<Index>& ids, std::size_t count, std::vector<Columns>&... columns) {
    std::size_t dropped = 0;
    for (std::size_t k = ids.size(); k-- > 0;) {
        if (ids[k] >= 0 && std::size_t(ids[k]) < count) continue;
        ids.erase(ids.begin() + std::ptrdiff_t(k));
        (columns.erase(columns.begin() + std::ptrdiff_t(k)), ...);
        ++dropped;
    }
    return dropped;
}

}  // namespace

// (the events come before the container changes: its count is the one before each event)
void TrianglePressureForceField::handle_topology_changes(const TopologyContainer& container,
                                                         std::span<const TopologyChange> changes) {
    follow_subset_data(subset_last_, current_last_index_ ? &container : nullptr, ElementType::triangle, triangles_,
                       changes, rest_areas_, forces_);
}

std::size_t TrianglePressureForceField::drop_entries_past_end() {
    return drop_past_end(triangles_, topology_->triangles().size(), rest_areas_, forces_);
}

// QuadPressureForceField's quadPressureMap, a QuadSubsetData (init's createTopologyHandler):
// addForce reads each kept entry's force (P·A₀ of its quad at init) on its quad's current points.
void QuadPressureForceField::handle_topology_changes(const TopologyContainer& container,
                                                     std::span<const TopologyChange> changes) {
    follow_subset_data(subset_last_, current_last_index_ ? &container : nullptr, ElementType::quad, quads_, changes,
                       rest_areas_, forces_);
}

std::size_t QuadPressureForceField::drop_entries_past_end() {
    return drop_past_end(quads_, topology_->quads().size(), rest_areas_, forces_);
}

std::size_t EdgePressureForceField::drop_entries_past_end() {
    return drop_past_end(edges_, topology_->edges().size(), rest_lengths_, forces_);
}

}  // namespace penalty
