// Tetra2TriangleTopologicalMapping::updateTopologicalMappingTopDown, event by event, and what every
// topological mapping forwards (ENDING_EVENT, POINTSADDED, POINTSREMOVED).
#include "penalty/mechanics/topological_mapping_changes.hpp"

#include <algorithm>
#include <functional>

namespace penalty {

bool TopologicalMappingFollower::forward_common(const TopologyChange& c) {
    switch (c.kind) {
        case TopologyChangeKind::ending:
            output_->notify_ending_event();
            return true;
        case TopologyChangeKind::added:
            if (c.element != ElementType::point) return false;
            output_->add_points(c.indices.size(), c.ancestors, c.coefficients, true);
            return true;
        case TopologyChangeKind::removed:
            if (c.element != ElementType::point) return false;
            output_->remove_points(c.indices, false);
            return true;
        case TopologyChangeKind::renumbered:
        case TopologyChangeKind::moved:
            return false;
    }
    return false;
}

Tetra2TriangleMappingFollower::Tetra2TriangleMappingFollower(TopologyContainer& input, TopologyContainer& output,
                                                             bool flip_normals, bool no_new_triangles,
                                                             bool no_initial_triangles)
    : TopologicalMappingFollower(input, output), flip_normals_(flip_normals), no_new_triangles_(no_new_triangles) {
    if (no_initial_triangles) return;
    const auto& around = input.tetrahedra_around_triangle();
    for (std::size_t t = 0; t < around.size(); ++t) {
        if (around[t].size() != 1) continue;
        loc2glob_.push_back(ElementId(t));
        glob2loc_[ElementId(t)] = ElementId(loc2glob_.size()) - 1;
    }
}

void Tetra2TriangleMappingFollower::handle_topology_changes(std::span<const TopologyChange> changes) {
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::removed, ElementType::triangle)) triangles_removed(c);
        else if (c.is(TopologyChangeKind::added, ElementType::tetrahedron)) tetrahedra_added(c);
        else if (c.is(TopologyChangeKind::removed, ElementType::tetrahedron)) tetrahedra_removed(c);
        else if (c.is(TopologyChangeKind::added, ElementType::edge)) {
            std::vector<Edge> edges;
            for (std::size_t k = 0; k < c.indices.size(); ++k) edges.push_back(c.added_element<2>(k));
            output_->add_edges(edges, c.ancestors, c.coefficients);
        } else {
            forward_common(c);
        }
    }
}

// getFromIndex(getGlobIndex(t)): the tetrahedron of the input triangle, when it has one only.
ElementId Tetra2TriangleMappingFollower::input_cell_of(ElementId t) const {
    if (t < 0 || std::size_t(t) >= loc2glob_.size()) return -1;
    const auto& around = input_->tetrahedra_around_triangle()[std::size_t(loc2glob_[std::size_t(t)])];
    return around.size() == 1 ? around[0] : 0;
}

// TRIANGLESREMOVED: the output triangles of the removed input triangles go; the maps follow both
// swap-and-pops (the input's, then the output's).
void Tetra2TriangleMappingFollower::triangles_removed(const TopologyChange& c) {
    std::vector<ElementId> local;
    for (const ElementId g : c.indices) {
        const auto it = glob2loc_.find(g);
        if (it != glob2loc_.end()) local.push_back(it->second);
    }
    std::sort(local.begin(), local.end(), std::greater<>());
    const auto input_count = ElementId(input_->count(ElementType::triangle));
    auto last_global = input_count - 1;
    const auto remaining_global = input_count - ElementId(c.indices.size());
    const auto remaining_local = ElementId(output_->count(ElementType::triangle)) - ElementId(local.size());
    for (const ElementId old_global : c.indices) {
        auto it = glob2loc_.find(last_global);
        if (it != glob2loc_.end()) {
            const ElementId last_local = it->second;
            glob2loc_[old_global] = last_local;
            if (std::size_t(last_local) < loc2glob_.size()) loc2glob_[std::size_t(last_local)] = old_global;
            it = glob2loc_.find(last_global);  // (the insertion above does not move it)
        } else {
            it = glob2loc_.find(old_global);
            if (it == glob2loc_.end()) {
                --last_global;
                continue;
            }
        }
        glob2loc_.erase(it);
        --last_global;
    }
    for (const ElementId old_local : local) {
        const ElementId new_global = loc2glob_.back();
        loc2glob_[std::size_t(old_local)] = new_global;
        if (new_global < remaining_global && old_local < remaining_local) glob2loc_[new_global] = old_local;
        loc2glob_.pop_back();
    }
    output_->remove_triangles(local, true, false);
}

// TETRAHEDRAADDED: faces of the new tetrahedra on one tetrahedron join the output; mapped faces
// now inside leave it.
void Tetra2TriangleMappingFollower::tetrahedra_added(const TopologyChange& c) {
    if (no_new_triangles_) return;
    std::vector<Triangle> created;
    std::vector<ElementId> inside;
    for (const ElementId tet : c.indices) {
        for (const ElementId g : input_->triangles_in_tetrahedron()[std::size_t(tet)]) {
            const std::size_t around = input_->tetrahedra_around_triangle()[std::size_t(g)].size();
            if (glob2loc_.count(g) != 0) {
                if (around != 1) inside.push_back(g);
            } else if (around <= 1) {
                created.push_back(input_->mesh().triangles()[std::size_t(g)]);
                loc2glob_.push_back(g);
                glob2loc_[g] = ElementId(loc2glob_.size()) - 1;
            }
        }
    }
    output_->add_triangles(created);
    std::vector<ElementId> local;
    for (const ElementId g : inside) {
        const auto it = glob2loc_.find(g);
        if (it == glob2loc_.end()) continue;
        local.push_back(it->second);
        glob2loc_.erase(it);
    }
    std::sort(local.begin(), local.end(), std::greater<>());
    for (const ElementId l : local) {
        const ElementId last_global = loc2glob_.back();
        loc2glob_[std::size_t(l)] = last_global;
        loc2glob_.pop_back();
        glob2loc_[last_global] = l;
    }
    output_->remove_triangles(local, true, false);
}

// TETRAHEDRAREMOVED (before they go): a face shared with a tetrahedron that stays becomes a border
// triangle, oriented as a face of that tetrahedron, smallest vertex first.
void Tetra2TriangleMappingFollower::tetrahedra_removed(const TopologyChange& c) {
    if (no_new_triangles_) return;
    const auto& tetrahedra = input_->mesh().tetrahedra();
    std::vector<Triangle> created;
    for (std::size_t i = 0; i < c.indices.size(); ++i) {
        const ElementId tet = c.indices[i];
        for (const ElementId g : input_->triangles_in_tetrahedron()[std::size_t(tet)]) {
            const auto& around = input_->tetrahedra_around_triangle()[std::size_t(g)];
            if (around.size() != 2) continue;
            const ElementId other = around[0] == tet ? around[1] : around[0];
            if (std::find(c.indices.begin(), c.indices.begin() + std::ptrdiff_t(i), other) !=
                c.indices.begin() + std::ptrdiff_t(i))
                continue;
            const auto& faces = input_->triangles_in_tetrahedron()[std::size_t(other)];
            const auto at = std::size_t(std::find(faces.begin(), faces.end(), g) - faces.begin());
            const auto& orientation = MeshTopology::kTetraFaces[at];
            const Tetrahedron& o = tetrahedra[std::size_t(other)];
            Triangle tri{o[std::size_t(orientation[0])], o[std::size_t(orientation[1])],
                         o[std::size_t(orientation[2])]};
            if (flip_normals_) std::swap(tri[1], tri[2]);
            while (tri[0] > tri[1] || tri[0] > tri[2]) tri = Triangle{tri[1], tri[2], tri[0]};
            created.push_back(tri);
            loc2glob_.push_back(g);
            glob2loc_[g] = ElementId(loc2glob_.size()) - 1;
        }
    }
    output_->add_triangles(created);
}

}  // namespace penalty
