// Pressure loads on the elements of a topology: TrianglePressureForceField, QuadPressureForceField,
// EdgePressureForceField, SurfacePressureForceField (penalty/mechanics/pressure_loads.hpp;
// docs/components/pressure_loads.md). Each acts on the state of its node or, as SOFA's context, of the nearest ancestor
// with one (SceneBuilder::vec3_state), and on the elements of `topology="@..."`, else of the nearest topology
// (SceneBuilder::topology_of).
#include "penalty/mechanics/pressure_loads.hpp"
#include "scene/builder/element_topology.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

std::vector<Index> as_indices(const std::vector<PointId>& ids) { return {ids.begin(), ids.end()}; }

// ---- TrianglePressureForceField -------------------------------------------------------------
// SOFA HEAD's data (TrianglePressureForceField constructor): pressure (a vector, default 0),
// cauchyStress (symmetric, default 0), triangleList (no default), showForces (0),
// useConstantForce (1). There is no normal/dmin/dmax selection any more: the triangles come from
// triangleList only (an unknown attribute such as `triangleIndices` leaves the list empty, as SOFA).
constexpr AttributeSpec kTrianglePressure[] = {
    {"pressure", K::vector3, "0 0 0", "N/m^2", ValueCheck::none, "force per unit area (a vector)"},
    {"triangleList", K::indices, "", "", ValueCheck::none, "the loaded triangles of the topology (inline or a link)"},
    {"useConstantForce", K::boolean, "1", "", ValueCheck::none, "1: pressure x rest area; 0: cauchyStress"},
    {"cauchyStress", K::numbers, "0 0 0 0 0 0", "Pa", ValueCheck::none,
     "symmetric sigma: xx xy yy xz yz zz (used when useConstantForce is 0)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles"},
    {"showForces", K::boolean, "0", "", ValueCheck::none, "drawing only"},
};

void build_triangle_pressure(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const MeshTopology& topology = b.topology_of(a, info);
        std::vector<Index> triangles =
            a.has("triangleList") ? as_indices(b.indices(a, "triangleList")) : std::vector<Index>{};
        auto* ff = &info.node->add_force_field<TrianglePressureForceField>(s, topology, std::move(triangles),
                                                                           a.vector3("pressure"));
        ff->set_use_constant_force(a.boolean("useConstantForce"));
        const std::vector<double> sigma = a.numbers("cauchyStress");
        if (!sigma.empty()) {
            // SOFA's MatSym<3> order: the lower triangle row by row (xx, yx, yy, zx, zy, zz).
            if (sigma.size() != 6) a.fail("cauchyStress", "expected 6 numbers, found " + std::to_string(sigma.size()));
            Mat3 m;
            m << sigma[0], sigma[1], sigma[3], sigma[1], sigma[2], sigma[4], sigma[3], sigma[4], sigma[5];
            ff->set_cauchy_stress(m);
        }
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff] {
            if (!ff->use_constant_force())
                return counted(ff->triangles().size(), "triangle", "triangles") + " loaded by a Cauchy stress";
            return "pressure " + vec(ff->pressure()) + " N/m^2 on " +
                   counted(ff->triangles().size(), "triangle", "triangles") + " (rest area " +
                   num(ff->total_rest_area()) + " m^2)";
        });
    });
    b.note_unread_attributes(c);
}

// ---- QuadPressureForceField -----------------------------------------------------------------
// SOFA's data (QuadPressureForceField constructor): pressure (a vector), quadList, normal,
// dmin = dmax = 0, showForces. init selects the quads between the planes (when dmin != dmax),
// then REPLACES the selection with quadList when it is not empty (selectQuadsAlongPlane,
// selectQuadsFromString: quadList becomes the subset's element list).
constexpr AttributeSpec kQuadPressure[] = {
    {"pressure", K::vector3, "0 0 0", "N/m^2", ValueCheck::none, "force per unit area (a vector)"},
    {"quadList", K::indices, "", "", ValueCheck::none, "the loaded quads of the topology (inline or a link)"},
    {"normal", K::vector3, "0 0 0", "", ValueCheck::none, "plane selection: dmin < p.normal < dmax"},
    {"dmin", K::real, "0", "m", ValueCheck::none, "plane selection (when dmin != dmax)"},
    {"dmax", K::real, "0", "m", ValueCheck::none, "plane selection (when dmin != dmax)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its quads"},
    {"showForces", K::boolean, "0", "", ValueCheck::none, "drawing only"},
};

void build_quad_pressure(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const MeshTopology& topology = b.topology_of(a, info);
        std::vector<Index> quads;
        const double dmin = a.real("dmin");
        const double dmax = a.real("dmax");
        if (dmin != dmax) quads = quads_between_planes(topology, s.rest_position, a.vector3("normal"), dmin, dmax);
        if (a.has("quadList")) {
            std::vector<Index> given = as_indices(b.indices(a, "quadList"));
            if (!given.empty()) quads = std::move(given);
        }
        auto* ff =
            &info.node->add_force_field<QuadPressureForceField>(s, topology, std::move(quads), a.vector3("pressure"));
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff] {
            return "pressure " + vec(ff->pressure()) + " N/m^2 on " + counted(ff->quads().size(), "quad", "quads") +
                   " (rest area " + num(ff->total_rest_area()) + " m^2)";
        });
    });
    b.note_unread_attributes(c);
}

// ---- EdgePressureForceField -----------------------------------------------------------------
// SOFA's data (EdgePressureForceField constructor): pressure (vector), edgeIndices, edges,
// normal, dmin = dmax = 0, p_intensity, binormal, arrowSizeCoef, showForces. init selects the
// edges between the planes (when dmin != dmax), then REPLACES the selection with edgeIndices when
// given, then with `edges` when given (selectEdgesAlongPlane, selectEdgesFromString,
// selectEdgesFromEdgeList).
constexpr AttributeSpec kEdgePressure[] = {
    {"pressure", K::vector3, "0 0 0", "N/m", ValueCheck::none, "force per unit length (a vector); must be non-zero"},
    {"edgeIndices", K::indices, "", "", ValueCheck::none, "loaded edges of the topology (inline or a link)"},
    {"edges", K::elements, "", "", ValueCheck::none, "loaded edges by their ends (inline or a link)"},
    {"normal", K::vector3, "0 0 0", "", ValueCheck::none, "plane selection: dmin < p.normal < dmax"},
    {"dmin", K::real, "0", "m", ValueCheck::none, "plane selection (when dmin != dmax)"},
    {"dmax", K::real, "0", "m", ValueCheck::none, "plane selection (when dmin != dmax)"},
    {"p_intensity", K::numbers, "", "N/m", ValueCheck::none, "used by SOFA only when pressure is 0 (refused then)"},
    {"binormal", K::vector3, "0 0 0", "", ValueCheck::none, "used by SOFA only when pressure is 0 (refused then)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its edges"},
    {"arrowSizeCoef", K::real, "0", "", ValueCheck::none, "drawing only"},
    {"showForces", K::boolean, "0", "", ValueCheck::none, "drawing only"},
};

void build_edge_pressure(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const MeshTopology& topology = b.topology_of(a, info);
        const Vec3 pressure = a.vector3("pressure");
        if (pressure.norm() == 0.0)
            a.fail("pressure", "a zero pressure (SOFA's p_intensity along edge normals) is not supported by penalty");
        std::vector<Index> edges;
        const double dmin = a.real("dmin");
        const double dmax = a.real("dmax");
        if (dmin != dmax) edges = edges_between_planes(topology, s.rest_position, a.vector3("normal"), dmin, dmax);
        if (a.has("edgeIndices")) {
            std::vector<Index> given = as_indices(b.indices(a, "edgeIndices"));
            if (!given.empty()) edges = std::move(given);
        }
        if (a.has("edges")) {
            const std::vector<Edge> given =
                a.is_link("edges") ? linked_elements(b, a, "edges", &io::MeshData::edges, &MeshTopology::edges)
                                   : a.elements<2>("edges");
            if (!given.empty()) edges = edge_indices_of(topology, given);
        }
        auto* ff = &info.node->add_force_field<EdgePressureForceField>(s, topology, std::move(edges), pressure);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff] {
            return "pressure " + vec(ff->pressure()) + " N/m on " + counted(ff->edges().size(), "edge", "edges") +
                   " (rest length " + num(ff->total_rest_length()) + " m)";
        });
    });
    b.note_unread_attributes(c);
}

// ---- SurfacePressureForceField --------------------------------------------------------------
// SOFA's data (SurfacePressureForceField constructor): pressure 0, min = max = 0 0 0 (no box),
// triangleIndices, quadIndices, pulseMode 0, pressureLowerBound 0, pressureSpeed 0,
// volumeConservationMode 0, useTangentStiffness 1, defaultVolume −1, mainDirection 0 0 0,
// drawForceScale 0.
constexpr AttributeSpec kSurfacePressure[] = {
    {"pressure", K::real, "0", "Pa", ValueCheck::none, "along the triangles' (b-a)x(c-a)"},
    {"min", K::vector3, "0 0 0", "m", ValueCheck::none, "selection box (with max; both 0: every element)"},
    {"max", K::vector3, "0 0 0", "m", ValueCheck::none, "selection box"},
    {"triangleIndices", K::indices, "", "", ValueCheck::none, "loaded triangles (none: the box's)"},
    {"quadIndices", K::indices, "", "", ValueCheck::none, "loaded quads (none: the box's)"},
    {"pulseMode", K::boolean, "0", "", ValueCheck::none, "pressure ramps between the bounds"},
    {"pressureLowerBound", K::real, "0", "Pa", ValueCheck::none, "pulse mode"},
    {"pressureSpeed", K::real, "0", "Pa/s", ValueCheck::none, "pulse mode (0: |pressure|)"},
    {"volumeConservationMode", K::boolean, "0", "", ValueCheck::none, "pressure x defaultVolume / volume"},
    {"useTangentStiffness", K::boolean, "1", "", ValueCheck::none, "the triangles' (non-symmetric) stiffness"},
    {"defaultVolume", K::real, "-1", "m^3", ValueCheck::none, "-1: the volume at the first step"},
    {"mainDirection", K::vector3, "0 0 0", "", ValueCheck::none, "non-zero: force x |n.d|"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles and quads"},
    {"drawForceScale", K::real, "0", "", ValueCheck::none, "drawing only"},
};

void build_surface_pressure(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const MeshTopology& topology = b.topology_of(a, info);
        SurfacePressureParameters p;
        p.pressure = a.real("pressure");
        p.box_min = a.vector3("min");
        p.box_max = a.vector3("max");
        if (a.has("triangleIndices")) p.triangle_indices = as_indices(b.indices(a, "triangleIndices"));
        if (a.has("quadIndices")) p.quad_indices = as_indices(b.indices(a, "quadIndices"));
        p.pulse_mode = a.boolean("pulseMode");
        p.pressure_lower_bound = a.real("pressureLowerBound");
        p.pressure_speed = a.real("pressureSpeed");
        p.volume_conservation = a.boolean("volumeConservationMode");
        p.use_tangent_stiffness = a.boolean("useTangentStiffness");
        p.default_volume = a.real("defaultVolume");
        p.main_direction = a.vector3("mainDirection");
        auto* ff = &info.node->add_force_field<SurfacePressureForceField>(s, topology, std::move(p), info.node->dt());
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, &topology] {
            const SurfacePressureParameters& q = ff->parameters();
            std::string text =
                "pressure " + num(q.pressure) + " Pa on " + element_counts(topology.num_points(), topology);
            if (q.pulse_mode)
                text += ", pulsing between " + num(q.pressure > 0 ? q.pressure_lower_bound : q.pressure) + " and " +
                        num(q.pressure > 0 ? q.pressure : q.pressure_lower_bound) + " Pa at " + num(q.pressure_speed) +
                        " Pa/s";
            if (q.volume_conservation) text += ", volume-conserving";
            return text;
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kPressureLoadComponents[] = {
    {.type = "TrianglePressureForceField",
     .family = F::force_field,
     .summary = "a pressure vector times each listed triangle's rest area",
     .attributes = kTrianglePressure,
     .build = build_triangle_pressure},
    {.type = "QuadPressureForceField",
     .family = F::force_field,
     .summary = "a pressure vector times each selected quad's rest area",
     .attributes = kQuadPressure,
     .build = build_quad_pressure},
    {.type = "EdgePressureForceField",
     .family = F::force_field,
     .summary = "a pressure vector times each selected edge's rest length",
     .attributes = kEdgePressure,
     .build = build_edge_pressure},
    {.type = "SurfacePressureForceField",
     .family = F::force_field,
     .summary = "a normal pressure on a surface's triangles and quads",
     .attributes = kSurfacePressure,
     .build = build_surface_pressure},
};

}  // namespace

std::span<const ComponentSpec> pressure_load_components() { return kPressureLoadComponents; }

}  // namespace penalty::scene::builder
