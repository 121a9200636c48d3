// SOFA's dynamic topology containers used statically (Point/Edge/Triangle/Quad/Tetrahedron/
// HexahedronSetTopologyContainer), their modifiers and geometry algorithms (accepted: they act only
// on topological changes), TopologicalChangeProcessor (refused), and the static topological
// mappings (Tetra2Triangle, Hexa2Quad, Triangle2Edge, Quad2Triangle, Hexa2Tetra), which replace
// their output topology's elements at build time (penalty/mechanics/topological_mapping.hpp).
//
// A container is a MeshTopology restricted to the lists its class declares (ElementLists). Its
// derived elements are MeshTopology's, which are the containers' own: SOFA's
// TriangleSetTopologyContainer::createEdgeSetArray (edge opposite vertex j = (t[j+1], t[j+2]),
// first occurrence, kept oriented), QuadSetTopologyContainer::createEdgeSetArray (sorted pairs),
// TetrahedronSetTopologyContainer::createEdgeSetArray / createTriangleSetArray
// (edgesInTetrahedronArray, trianglesOrientationInTetrahedronArray, smallest vertex first, a face
// stored once whatever its orientation) and HexahedronSetTopologyContainer::createEdgeSetArray /
// createQuadSetArray (edgesInHexahedronArray, the six faces in MeshTopology::kHexaFaces order).
// Lists given in the scene are kept; only missing ones are derived (createEdgeSetArray runs only
// when hasEdges() is false).
#include "scene/builder/element_topology.hpp"
#include "scene/builder/families.hpp"

#include "penalty/mechanics/topological_mapping.hpp"

#include <algorithm>
#include <map>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

#define PENALTY_POINTS_ATTRIBUTES                                                                         \
    {"src",                                                                                               \
     K::link,                                                                                             \
     "",                                                                                                  \
     "",                                                                                                  \
     ValueCheck::none,                                                                                    \
     "mesh loader, or a topology built before, whose points and elements of this class it takes"},        \
        {"position", K::points, "", "m", ValueCheck::none, "points (override src), or a link"},           \
        {"points", K::points, "", "m", ValueCheck::none, "alias of position"},                            \
        {"nbPoints", K::integer, "0", "", ValueCheck::none, "point count when no positions are given"}, { \
        "filename", K::text, "", "", ValueCheck::none,                                                    \
            "mesh file read directly (no transform; the lists of this class)"                             \
    }
#define PENALTY_EDGES_ATTRIBUTE \
    { "edges", K::elements, "(derived)", "", ValueCheck::none, "point pairs, or a link" }

constexpr AttributeSpec kPointSet[] = {PENALTY_POINTS_ATTRIBUTES};
constexpr AttributeSpec kEdgeSet[] = {PENALTY_POINTS_ATTRIBUTES, PENALTY_EDGES_ATTRIBUTE};
constexpr AttributeSpec kTriangleSet[] = {
    PENALTY_POINTS_ATTRIBUTES,
    PENALTY_EDGES_ATTRIBUTE,
    {"triangles", K::elements, "", "", ValueCheck::none, "point triples, or a link"}};
constexpr AttributeSpec kQuadSet[] = {PENALTY_POINTS_ATTRIBUTES,
                                      PENALTY_EDGES_ATTRIBUTE,
                                      {"quads", K::elements, "", "", ValueCheck::none, "4 points each, or a link"}};
constexpr AttributeSpec kTetrahedronSet[] = {
    PENALTY_POINTS_ATTRIBUTES,
    PENALTY_EDGES_ATTRIBUTE,
    {"triangles", K::elements, "(derived)", "", ValueCheck::none, "point triples, or a link"},
    {"tetrahedra", K::elements, "", "", ValueCheck::none, "4 points each, or a link"},
    {"tetras", K::elements, "", "", ValueCheck::none, "alias of tetrahedra"},
    {"createTriangleArray", K::boolean, "0", "", ValueCheck::none, "no effect: triangles are always derived"},
};
constexpr AttributeSpec kHexahedronSet[] = {
    PENALTY_POINTS_ATTRIBUTES,
    PENALTY_EDGES_ATTRIBUTE,
    {"quads", K::elements, "(derived)", "", ValueCheck::none, "4 points each, or a link"},
    {"hexahedra", K::elements, "", "", ValueCheck::none, "8 points each, or a link"},
    {"hexas", K::elements, "", "", ValueCheck::none, "alias of hexahedra"},
    {"createQuadArray", K::boolean, "0", "", ValueCheck::none, "no effect: quads are always derived"},
};
#undef PENALTY_POINTS_ATTRIBUTES
#undef PENALTY_EDGES_ATTRIBUTE

// Each container reads `points`/`nbPoints` (PointSetTopologyContainer) and the lists of its class.
constexpr ElementLists kPointLists{.nb_points = true};
constexpr ElementLists kEdgeLists{.edges = true, .nb_points = true};
constexpr ElementLists kTriangleLists{.edges = true, .triangles = true, .nb_points = true};
constexpr ElementLists kQuadLists{.edges = true, .quads = true, .nb_points = true};
constexpr ElementLists kTetrahedronLists{.edges = true, .triangles = true, .tetrahedra = true, .nb_points = true};
constexpr ElementLists kHexahedronLists{.edges = true, .quads = true, .hexahedra = true, .nb_points = true};

template <const ElementLists& lists>
void build_container(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    build_element_topology(b, c, info, lists);
}

/// Modifiers and geometry algorithms: nothing to build here (a modifier makes its container
/// changeable: src/scene/topology/wiring.cpp).
void build_topology_helper(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    const ComponentSpec* spec = find_component(c.type);
    if (spec != nullptr) {  // a modifier's options (read by src/scene/topology/wiring.cpp): checked here
        const Attributes a(c);
        for (const AttributeSpec& attribute : spec->attributes)
            if (a.has(attribute.name)) (void)a.boolean(attribute.name);
    }
    b.role(c, [] { return std::string("accepted: acts only on topological changes"); });
    b.note_unread_attributes(c);
}

// ---- topological mappings ---------------------------------------------------------------------
constexpr AttributeSpec kTopologicalMappingLinks[] = {
    {"input", K::link, "", "", ValueCheck::none, "topology read (built before: same node or above)"},
    {"output", K::link, "", "", ValueCheck::none, "topology whose elements it replaces (built before)"},
};
constexpr AttributeSpec kTetra2Triangle[] = {
    {"flipNormals", K::boolean, "0", "", ValueCheck::none, "store (t0, t2, t1)"},
    {"noInitialTriangles", K::boolean, "0", "", ValueCheck::none, "leave the output without triangles"},
    {"noNewTriangles", K::boolean, "0", "", ValueCheck::none, "no effect: only topological changes use it"},
};
constexpr AttributeSpec kHexa2Quad[] = {
    {"flipNormals", K::boolean, "0", "", ValueCheck::none, "store (q3, q2, q1, q0)"},
};
constexpr AttributeSpec kQuad2Triangle[] = {
    {"swapping", K::boolean, "1", "", ValueCheck::none, "alternate the diagonal cell by cell (grid input)"},
};
constexpr AttributeSpec kHexa2Tetra[] = {
    {"swapping", K::boolean, "0", "", ValueCheck::none, "mirror alternate cells (grid input)"},
};

/// The build record of the node whose topology is `target` (built already), or nullptr.
NodeBuild* topology_node(SceneBuilder& b, const SceneComponent* target) {
    if (target == nullptr) return nullptr;
    for (const auto& [scene_node, info] : b.node_builds())
        if (info.topology_component == target && info.topology != nullptr) return &b.node_build(*scene_node);
    return nullptr;
}

NodeBuild& linked_topology_node(SceneBuilder& b, const Attributes& a, std::string_view attr) {
    const io::LinkTarget target = a.link(attr);
    const SceneComponent* topology = target.component;
    // a link to a node (`input="@../"`): that node's topology, as SOFA's link to a
    // BaseMeshTopology resolves a node path
    if (topology == nullptr && target.node != nullptr && b.node_builds().count(target.node) != 0)
        topology = b.node_build(*target.node).topology_component;
    NodeBuild* n = topology_node(b, topology);
    if (n == nullptr) a.fail(attr, "must link to a topology built before this mapping (in its node or above)");
    return *n;
}

/// The output topology: in the mapping's own node (as in SOFA's scenes), so that everything of
/// that node built after the topology family (state, force fields, collision models) uses it.
NodeBuild& output_topology_node(SceneBuilder& b, const Attributes& a, const NodeBuild& mapping_node) {
    NodeBuild& out = linked_topology_node(b, a, "output");
    if (out.scene_node != mapping_node.scene_node)
        a.fail("output", "must link to the topology of the mapping's own node");
    return out;
}

/// True when the output's node holds a component of type `modifier`: SOFA's Hexa2Quad,
/// Quad2Triangle and Triangle2Edge mappings are invalid without one (their output stays as built).
bool output_has_modifier(SceneBuilder& b, const SceneComponent& c, const NodeBuild& output, std::string_view modifier) {
    const auto& components = output.scene_node->components;
    if (std::any_of(components.begin(), components.end(), [&](const auto& x) { return x->type == modifier; }))
        return true;
    b.warn(c.file + ":" + std::to_string(c.line) + ": " + c.describe() + ": no " + std::string(modifier) +
           " in the output's node: SOFA leaves the output topology unchanged, and so does penalty");
    return false;
}

/// Replaces the output's elements by `fill`'s (SOFA: toModel->clear(), setNbPoints(input's),
/// add the elements, toModel->init()); the output keeps no positions of its own.
template <class Fill>
void replace_output(SceneBuilder& b, const SceneComponent& c, NodeBuild& output, std::size_t num_points, Fill&& fill) {
    auto t = std::make_unique<MeshTopology>();
    t->set_num_points(num_points);
    fill(*t);
    (void)t->edges();  // checks indices now
    output.topology_positions.clear();
    output.topology = b.add_topology(std::move(t));
    b.record_built_topology(output);
    b.role(c, [&output] {
        return "fills " + output.topology_component->describe() + ": " +
               element_counts(output.topology->num_points(), *output.topology);
    });
}

/// Cells of a grid input along x and y; SOFA's 2 and 1 for any other input.
std::pair<int, int> grid_cells(const NodeBuild& input) {
    if (!input.grid) return {2, 1};
    return {input.grid->n()[0] - 1, input.grid->n()[1] - 1};
}

void build_tetra2triangle(SceneBuilder& b, const SceneComponent& c, NodeBuild& node) {
    const Attributes a(c);
    b.guarded(c, [&] {
        const NodeBuild& in = linked_topology_node(b, a, "input");
        NodeBuild& out = output_topology_node(b, a, node);
        const bool none = a.boolean("noInitialTriangles");
        const bool flip = a.boolean("flipNormals");
        replace_output(b, c, out, in.topology->num_points(), [&](MeshTopology& t) {
            if (!none) t.set_triangles(border_triangles(*in.topology, flip));
        });
    });
    b.note_unread_attributes(c);
}

void build_hexa2quad(SceneBuilder& b, const SceneComponent& c, NodeBuild& node) {
    const Attributes a(c);
    b.guarded(c, [&] {
        const NodeBuild& in = linked_topology_node(b, a, "input");
        NodeBuild& out = output_topology_node(b, a, node);
        if (!output_has_modifier(b, c, out, "QuadSetTopologyModifier")) return;
        const bool flip = a.boolean("flipNormals");
        replace_output(b, c, out, in.topology->num_points(),
                       [&](MeshTopology& t) { t.set_quads(border_quads(*in.topology, flip)); });
    });
    b.note_unread_attributes(c);
}

void build_triangle2edge(SceneBuilder& b, const SceneComponent& c, NodeBuild& node) {
    const Attributes a(c);
    b.guarded(c, [&] {
        const NodeBuild& in = linked_topology_node(b, a, "input");
        NodeBuild& out = output_topology_node(b, a, node);
        if (!output_has_modifier(b, c, out, "EdgeSetTopologyModifier")) return;
        replace_output(b, c, out, in.topology->num_points(),
                       [&](MeshTopology& t) { t.set_edges(border_edges(*in.topology)); });
    });
    b.note_unread_attributes(c);
}

/// SimpleTesselatedTetraTopologicalMapping::init: the output's points are the input's, then the
/// middle of each input edge in edge order ((a + b)/2 per coordinate); each input tetrahedron
/// (t, its edges e in SOFA's local order) gives eight: one per corner, four around the middle
/// octahedron, in SOFA's order and orientation.
void build_simple_tesselated_tetra(SceneBuilder& b, const SceneComponent& c, NodeBuild& node) {
    const Attributes a(c);
    b.guarded(c, [&] {
        const NodeBuild& in = linked_topology_node(b, a, "input");
        NodeBuild& out = output_topology_node(b, a, node);
        const MeshTopology& from = *in.topology;
        if (in.topology_positions.size() != from.num_points())
            a.fail("input", "the input topology has no points of its own (penalty reads them from its container)");
        std::vector<Vec3> points = in.topology_positions;
        std::map<std::pair<PointId, PointId>, PointId> middle_of;  // sorted edge -> its middle point
        for (const Edge& e : from.edges()) {
            middle_of[std::minmax(e[0], e[1])] = PointId(points.size());
            points.push_back((in.topology_positions[std::size_t(e[0])] + in.topology_positions[std::size_t(e[1])]) / 2);
        }
        std::vector<Tetrahedron> tetras;
        tetras.reserve(8 * from.tetrahedra().size());
        for (const Tetrahedron& t : from.tetrahedra()) {
            std::array<PointId, 6> m{};
            for (std::size_t j = 0; j < 6; ++j) {
                const auto& le = MeshTopology::kTetraEdges[j];
                m[j] = middle_of.at(std::minmax(t[std::size_t(le[0])], t[std::size_t(le[1])]));
            }
            tetras.push_back({t[0], m[0], m[1], m[2]});
            tetras.push_back({t[1], m[0], m[4], m[3]});
            tetras.push_back({t[2], m[1], m[3], m[5]});
            tetras.push_back({t[3], m[2], m[5], m[4]});
            tetras.push_back({m[1], m[0], m[3], m[5]});
            tetras.push_back({m[1], m[0], m[5], m[2]});
            tetras.push_back({m[4], m[0], m[5], m[3]});
            tetras.push_back({m[4], m[0], m[2], m[5]});
        }
        replace_output(b, c, out, points.size(), [&](MeshTopology& t) { t.set_tetrahedra(std::move(tetras)); });
        out.topology_positions = std::move(points);
        b.record_built_topology(out);
    });
    b.note_unread_attributes(c);
}

// ---- Mesh2PointTopologicalMapping ---------------------------------------------------------------
constexpr AttributeSpec kMesh2Point[] = {
    {"pointBaryCoords", K::numbers, "", "m", ValueCheck::none, "per input point, points at p + (x y z)"},
    {"edgeBaryCoords", K::numbers, "", "", ValueCheck::none,
     "per input edge, points at p0 (1-fx) + p1 fx (3 numbers each)"},
    {"triangleBaryCoords", K::numbers, "", "", ValueCheck::none, "per input triangle, p0 (1-fx-fy) + p1 fx + p2 fy"},
    {"quadBaryCoords", K::numbers, "", "", ValueCheck::none, "per input quad, bilinear in (fx, fy)"},
    {"tetraBaryCoords", K::numbers, "", "", ValueCheck::none,
     "per input tetrahedron, p0 (1-fx-fy-fz) + p1 fx + p2 fy + p3 fz"},
    {"hexaBaryCoords", K::numbers, "", "", ValueCheck::none, "not supported"},
    {"copyEdges", K::boolean, "0", "", ValueCheck::none, "only false is supported"},
    {"copyTriangles", K::boolean, "0", "", ValueCheck::none, "only false is supported"},
    {"copyTetrahedra", K::boolean, "0", "", ValueCheck::none, "only false is supported"},
};

/// Mesh2PointTopologicalMapping::init (addInputPoint, addInputEdge, addInputTriangle, the quads'
/// loop, addInputTetrahedron): the output holds only points, made from the input's points, edges,
/// triangles, quads then tetrahedra, for each element one point per given coordinate triple, from
/// the input container's own points (getPX), summed left to right as SOFA writes each formula.
std::vector<Vec3> mesh_to_points(const Attributes& a, const MeshTopology& from, const std::vector<Vec3>& x) {
    const auto triples = [&](std::string_view name) {
        std::vector<Vec3> out;
        if (!a.has(name)) return out;
        const std::vector<double> v = a.numbers(name);
        if (v.size() % 3 != 0) a.fail(name, "expected 3 numbers per point");
        for (std::size_t i = 0; i + 2 < v.size(); i += 3) out.emplace_back(v[i], v[i + 1], v[i + 2]);
        return out;
    };
    const auto at = [&](PointId i) { return x[std::size_t(i)]; };
    std::vector<Vec3> out;
    const std::vector<Vec3> point = triples("pointBaryCoords");
    for (std::size_t i = 0; i < (point.empty() ? 0 : x.size()); ++i)
        for (const Vec3& f : point) out.emplace_back(x[i][0] + f[0], x[i][1] + f[1], x[i][2] + f[2]);
    const std::vector<Vec3> edge = triples("edgeBaryCoords");
    for (const Edge& e : edge.empty() ? std::vector<Edge>{} : from.edges())
        for (const Vec3& f : edge) out.push_back(at(e[0]) * (1 - f[0]) + at(e[1]) * f[0]);
    const std::vector<Vec3> triangle = triples("triangleBaryCoords");
    for (const Triangle& t : triangle.empty() ? std::vector<Triangle>{} : from.triangles())
        for (const Vec3& f : triangle) out.push_back(at(t[0]) * (1 - f[0] - f[1]) + at(t[1]) * f[0] + at(t[2]) * f[1]);
    const std::vector<Vec3> quad = triples("quadBaryCoords");
    for (const Quad& q : quad.empty() ? std::vector<Quad>{} : from.quads())
        for (const Vec3& f : quad)
            out.push_back(at(q[0]) * ((1 - f[0]) * (1 - f[1])) + at(q[1]) * ((f[0]) * (1 - f[1])) +
                          at(q[2]) * ((1 - f[0]) * (f[1])) + at(q[3]) * ((f[0]) * (f[1])));
    const std::vector<Vec3> tetra = triples("tetraBaryCoords");
    for (const Tetrahedron& t : tetra.empty() ? std::vector<Tetrahedron>{} : from.tetrahedra())
        for (const Vec3& f : tetra)
            out.push_back(at(t[0]) * (1 - f[0] - f[1] - f[2]) + at(t[1]) * f[0] + at(t[2]) * f[1] + at(t[3]) * f[2]);
    return out;
}

void build_mesh2point(SceneBuilder& b, const SceneComponent& c, NodeBuild& node) {
    const Attributes a(c);
    b.guarded(c, [&] {
        for (const char* flag : {"copyEdges", "copyTriangles", "copyTetrahedra"})
            if (a.boolean(flag)) a.fail(flag, "only false is supported (the output holds points only)");
        if (a.has("hexaBaryCoords") && !a.numbers("hexaBaryCoords").empty())
            a.fail("hexaBaryCoords", "is not supported");
        const NodeBuild& in = linked_topology_node(b, a, "input");
        NodeBuild& out = output_topology_node(b, a, node);
        if (in.topology_positions.size() != in.topology->num_points())
            a.fail("input", "the input topology has no points of its own (penalty reads them from its container)");
        std::vector<Vec3> points = mesh_to_points(a, *in.topology, in.topology_positions);
        replace_output(b, c, out, points.size(), [](MeshTopology&) {});
        out.topology_positions = std::move(points);
        b.record_built_topology(out);
    });
    b.note_unread_attributes(c);
}

void build_quad2triangle(SceneBuilder& b, const SceneComponent& c, NodeBuild& node) {
    const Attributes a(c);
    b.guarded(c, [&] {
        const NodeBuild& in = linked_topology_node(b, a, "input");
        NodeBuild& out = output_topology_node(b, a, node);
        if (!output_has_modifier(b, c, out, "TriangleSetTopologyModifier")) return;
        const auto cells = grid_cells(in);  // (nx, ny); no structured binding: clang 14 cannot capture one
        const bool swapping = a.boolean("swapping");
        replace_output(b, c, out, in.topology->num_points(), [&](MeshTopology& t) {
            t.set_triangles(triangles_of_quads(in.topology->quads(), swapping, std::get<0>(cells), std::get<1>(cells)));
        });
    });
    b.note_unread_attributes(c);
}

void build_hexa2tetra(SceneBuilder& b, const SceneComponent& c, NodeBuild& node) {
    const Attributes a(c);
    b.guarded(c, [&] {
        const NodeBuild& in = linked_topology_node(b, a, "input");
        NodeBuild& out = output_topology_node(b, a, node);
        const auto cells = grid_cells(in);  // (nx, ny); no structured binding: clang 14 cannot capture one
        const bool swapping = a.boolean("swapping");
        replace_output(b, c, out, in.topology->num_points(), [&](MeshTopology& t) {
            t.set_tetrahedra(
                tetrahedra_of_hexahedra(in.topology->hexahedra(), swapping, std::get<0>(cells), std::get<1>(cells)));
        });
    });
    b.note_unread_attributes(c);
}

constexpr AttributeSpec kPointModifier[] = {
    {"propagateToDOF", K::boolean, "1", "", ValueCheck::none, "the states follow point removals"},
};
constexpr AttributeSpec kVolumeModifier[] = {
    {"propagateToDOF", K::boolean, "1", "", ValueCheck::none, "the states follow point removals"},
    {"removeIsolated", K::boolean, "1", "", ValueCheck::none, "points left without an element are removed"},
};

constexpr std::string_view kModifier = "topology modifier: makes its node's container changeable (topological changes)";
constexpr std::string_view kAlgorithms =
    "geometry algorithms of a topology: used by topological changes and drawing (accepted, builds nothing)";

constexpr ComponentSpec kTopologyContainerComponents[] = {
    {.type = "PointSetTopologyContainer",
     .family = F::topology,
     .summary = "points only (static use)",
     .attributes = kPointSet,
     .build = build_container<kPointLists>},
    {.type = "EdgeSetTopologyContainer",
     .family = F::topology,
     .summary = "edges (static use)",
     .attributes = kEdgeSet,
     .build = build_container<kEdgeLists>},
    {.type = "TriangleSetTopologyContainer",
     .family = F::topology,
     .summary = "triangles, derived edges (static use)",
     .attributes = kTriangleSet,
     .build = build_container<kTriangleLists>},
    {.type = "QuadSetTopologyContainer",
     .family = F::topology,
     .summary = "quads, derived edges (static use)",
     .attributes = kQuadSet,
     .build = build_container<kQuadLists>},
    {.type = "TetrahedronSetTopologyContainer",
     .family = F::topology,
     .summary = "tetrahedra, derived triangles and edges (static use)",
     .attributes = kTetrahedronSet,
     .build = build_container<kTetrahedronLists>},
    {.type = "HexahedronSetTopologyContainer",
     .family = F::topology,
     .summary = "hexahedra, derived quads and edges (static use)",
     .attributes = kHexahedronSet,
     .build = build_container<kHexahedronLists>},
    {.type = "PointSetTopologyModifier",
     .family = F::topology_helper,
     .summary = kModifier,
     .attributes = kPointModifier,
     .build = build_topology_helper},
    {.type = "EdgeSetTopologyModifier",
     .family = F::topology_helper,
     .summary = kModifier,
     .attributes = kPointModifier,
     .build = build_topology_helper},
    {.type = "TriangleSetTopologyModifier",
     .family = F::topology_helper,
     .summary = kModifier,
     .attributes = kPointModifier,
     .build = build_topology_helper},
    {.type = "QuadSetTopologyModifier",
     .family = F::topology_helper,
     .summary = kModifier,
     .attributes = kPointModifier,
     .build = build_topology_helper},
    {.type = "TetrahedronSetTopologyModifier",
     .family = F::topology_helper,
     .summary = kModifier,
     .attributes = kVolumeModifier,
     .build = build_topology_helper},
    {.type = "HexahedronSetTopologyModifier",
     .family = F::topology_helper,
     .summary = kModifier,
     .attributes = kVolumeModifier,
     .build = build_topology_helper},
    {.type = "PointSetGeometryAlgorithms",
     .family = F::topology_helper,
     .summary = kAlgorithms,
     .build = build_topology_helper},
    {.type = "EdgeSetGeometryAlgorithms",
     .family = F::topology_helper,
     .summary = kAlgorithms,
     .build = build_topology_helper},
    {.type = "TriangleSetGeometryAlgorithms",
     .family = F::topology_helper,
     .summary = kAlgorithms,
     .build = build_topology_helper},
    {.type = "QuadSetGeometryAlgorithms",
     .family = F::topology_helper,
     .summary = kAlgorithms,
     .build = build_topology_helper},
    {.type = "TetrahedronSetGeometryAlgorithms",
     .family = F::topology_helper,
     .summary = kAlgorithms,
     .build = build_topology_helper},
    {.type = "HexahedronSetGeometryAlgorithms",
     .family = F::topology_helper,
     .summary = kAlgorithms,
     .build = build_topology_helper},
    {.type = "Tetra2TriangleTopologicalMapping",
     .family = F::topology_helper,
     .summary = "output topology := the triangles of the input on one tetrahedron only (static)",
     .attributes = kTetra2Triangle,
     .shared_attributes = kTopologicalMappingLinks,
     .build = build_tetra2triangle},
    {.type = "Hexa2QuadTopologicalMapping",
     .family = F::topology_helper,
     .summary = "output topology := the quads of the input on one hexahedron only (static)",
     .attributes = kHexa2Quad,
     .shared_attributes = kTopologicalMappingLinks,
     .build = build_hexa2quad},
    {.type = "Triangle2EdgeTopologicalMapping",
     .family = F::topology_helper,
     .summary = "output topology := the edges of the input on one triangle only (static)",
     .shared_attributes = kTopologicalMappingLinks,
     .build = build_triangle2edge},
    {.type = "Quad2TriangleTopologicalMapping",
     .family = F::topology_helper,
     .summary = "output topology := two triangles per quad of the input (static)",
     .attributes = kQuad2Triangle,
     .shared_attributes = kTopologicalMappingLinks,
     .build = build_quad2triangle},
    {.type = "Mesh2PointTopologicalMapping",
     .family = F::topology_helper,
     .summary = "fills its output with points made from the input's points, edges, triangles, quads, tetrahedra",
     .attributes = kMesh2Point,
     .shared_attributes = kTopologicalMappingLinks,
     .build = build_mesh2point},
    {.type = "SimpleTesselatedTetraTopologicalMapping",
     .family = F::topology_helper,
     .summary = "output topology := each input tetrahedron cut in eight at its edges' middles (static)",
     .shared_attributes = kTopologicalMappingLinks,
     .build = build_simple_tesselated_tetra},
    {.type = "Hexa2TetraTopologicalMapping",
     .family = F::topology_helper,
     .summary = "output topology := six tetrahedra per hexahedron of the input (static)",
     .attributes = kHexa2Tetra,
     .shared_attributes = kTopologicalMappingLinks,
     .build = build_hexa2tetra},
};

}  // namespace

std::span<const ComponentSpec> topology_container_components() { return kTopologyContainerComponents; }

}  // namespace penalty::scene::builder
