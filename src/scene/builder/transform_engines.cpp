// Data engines that transform or merge points (SOFA's Sofa/Component/Engine/Transform and
// Generate): TransformEngine, TransformPosition, MergePoints, MeshTetraStuffing. Each reads its input
// points (inline or a link, `@[-1].position`), computes its output at the build (over moving points,
// TransformEngine, TransformPosition and MergePoints run again on read, TransformEngine and
// TransformPosition also when their translation, rotation or scale links moving points:
// live_engines.cpp) and
// records it as `output_position`, which a MechanicalObject, a topology or another engine reads
// through a link. Formulas: include/penalty/mechanics/transform_engines.hpp and
// docs/components/data_engines.md.
#include "penalty/mechanics/transform_engines.hpp"
#include "penalty/io/data_path.hpp"
#include "penalty/mechanics/mesh_tetra_stuffing.hpp"
#include "scene/builder/element_topology.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

/// The points of `name` (inline, or a link to positions), or those of `alias` when only it is set.
std::vector<Vec3> input_points(SceneBuilder& b, const Attributes& a, std::string_view name, std::string_view alias) {
    const std::string_view used = !a.has(name) && !alias.empty() && a.has(alias) ? alias : name;
    if (!a.has(used))
        io::throw_element_error(a.component(), "needs its input points: give `" + std::string(name) + "`");
    return b.point_data(a, used);
}

void record_points(SceneBuilder& b, const SceneComponent& c, std::initializer_list<const char*> names,
                   const std::vector<Vec3>& points) {
    for (const char* name : names) {
        io::MeshData mesh;
        mesh.positions = points;
        b.record_engine_mesh(c, name, std::move(mesh));
    }
}

// ---- TransformEngine ------------------------------------------------------------------------
/// A Vec3 Data: inline, three numbers; linked to another Data, the first three numbers of its value
/// (BaseData::genericCopyValueFrom: `translation="@mover.position"` takes the first point).
Vec3 vector3_or_first(const Attributes& a, std::string_view name) {
    if (!a.is_link(name)) return a.vector3(name);
    const std::vector<double> v = a.numbers(name);
    if (v.size() < 3) a.fail(name, "the linked Data has " + std::to_string(v.size()) + " numbers, expected 3 or more");
    return Vec3(v[0], v[1], v[2]);
}

/// A followed Vec3 input of a live engine (kLiveEngineKinds) linked to a list of points takes the
/// first (BaseData::genericCopyValueFrom copies the first 3 numbers; none: the value stays).
void take_followed(const LiveEngine& engine, std::string_view name, Vec3& value) {
    const std::vector<Vec3>* moved = engine.followed(name);
    if (moved != nullptr && !moved->empty()) value = moved->front();
}

// Defaults: TransformEngine's constructor.
constexpr AttributeSpec kTransformEngine[] = {
    {"input_position", K::points, "", "m", ValueCheck::none, "points to transform (inline or a link)"},
    {"translation", K::vector3, "0 0 0", "m", ValueCheck::none, "applied last"},
    {"rotation", K::vector3, "0 0 0", "deg", ValueCheck::none, "Euler angles, R = Rz·Ry·Rx, after the scale"},
    {"quaternion", K::numbers, "0 0 0 1", "", ValueCheck::none, "qx qy qz qw, applied after `rotation`"},
    {"scale", K::vector3, "1 1 1", "", ValueCheck::none, "per-axis factors, applied first"},
    {"inverse", K::boolean, "0", "", ValueCheck::none, "apply the inverse transformation"},
};

void build_transform_engine(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    const Attributes a(c);
    require_vec3_template(c);
    std::vector<Vec3> out;
    b.guarded(c, [&] {
        TransformEngineParameters p;
        p.translation = vector3_or_first(a, "translation");
        p.rotation_deg = vector3_or_first(a, "rotation");
        p.scale = vector3_or_first(a, "scale");
        p.inverse = a.boolean("inverse");
        if (a.has("quaternion")) {
            const std::vector<double> q = a.numbers("quaternion");
            if (q.size() != 4) a.fail("quaternion", "expected 4 numbers (qx qy qz qw)");
            p.quaternion = Quat(q[3], q[0], q[1], q[2]);
        }
        if (p.inverse && (p.scale[0] == 0 || p.scale[1] == 0 || p.scale[2] == 0))
            a.fail("scale", "a zero factor has no inverse");
        const std::vector<Vec3> in = input_points(b, a, "input_position", "");
        out = transform_engine(in, p);
        // over moving positions (a state's, which the solve writes), or a translation, rotation or
        // scale linking moving points: run again on read (live_engines.cpp)
        b.add_live_engine(a, in, [p](const std::vector<Vec3>& x, LiveEngine& engine) {
            TransformEngineParameters now = p;
            take_followed(engine, "translation", now.translation);
            take_followed(engine, "rotation", now.rotation_deg);
            take_followed(engine, "scale", now.scale);
            engine.meshes["output_position"].positions = transform_engine(x, now);
        });
    });
    record_points(b, c, {"output_position"}, out);
    b.role(c, [n = out.size()] { return "transforms " + counted(n, "point", "points") + " (output_position)"; });
    b.note_unread_attributes(c);
}

// ---- TransformPosition ----------------------------------------------------------------------
constexpr AttributeSpec kTransformPosition[] = {
    {"input_position", K::points, "", "m", ValueCheck::none, "points to transform (inline or a link)"},
    {"inputPosition", K::points, "", "m", ValueCheck::none, "alias of input_position"},
    {"method", K::text, "projectOnPlane", "", ValueCheck::none,
     "projectOnPlane, translation, rotation, scale, scaleTranslation, scaleRotationTranslation, affine, fromFile"},
    {"origin", K::vector3, "0 0 0", "m", ValueCheck::none, "a point of the plane; the centre of `scale`"},
    {"normal", K::vector3, "0 0 0", "", ValueCheck::none, "the plane's normal (normalised)"},
    {"translation", K::vector3, "0 0 0", "m", ValueCheck::none, ""},
    {"rotation", K::vector3, "0 0 0", "deg", ValueCheck::none, "Euler angles, R = Rz·Ry·Rx"},
    {"scale", K::vector3, "1 1 1", "", ValueCheck::none, "per-axis factors"},
    {"matrix", K::numbers, "(identity)", "", ValueCheck::none, "4x4 affine matrix, row by row (method affine)"},
    {"filename", K::text, "", "", ValueCheck::none, "the affine matrix (method fromFile): .tfm, .trm, .xfm, .txt"},
    {"fixedIndices", K::indices, "", "", ValueCheck::none, "points that keep their input position"},
    {"output_position", K::points, "", "m", ValueCheck::none, "output (a written value is replaced)"},
    {"outputPosition", K::points, "", "m", ValueCheck::none, "alias of output_position"},
    {"drawInput", K::boolean, "0", "", ValueCheck::none, "display only"},
    {"drawOutput", K::boolean, "0", "", ValueCheck::none, "display only"},
    {"pointSize", K::real, "1", "", ValueCheck::none, "display only"},
};

TransformPositionMethod position_method(const Attributes& a, SceneBuilder& b, Eigen::Matrix4d& matrix) {
    using M = TransformPositionMethod;
    const std::string method = a.text("method");
    if (method == "projectOnPlane") return M::project_on_plane;
    if (method == "translation") return M::translation;
    if (method == "rotation") return M::rotation;
    if (method == "scale") return M::scale;
    if (method == "scaleTranslation") return M::scale_translation;
    if (method == "scaleRotationTranslation") return M::scale_rotation_translation;
    if (method == "affine") return M::affine;
    if (method == "fromFile") {
        if (!a.has("filename")) a.fail("filename", "method fromFile needs a file");
        try {
            matrix = read_affine_transform_file(
                io::resolve_data_file(a.text("filename"), b.scene_dir(), b.options().data_dirs));
        } catch (const std::exception& e) {  // not found (io::LoadError), or not a transformation
            a.fail("filename", e.what());
        }
        return M::affine;
    }
    if (method == "random")
        a.fail("method", "'random' is not supported (SOFA's RandomGenerator sequence is not reproduced)");
    a.fail("method", "unknown method '" + method + "'");
}

void build_transform_position(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    const Attributes a(c);
    require_vec3_template(c);
    std::vector<Vec3> out;
    b.guarded(c, [&] {
        TransformPositionParameters p;
        if (a.has("matrix")) {
            const std::vector<double> m = a.numbers("matrix");
            if (m.size() != 16) a.fail("matrix", "expected 16 numbers (a 4x4 matrix, row by row)");
            for (int r = 0; r < 4; ++r)
                for (int k = 0; k < 4; ++k) p.matrix(r, k) = m[4 * std::size_t(r) + std::size_t(k)];
        }
        p.method = position_method(a, b, p.matrix);
        p.origin = vector3_or_first(a, "origin");
        p.normal = a.vector3("normal");
        if (p.method == TransformPositionMethod::project_on_plane && p.normal == Vec3::Zero())
            a.fail("normal", "method projectOnPlane needs a non-zero normal");
        p.translation = vector3_or_first(a, "translation");
        p.rotation_deg = vector3_or_first(a, "rotation");
        p.scale = vector3_or_first(a, "scale");
        if (a.has("fixedIndices")) p.fixed_indices = b.indices(a, "fixedIndices");
        const std::vector<Vec3> in = input_points(b, a, "input_position", "inputPosition");
        out = transform_position(in, p);
        // over moving positions, or a translation, rotation, scale or origin linking moving points:
        // run again on read (live_engines.cpp)
        b.add_live_engine(a, in, [p](const std::vector<Vec3>& x, LiveEngine& engine) {
            TransformPositionParameters now = p;
            take_followed(engine, "translation", now.translation);
            take_followed(engine, "rotation", now.rotation_deg);
            take_followed(engine, "scale", now.scale);
            take_followed(engine, "origin", now.origin);
            std::vector<Vec3> moved = transform_position(x, now);
            engine.meshes["outputPosition"].positions = moved;  // alias
            engine.meshes["output_position"].positions = std::move(moved);
        });
    });
    record_points(b, c, {"output_position", "outputPosition"}, out);
    b.role(c, [n = out.size(), method = a.text("method")] {
        return "transforms " + counted(n, "point", "points") + " by method " + method + " (output_position)";
    });
    b.note_unread_attributes(c);
}

// ---- MergePoints ----------------------------------------------------------------------------
constexpr AttributeSpec kMergePoints[] = {
    {"position1", K::points, "", "m", ValueCheck::none, "the first points (inline or a link)"},
    {"position2", K::points, "", "m", ValueCheck::none, "the second points"},
    {"mappingX2", K::indices, "", "", ValueCheck::none, "indices in position1 where position2's points go"},
    {"noUpdate", K::boolean, "0", "", ValueCheck::none, "1: the output of init stays when the inputs move"},
    {"indices1", K::indices, "", "", ValueCheck::none, "output (a written value is replaced)"},
    {"indices2", K::indices, "", "", ValueCheck::none, "output (a written value is replaced)"},
    {"points", K::points, "", "m", ValueCheck::none, "output (a written value is replaced)"},
};

void build_merge_points(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    const Attributes a(c);
    require_vec3_template(c);
    MergedPoints out;
    b.guarded(c, [&] {
        const auto points_of = [&](std::string_view name) {
            if (!a.has(name)) return std::vector<Vec3>{};
            return b.point_data(a, name);
        };
        const std::vector<Vec3> x1 = points_of("position1");
        const std::vector<Vec3> x2 = points_of("position2");
        std::vector<PointId> mapping;
        if (a.has("mappingX2")) mapping = b.indices(a, "mappingX2");
        out = merge_points(x1, x2, mapping);
        // over moving positions (position1, or position2 followed): run again on read
        // (live_engines.cpp; MergePoints::doUpdate unless noUpdate)
        b.add_live_engine(a, x1, [x2, mapping](const std::vector<Vec3>& x, LiveEngine& engine) {
            const std::vector<Vec3>* moved = engine.followed("position2");
            MergedPoints merged = merge_points(x, moved != nullptr ? *moved : x2, mapping);
            engine.meshes["points"].positions = std::move(merged.points);
            engine.indices["indices1"] = std::move(merged.indices1);
            engine.indices["indices2"] = std::move(merged.indices2);
        });
    });
    record_points(b, c, {"points"}, out.points);
    b.record_engine_indices(c, "indices1", out.indices1);
    b.record_engine_indices(c, "indices2", out.indices2);
    b.role(c, [n = out.points.size()] { return "merges into " + counted(n, "point", "points") + " (points)"; });
    b.note_unread_attributes(c);
}

// ---- MeshTetraStuffing ----------------------------------------------------------------------
// Defaults: MeshTetraStuffing's constructor (docs/components/mesh_tetra_stuffing.md).
constexpr AttributeSpec kMeshTetraStuffing[] = {
    {"inputPoints", K::points, "", "m", ValueCheck::none, "the closed surface's points (inline or a link)"},
    {"inputTriangles", K::elements, "", "", ValueCheck::none, "its triangles (inline or a link)"},
    {"inputQuads", K::elements, "", "", ValueCheck::none, "its quads, each as two triangles"},
    {"vbbox", K::numbers, "(the surface's box grown by 1 %)", "m", ValueCheck::none, "xmin ymin zmin xmax ymax zmax"},
    {"size", K::real, "-8", "m", ValueCheck::none, "cell size; negative: -(cells along the box's largest side)"},
    {"alphaLong", K::real, "0.24999", "", ValueCheck::nonnegative, "snapping threshold on axis edges"},
    {"alphaShort", K::real, "0.42978", "", ValueCheck::nonnegative, "snapping threshold on diagonal edges"},
    {"snapPoints", K::boolean, "0", "", ValueCheck::none, "snap lattice points close to the surface onto it"},
    {"splitTetrahedra", K::boolean, "0", "", ValueCheck::none, "cut the tetrahedra crossing the surface"},
    {"splitTetras", K::boolean, "0", "", ValueCheck::none, "alias of splitTetrahedra"},
    {"draw", K::boolean, "0", "", ValueCheck::none, "display only"},
};

void build_mesh_tetra_stuffing(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    const Attributes a(c);
    StuffedVolume out;
    b.guarded(c, [&] {
        MeshTetraStuffingParameters p;
        if (a.has("vbbox")) {
            const std::vector<double> v = a.numbers("vbbox");
            if (v.size() != 6) a.fail("vbbox", "expected 6 numbers (xmin ymin zmin xmax ymax zmax)");
            p.box = std::array<Vec3, 2>{Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5])};
        }
        p.size = a.real("size");
        if (p.size == 0 || !std::isfinite(p.size)) a.fail("size", "must be non-zero");
        p.alpha_long = a.real("alphaLong");
        p.alpha_short = a.real("alphaShort");
        p.snap_points = a.boolean("snapPoints");
        p.split_tetrahedra = a.has("splitTetrahedra") ? a.boolean("splitTetrahedra") : a.boolean("splitTetras");
        static_cast<void>(a.boolean("draw"));
        std::vector<Triangle> triangles;
        std::vector<Quad> quads;
        read_element_list(b, a, "inputTriangles", triangles, &io::MeshData::triangles, &MeshTopology::triangles);
        read_element_list(b, a, "inputQuads", quads, &io::MeshData::quads, &MeshTopology::quads);
        if (!a.has("inputPoints")) a.fail("inputPoints", "is needed (SOFA: empty input mesh)");
        const std::vector<Vec3> points = b.point_data(a, "inputPoints");
        if (triangles.empty() && quads.empty())
            a.fail("inputTriangles", "no triangles or quads (SOFA: empty input mesh)");
        out = mesh_tetra_stuffing(points, triangles, quads, p, b.options().max_dofs);
        if (out.invalid_splits > 0)
            b.warn(c.describe() + ": " + counted(out.invalid_splits, "cut", "cuts") +
                   " SOFA reports as invalid (Invalid tetra split / cut point not found), reproduced");
    });
    io::MeshData mesh;
    mesh.positions = out.points;
    b.record_engine_mesh(c, "outputPoints", mesh);
    mesh.tetrahedra = out.tetrahedra;
    for (const char* name : {"outputTetrahedra", "outputTetras"}) b.record_engine_mesh(c, name, mesh);
    b.role(c, [n = out.points.size(), t = out.tetrahedra.size()] {
        return "fills the surface with " + counted(t, "tetrahedron", "tetrahedra") + " on " +
               counted(n, "point", "points") + " (outputPoints, outputTetrahedra)";
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kTransformEngineComponents[] = {
    {.type = "MeshTetraStuffing",
     .family = F::data_engine,
     .summary = "fills a closed triangle surface with tetrahedra (isosurface stuffing)",
     .attributes = kMeshTetraStuffing,
     .build = build_mesh_tetra_stuffing},
    {.type = "MergePoints",
     .family = F::data_engine,
     .summary = "merges two point lists (appended, or injected)",
     .attributes = kMergePoints,
     .build = build_merge_points},
    {.type = "TransformEngine",
     .family = F::data_engine,
     .summary = "scales, rotates and translates points (output_position)",
     .attributes = kTransformEngine,
     .build = build_transform_engine},
    {.type = "TransformPosition",
     .family = F::data_engine,
     .summary = "transforms points by one method: plane projection, translation, rotation, scale, affine matrix",
     .attributes = kTransformPosition,
     .build = build_transform_position},
};

}  // namespace

std::span<const ComponentSpec> transform_engine_components() { return kTransformEngineComponents; }

}  // namespace penalty::scene::builder
