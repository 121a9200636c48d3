// TetrahedronFEMForceField's topological changes (docs/topological-changes.md). SOFA's
// TetrahedronFEMForceField recomputes every element at the next addForce after a change
// (needUpdateTopology → reinit()); each element's data is a function of its own vertices' rest
// positions, so following the container's swap-and-pop, appending the new elements and
// refreshing the vertices of the elements on renumbered points gives the same data in time
// proportional to the change (tests/scene/test_topological_changes.cpp compares with a fresh
// build on the reduced mesh).
#include "penalty/core/error.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <algorithm>

namespace penalty {

void TetrahedronFEMForceField::handle_topology_changes(const TopologyContainer& container,
                                                       std::span<const TopologyChange> changes) {
    pending_.container = &container;
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::removed, ElementType::tetrahedron)) {
            if (pending_.first_new != std::numeric_limits<std::size_t>::max())
                pending_.rebuild = true;  // new ones moved
            if (pending_.rebuild) continue;
            const std::size_t n = elements_.size();
            const bool lanes = large_fits(n);
            const auto swap_pop = [&](auto& data, std::size_t i, std::size_t last) {
                if (data.size() != n) return;  // not used by this method
                if (i != last) data[i] = data[last];
            };
            std::size_t last = n;
            for (const ElementId id : c.indices) {
                const auto i = std::size_t(id);
                PENALTY_DEMAND(last > 0 && i < last);
                --last;
                swap_pop(elements_, i, last);
                swap_pop(ke_, i, last);
                swap_pop(stiffness_rest_, i, last);
                swap_pop(rest_local_, i, last);
                swap_pop(rotation_, i, last);
                if (lanes && i != last) copy_large(last, i);  // J, D/(36V) and R
                swap_pop(rest_edges_inverse_, i, last);
                swap_pop(rest_rotation_, i, last);
                pending_.moved.push_back(i);
            }
            const auto shrink = [&](auto& data) {
                if (data.size() == n) data.resize(last);
            };
            shrink(ke_);
            shrink(stiffness_rest_);
            shrink(rest_local_);
            shrink(rotation_);
            if (lanes) resize_large(last);
            shrink(rest_edges_inverse_);
            shrink(rest_rotation_);
            elements_.resize(last);
        } else if (c.is(TopologyChangeKind::added, ElementType::tetrahedron)) {
            pending_.first_new = std::min(pending_.first_new, elements_.size());
            for (std::size_t k = 0; k < c.indices.size(); ++k) elements_.push_back(c.added_element<4>(k));
        } else if (c.is(TopologyChangeKind::removed, ElementType::point)) {
            pending_.renumbered.insert(pending_.renumbered.end(), c.indices.begin(), c.indices.end());
        } else if (c.kind == TopologyChangeKind::renumbered &&
                   (c.element == ElementType::tetrahedron || c.element == ElementType::point)) {
            pending_.rebuild = true;
        }
    }
}

void TetrahedronFEMForceField::topology_change_done() {
    if (pending_.container == nullptr) return;
    const MeshTopology& mesh = pending_.container->mesh();
    PendingTopologyChange pending = std::move(pending_);
    pending_ = {};
    // SOFA's reinit: _plasticStrains.resize(element count): the strains stay with the slots (not
    // the elements a swap-and-pop moves), new slots start at zero
    if (!plastic_strain_.empty()) plastic_strain_.resize(mesh.tetrahedra().size(), std::array<double, 6>{});
    if (pending.rebuild) {
        set_elements(mesh.tetrahedra());
        init();
        return;
    }
    const auto& tetrahedra = mesh.tetrahedra();
    PENALTY_DEMAND(tetrahedra.size() == elements_.size());
    std::vector<std::size_t>& changed = pending.moved;
    // the elements on a point that took the last point's index (swap-and-pop of the points)
    const auto& around = mesh.tetrahedra_around_vertex();
    for (const PointId p : pending.renumbered)
        if (std::size_t(p) < around.size())
            for (const auto e : around[std::size_t(p)]) changed.push_back(std::size_t(e));
    for (const std::size_t e : changed)
        if (e < elements_.size()) elements_[e] = tetrahedra[e];
    product_scatter_.clear();  // the moved and renumbered elements' vertices
    if (pending.first_new < elements_.size()) init_elements(pending.first_new);
}

}  // namespace penalty
