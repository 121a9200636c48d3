// The components that change a topology while the scene runs: TopologicalChangeProcessor and
// TopologyBoundingTrasher. Their build checks the attributes; the scene's topology runtime makes
// them once every node is built (src/scene/topology/change_sources.cpp), since they act on
// everything that follows the topology.
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

constexpr AttributeSpec kProcessor[] = {
    {"filename", K::text, "", "", ValueCheck::none, "file of timed REMOVE= / ADD= / INCISE= commands (SOFA's format)"},
    {"interval", K::real, "0", "s", ValueCheck::nonnegative, "useDataInputs: time between two removals (0: once)"},
    {"shift", K::real, "0", "s", ValueCheck::none, "added to the time before the file's times are compared"},
    {"loop", K::boolean, "0", "", ValueCheck::none, "read the file again from its start at its end"},
    {"useDataInputs", K::boolean, "0", "", ValueCheck::none, "remove the listed elements instead of reading a file"},
    {"timeToRemove", K::real, "0", "s", ValueCheck::none, "useDataInputs: the lists are removed after this time"},
    {"pointsToRemove", K::indices, "", "", ValueCheck::none, "useDataInputs: points (or a link to a BoxROI output)"},
    {"edgesToRemove", K::indices, "", "", ValueCheck::none, "useDataInputs: edges (or a link)"},
    {"trianglesToRemove", K::indices, "", "", ValueCheck::none, "useDataInputs: triangles (or a link)"},
    {"quadsToRemove", K::indices, "", "", ValueCheck::none, "useDataInputs: quads (or a link)"},
    {"tetrahedraToRemove", K::indices, "", "", ValueCheck::none, "useDataInputs: tetrahedra (or a link)"},
    {"hexahedraToRemove", K::indices, "", "", ValueCheck::none, "useDataInputs: hexahedra (or a link)"},
    {"topology", K::link, "", "", ValueCheck::none, "the topology changed (default: the node's)"},
    {"listening", K::boolean, "1", "", ValueCheck::none, "no effect: always listening"},
    {"saveIndicesAtInit", K::boolean, "0", "", ValueCheck::none,
     "INCISE=: locate the cuts' points at init and follow them (refused with INCISE= lines)"},
    {"epsilonSnapPath", K::real, "0.1", "", ValueCheck::none,
     "INCISE= with saveIndicesAtInit only (SOFA's file mode snaps at 0.1)"},
    {"epsilonSnapBorder", K::real, "0.25", "", ValueCheck::none,
     "INCISE= with saveIndicesAtInit only (SOFA's file mode snaps at 0.25)"},
    {"draw", K::boolean, "0", "", ValueCheck::none, "drawing only"},
};

constexpr AttributeSpec kTrasher[] = {
    {"box", K::numbers, "-1000 -1000 -1000 1000 1000 1000", "m", ValueCheck::none,
     "xmin ymin zmin xmax ymax zmax: elements whose barycentre leaves it are removed"},
    {"position", K::points, "(the node's state)", "m", ValueCheck::none, "link to the positions tested"},
    {"topology", K::link, "", "", ValueCheck::none, "the topology changed (default: the node's)"},
    {"drawBox", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"listening", K::boolean, "1", "", ValueCheck::none, "no effect: always listening"},
};

constexpr AttributeSpec kCarving[] = {
    {"toolModel", K::link, "", "", ValueCheck::none,
     "the tool's collision model (default: the one tagged CarvingTool)"},
    {"surfaceModelPath", K::text, "", "", ValueCheck::none,
     "the carved collision model's path (default: every model tagged CarvingSurface)"},
    {"carvingDistance", K::real, "0", "m", ValueCheck::none,
     "an element whose detection output value (distance minus contact distance) is below it is removed"},
    {"active", K::boolean, "0", "", ValueCheck::none, "carve at the end of each step (no key events headless)"},
    {"narrowPhaseDetection", K::link, "", "", ValueCheck::none,
     "no effect: every collision pipeline's detection is read"},
    {"key", K::text, "1", "", ValueCheck::none, "keyboard only (no effect)"},
    {"keySwitch", K::text, "4", "", ValueCheck::none, "keyboard only (no effect)"},
};

void build_carving(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    const Attributes a(c);
    b.guarded(c, [&] { (void)a.real("carvingDistance"), (void)a.boolean("active"); });
    b.role(c, [&c] {
        return io::get_bool_or(c, "active", false)
                   ? std::string(
                         "removes, at each step's end, the elements of the carved models its tool comes closer to "
                         "than carvingDistance")
                   : std::string("inactive (active=\"0\"; no key events headless)");
    });
    b.note_unread_attributes(c);
}

void build_processor(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    const Attributes a(c);
    b.guarded(c, [&] {
        if (!a.boolean("useDataInputs") && !a.has("filename"))
            a.fail("filename", "names the file of topological changes (or set useDataInputs)");
        (void)a.real("interval");
    });
    b.role(c, [&c] {
        return c.has("filename") ? "changes its topology at the times of " + *io::get_string(c, "filename")
                                 : std::string("removes the listed elements of its topology after timeToRemove");
    });
    b.note_unread_attributes(c);
}

void build_trasher(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    const Attributes a(c);
    b.guarded(c, [&] {
        if (a.numbers("box").size() != 6) a.fail("box", "expected 6 numbers: xmin ymin zmin xmax ymax zmax");
    });
    b.role(c, [] { return std::string("removes, at each step's end, the elements whose barycentre leaves its box"); });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kTopologyChangeComponents[] = {
    {.type = "TopologicalChangeProcessor",
     .family = F::engine,
     .summary = "removes and adds elements of its topology at given times (SOFA's file format)",
     .attributes = kProcessor,
     .build = build_processor},
    {.type = "CarvingManager",
     .family = F::engine,
     .summary = "removes the elements of the models tagged CarvingSurface that its tool touches",
     .attributes = kCarving,
     .build = build_carving},
    {.type = "TopologyBoundingTrasher",
     .family = F::engine,
     .summary = "removes the elements whose barycentre leaves a box",
     .attributes = kTrasher,
     .build = build_trasher},
};

}  // namespace

std::span<const ComponentSpec> topology_change_components() { return kTopologyChangeComponents; }

}  // namespace penalty::scene::builder
