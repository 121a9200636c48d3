#pragma once
/// @file
/// SOFA's dynamic topology containers and modifiers (Point/Edge/Triangle/Quad/Tetrahedron/
/// HexahedronSetTopologyContainer and ...SetTopologyModifier) over a MeshTopology, which they
/// edit in place: every reader of the MeshTopology sees the changed mesh.
///
/// The container keeps SOFA's cross tables (elements around each vertex, edge, face; edges and
/// faces in each element) and updates them element by element, as SOFA's modifiers do: a removal
/// moves the last element into the removed one's slot (swap-and-pop, indices processed in
/// decreasing order), an addition appends. A removal's cost is proportional to the elements
/// removed and their neighbours, never to the mesh.
///
/// Events and their order (SOFA's): a change is announced (...Warning: the event joins the
/// container's list, its element type becomes dirty) and propagated (propagate(): an `ending`
/// event is appended; the handlers registered on each dirty element type run, highest type first,
/// each once, in registration order; then the listeners (topological mappings, then each
/// component's handleTopologyChange, in scene order); the list is cleared). A removal propagates
/// before the elements go (handlers see them), an addition after they are appended. Removing
/// elements of the container's highest type removes, in that order, the faces and edges no other
/// element uses (one propagation), then the points (another; SOFA's removeIsolatedItems); the
/// states follow the points (StateFollower) after the point handlers have run.

#include "penalty/mechanics/topology.hpp"
#include "penalty/mechanics/topology_change.hpp"

#include <array>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace penalty {

/// Options of SOFA's modifiers.
struct TopologyModifierOptions {
    /// TetrahedronSetTopologyModifier / HexahedronSetTopologyModifier `removeIsolated`: points no
    /// element uses any more are removed with the elements.
    bool remove_isolated = true;
    /// PointSetTopologyModifier `propagateToDOF`: the states follow point removals.
    bool propagate_to_dof = true;
};

/// The operations in progress over containers that change one another (a topological mapping's
/// input and output share one): the handlers' topology_change_done() is called once the outermost
/// operation is complete (the states then follow every point change, the output every input
/// change), each handler once, in the order they first received events.
struct TopologyChangeScope {
    int depth = 0;
    std::vector<TopologyHandler*> pending;
};

class TopologyContainer {
public:
    using Shells = std::vector<std::vector<ElementId>>;

    /// `level`: the container's class (its highest element type, SOFA's *SetTopologyContainer),
    /// which decides the element types it keeps and the order of its handlers. Builds the cross
    /// tables of `mesh` (its derived lists become the container's own, as SOFA's init).
    TopologyContainer(MeshTopology& mesh, ElementType level, std::string name, TopologyModifierOptions options = {});
    TopologyContainer(const TopologyContainer&) = delete;
    TopologyContainer& operator=(const TopologyContainer&) = delete;
    ~TopologyContainer();

    [[nodiscard]] const MeshTopology& mesh() const { return *mesh_; }
    [[nodiscard]] ElementType level() const { return level_; }
    [[nodiscard]] const std::string& name() const { return name_; }
    [[nodiscard]] const TopologyModifierOptions& options() const { return options_; }
    /// True when the container keeps elements of `type` (its level and the types below it;
    /// a hexahedron container keeps quads, a tetrahedron container triangles).
    [[nodiscard]] bool keeps(ElementType type) const;
    [[nodiscard]] std::size_t num_points() const;
    [[nodiscard]] std::size_t count(ElementType type) const;
    /// Vertices of element `id` of `type` (vertices_per_element(type) values).
    [[nodiscard]] std::span<const PointId> vertices(ElementType type, ElementId id) const;

    // ---- SOFA's cross tables beyond MeshTopology's ------------------------------------------
    [[nodiscard]] const std::vector<std::array<ElementId, 6>>& edges_in_tetrahedron() const {
        return edges_in_tetrahedron_;
    }
    [[nodiscard]] const std::vector<std::array<ElementId, 4>>& triangles_in_tetrahedron() const {
        return triangles_in_tetrahedron_;
    }
    [[nodiscard]] const Shells& tetrahedra_around_edge() const { return tetrahedra_around_edge_; }
    [[nodiscard]] const Shells& tetrahedra_around_triangle() const { return tetrahedra_around_triangle_; }
    [[nodiscard]] const std::vector<std::array<ElementId, 12>>& edges_in_hexahedron() const {
        return edges_in_hexahedron_;
    }
    [[nodiscard]] const std::vector<std::array<ElementId, 6>>& quads_in_hexahedron() const {
        return quads_in_hexahedron_;
    }
    [[nodiscard]] const Shells& hexahedra_around_edge() const { return hexahedra_around_edge_; }
    [[nodiscard]] const Shells& hexahedra_around_quad() const { return hexahedra_around_quad_; }
    /// SOFA's getEdgeIndex / getTriangleIndex / getQuadIndex: the element with these vertices in
    /// any order (the first edge around `a`; the only triangle or quad), or -1.
    [[nodiscard]] ElementId edge_index(PointId a, PointId b) const;
    [[nodiscard]] ElementId triangle_index(PointId a, PointId b, PointId c) const;
    [[nodiscard]] ElementId quad_index(PointId a, PointId b, PointId c, PointId d) const;

    // ---- who follows the changes ------------------------------------------------------------
    /// Registers a data handler (SOFA's TopologyData handler) on element types `types` (its own
    /// type, and those whose events its callbacks need). It runs once per propagation in which
    /// one of these types is dirty, in the phase of the highest dirty one.
    void add_handler(TopologyHandler& handler, std::initializer_list<ElementType> types);
    /// Registers a listener: SOFA's TopologyChangeVisitor (topological mappings from this
    /// container, then the components whose context topology this is), after the handlers.
    void add_listener(TopologyHandler& listener);
    /// Registers a state that follows the points (SOFA's StateChangeVisitor).
    void add_state_follower(StateFollower& follower);
    /// Shares `scope` with other containers (TopologyChangeScope); each has its own by default.
    void set_scope(std::shared_ptr<TopologyChangeScope> scope) { scope_ = std::move(scope); }
    /// Unregisters `object` from every list (no-op when absent).
    void remove(const TopologyHandler& object);
    void remove(const StateFollower& object);

    // ---- SOFA's modifier ----------------------------------------------------------------------
    /// removeItems: removes elements of the container's level (points for a point container),
    /// with isolated items. Throws std::invalid_argument (nothing changed) for an index out of
    /// range or repeated.
    void remove_items(std::vector<ElementId> indices);
    /// The removals of each type, as SOFA's remove...() calls (checked as remove_items).
    void remove_points(std::vector<ElementId> indices, bool remove_dof = true);
    void remove_edges(std::vector<ElementId> indices, bool remove_isolated_points = true);
    void remove_triangles(std::vector<ElementId> indices, bool remove_isolated_edges = true,
                          bool remove_isolated_points = true);
    void remove_quads(std::vector<ElementId> indices, bool remove_isolated_edges = true,
                      bool remove_isolated_points = true);
    void remove_tetrahedra(std::vector<ElementId> indices, bool remove_isolated_items = true);
    void remove_hexahedra(std::vector<ElementId> indices);

    /// addPoints: appends `count` points (each one's value weighted from its ancestors, when given).
    void add_points(std::size_t count, const std::vector<std::vector<ElementId>>& ancestors = {},
                    const std::vector<std::vector<double>>& coefficients = {}, bool add_dof = true);
    /// addPoints(n, srcElems): one point in each of `elements` (an edge or a triangle of this
    /// container), weighted from its vertices; a state's coordinates placed as SOFA's
    /// initPointAdded places them (src/mechanics/topology/topology_point_moves.cpp).
    void add_points(const std::vector<PointAncestorElement>& elements);
    /// TriangleSetTopologyModifier::movePointsProcess: each point of `ids` takes in every state
    /// vector the weighted value of its ancestors; the topology data stay (SOFA's ignore it).
    void move_points(const std::vector<PointId>& ids, const std::vector<std::vector<ElementId>>& ancestors,
                     const std::vector<std::vector<double>>& coefficients);
    /// addEdges / addTriangles / ...: appends the elements and the lower elements they need
    /// (triangle edges, tetrahedron faces and edges, ...), as SOFA's add...Process. Throws
    /// std::invalid_argument (nothing changed) for a vertex out of range or repeated in an element.
    void add_edges(const std::vector<Edge>& edges, const std::vector<std::vector<ElementId>>& ancestors = {},
                   const std::vector<std::vector<double>>& coefficients = {});
    void add_triangles(const std::vector<Triangle>& triangles,
                       const std::vector<std::vector<ElementId>>& ancestors = {},
                       const std::vector<std::vector<double>>& coefficients = {});
    void add_quads(const std::vector<Quad>& quads, const std::vector<std::vector<ElementId>>& ancestors = {},
                   const std::vector<std::vector<double>>& coefficients = {});
    void add_tetrahedra(const std::vector<Tetrahedron>& tetrahedra,
                        const std::vector<std::vector<ElementId>>& ancestors = {},
                        const std::vector<std::vector<double>>& coefficients = {});
    void add_hexahedra(const std::vector<Hexahedron>& hexahedra,
                       const std::vector<std::vector<ElementId>>& ancestors = {},
                       const std::vector<std::vector<double>>& coefficients = {});
    /// notifyEndingEvent: an `ending` event, propagated (what a topological mapping sends its
    /// output when its input's propagation ends).
    void notify_ending_event();

    /// Throws std::invalid_argument naming the first index of `indices` out of [0, count(type))
    /// or repeated; what every removal checks before changing anything.
    void check_removal(ElementType type, std::span<const ElementId> indices) const;

private:
    struct Registered {
        TopologyHandler* handler = nullptr;
        std::uint8_t types = 0;  ///< bit t: registered on ElementType t
        bool dirty = false;
    };

    // lists
    MeshTopology::Cache& lists();
    std::vector<ElementId>& shell_of(Shells& s, ElementId i) { return s[static_cast<std::size_t>(i)]; }
    void build_volume_tables();

    // events (topology_container.cpp)
    void set_dirty(ElementType type);
    void add_change(TopologyChange change);
    void propagate();
    void propagate_state_changes();
    void remove_warning(ElementType type, std::vector<ElementId>& indices);
    void remove_points_warning(std::vector<ElementId>& indices, bool remove_dof);
    void add_points_warning(std::size_t count, const std::vector<std::vector<ElementId>>& ancestors,
                            const std::vector<std::vector<double>>& coefficients, bool add_dof,
                            const std::vector<PointAncestorElement>& elements = {});
    template <class Element>
    void add_warning(ElementType type, const std::vector<Element>& elements, ElementId first,
                     const std::vector<std::vector<ElementId>>& ancestors,
                     const std::vector<std::vector<double>>& coefficients);
    void changed();  ///< bumps the mesh's revision and refreshes the touched vertices' neighbours
    void begin();    ///< the start of a public operation (the scope's depth)
    void done();     ///< its end: changed(); the outermost one calls the pending topology_change_done()
    void pending(TopologyHandler* h);

    // removal processes (topology_removal.cpp), SOFA's remove...Process
    void remove_tetrahedra_process(const std::vector<ElementId>& indices, bool remove_isolated_items);
    void remove_hexahedra_process(const std::vector<ElementId>& indices, bool remove_isolated_items);
    void remove_triangles_process(const std::vector<ElementId>& indices, bool remove_isolated_edges,
                                  bool remove_isolated_points);
    void remove_quads_process(const std::vector<ElementId>& indices, bool remove_isolated_edges,
                              bool remove_isolated_points);
    void remove_edges_process(const std::vector<ElementId>& indices, bool remove_isolated_points);
    void remove_points_process(const std::vector<ElementId>& indices, bool remove_dof);
    /// Lower elements a removal left without a higher one: warned (faces, then edges, one
    /// propagation), removed, then the points (warned, propagated, removed).
    void remove_isolated(std::vector<ElementId>& faces, ElementType face_type, std::vector<ElementId>& edges,
                         std::vector<ElementId>& points);

    // addition processes (topology_addition.cpp), SOFA's add...Process
    void add_points_process(std::size_t count);
    void add_edge_process(const Edge& e);
    void add_triangle_process(const Triangle& t);
    void add_quad_process(const Quad& q);
    void add_tetrahedron_process(const Tetrahedron& t);
    void add_hexahedron_process(const Hexahedron& h);
    /// The edge (a, b), created (with its EdgesAdded event) if missing.
    ElementId edge_or_create(PointId a, PointId b);
    void grow_points(PointId largest);
    template <std::size_t N>
    void check_addition(ElementType type, const std::vector<std::array<PointId, N>>& elements) const;

    MeshTopology* mesh_;
    ElementType level_;
    std::string name_;
    TopologyModifierOptions options_;

    std::vector<std::array<ElementId, 6>> edges_in_tetrahedron_;
    std::vector<std::array<ElementId, 4>> triangles_in_tetrahedron_;
    Shells tetrahedra_around_edge_;
    Shells tetrahedra_around_triangle_;
    std::vector<std::array<ElementId, 12>> edges_in_hexahedron_;
    std::vector<std::array<ElementId, 6>> quads_in_hexahedron_;
    Shells hexahedra_around_edge_;
    Shells hexahedra_around_quad_;

    std::vector<Registered> handlers_;  ///< registration order
    std::vector<TopologyHandler*> listeners_;
    std::vector<StateFollower*> state_followers_;
    std::vector<TopologyChange> changes_;        ///< SOFA's m_changeList
    std::vector<TopologyChange> state_changes_;  ///< SOFA's m_stateChangeList
    std::array<bool, kElementTypeCount> dirty_{};
    std::vector<PointId> touched_vertices_;  ///< whose verticesAroundVertex may have changed
    std::shared_ptr<TopologyChangeScope> scope_ = std::make_shared<TopologyChangeScope>();
};

}  // namespace penalty
