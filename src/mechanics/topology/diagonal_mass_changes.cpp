// DiagonalMass::handle_topology_changes: SOFA's DiagonalMass topology callbacks
// (applyPointCreation, applyPointDestruction, applyEdge/Triangle/Quad/Tetrahedron/Hexahedron-
// Creation and -Destruction) and the vertex masses' TopologyData rules.
#include "penalty/mechanics/diagonal_mass.hpp"

#include "penalty/mechanics/topology_container.hpp"
#include "penalty/mechanics/topology_data.hpp"

#include <limits>
#include <numeric>

namespace penalty {

void DiagonalMass::handle_topology_changes(const TopologyContainer& container,
                                           std::span<const TopologyChange> changes) {
    const ElementType lumped = element_type_of(kind_);
    const auto& x0 = state_->rest_position;
    // the share of element `id`: mass = ρ·measure/N (DataTypes::Real), added or removed at each
    // vertex, and N·mass from the total
    const auto apply = [&](ElementId id, double sign) {
        const auto v = container.vertices(lumped, id);
        std::array<Vec3, 8> p;
        for (std::size_t k = 0; k < v.size(); ++k) p[k] = x0[std::size_t(v[k])];
        const double n = double(v.size());
        const double mass = (density_ * lumped_element_measure(kind_, std::span<const Vec3>(p.data(), v.size()))) / n;
        for (const PointId vertex : v) masses_[std::size_t(vertex)] += sign * mass;
        total_ += sign * (n * mass);
    };
    for (const TopologyChange& c : changes) {
        if (c.element == ElementType::point) {
            // TopologyData's append, swap-and-pop or permutation writes d_vertexMass after the
            // point callbacks (SOFA's topology data ignore a move)
            const bool writes = c.kind == TopologyChangeKind::added || c.kind == TopologyChangeKind::removed ||
                                c.kind == TopologyChangeKind::renumbered;
            vertex_masses_edited_ = vertex_masses_edited_ || writes;
            if (c.kind == TopologyChangeKind::added) {
                masses_.resize(masses_.size() + c.indices.size(), 0.0);  // applyPointCreation: m = 0
            } else if (c.kind == TopologyChangeKind::removed) {
                topology_data_remove(masses_, c.indices, [&](ElementId, double& m) { total_ -= m; });
            } else if (c.kind == TopologyChangeKind::renumbered) {
                topology_data_renumber(masses_, c.indices);
            }
        } else if (c.element == lumped && c.kind == TopologyChangeKind::added) {
            for (const ElementId id : c.indices) apply(id, +1.0);
            vertex_masses_edited_ = false;  // apply<Element>Creation ends with cleanTracker()
        } else if (c.element == lumped && c.kind == TopologyChangeKind::removed) {
            for (const ElementId id : c.indices) apply(id, -1.0);
            vertex_masses_edited_ = false;  // apply<Element>Destruction ends with cleanTracker()
        }
    }
}

void DiagonalMass::update_internal_data() {
    if (!vertex_masses_edited_) return;
    vertex_masses_edited_ = false;
    // initFromVertexMass: the total as std::accumulate sums it, ρ from computeVertexMass(1)
    total_ = std::accumulate(masses_.begin(), masses_.end(), 0.0);
    std::vector<double> at_unit_density;
    const double sum = lump_vertex_masses(*topology_, kind_, std::span<const Vec3>(state_->rest_position), 1.0,
                                          state_->num_dofs(), at_unit_density);
    density_ = sum < std::numeric_limits<double>::epsilon() ? 1.0 : total_ / sum;
}

}  // namespace penalty
