// SofaPython3's Python components in a scene: PythonForceField (a Sofa.Core.ForceFieldVec3d or
// ForceFieldRigid3d subclass) and PythonMapping (a Sofa.Core.Mapping_Vec3d_Vec3d subclass),
// whose methods are Python. The builder places them as any force field or mapping of their node;
// BuildOptions::external makes the objects (python/src/python_components.cpp), so the library
// does not depend on Python.
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

constexpr AttributeSpec kPythonForceField[] = {
    {"pythonObject", K::integer, "", "", ValueCheck::nonnegative, "the Python object (set by penalty's Sofa.Core)"},
};
constexpr AttributeSpec kPythonMapping[] = {
    {"pythonObject", K::integer, "", "", ValueCheck::nonnegative, "the Python object (set by penalty's Sofa.Core)"},
    {"input", K::link, "(the parent node's state)", "", ValueCheck::none, "MechanicalObject mapped from"},
    {"output", K::link, "(this node's state)", "", ValueCheck::none, "this node's MechanicalObject"},
};

ExternalComponents& external(SceneBuilder& b, const SceneComponent& c) {
    if (!b.options().external)
        io::throw_element_error(c, "is a Python component: it exists only in a SofaPython3 script run by penalty");
    return *b.options().external;
}

void build_python_force_field(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    b.guarded(c, [&] {
        std::unique_ptr<BaseForceField> ff = external(b, c).force_field(a.integer_or("pythonObject", -1), s);
        BaseForceField& added = info.node->add_force_field_ptr(std::move(ff));
        b.record_origin(&added, c);
        b.add_init(1, c, [f = &added] { f->init(); });
    });
    b.role(c, [st = &s] { return "force field in Python on " + counted(st->num_dofs(), "DOF", "DOFs"); });
}

/// A mapping made outside the library, held by the node as its mapping (Node::set_mapping
/// constructs the mapping it holds).
class HeldMapping final : public BaseMapping {
public:
    explicit HeldMapping(std::unique_ptr<BaseMapping> m) : m_(std::move(m)) {}
    [[nodiscard]] BaseState* from() const override { return m_->from(); }
    [[nodiscard]] BaseState* to() const override { return m_->to(); }
    void init() override { m_->init(); }
    void apply_position() override { m_->apply_position(); }
    void apply_velocity() override { m_->apply_velocity(); }
    void apply_dx() override { m_->apply_dx(); }
    void apply_jt_force() override { m_->apply_jt_force(); }
    void apply_jt_df() override { m_->apply_jt_df(); }
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override {
        m_->add_jacobian_triplets(t, row_offset, col_offset);
    }

private:
    std::unique_ptr<BaseMapping> m_;
};

/// The state a mapping's `input`/`output` links to (a MechanicalObject or a node), else the
/// parent node's / the node's own.
BaseState& python_mapping_end(SceneBuilder& b, const Attributes& a, std::string_view attr,
                              const io::SceneNode* fallback) {
    const io::SceneNode* target = fallback;
    if (a.has(attr)) {
        const io::LinkTarget t = a.link(attr);
        target = t.node != nullptr ? t.node : t.component != nullptr ? t.component->node : nullptr;
    }
    if (target == nullptr || b.node_builds().count(target) == 0 || b.node_build(*target).node == nullptr ||
        b.node_build(*target).node->state() == nullptr)
        a.fail(attr, "no MechanicalObject to map " + std::string(attr == "input" ? "from" : "to"));
    return *b.node_build(*target).node->state();
}

void build_python_mapping(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    if (info.state_component == nullptr)
        io::throw_element_error(c, "needs a MechanicalObject in its node (its output)");
    BaseState& in = python_mapping_end(b, a, "input", info.scene_node->parent);
    BaseState& out = python_mapping_end(b, a, "output", info.scene_node);
    if (&out != info.node->state()) a.fail("output", "must be the MechanicalObject of the mapping's own node");
    b.guarded(c, [&] {
        BaseMapping& m =
            info.node->set_mapping<HeldMapping>(external(b, c).mapping(a.integer_or("pythonObject", -1), in, out));
        b.add_init(0, c, [p = &m] { p->init(); });
    });
    b.role(c, [o = &out] { return "mapping in Python onto this node's " + counted(o->num_dofs(), "point", "points"); });
}

constexpr ComponentSpec kPythonComponents[] = {
    {.type = "PythonForceField",
     .family = F::force_field,
     .summary = "force field written in Python (Sofa.Core.ForceFieldVec3d / ForceFieldRigid3d)",
     .attributes = kPythonForceField,
     .build = build_python_force_field},
    {.type = "PythonMapping",
     .family = F::mapping,
     .summary = "mapping written in Python (Sofa.Core.Mapping_Vec3d_Vec3d)",
     .attributes = kPythonMapping,
     .build = build_python_mapping},
};

}  // namespace

std::span<const ComponentSpec> python_components() { return kPythonComponents; }

}  // namespace penalty::scene::builder
