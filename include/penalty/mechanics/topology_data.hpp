#pragma once
/// @file
/// SOFA's rules for the data a component keeps per element or for a subset of elements
/// (core::topology::TopologyData, TopologySubsetIndices), for the components' topology handlers:
///  - per-element data (one value per edge, triangle, ... of the container): a removal swaps each
///    removed value with the last one and pops it, indices in decreasing order (TopologyData::
///    remove), an addition appends (TopologyData::add), a renumbering permutes;
///  - a subset of indices (FixedProjectiveConstraint's `indices`, ...): a removed index leaves the
///    list (which keeps its order) and the entries naming the container's last element take the
///    removed one's index (TopologySubsetIndices::remove).

#include "penalty/mechanics/topology_change.hpp"

#include <algorithm>
#include <span>
#include <utility>
#include <vector>

namespace penalty {

/// TopologyData::remove: for each index of `removed` (decreasing), `on_destroy(index, value)`, then
/// the value swaps with the last one, which is popped.
template <class T, class OnDestroy>
void topology_data_remove(std::vector<T>& data, std::span<const ElementId> removed, OnDestroy&& on_destroy) {
    if (data.empty()) return;
    auto last = data.size() - 1;
    for (const ElementId i : removed) {
        on_destroy(i, data[std::size_t(i)]);
        std::swap(data[std::size_t(i)], data[last]);
        --last;
    }
    data.resize(data.size() - removed.size());
}

template <class T>
void topology_data_remove(std::vector<T>& data, std::span<const ElementId> removed) {
    topology_data_remove(data, removed, [](ElementId, T&) {});
}

/// TopologyData::renumber: new i takes old index[i].
template <class T>
void topology_data_renumber(std::vector<T>& data, std::span<const ElementId> index) {
    const std::vector<T> copy = data;
    for (std::size_t i = 0; i < index.size() && i < data.size(); ++i) data[i] = copy[std::size_t(index[i])];
}

/// TopologySubsetIndices::remove: `removed` (decreasing) from a container of `count` elements
/// (before the removal). Entries equal to a removed index are erased (the list keeps its order);
/// then the entries equal to the current last element take the removed index.
template <class IndexT>
void subset_indices_remove(std::vector<IndexT>& indices, std::span<const ElementId> removed, std::size_t count) {
    auto last = IndexT(count) - 1;
    for (const ElementId r : removed) {
        if (indices.empty()) return;
        indices.erase(std::remove(indices.begin(), indices.end(), IndexT(r)), indices.end());
        std::replace(indices.begin(), indices.end(), last, IndexT(r));
        --last;
    }
}

/// TopologySubsetIndices::renumber (TopologySubsetData::renumber): entry i takes the entry at
/// index[i] (SOFA permutes the list by the container's renumbering, as it does).
template <class IndexT>
void subset_indices_renumber(std::vector<IndexT>& indices, std::span<const ElementId> index) {
    const std::vector<IndexT> copy = indices;
    for (std::size_t i = 0; i < indices.size() && i < index.size(); ++i)
        if (std::size_t(index[i]) < copy.size()) indices[i] = copy[std::size_t(index[i])];
}

}  // namespace penalty
