// States and topologies: MechanicalObject, MeshTopology, RegularGridTopology.
#include "scene/builder/element_topology.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// ---- MeshTopology ---------------------------------------------------------------------------
constexpr AttributeSpec kMeshTopology[] = {
    {"src", K::link, "", "", ValueCheck::none, "mesh loader whose points and elements it takes"},
    {"filename", K::text, "", "", ValueCheck::none, "mesh file read directly (no transform)"},
    {"position", K::points, "", "m", ValueCheck::none, "points (override src/filename)"},
    {"edges", K::elements, "", "", ValueCheck::none, "point pairs"},
    {"triangles", K::elements, "", "", ValueCheck::none, "point triples"},
    {"quads", K::elements, "", "", ValueCheck::none, "4 points each"},
    {"tetrahedra", K::elements, "", "", ValueCheck::none, "4 points each"},
    {"tetras", K::elements, "", "", ValueCheck::none, "alias of tetrahedra"},
    {"hexahedra", K::elements, "", "", ValueCheck::none, "8 points each"},
    {"hexas", K::elements, "", "", ValueCheck::none, "alias of hexahedra"},
};

void build_mesh_topology(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    build_element_topology(b, c, info,
                           {.edges = true, .triangles = true, .quads = true, .tetrahedra = true, .hexahedra = true});
}

// ---- RegularGridTopology --------------------------------------------------------------------
constexpr AttributeSpec kRegularGrid[] = {
    {"n", K::indices, "2 2 2", "", ValueCheck::none, "points along x, y, z (1 to 100000 each)"},
    {"nx", K::integer, "(n[0])", "", ValueCheck::none, "points along x (read only when nx, ny and nz are all given)"},
    {"ny", K::integer, "(n[1])", "", ValueCheck::none, "points along y"},
    {"nz", K::integer, "(n[2])", "", ValueCheck::none, "points along z"},
    {"min", K::vector3, "0 0 0", "m", ValueCheck::none, "lower corner (max may be below it)"},
    {"max", K::vector3, "1 1 1", "m", ValueCheck::none, "upper corner"},
    {"p0", K::vector3, "(min; the middle of min and max on x or y when that axis has one point)", "m", ValueCheck::none,
     "the first point (offsets the grid)"},
    {"xmin", K::real, "(min[0])", "m", ValueCheck::none,
     "read only when the six of xmin..zmax are all given, as floats (SOFA's parse)"},
    {"xmax", K::real, "(max[0])", "m", ValueCheck::none, ""},
    {"ymin", K::real, "(min[1])", "m", ValueCheck::none, ""},
    {"ymax", K::real, "(max[1])", "m", ValueCheck::none, ""},
    {"zmin", K::real, "(min[2])", "m", ValueCheck::none, ""},
    {"zmax", K::real, "(max[2])", "m", ValueCheck::none, ""},
    {"scale", K::real, "1", "", ValueCheck::none, "multiplies xmin..zmax (not min and max), read as a float"},
    {"computeTriangleList", K::boolean, "1", "", ValueCheck::none,
     "two triangles per quad, and the edges taken from them (else the edges along the axes)"},
    {"computeHexaList", K::boolean, "1", "", ValueCheck::none, "0: no hexahedra"},
    {"computeQuadList", K::boolean, "1", "", ValueCheck::none, "only 1"},
    {"computeEdgeList", K::boolean, "1", "", ValueCheck::none, "only 1"},
    {"src", K::link, "", "", ValueCheck::none,
     "a RegularGridTopology built before: its n, min, max and p0, unless given here (SOFA's src links the Data "
     "of the same names)"},
};

/// RegularGridTopology::parse: xmin, ..., zmax replace min and max only when the six are given,
/// each read with getAttributeAsFloat (strtof) and multiplied by `scale` (a float too); in
/// double with the quirk fix regular_grid_float_bounds.
std::optional<std::pair<Vec3, Vec3>> scalar_grid_bounds(const Attributes& a, const SofaQuirkFixes& quirks) {
    constexpr std::array<std::string_view, 6> kNames{"xmin", "ymin", "zmin", "xmax", "ymax", "zmax"};
    const auto given = std::count_if(kNames.begin(), kNames.end(), [&](std::string_view n) { return a.has(n); });
    if (given < 6) return std::nullopt;
    const bool in_double = quirks.fix_regular_grid_float_bounds;
    const auto value = [&](std::string_view name, double fallback) {
        const double v = a.real_or(name, fallback);  // a number, or the attribute's error
        if (in_double) return v;
        const float f = std::strtof(a.text(name).c_str(), nullptr);
        if (!std::isfinite(f))
            a.fail(name, "'" + a.text(name) +
                             "' is beyond float range, and SOFA reads this attribute as a float "
                             "(--fix-sofa-quirk regular_grid_float_bounds reads it in double)");
        return double(f);
    };
    const double scale = value("scale", 1.0);
    std::array<double, 6> v{};
    for (std::size_t k = 0; k < 6; ++k) v[k] = value(kNames[k], 0.0) * scale;
    return std::pair{Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5])};
}

void build_regular_grid(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    info.topology_component = &c;
    b.guarded(c, [&] {
        // BaseObject::parse, src: each Data this component does not set takes the linked one's value
        const RegularGridTopology* source = nullptr;
        if (a.has("src")) {
            const io::LinkTarget t = a.link("src");
            const SceneBuilder::BuiltTopology* built =
                t.component != nullptr ? b.built_topology(*t.component) : nullptr;
            if (built == nullptr || !built->grid)
                a.fail("src", "must link to a RegularGridTopology built before this one");
            source = &*built->grid;
        }
        std::array<int, 3> n = source != nullptr ? source->n() : std::array<int, 3>{2, 2, 2};
        if (a.has("n")) {
            const std::vector<double> v = a.numbers("n");
            if (v.size() != 3) a.fail("n", "expected 3 integers");
            for (const double x : v)
                if (!(x >= 1 && x <= 100000)) a.fail("n", "each count must be between 1 and 100000");
            n = {int(v[0]), int(v[1]), int(v[2])};
        }
        // GridTopology::parse: nx, ny, nz replace n only when the three are given
        if (a.has("nx") && a.has("ny") && a.has("nz")) {
            for (int k = 0; k < 3; ++k) {
                const std::string axis = std::string("n") + char('x' + k);
                const std::int64_t count = a.integer_or(axis, n[std::size_t(k)]);
                if (count < 1 || count > 100000) a.fail(axis, "must be between 1 and 100000");
                n[std::size_t(k)] = int(count);  // checked before the narrowing cast
            }
        } else if (a.has("nx") || a.has("ny") || a.has("nz")) {
            b.warn(c.describe() + ": nx, ny, nz ignored (SOFA reads them only when the three are given)");
        }
        const auto points = std::uint64_t(n[0]) * std::uint64_t(n[1]) * std::uint64_t(n[2]);
        if (points > b.options().max_dofs)
            io::throw_element_error(
                c, std::to_string(points) + " grid points (more than " + std::to_string(b.options().max_dofs) + ")");
        Vec3 lo = source != nullptr && !a.has("min") ? source->min() : a.vector3("min");
        Vec3 hi = source != nullptr && !a.has("max") ? source->max() : a.vector3("max");
        std::optional<Vec3> p0 = a.optional_vector3("p0");
        const auto bounds = scalar_grid_bounds(a, b.options().sofa_quirk_fixes);
        if (source != nullptr && !p0 && !bounds && !a.has("n") && !a.has("nx") && !a.has("min") && !a.has("max"))
            p0 = source->origin();  // the same grid: its first point
        if (bounds) {
            lo = bounds->first;
            hi = bounds->second;
        } else if (a.has("xmin") || a.has("xmax") || a.has("ymin") || a.has("ymax") || a.has("zmin") || a.has("zmax")) {
            b.warn(c.describe() +
                   ": xmin..zmax ignored (SOFA reads them only when the six are given); min and max used");
        }
        info.grid.emplace(n, lo, hi, p0);
        info.topology_positions = info.grid->points();
        for (const char* flag : {"computeQuadList", "computeEdgeList"})
            if (!a.boolean(flag)) a.fail(flag, "only 1 is supported");
        // GridTopology::GridUpdate::doUpdate (run as soon as a list is read, SOFA's init reading the
        // hexahedra): hexahedra, quads, two triangles per quad, then the edges of the triangles
        auto t = std::make_unique<MeshTopology>(
            info.grid->mesh(a.boolean("computeTriangleList"), a.boolean("computeHexaList")));
        info.topology = b.add_topology(std::move(t));
    });
    b.role(c, [g = &*info.grid, t = info.topology] {
        return "grid " + std::to_string(g->n()[0]) + " x " + std::to_string(g->n()[1]) + " x " +
               std::to_string(g->n()[2]) + " from " + vec(g->min()) + " to " + vec(g->max()) + ": " +
               element_counts(g->num_points(), *t);
    });
    b.note_unread_attributes(c);
}

// ---- MechanicalObject -----------------------------------------------------------------------
constexpr AttributeSpec kMechanicalObject[] = {
    {"position", K::points, "(the topology's points, else size points at 0)", "m", ValueCheck::none,
     "Vec3d: x y z per point, or a link; Rigid3d: x y z qx qy qz qw per frame"},
    {"velocity", K::points, "0", "m/s", ValueCheck::none, "Rigid3d: v and omega, 6 numbers per frame"},
    {"rest_position", K::points, "(position)", "m", ValueCheck::none, ""},
    {"src", K::link, "", "", ValueCheck::none, "mesh loader, or a topology built before, whose points it takes"},
    {"size", K::integer, "1", "", ValueCheck::none, "DOF count when no positions are given"},
    {"translation", K::vector3, "0 0 0", "m", ValueCheck::none, "applied to the initial positions, after rotation"},
    {"rotation", K::vector3, "0 0 0", "deg", ValueCheck::none, "Euler angles, X then Y then Z"},
    {"scale3d", K::vector3, "1 1 1", "", ValueCheck::none, "applied first"},
    {"dx", K::real, "(translation[0])", "m", ValueCheck::none, ""},
    {"dy", K::real, "(translation[1])", "m", ValueCheck::none, ""},
    {"dz", K::real, "(translation[2])", "m", ValueCheck::none, ""},
    {"rx", K::real, "(rotation[0])", "deg", ValueCheck::none, ""},
    {"ry", K::real, "(rotation[1])", "deg", ValueCheck::none, ""},
    {"rz", K::real, "(rotation[2])", "deg", ValueCheck::none, ""},
    {"scale", K::real, "(scale3d)", "", ValueCheck::none, "uniform scale: scale3d = (s, s, s)"},
    {"sx", K::real, "1", "", ValueCheck::none, "if any of sx sy sz is given: scale3d = (sx, sy, sz)"},
    {"sy", K::real, "1", "", ValueCheck::none, ""},
    {"sz", K::real, "1", "", ValueCheck::none, ""},
};

/// `size`, bounded so that a typo cannot allocate the machine's memory.
std::size_t dof_count(const SceneBuilder& b, const Attributes& a) {
    const auto n = a.integer("size");
    if (n < 0 || std::uint64_t(n) > b.options().max_dofs)
        a.fail("size", "must be between 0 and " + std::to_string(b.options().max_dofs));
    return std::size_t(n);
}

/// A short form of MechanicalObject (`dx`, `rx`, `scale`, `sx` …) as SOFA's
/// MechanicalObject::parse reads it: BaseObjectDescription::getAttributeAsFloat, strtof on the
/// text, so rounded to float (0.7 → 0.699999988079071); in double with the SOFA quirk fix
/// `mechanical_object_float_short_forms`. Missing: `fallback`. A text that is not one number
/// (SOFA's scenes write the state vector `dx` with one number per DOF) is, as
/// getAttributeAsFloat does, the default `fallback`, with a note through `notes` when given.
double short_form(const Attributes& a, std::string_view name, double fallback, bool in_double, SceneBuilder* notes) {
    if (!a.has(name)) return fallback;
    const std::string text = a.text(name);
    char* end = nullptr;
    static_cast<void>(std::strtod(text.c_str(), &end));
    if (text.empty() || end != text.c_str() + text.size()) {
        if (notes != nullptr) {
            const io::SceneComponent& c = a.component();
            const io::SceneAttribute* at = c.find(name);
            notes->warn(c.file + ":" + std::to_string(at != nullptr ? at->line : c.line) + ": " + c.describe() + ": " +
                        std::string(name) + " '" + (text.size() > 40 ? text.substr(0, 40) + "..." : text) +
                        "' is not one number: " + display::number(fallback) +
                        " used (SOFA's MechanicalObject::parse reads it so, with an error message)");
        }
        return fallback;
    }
    const double value = a.real_or(name, fallback);  // checked (a number) with the scene's error messages
    if (in_double) return value;
    const float as_float = std::strtof(text.c_str(), nullptr);
    if (!std::isfinite(as_float))
        a.fail(std::string(name), "'" + text +
                                      "' is beyond float range, and SOFA reads this attribute as a float "
                                      "(--fix-sofa-quirk mechanical_object_float_short_forms reads it in double)");
    return double(as_float);
}

/// MechanicalObject::parse, after the long forms: `scale` sets scale3d = (s, s, s); any of
/// `sx sy sz` sets scale3d = (sx, sy, sz) (missing: 1); any of `rx ry rz` sets rotation
/// (missing: 0); any of `dx dy dz` sets translation (missing: 0). Notes on unreadable short
/// forms go to `notes` when given.
InitialTransform read_transform(const Attributes& a, const SofaQuirkFixes& quirks, SceneBuilder* notes = nullptr) {
    InitialTransform tr;
    tr.translation = a.vector3("translation");
    tr.rotation_deg = a.vector3("rotation");
    tr.scale3d = a.vector3("scale3d");
    const bool in_double = quirks.fix_mechanical_object_float_short_forms;
    const auto any_of = [&](const char* prefix) {
        return a.has(std::string(prefix) + "x") || a.has(std::string(prefix) + "y") || a.has(std::string(prefix) + "z");
    };
    const auto three = [&](const char* prefix, double fallback) {
        Vec3 v;
        for (int k = 0; k < 3; ++k)
            v[k] = short_form(a, std::string(prefix) + char('x' + k), fallback, in_double, notes);
        return v;
    };
    // BaseComponent::setSrc: a SphereLoader's translation, rotation and scale (alias scale3d) are
    // auto-linked into the state's Data of those names it does not set
    if (!quirks.fix_sphere_loader_src_transform && a.has("src"))
        if (const io::LinkTarget t = a.link("src"); t.component != nullptr && t.component->type == "SphereLoader") {
            const Attributes loader(*t.component);
            if (!a.has("translation") && loader.has("translation")) tr.translation = loader.vector3("translation");
            if (!a.has("rotation") && loader.has("rotation")) tr.rotation_deg = loader.vector3("rotation");
            if (!a.has("scale3d") && (loader.has("scale3d") || loader.has("scale")))
                tr.scale3d = loader.vector3(loader.has("scale3d") ? "scale3d" : "scale");
        }
    if (a.has("scale")) tr.scale3d = Vec3::Constant(short_form(a, "scale", 1.0, in_double, notes));
    if (any_of("s")) tr.scale3d = three("s", 1.0);
    if (any_of("r")) tr.rotation_deg = three("r", 0.0);
    if (any_of("d")) tr.translation = three("d", 0.0);
    return tr;
}

void fill_rigid_state(SceneBuilder& b, const Attributes& a, const NodeBuild& info, Rigid3Object& s) {
    if (a.has("position")) s.position = a.frames("position");
    if (a.has("rest_position")) s.rest_position = a.frames("rest_position");
    // SOFA keeps each quaternion as written; the fix `rigid_orientation_as_written` normalizes them
    if (b.options().sofa_quirk_fixes.fix_rigid_orientation_as_written)
        for (auto* frames : {&s.position, &s.rest_position})
            for (RigidFrame& f : *frames) f.orientation.normalize();
    if (a.has("velocity")) {
        const std::vector<double> v = a.numbers("velocity");
        if (v.size() % 6 != 0) a.fail("velocity", "expected a multiple of 6 numbers");
        for (std::size_t i = 0; i < v.size(); i += 6)
            s.velocity.push_back(RigidDeriv{Vec3(v[i], v[i + 1], v[i + 2]), Vec3(v[i + 3], v[i + 4], v[i + 5])});
    }
    // MechanicalObject<Rigid3>::init: a state without positions takes its topology's points as the
    // frames' centres (orientation identity), as the Vec3d one does
    if (s.position.empty() && s.rest_position.empty() && !a.has("size") && !info.topology_positions.empty()) {
        for (const Vec3& p : info.topology_positions) s.position.push_back(RigidFrame{p, Quat::Identity()});
        if (s.velocity.size() == 1) s.velocity.assign(s.position.size(), s.velocity.front());
    }
    if (s.position.empty() && s.rest_position.empty() && !info.mapped) s.position.assign(dof_count(b, a), RigidFrame{});
}

/// The points `src` links: a loader's, or (SOFA's `src` copying the `position` Data) those of a
/// topology built before (a RegularGridTopology's grid points, a container's given points).
std::vector<Vec3> linked_source_points(SceneBuilder& b, const Attributes& a) {
    const io::LinkTarget t = a.link("src");
    // (a topology built before: also one that a later topology of its node replaced, as SOFA's
    // Data link reads the linked container whatever the node's topology is)
    if (t.component != nullptr && component_category(t.component->type) != ComponentCategory::loader)
        if (const SceneBuilder::BuiltTopology* built = b.built_topology(*t.component);
            built != nullptr && built->topology != nullptr)
            return built->positions;
    return b.linked_mesh(a, "src").positions;
}

void fill_vec3_state(SceneBuilder& b, const Attributes& a, const NodeBuild& info, Vec3Object& s) {
    if (a.has("position")) {
        s.position = b.point_data(a, "position");
    } else if (a.has("src")) {
        s.position = linked_source_points(b, a);
    } else if (!info.topology_positions.empty()) {
        s.position = info.topology_positions;  // SOFA: a state without positions takes its topology's
    } else if (a.has("size")) {
        s.position.assign(dof_count(b, a), Vec3::Zero());
    } else if (!info.mapped) {
        s.position.assign(1, Vec3::Zero());  // SOFA's default size 1
    }
    if (a.has("rest_position")) s.rest_position = a.points("rest_position");
    if (a.has("velocity")) s.velocity = a.points("velocity");
    // MechanicalObject::init: positions and velocities of at most one entry give way to the
    // topology's points, the one velocity (if any) copied to every point.
    if (a.has("position") && s.position.size() <= 1 && s.velocity.size() <= 1 && s.rest_position.size() <= 1 &&
        info.topology_positions.size() > 1) {
        s.position = info.topology_positions;
        if (s.velocity.size() == 1) s.velocity.assign(s.position.size(), s.velocity.front());
    }
    if (s.position.size() > b.options().max_dofs)  // from a mesh file or a linked state
        io::throw_element_error(a.component(), std::to_string(s.position.size()) + " DOFs (more than " +
                                                   std::to_string(b.options().max_dofs) + ")");
}

}  // namespace

std::vector<Vec3> state_initial_points(SceneBuilder& b, const SceneComponent& state, const NodeBuild& info) {
    const Attributes a(state);
    const InitialTransform tr = read_transform(a, b.options().sofa_quirk_fixes);
    if (state.template_name.find("Vec1") != std::string::npos || state.template_name.find("Vec2") != std::string::npos)
        io::throw_element_error(state, "a " + state.template_name + " state has no 3-D points to give");
    // a state whose `src` links back to the topology asking would recurse
    static thread_local int depth = 0;
    if (depth > 0) io::throw_attribute_error(state, "src", "links form a cycle between a topology and this state");
    ++depth;
    struct Leave {
        ~Leave() { --depth; }
    } leave;
    std::vector<Vec3> points;
    b.guarded(state, [&] {
        if (is_rigid_template(state, state.template_name)) {
            Rigid3Object s;
            fill_rigid_state(b, a, info, s);
            s.transform = tr;
            s.init();
            for (const RigidFrame& f : s.position) points.push_back(f.center);
        } else {
            Vec3Object s;
            fill_vec3_state(b, a, info, s);
            s.transform = tr;
            s.init();
            points = std::move(s.position);
        }
    });
    return points;
}

namespace {

/// A Vec1d state (a distance mapping's output): `position` numbers, else `size` zeros, else one
/// (none when mapped: its mapping sizes it).
void fill_vec1_state(SceneBuilder& b, const Attributes& a, const NodeBuild& info, Vec1Object& s) {
    if (a.has("position")) {
        if (a.is_link("position")) a.fail("position", "a Vec1d state takes numbers, not a link");
        s.position = a.numbers("position");
    } else if (a.has("size")) {
        s.position.assign(dof_count(b, a), 0.0);
    } else if (!info.mapped) {
        s.position.assign(1, 0.0);
    }
    if (a.has("velocity")) s.velocity = a.numbers("velocity");
    if (a.has("rest_position")) {
        if (a.is_link("rest_position")) a.fail("rest_position", "a Vec1d state takes numbers, not a link");
        s.rest_position = a.numbers("rest_position");
    }
}

bool is_vec1_template(std::string_view name) { return name == "Vec1" || name == "Vec1d" || name == "Vec1f"; }

void build_mechanical_object(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    info.state_component = &c;
    if (is_vec1_template(c.template_name)) {
        const std::string name = c.name.empty() ? sofa_default_name(c) : c.name;
        b.guarded(c, [&] {
            auto& s = info.node->add_state<Vec1Types>(name);
            fill_vec1_state(b, a, info, s);
            s.init();
        });
        b.role(c, [st = info.node->state(), mapped = info.mapped] {
            return "Vec1d state, " + counted(st->num_dofs(), "DOF", "DOFs") + (mapped ? "; mapped" : "");
        });
        b.note_unread_attributes(c);
        return;
    }
    const bool rigid = is_rigid_template(c, c.template_name);
    const std::string name = c.name.empty() ? sofa_default_name(c) : c.name;
    Node& node = *info.node;
    b.guarded(c, [&] {
        const InitialTransform tr = read_transform(a, b.options().sofa_quirk_fixes, &b);
        if (rigid) {
            auto& s = node.add_state<Rigid3Types>(name);
            fill_rigid_state(b, a, info, s);
            s.transform = tr;
            if (!info.mapped) s.init();
        } else {
            auto& s = node.add_state<Vec3Types>(name);
            fill_vec3_state(b, a, info, s);
            s.transform = tr;
            s.init();
            b.record_vec3_state(c, s);
        }
    });
    std::string where;
    if (info.mapped) where = "mapped: positions and velocities from its mapping";
    else if (info.solver_node) where = "integrated by the ODE solver of " + node_path(*info.solver_node);
    else where = "static: in no solver's subtree, never moves";
    const InitialTransform tr = read_transform(a, b.options().sofa_quirk_fixes);
    std::string moved;
    if (!tr.scale3d.isOnes(0)) moved += ", scaled " + vec(tr.scale3d);
    if (!tr.rotation_deg.isZero(0)) moved += ", rotated " + vec(tr.rotation_deg) + " deg";
    if (!tr.translation.isZero(0)) moved += ", translated " + vec(tr.translation);
    b.role(c, [st = info.node->state(), rigid, where, moved] {
        return std::string(rigid ? "Rigid3d" : "Vec3d") + " state, " + counted(st->num_dofs(), "DOF", "DOFs") + moved +
               "; " + where;
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kStateAndTopologyComponents[] = {
    {.type = "MechanicalObject",
     .family = F::state,
     .summary = "state (Vec3d, Rigid3d, or Vec1d for a distance mapping's output)",
     .attributes = kMechanicalObject,
     .build = build_mechanical_object},
    {.type = "MeshTopology",
     .family = F::topology,
     .summary = "mesh topology (element lists or filename)",
     .attributes = kMeshTopology,
     .build = build_mesh_topology},
    {.type = "RegularGridTopology",
     .family = F::topology,
     .summary = "regular grid topology",
     .attributes = kRegularGrid,
     .build = build_regular_grid},
};

}  // namespace

std::span<const ComponentSpec> state_and_topology_components() { return kStateAndTopologyComponents; }

}  // namespace penalty::scene::builder
