// Mappings on rigid frames beyond RigidMapping, and the distance mapping (SOFA's
// Sofa/Component/Mapping): SkinningMapping, DeformableOnRigidFrameMapping and
// DistanceFromTargetMapping. Formulas: include/penalty/mechanics/frame_mappings.hpp and
// docs/components/frame_mappings.md.
#include "penalty/mechanics/frame_mappings.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <cmath>
#include <cstdlib>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

/// The state an input link names (default: the parent node's state), built already.
BaseState& input_state(SceneBuilder& b, const Attributes& a, std::string_view attr, const NodeBuild& info) {
    if (a.has(attr)) {
        BaseState* s = b.linked_state(a, attr);
        if (s == nullptr) a.fail(attr, "links to a state that is not built yet (it must be in this node or above)");
        return *s;
    }
    const io::SceneNode* parent = info.scene_node->parent;
    if (parent == nullptr) a.fail(attr, "no parent node to map from");
    const NodeBuild* owner = b.state_owner(b.node_build(*parent));
    if (owner == nullptr) a.fail(attr, "no MechanicalObject to map from");
    return *owner->node->state();
}

/// The node's own state, which a mapping's `output` may name.
BaseState& output_state(SceneBuilder& b, const Attributes& a, const NodeBuild& info) {
    if (info.node->state() == nullptr)
        io::throw_element_error(a.component(), "needs a MechanicalObject in its node (its output)");
    if (a.has("output") && b.linked_state(a, "output") != info.node->state())
        a.fail("output", "must be the MechanicalObject of the mapping's own node");
    return *info.node->state();
}

template <class T>
T& as_state(BaseState& s, const Attributes& a, std::string_view attr, const char* what) {
    auto* typed = dynamic_cast<T*>(&s);
    if (typed == nullptr) a.fail(attr, std::string("must be a ") + what + " state");
    return *typed;
}

void finish(SceneBuilder& b, const SceneComponent& c, const NodeBuild& info, const std::string& how) {
    BaseMapping* mapping = info.node->mapping();
    b.add_init(0, c, [mapping] { mapping->init(); });
    b.role(c, [out = info.node->state(), how] {
        return "maps onto this node's " + counted(out->num_dofs(), "point", "points") + " (" + how + ")";
    });
    b.note_unread_attributes(c);
}

// ---- SkinningMapping ------------------------------------------------------------------------
constexpr AttributeSpec kSkinning[] = {
    {"input", K::link, "(the parent node's state)", "", ValueCheck::none, "the Rigid3d frames"},
    {"output", K::link, "(this node's state)", "", ValueCheck::none, "this node's Vec3d MechanicalObject"},
    {"nbRef", K::indices, "4", "", ValueCheck::none, "frames influencing each point (one value, or one per point)"},
    {"indices", K::text, "", "", ValueCheck::none,
     "the frames of each point (with weight); default: the nbRef nearest"},
    {"weight", K::text, "", "", ValueCheck::none, "their weights, one list per point; default: normalised 1/d²"},
    {"initPos", K::points, "(the output's positions)", "m", ValueCheck::none, "the points' initial world positions"},
    {"computeWeightsFromPosition", K::boolean, "0", "", ValueCheck::none,
     "weights from the frames' positions, not rest"},
    {"showFromIndex", K::integer, "0", "", ValueCheck::none, "drawing only"},
    {"showWeights", K::boolean, "0", "", ValueCheck::none, "drawing only"},
};

/// SOFA's vector<SVector<T>>: `[a b c] [d e]` (one bracketed list per point), or, without brackets,
/// one value per point.
std::vector<std::vector<double>> nested_numbers(const Attributes& a, std::string_view name) {
    const std::string text = a.text(name);
    std::vector<std::vector<double>> out;
    if (text.find('[') == std::string::npos) {
        for (const double v : a.numbers(name)) out.push_back({v});
        return out;
    }
    std::size_t at = 0;
    while ((at = text.find('[', at)) != std::string::npos) {
        const std::size_t end = text.find(']', at);
        if (end == std::string::npos) a.fail(name, "a '[' without its ']'");
        std::vector<double> list;
        std::string item = text.substr(at + 1, end - at - 1);
        for (char& ch : item)
            if (ch == ',') ch = ' ';
        std::size_t pos = 0;
        while (pos < item.size()) {
            char* stop = nullptr;
            const double v = std::strtod(item.c_str() + pos, &stop);
            if (stop == item.c_str() + pos) {
                if (item.find_first_not_of(" \t\r\n", pos) != std::string::npos)
                    a.fail(name, "expected numbers inside [ ], found '" + item + "'");
                break;
            }
            if (!std::isfinite(v)) a.fail(name, "values must be finite");
            list.push_back(v);
            pos = std::size_t(stop - item.c_str());
        }
        out.push_back(std::move(list));
        at = end + 1;
    }
    return out;
}

void build_skinning_mapping(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    b.guarded(c, [&] {
        auto& from = as_state<Rigid3Object>(input_state(b, a, "input", info), a, "input", "Rigid3d");
        auto& to = as_state<Vec3Object>(output_state(b, a, info), a, "output", "Vec3d");
        auto& m = info.node->set_mapping<SkinningMapping>(from, to);
        if (a.has("nbRef")) {
            std::vector<int> nb;
            for (const PointId n : a.indices("nbRef")) nb.push_back(int(n));
            m.set_nb_ref(std::move(nb));
        }
        m.set_weights_from_position(a.boolean("computeWeightsFromPosition"));
        if (a.has("initPos")) m.set_initial_points(a.points("initPos"));
        if (a.has("indices") != a.has("weight"))
            a.fail(a.has("indices") ? "weight" : "indices", "indices and weight go together");
        if (a.has("indices")) {
            const auto frames = nested_numbers(a, "indices");
            const auto weights = nested_numbers(a, "weight");
            if (frames.size() != weights.size()) a.fail("weight", "needs one list per list of indices");
            std::vector<SkinningMapping::Influences> influences(frames.size());
            for (std::size_t i = 0; i < frames.size(); ++i) {
                if (frames[i].size() != weights[i].size())
                    a.fail("weight", "point " + std::to_string(i) + ": one weight per index");
                for (const double f : frames[i]) {
                    if (!(f >= 0) || f != std::floor(f))
                        a.fail("indices", "frame indices must be non-negative integers");
                    influences[i].frames.push_back(Index(f));
                }
                influences[i].weights = weights[i];
            }
            m.set_influences(std::move(influences));
        }
    });
    finish(b, c, info, "linear blend skinning on rigid frames");
}

// ---- DeformableOnRigidFrameMapping ----------------------------------------------------------
constexpr AttributeSpec kDeformableOnRigid[] = {
    {"input1", K::link, "(the parent node's state)", "", ValueCheck::none, "the Vec3d deformable state"},
    {"input2", K::link, "", "", ValueCheck::none, "the Rigid3d frames (required: SOFA maps identically without)"},
    {"output", K::link, "(this node's state)", "", ValueCheck::none, "this node's Vec3d MechanicalObject"},
    {"index", K::integer, "0", "", ValueCheck::none, "the frame"},
    {"indexFromEnd", K::boolean, "0", "", ValueCheck::none, "index counted from the last frame"},
    {"repartition", K::indices, "", "", ValueCheck::none, "points per frame (one value for all, or one per frame)"},
    {"globalToLocalCoords", K::boolean, "0", "", ValueCheck::none, "read by SOFA, not used by its mapping"},
    {"rootAngularForceScaleFactor", K::real, "1", "", ValueCheck::none, "read by SOFA, not used by its mapping"},
    {"rootLinearForceScaleFactor", K::real, "1", "", ValueCheck::none, "read by SOFA, not used by its mapping"},
};

void build_deformable_on_rigid_frame(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    b.guarded(c, [&] {
        auto& deformable = as_state<Vec3Object>(input_state(b, a, "input1", info), a, "input1", "Vec3d");
        if (!a.has("input2")) a.fail("input2", "needs the frames (SOFA maps the points unchanged without them)");
        auto& frames = as_state<Rigid3Object>(input_state(b, a, "input2", info), a, "input2", "Rigid3d");
        auto& to = as_state<Vec3Object>(output_state(b, a, info), a, "output", "Vec3d");
        const std::int64_t index = a.integer("index");
        if (index < 0) a.fail("index", "must be >= 0");
        std::vector<unsigned> repartition;
        if (a.has("repartition"))
            for (const PointId n : a.indices("repartition")) repartition.push_back(unsigned(n));
        info.node->set_mapping<DeformableOnRigidFrameMapping>(deformable, frames, to, Index(index),
                                                              a.boolean("indexFromEnd"), std::move(repartition));
    });
    finish(b, c, info, "a deformable body in a moving frame");
}

// ---- DistanceFromTargetMapping --------------------------------------------------------------
constexpr AttributeSpec kDistanceFromTarget[] = {
    {"input", K::link, "(the parent node's state)", "", ValueCheck::none, "the Vec3d points"},
    {"output", K::link, "(this node's state)", "", ValueCheck::none, "this node's Vec1d MechanicalObject"},
    {"indices", K::indices, "(0, 1, ... one per target)", "", ValueCheck::none, "the input points"},
    {"targetPositions", K::points, "", "m", ValueCheck::none, "a target per index (inline or a link)"},
    {"restLengths", K::numbers, "(0 each)", "m", ValueCheck::none, "subtracted from each distance"},
    {"geometricStiffness", K::text, "Stabilized", "", ValueCheck::none, "None, Exact or Stabilized (0, 1, 2)"},
    {"showObjectScale", K::real, "0", "", ValueCheck::none, "drawing only"},
};

void build_distance_from_target(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    b.guarded(c, [&] {
        auto& from = as_state<Vec3Object>(input_state(b, a, "input", info), a, "input", "Vec3d");
        auto& to = as_state<Vec1Object>(output_state(b, a, info), a, "output", "Vec1d");
        std::vector<Index> indices;
        if (a.has("indices"))
            for (const PointId i : a.indices("indices")) indices.push_back(i);
        std::vector<Vec3> targets;
        if (a.has("targetPositions")) targets = b.point_data(a, "targetPositions");
        const std::string mode = a.text("geometricStiffness");
        int geometric = 2;
        if (mode == "None" || mode == "0") geometric = 0;
        else if (mode == "Exact" || mode == "1") geometric = 1;
        else if (mode != "Stabilized" && mode != "2")
            a.fail("geometricStiffness", "expected None, Exact or Stabilized");
        info.node->set_mapping<DistanceFromTargetMapping>(from, to, std::move(indices), std::move(targets),
                                                          a.numbers("restLengths"), geometric);
    });
    finish(b, c, info, "distances to targets");
}

constexpr ComponentSpec kFrameMappingComponents[] = {
    {.type = "SkinningMapping",
     .family = F::mapping,
     .summary = "Vec3d points blended from Rigid3d frames (skinning)",
     .attributes = kSkinning,
     .build = build_skinning_mapping},
    {.type = "DeformableOnRigidFrameMapping",
     .family = F::mapping,
     .summary = "a Vec3d deformable body carried by a Rigid3d frame",
     .attributes = kDeformableOnRigid,
     .build = build_deformable_on_rigid_frame},
    {.type = "DistanceFromTargetMapping",
     .family = F::mapping,
     .summary = "Vec1d distances of Vec3d points to targets",
     .attributes = kDistanceFromTarget,
     .build = build_distance_from_target},
};

}  // namespace

std::span<const ComponentSpec> frame_mapping_components() { return kFrameMappingComponents; }

}  // namespace penalty::scene::builder
