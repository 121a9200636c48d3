// Components that, in SOFA's scenes, only make what is drawn: a beam's tube surface
// (Edge2QuadTopologicalMapping: circles of points around each edge and the quads between them;
// TubularMapping: those points carried by the beam's Rigid3d frames). penalty accepts them where
// they feed a visual model only (nothing it simulates reads them), and refuses them where they would
// feed a MechanicalObject, naming the attribute.
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <algorithm>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

bool holds_state(const io::SceneNode& n) {
    return std::any_of(n.components.begin(), n.components.end(), [](const auto& c) {
        const ComponentSpec* spec = find_component(c->type);
        return spec != nullptr && spec->family == F::state;
    });
}

// ---- Edge2QuadTopologicalMapping ------------------------------------------------------------
constexpr AttributeSpec kEdge2Quad[] = {
    {"input", K::link, "", "", ValueCheck::none, "the edge topology (a beam's)"},
    {"output", K::link, "", "", ValueCheck::none, "the quad container of the tube (its node: visual only)"},
    {"nbPointsOnEachCircle", K::integer, "0", "", ValueCheck::none, "drawing only"},
    {"radius", K::real, "0", "m", ValueCheck::none, "drawing only"},
    {"radiusFocal", K::real, "0", "m", ValueCheck::none, "drawing only"},
    {"focalAxis", K::vector3, "0 0 1", "", ValueCheck::none, "drawing only"},
    {"flipNormals", K::boolean, "0", "", ValueCheck::none, "drawing only"},
};

/// Edge2QuadTopologicalMapping::init fills the output container with the tube's quads, whose
/// points a TubularMapping places on the output node's state: penalty accepts it when that node
/// has no MechanicalObject (the state is then a visual model's, as in SOFA's example).
void build_edge2quad(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    if (!a.has("output")) a.fail("output", "names the quad container the tube is made in");
    const io::LinkTarget out = a.link("output");
    const io::SceneNode* node = out.component != nullptr ? out.component->node : out.node;
    if (node == nullptr) a.fail("output", "must link to a topology container");
    if (holds_state(*node))
        a.fail("output",
               "feeds node '" + node->path() +
                   "', which has a MechanicalObject: penalty builds the tube's quads only for drawing (a node without "
                   "a MechanicalObject)");
    b.role(c, [] { return std::string("a tube's quads for drawing only: not built by penalty"); });
    b.note_unread_attributes(c);
    static_cast<void>(info);
}

// ---- TubularMapping -------------------------------------------------------------------------
constexpr AttributeSpec kTubular[] = {
    {"input", K::link, "(the parent node's state)", "", ValueCheck::none, "the beam's Rigid3d frames"},
    {"output", K::link, "(this node's state)", "", ValueCheck::none, "a visual model (penalty: only)"},
    {"nbPointsOnEachCircle", K::integer, "0", "", ValueCheck::none, "drawing only"},
    {"radius", K::real, "0", "m", ValueCheck::none, "drawing only"},
    {"peak", K::integer, "0", "", ValueCheck::none, "drawing only"},
};

/// Reached only when the output is not a visual model (validate() ignores the mapping onto one).
void build_tubular_mapping(SceneBuilder&, const SceneComponent& c, NodeBuild&) {
    const Attributes a(c);
    a.fail("output", "penalty maps a tube only onto a visual model (OglModel), not onto a MechanicalObject");
}

constexpr ComponentSpec kDrawingComponents[] = {
    {.type = "Edge2QuadTopologicalMapping",
     .family = F::topology_helper,
     .summary = "a beam's tube quads, for drawing (accepted onto a node without a MechanicalObject)",
     .attributes = kEdge2Quad,
     .build = build_edge2quad},
    {.type = "TubularMapping",
     .family = F::mapping,
     .summary = "a beam's tube surface, for drawing (onto a visual model only)",
     .attributes = kTubular,
     .build = build_tubular_mapping},
};

}  // namespace

std::span<const ComponentSpec> drawing_components() { return kDrawingComponents; }

}  // namespace penalty::scene::builder
