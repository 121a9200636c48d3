// The builder's side of SofaPython3's Python components (scene/builder/python_components.cpp):
// PythonForceField and PythonMapping made by BuildOptions::external (here a C++ stand-in for
// python/src/python_components.cpp: a constant force, a translation) and placed as any force field
// or mapping of their node (a constant force on 2 kg moves it by h²·f/m in a step; a mapped force
// reaches the input through the held mapping's Jᵀ), their `penalty info` lines, and the refusals
// naming the file, line, component and attribute. tests/python/test_python_components.py runs
// them from Python scripts against SOFA HEAD.
#include "builder_scenes.hpp"

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/state.hpp"
#include "penalty/scene/live_data.hpp"

#include <memory>
#include <vector>

namespace {

using namespace penalty::test_builder_scenes;
using ::testing::ElementsAre;

/// f += (0, id, 0) on every DOF, no stiffness.
class ConstantUpForce final : public ForceField<Vec3Types> {
public:
    ConstantUpForce(Vec3Object& s, double up) : ForceField<Vec3Types>(s), up_(up) {}
    void add_force(std::span<Vec3> f, std::span<const Vec3>, std::span<const Vec3>) override {
        for (Vec3& x : f) x += Vec3(0, up_, 0);
    }
    void add_dforce(std::span<Vec3>, std::span<const Vec3>, double, double) const override {}
    void add_stiffness_triplets(TripletList&, Index, double) const override {}

private:
    double up_;
};

/// out = in + (1, 0, 0), J = identity.
class ShiftedCopy final : public Mapping<Vec3Types, Vec3Types> {
public:
    ShiftedCopy(Vec3Object& from, Vec3Object& to) : Mapping<Vec3Types, Vec3Types>(from, to) {}
    void apply(std::span<Vec3> out, std::span<const Vec3> in) override {
        for (std::size_t i = 0; i < out.size(); ++i) out[i] = in[i] + Vec3(1, 0, 0);
    }
    void apply_j(std::span<Vec3> out, std::span<const Vec3> in) const override {
        for (std::size_t i = 0; i < out.size(); ++i) out[i] = in[i];
    }
    void apply_jt(std::span<Vec3> in, std::span<const Vec3> out) const override {
        for (std::size_t i = 0; i < out.size(); ++i) in[i] += out[i];
    }
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override {
        for (Index i = 0; i < Index(3 * in_->num_dofs()); ++i) t.emplace_back(row_offset + i, col_offset + i, 1.0);
    }
    [[nodiscard]] std::size_t output_size() const override { return in_->num_dofs(); }
};

/// What penalty's Sofa.Core makes for a script: here the stand-ins, recording the ids asked for.
class StandInComponents final : public scene::ExternalComponents {
public:
    std::unique_ptr<BaseForceField> force_field(std::int64_t id, BaseState& state) override {
        ids.push_back(id);
        return std::make_unique<ConstantUpForce>(dynamic_cast<Vec3Object&>(state), double(id));
    }
    std::unique_ptr<BaseMapping> mapping(std::int64_t id, BaseState& from, BaseState& to) override {
        ids.push_back(id);
        return std::make_unique<ShiftedCopy>(dynamic_cast<Vec3Object&>(from), dynamic_cast<Vec3Object&>(to));
    }
    std::vector<std::int64_t> ids;
};

/// A body of two 1 kg points (no gravity) with `extra` in its node and `child` below it.
std::string python_body(const std::string& extra, const std::string& child = "") {
    return R"(<Node name="root" dt="0.1" gravity="0 0 0">
  <Node name="Body">
    <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="10" tolerance="1e-20" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0 0 0  0 1 0"/>
    <UniformMass totalMass="2"/>
    )" + extra +
           "\n" + child + R"(
  </Node>
</Node>
)";
}

scene::BuildOptions with_external(const std::shared_ptr<StandInComponents>& external) {
    scene::BuildOptions o;
    o.external = external;
    return o;
}

const std::vector<Vec3>& python_state_at(const scene::Scene& s, const std::string& node_path) {
    for (const auto& r : s.states())
        if (r.node_path == node_path) return dynamic_cast<const Vec3Object&>(*r.state).position;
    throw std::logic_error("no state at " + node_path);
}

TEST(PythonComponents, AForceFieldIsPlacedInItsNodeAndActsInTheStep) {
    auto external = std::make_shared<StandInComponents>();
    auto s = build(python_body(R"(<PythonForceField name="up" pythonObject="3"/>)"), with_external(external));
    EXPECT_EQ(external->ids, std::vector<std::int64_t>{3});
    const io::SceneComponent& c = *s->file().root->children[0]->components[4];
    EXPECT_EQ(s->role(c), "force field in Python on 2 DOFs");
    const Node& body = *s->simulation().root().children()[0];
    ASSERT_EQ(body.force_fields().size(), 1u);
    EXPECT_EQ(s->component_of(body.force_fields()[0].get()), &c);
    // a constant force of 3 N on 1 kg, implicit Euler: v = h·f/m = 0.3, x = h·v = 0.03
    s->step();
    const std::vector<Vec3>& x = python_state_at(*s, "/Body");
    EXPECT_NEAR(x[0].y(), 0.03, 1e-15);
    EXPECT_NEAR(x[1].y(), 1.03, 1e-15);
    EXPECT_EQ(x[0].x(), 0.0);
}

TEST(PythonComponents, AMappingIsHeldByItsNodeAndForwardsEveryPass) {
    auto external = std::make_shared<StandInComponents>();
    auto s = build(python_body(R"(<PythonForceField pythonObject="0"/>)", R"(    <Node name="Shifted">
      <MechanicalObject name="points"/>
      <PythonMapping pythonObject="5"/>
      <PythonForceField pythonObject="2"/>
    </Node>)"),
                   with_external(external));
    EXPECT_EQ(external->ids, (std::vector<std::int64_t>{0, 5, 2}));
    const Node& shifted = *s->simulation().root().children()[0]->children()[0];
    ASSERT_NE(shifted.mapping(), nullptr);
    EXPECT_EQ(shifted.mapping()->from(), s->simulation().root().children()[0]->state());
    EXPECT_EQ(shifted.mapping()->to(), shifted.state());
    // its init: the output's positions from the input's
    EXPECT_THAT(python_state_at(*s, "/Body/Shifted"), ElementsAre(Vec3(1, 0, 0), Vec3(1, 1, 0)));
    const io::SceneComponent& c = *s->file().root->children[0]->children[0]->components[1];
    EXPECT_EQ(s->role(c), "mapping in Python onto this node's 2 points");
    // the mapped 2 N per point reach the body through Jᵀ: v = 0.1·2/1, x = 0.1·v; the output follows
    s->step();
    EXPECT_NEAR(python_state_at(*s, "/Body")[1].y(), 1.02, 1e-15);
    EXPECT_NEAR(python_state_at(*s, "/Body/Shifted")[1].y(), 1.02, 1e-15);
    EXPECT_EQ(python_state_at(*s, "/Body/Shifted")[1].x(), 1.0);
}

TEST(PythonComponents, AreRefusedOutsideAScriptAndWithoutTheirStates) {
    EXPECT_EQ(error_of(python_body("<PythonForceField pythonObject=\"1\"/>")),
              "test.scn:7: PythonForceField: is a Python component: it exists only in a SofaPython3 script run by "
              "penalty");
    EXPECT_EQ(error_of(python_body("", "    <Node name=\"M\"><MechanicalObject/><PythonMapping/></Node>")),
              "test.scn:8: PythonMapping: is a Python component: it exists only in a SofaPython3 script run by "
              "penalty");
    auto external = std::make_shared<StandInComponents>();
    const auto refusal = [&](const std::string& text) {
        try {
            (void)build(text, with_external(external));
        } catch (const io::SceneError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(refusal(python_body("<PythonForceField pythonObject=\"-1\"/>"))
                  .rfind("test.scn:7: PythonForceField: attribute 'pythonObject': ", 0),
              0u);
    EXPECT_EQ(refusal(python_body("", "    <Node name=\"M\"><PythonMapping/></Node>")),
              "test.scn:8: PythonMapping: needs a MechanicalObject in its node (its output)");
    EXPECT_EQ(
        refusal(python_body("", R"(    <Node name="M"><MechanicalObject/><PythonMapping output="@../dofs"/></Node>)")),
        "test.scn:8: PythonMapping: attribute 'output': must be the MechanicalObject of the mapping's own node");
    EXPECT_EQ(refusal(R"(<Node name="root">
  <Node name="Empty"/>
  <Node name="M"><MechanicalObject/><PythonMapping input="@../Empty"/></Node>
</Node>
)"),
              "test.scn:3: PythonMapping: attribute 'input': no MechanicalObject to map from");
}

}  // namespace
