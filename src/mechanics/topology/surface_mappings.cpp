// Hexa2QuadTopologicalMapping, Quad2TriangleTopologicalMapping and Triangle2EdgeTopologicalMapping
// ::updateTopologicalMappingTopDown, event by event, with their maps' bookkeeping as SOFA writes it.
#include "penalty/mechanics/topological_mapping_changes.hpp"

#include <algorithm>
#include <functional>

namespace penalty {

namespace {

/// The one-by-one removal of Hexa2Quad's QUADSREMOVED and Triangle2Edge's EDGESREMOVED: each mapped
/// input element leaves the maps (a swap with the input's last element, then with the output's
/// last one) and its output element is removed alone.
void remove_one_by_one(const TopologyChange& c, std::size_t input_count, std::size_t output_count,
                       std::vector<ElementId>& loc2glob, std::map<ElementId, ElementId>& glob2loc,
                       const std::function<void(ElementId)>& remove_output) {
    auto last = ElementId(input_count) - 1;
    auto ind_last = ElementId(output_count);
    for (const ElementId k : c.indices) {
        if (glob2loc.count(k) != 0) {
            --ind_last;
            const ElementId ind_k = glob2loc[k];
            if (glob2loc.count(last) != 0) {
                const ElementId ind_real_last = glob2loc[last];
                if (k != last) {
                    glob2loc[k] = ind_real_last;
                    glob2loc[last] = ind_k;
                    std::swap(loc2glob[std::size_t(ind_real_last)], loc2glob[std::size_t(ind_k)]);
                }
            }
            if (ind_k != ind_last) {
                glob2loc[loc2glob[std::size_t(ind_last)]] = ind_k;
                glob2loc[loc2glob[std::size_t(ind_k)]] = ind_last;
                std::swap(loc2glob[std::size_t(ind_k)], loc2glob[std::size_t(ind_last)]);
            }
            glob2loc.erase(loc2glob.back());
            loc2glob.pop_back();
            remove_output(ind_k);
        }
        --last;
    }
}

}  // namespace

// ---- Hexa2Quad ----------------------------------------------------------------------------------

Hexa2QuadMappingFollower::Hexa2QuadMappingFollower(TopologyContainer& input, TopologyContainer& output,
                                                   bool flip_normals)
    : TopologicalMappingFollower(input, output), flip_normals_(flip_normals) {
    const auto& around = input.hexahedra_around_quad();
    for (std::size_t q = 0; q < around.size(); ++q) {
        if (around[q].size() != 1) continue;
        loc2glob_.push_back(ElementId(q));
        glob2loc_[ElementId(q)] = ElementId(loc2glob_.size()) - 1;
    }
}

void Hexa2QuadMappingFollower::handle_topology_changes(std::span<const TopologyChange> changes) {
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::removed, ElementType::quad)) {
            remove_one_by_one(c, input_->count(ElementType::quad), output_->count(ElementType::quad), loc2glob_,
                              glob2loc_, [this](ElementId q) { output_->remove_quads({q}, true, false); });
        } else if (c.is(TopologyChangeKind::removed, ElementType::hexahedron)) {
            hexahedra_removed(c);
        } else if (c.kind == TopologyChangeKind::ending || c.is(TopologyChangeKind::removed, ElementType::point)) {
            forward_common(c);
        }
    }
}

ElementId Hexa2QuadMappingFollower::input_cell_of(ElementId q) const {
    if (q < 0 || std::size_t(q) >= loc2glob_.size()) return -1;
    const auto& around = input_->hexahedra_around_quad()[std::size_t(loc2glob_[std::size_t(q)])];
    return around.size() == 1 ? around[0] : 0;
}

// HEXAHEDRAREMOVED (before they go): a face shared with a hexahedron that stays becomes visible,
// as a face of that hexahedron.
void Hexa2QuadMappingFollower::hexahedra_removed(const TopologyChange& c) {
    const auto& hexahedra = input_->mesh().hexahedra();
    std::vector<Quad> created;
    for (std::size_t i = 0; i < c.indices.size(); ++i) {
        const ElementId hexa = c.indices[i];
        for (std::size_t j = 0; j < 6; ++j) {
            const ElementId k = input_->quads_in_hexahedron()[std::size_t(hexa)][j];
            const auto& around = input_->hexahedra_around_quad()[std::size_t(k)];
            if (around.size() == 1) continue;  // removed with it (QUADSREMOVED)
            const ElementId other = hexa == around[0] ? around[1] : around[0];
            if (std::find(c.indices.begin(), c.indices.begin() + std::ptrdiff_t(i), other) !=
                c.indices.begin() + std::ptrdiff_t(i))
                continue;
            const auto& faces = input_->quads_in_hexahedron()[std::size_t(other)];
            const auto h = std::size_t(std::find(faces.begin(), faces.end(), k) - faces.begin());
            const Hexahedron& he = hexahedra[std::size_t(other)];
            const auto& f = MeshTopology::kHexaFaces[h];
            Quad q{he[std::size_t(f[0])], he[std::size_t(f[1])], he[std::size_t(f[2])], he[std::size_t(f[3])]};
            if (flip_normals_) q = Quad{q[3], q[2], q[1], q[0]};
            created.push_back(q);
            loc2glob_.push_back(k);
            glob2loc_[k] = ElementId(loc2glob_.size()) - 1;
        }
    }
    output_->add_quads(created);
}

// ---- Quad2Triangle ------------------------------------------------------------------------------

Quad2TriangleMappingFollower::Quad2TriangleMappingFollower(TopologyContainer& input, TopologyContainer& output)
    : TopologicalMappingFollower(input, output) {
    for (std::size_t q = 0; q < input.count(ElementType::quad); ++q) {
        loc2glob_.push_back(ElementId(q));
        loc2glob_.push_back(ElementId(q));
        in2out_[ElementId(q)] = {ElementId(loc2glob_.size()) - 2, ElementId(loc2glob_.size()) - 1};
    }
}

void Quad2TriangleMappingFollower::handle_topology_changes(std::span<const TopologyChange> changes) {
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::added, ElementType::quad)) {
            // QUADSADDED: (p0, p1, p2) and (p0, p2, p3) (not init's split)
            std::vector<Triangle> created;
            for (const ElementId k : c.indices) {
                const Quad& q = input_->mesh().quads()[std::size_t(k)];
                created.push_back({q[0], q[1], q[2]});
                created.push_back({q[0], q[2], q[3]});
                loc2glob_.push_back(k);
                loc2glob_.push_back(k);
                in2out_[k] = {ElementId(loc2glob_.size()) - 2, ElementId(loc2glob_.size()) - 1};
            }
            output_->add_triangles(created);
        } else if (c.is(TopologyChangeKind::removed, ElementType::quad)) {
            quads_removed(c);
        } else if (c.is(TopologyChangeKind::added, ElementType::point)) {
            output_->add_points(c.indices.size(), c.ancestors, c.coefficients, false);
        } else {
            forward_common(c);
        }
    }
}

// QUADSREMOVED: each mapped quad's two triangles go, one quad at a time, the maps following SOFA's
// swaps.
void Quad2TriangleMappingFollower::quads_removed(const TopologyChange& c) {
    auto last = ElementId(input_->count(ElementType::quad)) - 1;
    auto ind_last = ElementId(output_->count(ElementType::triangle));
    for (const ElementId k : c.indices) {
        if (in2out_.count(k) != 0) {
            const auto ind_k = in2out_[k];
            const ElementId t1 = ind_k[0], t2 = ind_k[1];
            --ind_last;
            if (in2out_.count(last) != 0) {
                const auto ind_real_last = in2out_[last];
                if (k != last) {
                    in2out_[k] = ind_real_last;
                    in2out_[last] = ind_k;
                    std::swap(loc2glob_[std::size_t(ind_real_last[0])], loc2glob_[std::size_t(ind_k[0])]);
                    std::swap(loc2glob_[std::size_t(ind_real_last[1])], loc2glob_[std::size_t(ind_k[1])]);
                }
            }
            if (ind_k[1] != ind_last) {
                in2out_[loc2glob_[std::size_t(ind_last)]] = ind_k;
                in2out_[loc2glob_[std::size_t(ind_k[1])]] = {ind_last, ind_last - 1};
                std::swap(loc2glob_[std::size_t(ind_k[1])], loc2glob_[std::size_t(ind_last)]);
            }
            --ind_last;
            if (ind_k[0] != ind_last) std::swap(loc2glob_[std::size_t(ind_k[0])], loc2glob_[std::size_t(ind_last)]);
            in2out_.erase(loc2glob_.back());
            loc2glob_.resize(loc2glob_.size() - 2);
            output_->remove_triangles({t1, t2}, true, false);
        }
        --last;
    }
}

// ---- Triangle2Edge ------------------------------------------------------------------------------

Triangle2EdgeMappingFollower::Triangle2EdgeMappingFollower(TopologyContainer& input, TopologyContainer& output)
    : TopologicalMappingFollower(input, output) {
    const auto& around = input.mesh().triangles_around_edge();
    for (std::size_t e = 0; e < around.size(); ++e) {
        if (around[e].size() != 1) continue;
        loc2glob_.push_back(ElementId(e));
        glob2loc_[ElementId(e)] = ElementId(loc2glob_.size()) - 1;
    }
}

void Triangle2EdgeMappingFollower::handle_topology_changes(std::span<const TopologyChange> changes) {
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::removed, ElementType::edge)) {
            remove_one_by_one(c, input_->count(ElementType::edge), output_->count(ElementType::edge), loc2glob_,
                              glob2loc_, [this](ElementId e) { output_->remove_edges({e}, false); });
        } else if (c.is(TopologyChangeKind::removed, ElementType::triangle)) {
            triangles_removed(c);
        } else if (c.is(TopologyChangeKind::added, ElementType::triangle)) {
            triangles_added(c);
        } else if (c.is(TopologyChangeKind::added, ElementType::point)) {
            output_->add_points(c.indices.size(), c.ancestors, c.coefficients, false);
        } else {
            forward_common(c);
        }
    }
}

// TRIANGLESREMOVED (before they go): an edge shared with a triangle that stays becomes a border
// edge, smallest vertex first.
void Triangle2EdgeMappingFollower::triangles_removed(const TopologyChange& c) {
    const MeshTopology& m = input_->mesh();
    std::vector<Edge> created;
    for (std::size_t i = 0; i < c.indices.size(); ++i) {
        const ElementId t = c.indices[i];
        for (const std::int32_t e : m.edges_in_triangle()[std::size_t(t)]) {
            const auto& around = m.triangles_around_edge()[std::size_t(e)];
            if (around.size() != 2) continue;
            const ElementId neighbour = t == around[0] ? around[1] : around[0];
            if (std::find(c.indices.begin(), c.indices.begin() + std::ptrdiff_t(i), neighbour) !=
                c.indices.begin() + std::ptrdiff_t(i))
                continue;
            Edge edge = m.edges()[std::size_t(e)];
            if (edge[0] > edge[1]) std::swap(edge[0], edge[1]);
            created.push_back(edge);
            loc2glob_.push_back(e);
            glob2loc_[e] = ElementId(loc2glob_.size()) - 1;
        }
    }
    output_->add_edges(created);
}

// TRIANGLESADDED: the new triangles' edges on one triangle join the output; mapped edges now
// inside leave it (SOFA's bookkeeping, in decreasing input order).
void Triangle2EdgeMappingFollower::triangles_added(const TopologyChange& c) {
    const MeshTopology& m = input_->mesh();
    std::vector<Edge> created;
    std::vector<ElementId> inside;
    for (const ElementId t : c.indices) {
        for (const std::int32_t e : m.edges_in_triangle()[std::size_t(t)]) {
            const std::size_t around = m.triangles_around_edge()[std::size_t(e)].size();
            if (glob2loc_.count(e) != 0) {
                if (around != 1) inside.push_back(e);
            } else if (around <= 1) {
                created.push_back(m.edges()[std::size_t(e)]);
                loc2glob_.push_back(e);
                glob2loc_[e] = ElementId(loc2glob_.size()) - 1;
            }
        }
    }
    output_->add_edges(created);
    std::sort(inside.begin(), inside.end(), std::greater<>());
    std::vector<ElementId> local;
    for (const ElementId g : inside) {
        const auto it = glob2loc_.find(g);
        if (it == glob2loc_.end()) continue;
        const ElementId l = it->second;
        const ElementId last_global = loc2glob_.back();
        loc2glob_[std::size_t(l)] = last_global;
        loc2glob_.pop_back();
        glob2loc_.erase(it);
        glob2loc_[last_global] = l;
        local.push_back(l);
    }
    output_->remove_edges(local);
}

}  // namespace penalty
