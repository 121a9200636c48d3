// Regions of interest beyond BoxROI (masses_and_regions.cpp): PlaneROI and SphereROI; and what
// every ROI shares (regions_of_interest.hpp): inputs with SOFA's defaults and the recorded
// outputs read through `@roi.indices`, `@roi.triangleIndices`, ...
#include "scene/builder/regions_of_interest.hpp"

#include "scene/builder/element_topology.hpp"
#include "scene/builder/families.hpp"

#include <algorithm>
#include <iterator>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

const Vec3Object* vec3_state_of(const NodeBuild& n) {
    return n.node != nullptr ? dynamic_cast<const Vec3Object*>(n.node->state()) : nullptr;
}

/// The nearest state from the node up (SOFA's context search upward, SceneBuilder::state_owner).
const Vec3Object* nearest_state(SceneBuilder& b, const NodeBuild& info) {
    const NodeBuild* owner = b.state_owner(info);
    return owner != nullptr ? vec3_state_of(*owner) : nullptr;
}

/// The node's first loader (SOFA's context->get(MeshLoader*, Local)).
const SceneComponent* first_loader(const NodeBuild& info) {
    for (const auto& c : info.scene_node->components)
        if (component_category(c->type) == ComponentCategory::loader) return c.get();
    return nullptr;
}

template <class Element>
std::vector<Element> roi_list(SceneBuilder& b, const Attributes& a, std::string_view attr, const char* compute,
                              const MeshTopology* fallback, std::vector<Element> io::MeshData::*loaded,
                              const std::vector<Element>& (MeshTopology::*built)() const) {
    if (!a.boolean(compute)) return {};
    if (a.has(attr)) {
        if (a.is_link(attr)) return linked_elements(b, a, attr, loaded, built);
        return a.elements<std::tuple_size_v<Element>>(attr);
    }
    if (fallback != nullptr) return (fallback->*built)();
    return {};
}

}  // namespace

std::optional<std::vector<Vec3>> given_points(SceneBuilder& b, const Attributes& a, std::string_view name) {
    if (!a.has(name)) return std::nullopt;
    return b.point_data(a, name);
}

std::vector<Vec3> roi_points(SceneBuilder& b, const Attributes& a, const NodeBuild& info, RoiContext context) {
    for (const char* attr : {"position", "rest_position"}) {
        if (!a.has(attr)) continue;
        if (!a.is_link(attr)) return a.points(attr);
        if (!roi_link_resolves(a.component(), attr)) {
            // SOFA keeps a Data whose link finds no parent set and empty: the ROI selects nothing
            b.warn(a.component().file + ":" + std::to_string(a.component().find(attr)->line) + ": " +
                   a.component().describe() + ": attribute '" + attr + "': the link '" +
                   a.component().find(attr)->value +
                   "' finds nothing; as SOFA, the region tests no point and selects nothing");
            return {};
        }
        return b.linked_positions(a, attr);
    }
    if (context == RoiContext::base_roi) {
        if (const Vec3Object* s = vec3_state_of(info)) return s->rest_position;
        if (const SceneComponent* loader = first_loader(info)) return b.mesh_of(*loader).positions;
        if (const Vec3Object* s = nearest_state(b, info)) return s->rest_position;
    } else {
        if (const Vec3Object* s = nearest_state(b, info)) return s->rest_position;
        if (const SceneComponent* loader = first_loader(info)) return b.mesh_of(*loader).positions;
    }
    io::throw_element_error(a.component(),
                            "finds no points: give `position`, or put it with a MechanicalObject or a loader");
}

RoiElements roi_elements(SceneBuilder& b, const Attributes& a, const NodeBuild& info, RoiContext context,
                         RoiListNames names) {
    const MeshTopology* fallback = info.topology;
    if (context == RoiContext::plane_roi)
        for (const io::SceneNode* sn = info.scene_node; fallback == nullptr && sn != nullptr; sn = sn->parent)
            fallback = b.node_build(*sn).topology;
    RoiElements e;
    using M = io::MeshData;
    using T = MeshTopology;
    e.edges = roi_list<Edge>(b, a, "edges", "computeEdges", fallback, &M::edges, &T::edges);
    e.triangles = roi_list<Triangle>(b, a, "triangles", "computeTriangles", fallback, &M::triangles, &T::triangles);
    e.tetrahedra =
        roi_list<Tetrahedron>(b, a, "tetrahedra", "computeTetrahedra", fallback, &M::tetrahedra, &T::tetrahedra);
    if (names.quads_and_hexahedra) {
        // BoxROI's alias `quad` (BoxROI::BoxROI's addAlias)
        const std::string_view quads = names.quad_alias && !a.has("quads") && a.has("quad") ? "quad" : "quads";
        e.quads = roi_list<Quad>(b, a, quads, "computeQuads", fallback, &M::quads, &T::quads);
        e.hexahedra =
            roi_list<Hexahedron>(b, a, "hexahedra", "computeHexahedra", fallback, &M::hexahedra, &T::hexahedra);
    }
    return e;
}

bool roi_link_resolves(const SceneComponent& c, std::string_view attr) {
    try {
        static_cast<void>(io::resolve_links(c, attr));
        return true;
    } catch (const io::SceneError&) {
        return false;
    }
}

std::vector<std::pair<std::string, std::vector<PointId>>> roi_index_outputs(
    RoiSelection s, std::initializer_list<const char*> aliases_of_indices) {
    std::vector<std::pair<std::string, std::vector<PointId>>> out;
    for (const char* alias : aliases_of_indices) out.emplace_back(alias, s.points);
    out.emplace_back("indices", std::move(s.points));
    out.emplace_back("edgeIndices", std::move(s.edges));
    out.emplace_back("triangleIndices", std::move(s.triangles));
    out.emplace_back("quadIndices", std::move(s.quads));
    out.emplace_back("tetrahedronIndices", std::move(s.tetrahedra));
    out.emplace_back("hexahedronIndices", std::move(s.hexahedra));
    return out;
}

std::vector<std::pair<std::string, io::MeshData>> roi_element_outputs(const RoiSelection& s, const RoiElements& e) {
    const auto pick = [](const auto& all, const std::vector<PointId>& ids) {
        std::remove_cvref_t<decltype(all)> out;
        for (PointId i : ids) out.push_back(all[static_cast<std::size_t>(i)]);
        return out;
    };
    std::vector<std::pair<std::string, io::MeshData>> out(5);
    out[0].first = "edgesInROI";
    out[0].second.edges = pick(e.edges, s.edges);
    out[1].first = "trianglesInROI";
    out[1].second.triangles = pick(e.triangles, s.triangles);
    out[2].first = "quadsInROI";
    out[2].second.quads = pick(e.quads, s.quads);
    out[3].first = "tetrahedraInROI";
    out[3].second.tetrahedra = pick(e.tetrahedra, s.tetrahedra);
    out[4].first = "hexahedraInROI";
    out[4].second.hexahedra = pick(e.hexahedra, s.hexahedra);
    return out;
}

void record_roi_selection(SceneBuilder& b, const SceneComponent& c, RoiSelection s,
                          std::initializer_list<const char*> aliases_of_indices) {
    for (auto& [name, indices] : roi_index_outputs(std::move(s), aliases_of_indices))
        b.record_engine_indices(c, name, std::move(indices));
}

void record_roi_elements_in(SceneBuilder& b, const SceneComponent& c, const RoiSelection& s, const RoiElements& e) {
    for (auto& [name, mesh] : roi_element_outputs(s, e)) b.record_engine_mesh(c, name, std::move(mesh));
}

std::string describe_roi_selection(const RoiSelection& s, std::size_t num_points, const RoiElements& e,
                                   const std::string& shapes) {
    std::string text = "selects " + std::to_string(s.points.size()) + " of " + counted(num_points, "point", "points");
    const auto add = [&](std::size_t selected, std::size_t all, const char* one, const char* many) {
        if (all > 0) text += ", " + std::to_string(selected) + " of " + counted(all, one, many);
    };
    add(s.edges.size(), e.edges.size(), "edge", "edges");
    add(s.triangles.size(), e.triangles.size(), "triangle", "triangles");
    add(s.quads.size(), e.quads.size(), "quad", "quads");
    add(s.tetrahedra.size(), e.tetrahedra.size(), "tetrahedron", "tetrahedra");
    add(s.hexahedra.size(), e.hexahedra.size(), "hexahedron", "hexahedra");
    return text + " (inside " + shapes + ")";
}

namespace {

// Element inputs of every ROI (BaseROI; PlaneROI has no quads nor hexahedra).
#define PENALTY_ROI_POINTS                                                                                        \
    {"position", K::points, "(rest positions of the context's state)", "m", ValueCheck::none, "points tested"}, { \
        "rest_position", K::points, "", "m", ValueCheck::none, "alias of position"                                \
    }
#define PENALTY_ROI_LISTS(ELEMENTS, ELEMENT) \
    { ELEMENTS, K::elements, "(the node's topology)", "", ValueCheck::none, ELEMENT " tested (inline or a link)" }
#define PENALTY_ROI_COMPUTE(NAME) \
    { NAME, K::boolean, "1", "", ValueCheck::none, "0: that list is not tested" }
#define PENALTY_ROI_OUTPUT(NAME) \
    { NAME, K::indices, "", "", ValueCheck::none, "output (a written value is replaced)" }
#define PENALTY_ROI_DRAW(NAME) \
    { NAME, K::boolean, "0", "", ValueCheck::none, "drawing only" }

// ---- PlaneROI -------------------------------------------------------------------------------
// PlaneROI (a DataEngine of its own, not a BaseROI): `plane` = 10 numbers per box (three corners
// and a depth, PlaneROI::computePlane); a point is selected when inside any box, an edge,
// triangle or tetrahedron when all of its points are inside the same box (PlaneROI::doUpdate).
// The default plane (ten zeros) is degenerate: every normal and size is 0, so it selects every
// point (as SOFA's tests, all of the form |0| <= 0).
constexpr AttributeSpec kPlaneRoi[] = {
    {"plane", K::numbers, "0 0 0 0 0 0 0 0 0 0", "m", ValueCheck::none, "boxes: p0 p1 p2 (corners) and depth, each"},
    PENALTY_ROI_POINTS,
    PENALTY_ROI_LISTS("edges", "edges"),
    PENALTY_ROI_LISTS("triangles", "triangles"),
    PENALTY_ROI_LISTS("tetrahedra", "tetrahedra"),
    PENALTY_ROI_COMPUTE("computeEdges"),
    PENALTY_ROI_COMPUTE("computeTriangles"),
    PENALTY_ROI_COMPUTE("computeTetrahedra"),
    PENALTY_ROI_OUTPUT("indices"),
    PENALTY_ROI_OUTPUT("edgeIndices"),
    PENALTY_ROI_OUTPUT("triangleIndices"),
    PENALTY_ROI_OUTPUT("tetrahedronIndices"),
    PENALTY_ROI_DRAW("drawBoxes"),
    PENALTY_ROI_DRAW("isVisible"),
    PENALTY_ROI_DRAW("drawPoints"),
    PENALTY_ROI_DRAW("drawEdges"),
    PENALTY_ROI_DRAW("drawTriangles"),
    PENALTY_ROI_DRAW("drawTetrahedra"),
    {"drawSize", K::real, "1", "", ValueCheck::none, "drawing only"},
};

/// Sorted union of two increasing index lists.
std::vector<PointId> merged(const std::vector<PointId>& a, const std::vector<PointId>& b) {
    std::vector<PointId> out;
    std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
    return out;
}

/// PlaneROI::doUpdate: the union of the selections of each plane box.
RoiSelection select_in_plane_roi(const std::vector<Vec3>& points, const RoiElements& elements,
                                 const std::vector<double>& v) {
    RoiSelection selection;
    for (std::size_t i = 0; i < v.size(); i += 10) {
        const PlaneRegion plane(Vec3(v[i], v[i + 1], v[i + 2]), Vec3(v[i + 3], v[i + 4], v[i + 5]),
                                Vec3(v[i + 6], v[i + 7], v[i + 8]), v[i + 9]);
        const RoiSelection one = select_in_region(
            points, elements, [&plane](const Vec3& p) { return plane.contains(p); }, ElementTest::all_points);
        selection.points = merged(selection.points, one.points);
        selection.edges = merged(selection.edges, one.edges);
        selection.triangles = merged(selection.triangles, one.triangles);
        selection.tetrahedra = merged(selection.tetrahedra, one.tetrahedra);
    }
    return selection;
}

void build_plane_roi(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    RoiSelection selection;
    RoiElements elements;
    std::size_t num_points = 0;
    std::size_t num_planes = 0;
    b.guarded(c, [&] {
        const std::vector<double> v = a.numbers("plane");
        if (v.size() % 10 != 0) a.fail("plane", "expected 10 numbers per plane, found " + std::to_string(v.size()));
        num_planes = v.size() / 10;
        const std::vector<Vec3> points = roi_points(b, a, info, RoiContext::plane_roi);
        num_points = points.size();
        elements = roi_elements(b, a, info, RoiContext::plane_roi, {.quads_and_hexahedra = false});
        selection = select_in_plane_roi(points, elements, v);
        // over moving positions: run again on read (live_engines.cpp); no plane: the outputs stay
        if (!v.empty())
            b.add_live_engine(a, points, [elements, v](const std::vector<Vec3>& x, LiveEngine& engine) {
                for (auto& [name, indices] : roi_index_outputs(select_in_plane_roi(x, elements, v)))
                    engine.indices[name] = std::move(indices);
            });
    });
    b.role(c, [selection, num_points, elements, num_planes] {
        return describe_roi_selection(selection, num_points, elements, counted(num_planes, "plane box", "plane boxes"));
    });
    record_roi_selection(b, c, std::move(selection));
    b.note_unread_attributes(c);
}

// ---- SphereROI ------------------------------------------------------------------------------
// SphereROI (a BaseROI): points within any ball (|p − c|² ≤ r²); one radius for several centres
// is repeated (SphereROI::roiDoUpdate); no centre selects nothing. Elements: BaseROI's strict
// test (all points inside, the default) or the centre's; edges and triangles may be further
// filtered by edgeAngle / triAngle (degrees, 0 = off).
constexpr AttributeSpec kSphereRoi[] = {
    {"centers", K::points, "", "m", ValueCheck::none, "ball centres"},
    {"radii", K::numbers, "", "m", ValueCheck::none, "one per centre, or one for all"},
    {"direction", K::vector3, "0 0 0", "", ValueCheck::none, "edge direction (edgeAngle > 0)"},
    {"normal", K::vector3, "0 0 0", "", ValueCheck::none, "triangle normal (triAngle > 0)"},
    {"edgeAngle", K::real, "0", "deg", ValueCheck::none, "> 0: keeps edges with |e.direction| < |cos|"},
    {"triAngle", K::real, "0", "deg", ValueCheck::none, "> 0: keeps triangles with n.normal < cos"},
    {"angle", K::real, "0", "deg", ValueCheck::none, "alias of triAngle"},
    {"strict", K::boolean, "1", "", ValueCheck::none, "1: all points of an element inside; 0: its centre"},
    {"doUpdate", K::boolean, "1", "", ValueCheck::none,
     "1: selects again when `position` links moving positions; 0: the selection of init stays"},
    PENALTY_ROI_POINTS,
    PENALTY_ROI_LISTS("edges", "edges"),
    PENALTY_ROI_LISTS("triangles", "triangles"),
    PENALTY_ROI_LISTS("quads", "quads"),
    PENALTY_ROI_LISTS("tetrahedra", "tetrahedra"),
    PENALTY_ROI_LISTS("hexahedra", "hexahedra"),
    PENALTY_ROI_COMPUTE("computeEdges"),
    PENALTY_ROI_COMPUTE("computeTriangles"),
    PENALTY_ROI_COMPUTE("computeQuads"),
    PENALTY_ROI_COMPUTE("computeTetrahedra"),
    PENALTY_ROI_COMPUTE("computeHexahedra"),
    PENALTY_ROI_OUTPUT("indices"),
    PENALTY_ROI_OUTPUT("pointIndices"),
    PENALTY_ROI_OUTPUT("edgeIndices"),
    PENALTY_ROI_OUTPUT("triangleIndices"),
    PENALTY_ROI_OUTPUT("quadIndices"),
    PENALTY_ROI_OUTPUT("tetrahedronIndices"),
    PENALTY_ROI_OUTPUT("hexahedronIndices"),
    PENALTY_ROI_DRAW("drawSphere"),
    PENALTY_ROI_DRAW("isVisible"),
    PENALTY_ROI_DRAW("drawROI"),
    PENALTY_ROI_DRAW("drawPoints"),
    PENALTY_ROI_DRAW("drawEdges"),
    PENALTY_ROI_DRAW("drawTriangles"),
    PENALTY_ROI_DRAW("drawQuads"),
    PENALTY_ROI_DRAW("drawTetrahedra"),
    PENALTY_ROI_DRAW("drawHexahedra"),
    {"drawSize", K::real, "1", "", ValueCheck::none, "drawing only"},
};

/// SphereROI's balls and element filters (SphereROI::roiDoUpdate), `direction` and `normal`
/// normalised.
struct SphereRoi {
    std::vector<SphereRegion> spheres;
    Vec3 direction;
    Vec3 normal;
    double edge_angle = 0;  ///< deg; > 0 filters the edges
    double tri_angle = 0;   ///< deg; > 0 filters the triangles
    ElementTest test = ElementTest::all_points;
};

RoiSelection select_in_sphere_roi(const std::vector<Vec3>& points, const RoiElements& elements, const SphereRoi& roi) {
    ElementFilters filters;
    if (roi.edge_angle > 0)
        filters.edge = [&points, &roi](const Edge& e) {
            return edge_passes_angle(points[std::size_t(e[0])], points[std::size_t(e[1])], roi.direction,
                                     roi.edge_angle);
        };
    if (roi.tri_angle > 0)
        filters.triangle = [&points, &roi](const Triangle& t) {
            return triangle_passes_angle(points[std::size_t(t[0])], points[std::size_t(t[1])],
                                         points[std::size_t(t[2])], roi.normal, roi.tri_angle);
        };
    const auto inside = [&roi](const Vec3& p) {
        return std::any_of(roi.spheres.begin(), roi.spheres.end(),
                           [&p](const SphereRegion& s) { return s.contains(p); });
    };
    return select_in_region(points, elements, inside, roi.test, filters);
}

void build_sphere_roi(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    RoiSelection selection;
    RoiElements elements;
    std::size_t num_points = 0;
    std::size_t num_spheres = 0;
    b.guarded(c, [&] {
        const std::vector<Vec3> centers = given_points(b, a, "centers").value_or(std::vector<Vec3>{});
        std::vector<double> radii = a.numbers("radii");
        for (double r : radii)
            if (!(r >= 0.0)) a.fail("radii", "must be >= 0");
        if (radii.size() == 1 && centers.size() > 1) radii.resize(centers.size(), radii[0]);
        std::vector<SphereRegion> spheres;
        if (radii.size() != centers.size()) {
            b.warn(c.describe() + ": " + std::to_string(centers.size()) + " centres and " +
                   std::to_string(radii.size()) + " radii: selects nothing, as SOFA");
        } else {
            for (std::size_t i = 0; i < centers.size(); ++i) spheres.push_back({centers[i], radii[i]});
        }
        num_spheres = spheres.size();
        const std::vector<Vec3> points = roi_points(b, a, info, RoiContext::base_roi);
        num_points = points.size();
        elements = roi_elements(b, a, info, RoiContext::base_roi);
        if (spheres.empty()) return;  // roiDoUpdate false: every output empty
        SphereRoi roi{.spheres = std::move(spheres),
                      .direction = a.vector3("direction"),
                      .normal = a.vector3("normal"),
                      .edge_angle = a.real("edgeAngle"),
                      .tri_angle = a.has("triAngle") ? a.real("triAngle") : a.real("angle"),
                      .test = a.boolean("strict") ? ElementTest::all_points : ElementTest::center};
        if (roi.direction.norm() > std::numeric_limits<double>::epsilon()) roi.direction /= roi.direction.norm();
        if (roi.normal.norm() > std::numeric_limits<double>::epsilon()) roi.normal /= roi.normal.norm();
        selection = select_in_sphere_roi(points, elements, roi);
        // over moving positions or centres: run again on read (live_engines.cpp); moved centres keep
        // their radii (SphereROI::roiDoUpdate reads both)
        b.add_live_engine(a, points, [elements, roi](const std::vector<Vec3>& x, LiveEngine& engine) {
            SphereRoi now = roi;
            if (const std::vector<Vec3>* moved = engine.followed("centers"))
                for (std::size_t i = 0; i < now.spheres.size() && i < moved->size(); ++i)
                    now.spheres[i].center = (*moved)[i];
            for (auto& [name, indices] : roi_index_outputs(select_in_sphere_roi(x, elements, now), {"pointIndices"}))
                engine.indices[name] = std::move(indices);
        });
    });
    b.role(c, [selection, num_points, elements, num_spheres] {
        return describe_roi_selection(selection, num_points, elements, counted(num_spheres, "ball", "balls"));
    });
    record_roi_selection(b, c, std::move(selection), {"pointIndices"});
    b.note_unread_attributes(c);
}

#undef PENALTY_ROI_POINTS
#undef PENALTY_ROI_LISTS
#undef PENALTY_ROI_COMPUTE
#undef PENALTY_ROI_OUTPUT
#undef PENALTY_ROI_DRAW

constexpr ComponentSpec kRegionOfInterestComponents[] = {
    {.type = "PlaneROI",
     .family = F::engine,
     .summary = "indices of the points and elements inside plane boxes",
     .attributes = kPlaneRoi,
     .build = build_plane_roi},
    {.type = "SphereROI",
     .family = F::engine,
     .summary = "indices of the points and elements inside balls",
     .attributes = kSphereRoi,
     .build = build_sphere_roi},
};

}  // namespace

std::span<const ComponentSpec> region_of_interest_components() { return kRegionOfInterestComponents; }

}  // namespace penalty::scene::builder
