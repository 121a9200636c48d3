#pragma once
/// @file
/// SOFA's topological change events (core::topology::TopologyChange and its subclasses
/// PointsAdded, PointsRemoved, PointsRenumbering, EdgesAdded, ..., HexahedraRemoved, EndingEvent)
/// and the two interfaces through which the components of a scene follow them:
///  - TopologyHandler: what SOFA's TopologyData handlers and handleTopologyChange() do. It gets
///    the whole list of events of one propagation (TopologyContainer::propagate), in order.
///  - StateFollower: what SOFA's MechanicalObject::handleStateChange does (the states' vectors
///    follow the points: swap-and-pop on removal, weighted ancestors on addition).
/// See docs/topological-changes.md for the order in which a change reaches each of them.

#include "penalty/mechanics/topology.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace penalty {

/// Index of an element (point, edge, ... hexahedron) in its list.
using ElementId = std::int32_t;

/// The kinds of topological element, lowest first (SOFA's geometry::ElementType order for these).
enum class ElementType : std::uint8_t { point, edge, triangle, quad, tetrahedron, hexahedron };
inline constexpr int kElementTypeCount = 6;

/// "points", "edges", "triangles", "quads", "tetrahedra", "hexahedra".
[[nodiscard]] const char* element_type_name(ElementType type);
/// Vertices of one element: 1, 2, 3, 4, 4, 8.
[[nodiscard]] constexpr int vertices_per_element(ElementType type) {
    constexpr int kCount[] = {1, 2, 3, 4, 4, 8};
    return kCount[static_cast<int>(type)];
}

/// The change an event reports (SOFA's TopologyChangeType: ...ADDED, ...REMOVED,
/// POINTSRENUMBERING, ENDING_EVENT).
/// `moved`: SOFA's POINTSMOVED, a state event only (TriangleSetTopologyModifier::movePointsProcess;
/// SOFA's topology data ignore it).
enum class TopologyChangeKind : std::uint8_t { added, removed, renumbered, ending, moved };

/// SOFA's PointAncestorElem of a new point: the edge or triangle it lies in (by its vertices at
/// the addition) and its local coordinates there (edge: [0] from vertex 0; triangle: [0], [1]
/// along the edges from vertex 0, [2] along the unit normal).
struct PointAncestorElement {
    ElementType type = ElementType::point;
    std::array<PointId, 3> vertices{};
    std::array<double, 3> local{};
};

/// One event. Removal events are sent before the elements are removed (their indices are valid
/// in the container then), addition events after the elements are appended.
struct TopologyChange {
    TopologyChangeKind kind = TopologyChangeKind::ending;
    ElementType element = ElementType::point;
    /// removed: the indices, sorted in decreasing order (the order the swap-and-pop follows);
    /// added: the new indices (the end of the list, increasing); renumbered: SOFA's `index`
    /// (new i takes the old index[i]).
    std::vector<ElementId> indices;
    /// renumbered: SOFA's `inv_index` (old i becomes inverse[i]).
    std::vector<ElementId> inverse;
    /// added: the elements' vertices, vertices_per_element(element) per element (points: none).
    std::vector<PointId> vertices;
    /// added: per new element, the ancestors (elements of the same type, points for points) and
    /// their barycentric coefficients (both may be empty).
    std::vector<std::vector<ElementId>> ancestors;
    std::vector<std::vector<double>> coefficients;
    /// added points, when given: their ancestor elements; a state's coordinates (positions, rest
    /// positions) then come from them (...SetGeometryAlgorithms::initPointAdded), its
    /// derivatives stay weighted. moved points: `indices`, `ancestors`, `coefficients`.
    std::vector<PointAncestorElement> ancestor_elements;

    /// Vertices of added element k.
    template <std::size_t N>
    [[nodiscard]] std::array<PointId, N> added_element(std::size_t k) const {
        std::array<PointId, N> e{};
        for (std::size_t j = 0; j < N; ++j) e[j] = vertices[k * N + j];
        return e;
    }
    [[nodiscard]] bool is(TopologyChangeKind k, ElementType t) const { return kind == k && element == t; }
};

/// Follows the topological changes of one container (SOFA's TopologyHandler: a TopologyData's
/// handler, a topological mapping's updateTopologicalMappingTopDown, a component's
/// handleTopologyChange). `changes` is the container's whole list for one propagation, ending
/// with an `ending` event; the handler acts on the kinds it knows and ignores the others.
class TopologyHandler {
public:
    virtual ~TopologyHandler() = default;
    virtual void handle_topology_changes(std::span<const TopologyChange> changes) = 0;
    /// Called once the container's operation (a removal or an addition, with its isolated items
    /// and the states) is complete: a handler that rebuilds from the container does it here.
    virtual void topology_change_done() {}
};

/// Follows the points of one container with a state's vectors (SOFA's
/// MechanicalObject::handleStateChange): `change` is a points `removed`, `added` or `renumbered`
/// event, sent once the topology's handlers have seen it (removal) or before (addition).
class StateFollower {
public:
    virtual ~StateFollower() = default;
    virtual void handle_state_change(const TopologyChange& change) = 0;
};

}  // namespace penalty
