// TaitSurfacePressureForceField: a closed surface filled with a fluid of Tait's equation of state
// (penalty/mechanics/tait_surface_pressure.hpp; docs/components/tait_surface_pressure.md).
#include "penalty/mechanics/tait_surface_pressure.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// SOFA's data (TaitSurfacePressureForceField constructor): p0, B, gamma, injectedVolume (0),
// maxInjectionRate (1000), the outputs, drawForceScale (0.001), drawForceColor.
constexpr AttributeSpec kTaitPressure[] = {
    {"p0", K::real, "0", "Pa", ValueCheck::none, "pressure at the rest volume V0"},
    {"B", K::real, "0", "Pa", ValueCheck::nonnegative, "bulk modulus (0: constant pressure p0)"},
    {"gamma", K::real, "0", "", ValueCheck::nonnegative, "Tait exponent (0: constant pressure p0)"},
    {"injectedVolume", K::real, "0", "m^3", ValueCheck::none, "volume injected (or, < 0, extracted) since the start"},
    {"maxInjectionRate", K::real, "1000", "m^3/s", ValueCheck::nonnegative, "how fast the injection proceeds"},
    {"currentInjectedVolume", K::real, "0", "m^3", ValueCheck::none, "the injected volume at the start"},
    {"drawForceScale", K::real, "0.001", "", ValueCheck::none, "display only"},
    {"drawForceColor", K::text, "0 1 1 1", "", ValueCheck::none, "display only"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none,
     "its triangles and quads (the closed surface)"},
};

void build_tait_pressure(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    TaitParameters p;
    p.p0 = a.real("p0");
    p.bulk_modulus = a.real("B");
    p.gamma = a.real("gamma");
    p.injected_volume = a.real("injectedVolume");
    p.max_injection_rate = a.real("maxInjectionRate");
    p.current_injected_volume = a.real("currentInjectedVolume");
    static_cast<void>(a.real("drawForceScale"));
    static_cast<void>(a.text("drawForceColor"));
    const MeshTopology& topology = b.topology_of(a, info);
    if (topology.triangles().empty() && topology.quads().empty())
        io::throw_element_error(c, "its topology has no triangles or quads (the closed surface that holds the fluid)");
    ContextClock clock = [sim = &b.simulation()] { return sim->time(); };
    ContextClock dt = [node = info.node] { return node->dt(); };
    b.guarded(c, [&] {
        auto* ff = &info.node->add_force_field<TaitSurfacePressureForceField>(s, topology, p, clock, dt);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, p] {
            return "fluid in " + counted(ff->triangles().size(), "surface triangle", "surface triangles") +
                   ", rest volume " + num(ff->rest_volume()) + " m^3, p0 = " + num(p.p0) +
                   " Pa, B = " + num(p.bulk_modulus) + " Pa, gamma = " + num(p.gamma) + ", injecting " +
                   num(p.injected_volume) + " m^3";
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kTaitPressureComponents[] = {
    {.type = "TaitSurfacePressureForceField",
     .family = F::force_field,
     .summary = "pressure of an enclosed fluid (Tait's equation of state), with injection",
     .attributes = kTaitPressure,
     .build = build_tait_pressure},
};

}  // namespace

std::span<const ComponentSpec> tait_pressure_components() { return kTaitPressureComponents; }

}  // namespace penalty::scene::builder
