// The live Data of a built scene (include/penalty/scene/live_data.hpp): every Data of a component
// or node read by SOFA path and name with SOFA's type, writes after init taking effect as SOFA's
// component takes them (bit for bit as a fresh scene built with the new value), the states keeping
// their memory through the rebuild, refused writes saying why.
#include "penalty/io/error.hpp"
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using penalty::scene::DataOwner;
using ::testing::HasSubstr;

/// A 3x3x4 hexahedral beam under gravity, its z = 0 face fixed through a BoxROI.
std::string live_beam(const std::string& young = "100", const std::string& indices = "@box.indices") {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <Node name="B">
    <EulerImplicitSolver name="ode" rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver name="cg" iterations="50" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology name="grid" nx="3" ny="3" nz="4" xmin="0" xmax="1" ymin="0" ymax="1" zmin="0" zmax="2"/>
    <MechanicalObject name="mo"/>
    <UniformMass name="mass" totalMass="1"/>
    <BoxROI name="box" box="-1 -1 -0.1 2 2 0.1"/>
    <FixedProjectiveConstraint name="fix" indices=")" +
           indices + R"("/>
    <HexahedronFEMForceField name="ff" youngModulus=")" +
           young + R"(" poissonRatio="0.3"/>
  </Node>
</Node>)";
}

std::vector<Vec3> live_positions_after(scene::Scene& s, int steps) {
    for (int k = 0; k < steps; ++k) s.step();
    return dynamic_cast<const Vec3Object&>(*s.states().front().state).position;
}

const DataOwner kFem{"/B/ff", false};

TEST(LiveData, ReadsEveryDataWithSofasType) {
    auto s = test::build(live_beam());
    const scene::DataValue young = s->data(kFem, "youngModulus");
    EXPECT_EQ(young.python_form, "ndarray:float64:1");  // SOFA's vector<double>
    EXPECT_EQ(young.numbers, std::vector<double>{100.0});
    EXPECT_EQ(s->data(kFem, "method").text, "large");  // SOFA's default, the scene does not set it
    const scene::DataValue indices = s->data({"/B/fix", false}, "indices");  // linked to the BoxROI's output
    EXPECT_EQ(indices.text, "0 1 2 3 4 5 6 7 8");
    EXPECT_EQ(s->data({"/", true}, "gravity").text, "0 -9.81 0");
    const scene::DataValue x = s->data({"/B/mo", false}, "position");
    EXPECT_EQ(x.columns, 3u);
    EXPECT_EQ(x.numbers.size(), 36u * 3u);
    EXPECT_NE(x.state, nullptr);
    // every Data SOFA declares for the type can be read
    for (const scene::DataField& f : s->data_fields(kFem)) EXPECT_NO_THROW((void)s->data(kFem, f.name)) << f.name;
    EXPECT_THROW((void)s->data(kFem, "youngModulos"), std::invalid_argument);
}

TEST(LiveData, WritesAtTheNextStepAsAFreshScene) {
    auto fresh = test::build(live_beam("100", "0 1 2 3 4 5 6 7 8 9 10"));
    auto written = test::build(live_beam());
    written->set_data({"/B/fix", false}, "indices", "0 1 2 3 4 5 6 7 8 9 10");
    EXPECT_EQ(live_positions_after(*written, 5), live_positions_after(*fresh, 5));
    auto unchanged = test::build(live_beam());
    EXPECT_NE(live_positions_after(*unchanged, 5), live_positions_after(*fresh, 5));
}

TEST(LiveData, UniformMassWriteWeighsTheNextStepWithTheOldMassAsSofaUnlessFixed) {
    // three free particles of 1 kg (totalMass 3), written to 3 kg each: SOFA's lazy update
    // (SofaQuirkFixes::fix_uniform_mass_lazy_write) weighs the first step with 1 kg, the mass
    // matrix has 3 kg: dv = h·g·1/3; fixed: dv = h·g
    const std::string particles = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <Node name="P"><EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="10" tolerance="1e-20" threshold="1e-20"/>
    <MechanicalObject name="mo" position="0 0 0  1 0 0  2 0 0"/><UniformMass name="mass" totalMass="3"/></Node>
</Node>)";
    for (const bool fixed : {false, true}) {
        scene::BuildOptions options;
        options.sofa_quirk_fixes.fix_uniform_mass_lazy_write = fixed;
        auto s = test::build(particles, options);
        s->set_data({"/P/mass", false}, "totalMass", "9");
        EXPECT_EQ(s->data({"/P/mass", false}, "vertexMass").numbers, std::vector<double>{fixed ? 3.0 : 1.0});
        s->step();
        const auto& v = dynamic_cast<const Vec3Object&>(*s->states().front().state).velocity;
        EXPECT_NEAR(v[0].y(), 0.01 * -9.81 * (fixed ? 1.0 : 1.0 / 3.0), 1e-15) << fixed;
        EXPECT_EQ(s->data({"/P/mass", false}, "vertexMass").numbers, std::vector<double>{3.0});
    }
}

TEST(LiveData, YoungsModulusWaitsForReinitAsSofa) {
    auto fresh = test::build(live_beam("400"));
    auto unchanged = test::build(live_beam());
    auto written = test::build(live_beam());
    written->set_data(kFem, "youngModulus", "400");
    EXPECT_EQ(written->data(kFem, "youngModulus").numbers, std::vector<double>{400.0});  // the Data holds it
    EXPECT_EQ(live_positions_after(*written, 3), live_positions_after(*unchanged, 3));
    auto reinit = test::build(live_beam());
    reinit->set_data(kFem, "youngModulus", "400");
    reinit->reinit(kFem);
    EXPECT_EQ(live_positions_after(*reinit, 5), live_positions_after(*fresh, 5));
}

TEST(LiveData, TheRebuildKeepsStatesTheirMemoryAndTheTime) {
    auto s = test::build(live_beam());
    live_positions_after(*s, 2);
    const auto& record = s->states().front();
    const Vec3* memory = dynamic_cast<const Vec3Object&>(*record.state).position.data();
    const Vec3 before = dynamic_cast<const Vec3Object&>(*record.state).position[30];
    s->set_data({"/B/ode", false}, "rayleighStiffness", "0.5");
    s->apply_pending_writes();
    EXPECT_EQ(s->generation(), 1u);
    EXPECT_EQ(&s->states().front(), &record);  // the record keeps its address
    const auto& state = dynamic_cast<const Vec3Object&>(*record.state);
    EXPECT_EQ(state.position.data(), memory);  // and the state its memory
    EXPECT_EQ(state.position[30], before);
    EXPECT_DOUBLE_EQ(s->simulation().time(), 0.02);
    EXPECT_EQ(s->data({"/B/ode", false}, "rayleighStiffness").numbers, std::vector<double>{0.5});
}

TEST(LiveData, RefusedWritesSayWhy) {
    auto s = test::build(live_beam());
    try {
        s->set_data(kFem, "topology", "@../grid");
        FAIL() << "a link written after init";
    } catch (const std::invalid_argument& e) {
        EXPECT_THAT(e.what(),
                    HasSubstr("HexahedronFEMForceField 'ff': data 'topology' cannot be written after init: links "
                              "are resolved at init"));
    }
    EXPECT_THROW(s->set_data({"/B/grid", false}, "nx", "5"), std::invalid_argument);
    try {
        s->set_data({"/B/mass", false}, "totalMass", "-2");
        FAIL() << "a negative mass";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(),
                    HasSubstr("test.scn:7: UniformMass 'mass': attribute 'totalMass': must be > 0, found '-2'"));
    }
}

TEST(LiveData, AStateWriteIsInPlaceAndKeepsTheSize) {
    auto s = test::build(R"(<Node name="root"><MechanicalObject name="m" position="0 0 0 1 1 1"/></Node>)");
    s->set_data({"/m", false}, "position", "5 6 7 8 9 10");
    EXPECT_EQ(s->data({"/m", false}, "position").text, "5 6 7 8 9 10");
    EXPECT_THROW(s->set_data({"/m", false}, "position", "1 2 3"), std::invalid_argument);
}

}  // namespace
