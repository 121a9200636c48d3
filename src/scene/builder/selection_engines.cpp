// Selection engines beyond the boxes, planes and balls (SOFA's Sofa/Component/Engine/Select):
// MeshROI (points and elements inside a closed triangle mesh), ProximityROI (the N points nearest
// a set of centres) and ValuesFromPositions (a scalar or vector field along a direction). Each
// computes its outputs at build and records them for links (`@roi.indices`, ...); over moving
// positions (MeshROI also over a moving ROI mesh, ProximityROI over moving centres) they run again
// on read (live_engines.cpp).
// Formulas: include/penalty/mechanics/selection_engines.hpp, docs/components/data_engines.md.
#include "penalty/mechanics/selection_engines.hpp"
#include "scene/builder/element_topology.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/regions_of_interest.hpp"

#include <memory>
#include <optional>
#include <tuple>
#include <utility>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

const Vec3Object* local_state(const NodeBuild& info) {
    return info.node != nullptr ? dynamic_cast<const Vec3Object*>(info.node->state()) : nullptr;
}

const SceneComponent* local_loader(const NodeBuild& info) {
    for (const auto& c : info.scene_node->components)
        if (component_category(c->type) == ComponentCategory::loader) return c.get();
    return nullptr;
}

#define PENALTY_ROI_LIST(ELEMENTS, ELEMENT) \
    { ELEMENTS, K::elements, "(the node's topology)", "", ValueCheck::none, ELEMENT " tested (inline or a link)" }
#define PENALTY_ROI_FLAG(NAME, DEFAULT, MEANING) \
    { NAME, K::boolean, DEFAULT, "", ValueCheck::none, MEANING }
#define PENALTY_OUTPUT(NAME) \
    { NAME, K::indices, "", "", ValueCheck::none, "output (a written value is replaced)" }

// ---- MeshROI --------------------------------------------------------------------------------
// MeshROI (a BaseROI): the ROI mesh (ROIposition, ROItriangles; by default the node's own state's
// rest positions, else its loader's points, and its topology's triangles) bounds the region;
// `strict` is 0 unless set (MeshROI's constructor), and a non-strict element is inside when all
// of its points are, or else when its centre is (MeshROI::isEdgeInROI, ...).
constexpr AttributeSpec kMeshRoi[] = {
    {"ROIposition", K::points, "(the node's state's rest positions, else its loader's points)", "m", ValueCheck::none,
     "points of the ROI mesh"},
    {"ROIedges", K::elements, "(the node's topology's edges)", "", ValueCheck::none, "read, not used by the test"},
    {"ROItriangles", K::elements, "(the node's topology's triangles)", "", ValueCheck::none, "the closed ROI surface"},
    PENALTY_ROI_FLAG("computeMeshROI", "1", "0: every point inside the ROI mesh's box is inside"),
    {"position", K::points, "(rest positions of the context's state)", "m", ValueCheck::none, "points tested"},
    {"rest_position", K::points, "", "m", ValueCheck::none, "alias of position"},
    PENALTY_ROI_LIST("edges", "edges"),
    PENALTY_ROI_LIST("triangles", "triangles"),
    PENALTY_ROI_LIST("quads", "quads"),
    PENALTY_ROI_LIST("tetrahedra", "tetrahedra"),
    PENALTY_ROI_LIST("hexahedra", "hexahedra"),
    PENALTY_ROI_FLAG("computeEdges", "1", "0: that list is not tested"),
    PENALTY_ROI_FLAG("computeTriangles", "1", "0: that list is not tested"),
    PENALTY_ROI_FLAG("computeQuads", "1", "0: that list is not tested"),
    PENALTY_ROI_FLAG("computeTetrahedra", "1", "0: that list is not tested"),
    PENALTY_ROI_FLAG("computeHexahedra", "1", "0: that list is not tested"),
    PENALTY_ROI_FLAG("strict", "0", "1: all points of an element inside; 0: all points, or else its centre"),
    PENALTY_ROI_FLAG("doUpdate", "1",
                     "1: selects again when `position` links moving positions; 0: the selection of init stays"),
    {"box", K::numbers, "", "m", ValueCheck::none, "output: the ROI mesh's bounding box"},
    PENALTY_OUTPUT("indices"),
    PENALTY_OUTPUT("edgeIndices"),
    PENALTY_OUTPUT("triangleIndices"),
    PENALTY_OUTPUT("quadIndices"),
    PENALTY_OUTPUT("tetrahedronIndices"),
    PENALTY_OUTPUT("hexahedronIndices"),
    PENALTY_ROI_FLAG("drawOut", "0", "drawing only"),
    PENALTY_ROI_FLAG("drawBox", "0", "drawing only"),
    PENALTY_ROI_FLAG("drawPoints", "0", "drawing only"),
    PENALTY_ROI_FLAG("drawEdges", "0", "drawing only"),
    PENALTY_ROI_FLAG("drawTriangles", "0", "drawing only"),
    PENALTY_ROI_FLAG("drawTetrahedra", "0", "drawing only"),
    PENALTY_ROI_FLAG("drawQuads", "0", "drawing only"),
    PENALTY_ROI_FLAG("drawHexahedra", "0", "drawing only"),
};

void build_mesh_roi(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    require_vec3_template(c);
    RoiSelection selection;
    RoiElements elements;
    std::size_t num_points = 0;
    std::size_t roi_triangles = 0;
    b.guarded(c, [&] {
        // MeshROI::checkInputData: the ROI mesh's defaults are the node's own (Local) objects
        std::vector<Vec3> roi_positions;
        if (auto given = given_points(b, a, "ROIposition")) roi_positions = std::move(*given);
        else if (const Vec3Object* s = local_state(info)) roi_positions = s->rest_position;
        else if (const SceneComponent* loader = local_loader(info)) roi_positions = b.mesh_of(*loader).positions;
        std::vector<Triangle> triangles;
        if (a.has("ROItriangles")) {
            read_element_list(b, a, "ROItriangles", triangles, &io::MeshData::triangles, &MeshTopology::triangles);
        } else if (a.boolean("computeTriangles") && info.topology != nullptr) {
            triangles = info.topology->triangles();
        }
        if (a.has("ROIedges")) {
            std::vector<Edge> edges;  // read (a bad value is an error), not used by the test
            read_element_list(b, a, "ROIedges", edges, &io::MeshData::edges, &MeshTopology::edges);
        }
        roi_triangles = triangles.size();
        auto region = std::make_shared<const MeshRegion>(std::move(roi_positions), std::move(triangles),
                                                         a.boolean("computeMeshROI"));
        const std::vector<Vec3> points = roi_points(b, a, info, RoiContext::base_roi);
        num_points = points.size();
        elements = roi_elements(b, a, info, RoiContext::base_roi);
        const ElementTest test = a.boolean("strict") ? ElementTest::all_points : ElementTest::all_points_or_center;
        const auto inside = [region](const Vec3& p) { return region->contains(p); };
        selection = select_in_region(points, elements, inside, test);
        // over moving positions, or a ROI mesh whose points link moving ones: run again on read
        // (live_engines.cpp); the moved ROI mesh keeps the bounding box of init (MeshROI::roiInit)
        b.add_live_engine(a, points, [elements, region, test](const std::vector<Vec3>& x, LiveEngine& engine) {
            std::optional<MeshRegion> moved;
            if (const std::vector<Vec3>* roi = engine.followed("ROIposition")) moved = region->moved(*roi);
            const MeshRegion& now = moved ? *moved : *region;
            const auto in = [&now](const Vec3& p) { return now.contains(p); };
            for (auto& [name, indices] : roi_index_outputs(select_in_region(x, elements, in, test)))
                engine.indices[name] = std::move(indices);
        });
    });
    b.role(c, [selection, num_points, elements, roi_triangles] {
        return describe_roi_selection(selection, num_points, elements,
                                      "a mesh of " + counted(roi_triangles, "triangle", "triangles"));
    });
    record_roi_selection(b, c, std::move(selection));
    b.note_unread_attributes(c);
}

// ---- ProximityROI ---------------------------------------------------------------------------
constexpr AttributeSpec kProximityRoi[] = {
    {"centers", K::points, "", "m", ValueCheck::none, "ball centres"},
    {"radii", K::numbers, "", "m", ValueCheck::none, "one per centre (missing ones repeat the last)"},
    {"N", K::integer, "0", "", ValueCheck::none, "the most points selected (0 selects nothing: indices = 0)"},
    {"position", K::points, "(rest positions of the nearest state, else the nearest loader's points)", "m",
     ValueCheck::none, "points tested"},
    {"rest_position", K::points, "", "m", ValueCheck::none, "alias of position"},
    PENALTY_OUTPUT("indices"),
    PENALTY_OUTPUT("pointIndices"),
    PENALTY_OUTPUT("indicesOut"),
    {"pointsInROI", K::points, "", "m", ValueCheck::none, "output (a written value is replaced)"},
    {"distance", K::numbers, "", "m", ValueCheck::none, "output (a written value is replaced)"},
    PENALTY_ROI_FLAG("drawSphere", "0", "drawing only"),
    PENALTY_ROI_FLAG("drawPoints", "0", "drawing only"),
    {"drawSize", K::real, "1", "", ValueCheck::none, "drawing only"},
};

void build_proximity_roi(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    require_vec3_template(c);
    ProximitySelection s;
    std::size_t num_points = 0;
    b.guarded(c, [&] {
        const std::vector<Vec3> centers = given_points(b, a, "centers").value_or(std::vector<Vec3>{});
        const std::vector<double> radii = a.numbers("radii");
        const std::int64_t n = a.integer("N");
        if (n < 0) a.fail("N", "must be >= 0");
        // ProximityROI::init: the context's state (searched upward), else its loader
        const std::vector<Vec3> points = roi_points(b, a, info, RoiContext::plane_roi);
        num_points = points.size();
        s = proximity_roi(points, centers, radii, std::size_t(n));
        // over moving positions: run again on read (live_engines.cpp); ProximityROI::doUpdate
        // leaves its outputs as they are without centres, radii or N
        if (!centers.empty() && !radii.empty() && n > 0)
            b.add_live_engine(a, points, [centers, radii, n](const std::vector<Vec3>& x, LiveEngine& engine) {
                const std::vector<Vec3>* moved_centers = engine.followed("centers");
                ProximitySelection moved =
                    proximity_roi(x, moved_centers != nullptr ? *moved_centers : centers, radii, std::size_t(n));
                engine.indices["indices"] = moved.indices;
                engine.indices["pointIndices"] = std::move(moved.indices);
                engine.indices["indicesOut"] = std::move(moved.indices_out);
                engine.meshes["pointsInROI"].positions = std::move(moved.points);
            });
    });
    b.role(c, [count = s.indices.size(), num_points] {
        return "selects " + std::to_string(count) + " of " + counted(num_points, "point", "points") +
               " (nearest the centres)";
    });
    b.record_engine_indices(c, "indices", s.indices);
    b.record_engine_indices(c, "pointIndices", s.indices);
    b.record_engine_indices(c, "indicesOut", s.indices_out);
    io::MeshData in_roi;
    in_roi.positions = s.points;
    b.record_engine_mesh(c, "pointsInROI", std::move(in_roi));
    b.note_unread_attributes(c);
}

// ---- ValuesFromPositions --------------------------------------------------------------------
constexpr AttributeSpec kValuesFromPositions[] = {
    {"inputValues", K::numbers, "", "", ValueCheck::none, "values interpolated along `direction`"},
    {"direction", K::vector3, "0 1 0", "", ValueCheck::none, "the interpolation direction; the vector field"},
    {"fieldType", K::text, "Scalar", "", ValueCheck::none, "Scalar or Vector"},
    {"position", K::points, "(rest positions of the nearest state, else the nearest loader's points)", "m",
     ValueCheck::none, ""},
    {"rest_position", K::points, "", "m", ValueCheck::none, "alias of position"},
    {"edges", K::elements, "(the nearest topology's)", "", ValueCheck::none, ""},
    {"triangles", K::elements, "(the nearest topology's)", "", ValueCheck::none, ""},
    {"tetrahedra", K::elements, "(the nearest topology's)", "", ValueCheck::none, ""},
    PENALTY_ROI_FLAG("drawVectors", "0", "drawing only"),
    {"drawVectorLength", K::real, "10", "", ValueCheck::none, "drawing only"},
};

/// The nearest topology from the node up (BaseContext::get searches upward).
const MeshTopology* nearest_topology(SceneBuilder& b, const NodeBuild& info) {
    for (const io::SceneNode* n = info.scene_node; n != nullptr; n = n->parent)
        if (const MeshTopology* t = b.node_build(*n).topology) return t;
    return nullptr;
}

/// The interval ValuesFromPositions interpolates over, or why penalty cannot give it:
/// ValuesFromPositions::doUpdate takes the first coordinates of the root context's bounding box's
/// min and max (`*bbox.minBBoxPtr()`, `*bbox.maxBBoxPtr()`: x, whatever the direction). That box is
/// the root node's `bbox` when the scene file gives it (Node::parse: bboxIsFixed), else what
/// SOFA's visitors compute from every component's computeBBox at the time the engine runs (drawn
/// states, FEM force fields and springs, fixed points, visual models: InitVisitor,
/// UpdateBoundingBoxVisitor after init and after each step), which penalty does not reproduce.
/// A script's root `bbox` is a Data written after the node was made, not parsed with it: SOFA's
/// visitors compute it again (no bboxIsFixed).
std::optional<std::pair<double, double>> scene_bbox_x(const SceneBuilder& b, std::string& why) {
    const io::SceneNode& root = *b.file().root;
    const io::SceneAttribute* bbox = root.find("bbox");
    const bool script = root.file.ends_with(".py") || root.file.ends_with(".pyscn");
    if (bbox == nullptr || script) {
        why =
            "scalar values over several inputValues are interpolated over the x extent of the scene's "
            "bounding box (ValuesFromPositions::doUpdate reads the root context's bbox), which SOFA computes "
            "from every component's computeBBox when the engine runs (drawn states, force fields, fixed "
            "points, visual models); penalty does not compute it: give the root node of a scene file a fixed "
            "bbox (<Node name=\"root\" bbox=\"xmin ymin zmin xmax ymax zmax\">; a script's root.bbox is not "
            "fixed, SOFA computes it again)";
        return std::nullopt;
    }
    const std::vector<double> v = io::get_doubles(root, "bbox");
    if (v.size() != 6)
        io::throw_element_error(root, "attribute 'bbox': expected 6 numbers (xmin ymin zmin xmax ymax zmax), found " +
                                          std::to_string(v.size()));
    return std::pair{v[0], v[3]};
}

/// ValuesFromPositions' outputs by their Data names: visit_reals(name, values) for the four
/// scalar lists, visit_vectors(name, vectors) for the four vector lists (moved out of `r`).
template <class Reals, class Vectors>
void visit_values_outputs(ValuesFromPositionsResult& r, Reals&& visit_reals, Vectors&& visit_vectors) {
    visit_reals("values", std::move(r.point_values));
    visit_reals("edgeValues", std::move(r.edge_values));
    visit_reals("triangleValues", std::move(r.triangle_values));
    visit_reals("tetrahedronValues", std::move(r.tetrahedron_values));
    visit_vectors("pointVectors", std::move(r.point_vectors));
    visit_vectors("edgeVectors", std::move(r.edge_vectors));
    visit_vectors("triangleVectors", std::move(r.triangle_vectors));
    visit_vectors("tetrahedronVectors", std::move(r.tetrahedron_vectors));
}

void build_values_from_positions(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    require_vec3_template(c);
    ValuesFromPositionsResult r;
    bool vectors = false;
    b.guarded(c, [&] {
        const std::string field = a.text("fieldType");
        if (field != "Scalar" && field != "Vector")
            a.fail("fieldType", "expected Scalar or Vector, found '" + field + "'");
        vectors = field == "Vector";
        const std::vector<Vec3> points = roi_points(b, a, info, RoiContext::plane_roi);
        const MeshTopology* topology = nearest_topology(b, info);
        std::vector<Edge> edges = topology != nullptr ? topology->edges() : std::vector<Edge>{};
        std::vector<Triangle> triangles = topology != nullptr ? topology->triangles() : std::vector<Triangle>{};
        std::vector<Tetrahedron> tetrahedra = topology != nullptr ? topology->tetrahedra() : std::vector<Tetrahedron>{};
        read_element_list(b, a, "edges", edges, &io::MeshData::edges, &MeshTopology::edges);
        read_element_list(b, a, "triangles", triangles, &io::MeshData::triangles, &MeshTopology::triangles);
        read_element_list(b, a, "tetrahedra", tetrahedra, &io::MeshData::tetrahedra, &MeshTopology::tetrahedra);
        const std::vector<double> input = a.numbers("inputValues");
        const Vec3 direction = a.vector3("direction");
        // the interval matters only for a scalar field over several values (valueFromPosition)
        double lo = 0.0, hi = 1.0;
        std::string why;
        if (!vectors && input.size() > 1) {
            if (const auto x = scene_bbox_x(b, why)) std::tie(lo, hi) = *x;
            else {
                const std::string where = c.file + ":" + std::to_string(c.line) + ": " + c.describe() + ": ";
                b.refuse_engine_reals(c, where + why);
                b.warn(where + "its scalar outputs (values, edgeValues, ...) cannot be read: " + why);
            }
        }
        r = values_from_positions(points, edges, triangles, tetrahedra, direction, input, lo, hi, vectors);
        // over moving positions: run again on read (live_engines.cpp)
        b.add_live_engine(a, points, [=](const std::vector<Vec3>& x, LiveEngine& engine) {
            // a `direction` linked to moving points takes the first (BaseData::genericCopyValueFrom)
            const std::vector<Vec3>* moved = engine.followed("direction");
            const Vec3 dir = moved != nullptr && !moved->empty() ? moved->front() : direction;
            ValuesFromPositionsResult out =
                values_from_positions(x, edges, triangles, tetrahedra, dir, input, lo, hi, vectors);
            visit_values_outputs(
                out, [&](const char* name, std::vector<double> v) { engine.reals[name] = std::move(v); },
                [&](const char* name, std::vector<Vec3> v) { engine.meshes[name].positions = std::move(v); });
        });
    });
    b.role(c, [n = vectors ? r.point_vectors.size() : r.point_values.size(), vectors] {
        return std::string(vectors ? "a vector" : "a scalar") + " per point and element (" +
               counted(n, "point", "points") + ")";
    });
    visit_values_outputs(
        r, [&](const char* name, std::vector<double> v) { b.record_engine_reals(c, name, std::move(v)); },
        [&](const char* name, std::vector<Vec3> v) {
            io::MeshData m;
            m.positions = std::move(v);
            b.record_engine_mesh(c, name, std::move(m));
        });
    b.note_unread_attributes(c);
}

#undef PENALTY_ROI_LIST
#undef PENALTY_ROI_FLAG
#undef PENALTY_OUTPUT

constexpr ComponentSpec kSelectionEngineComponents[] = {
    {.type = "MeshROI",
     .family = F::engine,
     .summary = "indices of the points and elements inside a closed triangle mesh",
     .attributes = kMeshRoi,
     .build = build_mesh_roi},
    {.type = "ProximityROI",
     .family = F::engine,
     .summary = "indices of the N points nearest a set of centres",
     .attributes = kProximityRoi,
     .build = build_proximity_roi},
    {.type = "ValuesFromPositions",
     .family = F::engine,
     .summary = "a scalar or vector field per point and element, along a direction",
     .attributes = kValuesFromPositions,
     .build = build_values_from_positions},
};

}  // namespace

std::span<const ComponentSpec> selection_engine_components() { return kSelectionEngineComponents; }

}  // namespace penalty::scene::builder
