// TriangularBiquadraticSpringsForceField::handle_topology_changes and
// TriangularQuadraticSpringsForceField::handle_topology_changes: SOFA's TopologyData callbacks of
// their edgeInfo and triangleInfo (set in each class's init):
//  - edges added: applyEdgeCreation (rest length, stiffness 0), appended;
//  - triangles added: applyTriangleCreation (its s_j added to its edges' stiffness), appended;
//  - triangles removed: applyTriangleDestruction (its s_j taken from its edges' stiffness: a
//    subtraction, not a new sum), then the triangle data's swap-and-pop (TopologyData::remove);
//  - edges removed: the edge data's swap-and-pop (no callback).
// Point events change no data of these force fields (the edges keep their rest lengths).
#include "penalty/mechanics/topology_container.hpp"
#include "penalty/mechanics/topology_data.hpp"
#include "penalty/mechanics/triangular_biquadratic_springs.hpp"
#include "penalty/mechanics/triangular_quadratic_springs.hpp"

namespace penalty {

namespace {

/// The shared walk: `edge_data` every per-edge vector, `create_edge(e)`, `create_triangle(t)`.
template <class TriangleData, class CreateEdge, class CreateTriangle>
void follow_edge_and_triangle_data(const TopologyContainer& container, std::span<const TopologyChange> changes,
                                   std::initializer_list<std::vector<double>*> edge_data,
                                   std::vector<double>& edge_stiffness, std::vector<TriangleData>& triangles,
                                   CreateEdge&& create_edge, CreateTriangle&& create_triangle) {
    const MeshTopology& mesh = container.mesh();
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::added, ElementType::edge)) {
            for (std::vector<double>* d : edge_data) d->resize(d->size() + c.indices.size(), 0.0);
            for (const ElementId e : c.indices) create_edge(std::size_t(e));
        } else if (c.is(TopologyChangeKind::added, ElementType::triangle)) {
            triangles.resize(triangles.size() + c.indices.size());
            for (const ElementId t : c.indices) create_triangle(std::size_t(t));
        } else if (c.is(TopologyChangeKind::removed, ElementType::triangle)) {
            // sent before the removal: the container still holds each triangle's edges
            topology_data_remove(triangles, c.indices, [&](ElementId t, const TriangleData& td) {
                const auto& te = mesh.edges_in_triangle()[std::size_t(t)];
                for (std::size_t j = 0; j < 3; ++j) edge_stiffness[std::size_t(te[j])] -= td.stiffness[j];
            });
        } else if (c.is(TopologyChangeKind::removed, ElementType::edge)) {
            for (std::vector<double>* d : edge_data) topology_data_remove(*d, c.indices);
        }
    }
}

}  // namespace

void TriangularBiquadraticSpringsForceField::handle_topology_changes(const TopologyContainer& container,
                                                                     std::span<const TopologyChange> changes) {
    follow_edge_and_triangle_data(
        container, changes, {&rest_square_length_, &edge_stiffness_, &square_length_, &delta_}, edge_stiffness_,
        triangles_, [this](std::size_t e) { create_edge(e); }, [this](std::size_t t) { create_triangle(t); });
    scatter_.clear();
    product_.invalidate();
}

void TriangularQuadraticSpringsForceField::handle_topology_changes(const TopologyContainer& container,
                                                                   std::span<const TopologyChange> changes) {
    follow_edge_and_triangle_data(
        container, changes, {&rest_length_, &edge_stiffness_, &length_, &delta_}, edge_stiffness_, triangles_,
        [this](std::size_t e) { create_edge(e); }, [this](std::size_t t) { create_triangle(t); });
    scatter_.clear();
    product_.invalidate();
}

}  // namespace penalty
