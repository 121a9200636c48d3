// SOFA's linear mappings that gather DOFs (Sofa/Component/Mapping/Linear): CenterOfMassMapping,
// SubsetMultiMapping and IdentityMultiMapping. Formulas: include/penalty/mechanics/multi_mappings.hpp
// and docs/components/multi_mappings.md.
#include "penalty/mechanics/multi_mappings.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <algorithm>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

/// The node's own state, the output every mapping here writes (SOFA: a MechanicalObject the
/// `output` link names; penalty requires it to be the mapping's node's, as SOFA's scenes do).
BaseState& own_output(SceneBuilder& b, const Attributes& a, const NodeBuild& info) {
    if (info.node->state() == nullptr)
        io::throw_element_error(a.component(), "needs a MechanicalObject in its node (its output)");
    if (a.has("output")) {
        const std::vector<io::LinkTarget> outputs = a.links("output");
        if (outputs.size() != 1) a.fail("output", "expected one output state, found " + std::to_string(outputs.size()));
        if (b.linked_state(a, "output", outputs.front()) != info.node->state())
            a.fail("output", "must be the MechanicalObject of the mapping's own node");
    }
    return *info.node->state();
}

/// The states `input` links (SOFA's MultiMapping input: several links), built already; default:
/// the parent node's state. At most two (penalty's graph holds a mapping of two inputs).
std::vector<BaseState*> input_states(SceneBuilder& b, const Attributes& a, const NodeBuild& info) {
    std::vector<BaseState*> inputs;
    if (a.has("input")) {
        for (const io::LinkTarget& t : a.links("input")) {
            BaseState* s = b.linked_state(a, "input", t);
            if (s == nullptr)
                a.fail("input", "links to a state that is not built yet (it must be in this node or above)");
            if (std::find(inputs.begin(), inputs.end(), s) != inputs.end())
                a.fail("input", "names the same state twice");
            inputs.push_back(s);
        }
    } else if (info.scene_node->parent != nullptr) {
        if (const NodeBuild* owner = b.state_owner(b.node_build(*info.scene_node->parent)))
            inputs.push_back(owner->node->state());
    }
    if (inputs.empty()) a.fail("input", "no MechanicalObject to map from");
    if (inputs.size() > 2)
        a.fail("input", "penalty maps from two states at most, found " + std::to_string(inputs.size()) + " links");
    if (inputs.front() == info.node->state()) a.fail("input", "cannot be the mapping's own output");
    return inputs;
}

template <class T>
T* as(BaseState* s) {
    return dynamic_cast<T*>(s);
}

void finish_multi_mapping(SceneBuilder& b, const SceneComponent& c, const NodeBuild& info, const std::string& how) {
    BaseMapping* mapping = info.node->mapping();
    b.record_origin(mapping, c);
    b.add_init(0, c, [mapping] { mapping->init(); });
    b.role(c, [out = info.node->state(), how] {
        return "maps onto this node's " + counted(out->num_dofs(), "point", "points") + " (" + how + ")";
    });
    b.note_unread_attributes(c);
}

// ---- CenterOfMassMapping --------------------------------------------------------------------
constexpr AttributeSpec kCenterOfMass[] = {
    {"input", K::link, "(the parent node's state)", "", ValueCheck::none,
     "the Rigid3d frames, with a mass in their node"},
    {"output", K::link, "(this node's state)", "", ValueCheck::none, "this node's Vec3d MechanicalObject (one point)"},
};

void build_center_of_mass_mapping(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    b.guarded(c, [&] {
        const std::vector<BaseState*> inputs = input_states(b, a, info);
        if (inputs.size() != 1) a.fail("input", "CenterOfMassMapping maps one state");
        auto* frames = as<Rigid3Object>(inputs.front());
        if (frames == nullptr) a.fail("input", "must be a Rigid3d state (SOFA's CenterOfMassMapping<Rigid3, Vec3>)");
        auto* to = as<Vec3Object>(&own_output(b, a, info));
        if (to == nullptr) a.fail("output", "must be a Vec3d state");
        // SOFA's CenterOfMassMapping::init: fromModel->getContext()->getMass(), the input's node's
        BaseMass* mass = nullptr;
        for (const auto& [sn, built] : b.node_builds())
            if (built.node != nullptr && built.node->state() == frames) mass = built.node->mass();
        if (mass == nullptr)
            a.fail("input", "the input's node has no mass (SOFA's CenterOfMassMapping weighs the frames by it)");
        info.node->set_mapping<CenterOfMassMapping>(*frames, *to, *mass);
    });
    finish_multi_mapping(b, c, info, "the frames' centre of mass");
}

// ---- SubsetMultiMapping and IdentityMultiMapping --------------------------------------------
constexpr AttributeSpec kSubsetMulti[] = {
    {"input", K::link, "(the parent node's state)", "", ValueCheck::none, "the input states (one or two links)"},
    {"output", K::link, "(this node's state)", "", ValueCheck::none, "this node's MechanicalObject"},
    {"indexPairs", K::indices, "", "", ValueCheck::none, "per output DOF: input (0 or 1), then its DOF in that input"},
};
constexpr AttributeSpec kIdentityMulti[] = {
    {"input", K::link, "(the parent node's state)", "", ValueCheck::none, "the input states (one or two links)"},
    {"output", K::link, "(this node's state)", "", ValueCheck::none, "this node's MechanicalObject"},
};

/// Builds SubsetMultiMapping<In, Out> on the typed inputs and output; `pairs` empty with
/// `concatenate`: IdentityMultiMapping.
template <class In, class Out>
void set_subset_multi(const Attributes& a, const std::vector<BaseState*>& inputs, MechanicalObject<Out>& to,
                      NodeBuild& info, bool concatenate, std::vector<SubsetSource> pairs) {
    auto* first = as<MechanicalObject<In>>(inputs[0]);
    auto* second = inputs.size() > 1 ? as<MechanicalObject<In>>(inputs[1]) : nullptr;
    if (first == nullptr || (inputs.size() > 1 && second == nullptr))
        a.fail("input", std::string("the inputs must all be ") + In::kName + " states");
    using M = SubsetMultiMapping<In, Out>;
    if (concatenate) info.node->set_mapping<M>(M::concatenation(*first, second, to));
    else info.node->set_mapping<M>(*first, second, to, std::move(pairs));
}

void build_multi_mapping(SceneBuilder& b, const SceneComponent& c, NodeBuild& info, bool concatenate) {
    const Attributes a(c);
    b.guarded(c, [&] {
        const std::vector<BaseState*> inputs = input_states(b, a, info);
        BaseState& out = own_output(b, a, info);
        std::vector<SubsetSource> pairs;
        if (!concatenate) {
            const std::vector<PointId> v = a.indices("indexPairs");
            if (v.size() % 2 != 0)
                a.fail("indexPairs", "expected pairs (input, index), found " + std::to_string(v.size()) + " numbers");
            for (std::size_t i = 0; i < v.size(); i += 2) {
                if (std::size_t(v[i]) >= inputs.size())
                    a.fail("indexPairs", "pair " + std::to_string(i / 2) + " names input " + std::to_string(v[i]) +
                                             ", and there are " + std::to_string(inputs.size()) + " inputs");
                pairs.push_back({unsigned(v[i]), Index(v[i + 1])});
            }
        }
        const bool rigid_in = as<Rigid3Object>(inputs[0]) != nullptr;
        if (auto* to3 = as<Vec3Object>(&out)) {
            if (rigid_in && concatenate)
                a.fail("output", "IdentityMultiMapping maps Rigid3d inputs onto a Rigid3d state only");
            if (rigid_in)
                set_subset_multi<Rigid3Types, Vec3Types>(a, inputs, *to3, info, concatenate, std::move(pairs));
            else set_subset_multi<Vec3Types, Vec3Types>(a, inputs, *to3, info, concatenate, std::move(pairs));
        } else if (auto* tor = as<Rigid3Object>(&out)) {
            if (!rigid_in) a.fail("output", "a Vec3d input maps onto a Vec3d state only");
            set_subset_multi<Rigid3Types, Rigid3Types>(a, inputs, *tor, info, concatenate, std::move(pairs));
        } else {
            a.fail("output", "must be a Vec3d or Rigid3d state");
        }
    });
    finish_multi_mapping(b, c, info, concatenate ? "the inputs one after the other" : "DOFs picked from the inputs");
}

void build_subset_multi_mapping(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    build_multi_mapping(b, c, info, false);
}
void build_identity_multi_mapping(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    build_multi_mapping(b, c, info, true);
}

constexpr ComponentSpec kMultiMappingComponents[] = {
    {.type = "CenterOfMassMapping",
     .family = F::mapping,
     .summary = "one Vec3d point at the mass-weighted centre of Rigid3d frames",
     .attributes = kCenterOfMass,
     .build = build_center_of_mass_mapping},
    {.type = "SubsetMultiMapping",
     .family = F::mapping,
     .summary = "DOFs picked from one or two states",
     .attributes = kSubsetMulti,
     .build = build_subset_multi_mapping},
    {.type = "IdentityMultiMapping",
     .family = F::mapping,
     .summary = "one or two states concatenated",
     .attributes = kIdentityMulti,
     .build = build_identity_multi_mapping},
};

}  // namespace

std::span<const ComponentSpec> multi_mapping_components() { return kMultiMappingComponents; }

}  // namespace penalty::scene::builder
