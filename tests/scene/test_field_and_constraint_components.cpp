// The projective constraints, rigid force fields, surface force fields and BoxROI oriented boxes
// of issue 52 built from .scn text: defaults agree with the library, the simulated motion follows
// the closed forms (a particle sliding on a line, a prescribed linear motion one step behind
// SOFA's clock, a cantilever of beams under its own weight), and bad attribute values are scene
// errors naming the file, line, component and attribute.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/beam_fem_force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/component_defaults.hpp"
#include "penalty_test/paths.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using penalty::test::default_number;
using penalty::test::error_of;
using ::testing::HasSubstr;

std::string particles(const std::string& positions, const std::string& components, const std::string& extra_root = "") {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">)" + extra_root + R"(
      <Node name="P"><EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
        <CGLinearSolver iterations="100" tolerance="1e-20" threshold="1e-30"/>
        <MechanicalObject name="dofs" position=")" +
           positions + R"("/>
        <UniformMass vertexMass="2"/>
        )" +
           components + R"(
      </Node>
    </Node>)";
}

const Vec3Object& vec3_dofs(const scene::Scene& s, std::size_t i = 0) {
    return dynamic_cast<const Vec3Object&>(*s.states()[i].state);
}

TEST(FieldAndConstraintComponents, RegistryDefaultsAgreeWithTheLibrary) {
    const BeamParameters beam;
    EXPECT_EQ(default_number("BeamFEMForceField", "radius"), beam.radius);
    EXPECT_EQ(default_number("BeamFEMForceField", "radiusInner"), beam.radius_inner);
    EXPECT_EQ(default_number("BeamFEMForceField", "youngModulus"), beam.young_modulus.front());
    EXPECT_EQ(default_number("BeamFEMForceField", "poissonRatio"), beam.poisson_ratio.front());
    EXPECT_EQ(default_number("FastTriangularBendingSprings", "bendingStiffness"), 1.0);
    EXPECT_EQ(default_number("QuadBendingFEMForceField", "youngModulus"), 1000.0);
    EXPECT_EQ(default_number("TriangularFEMForceFieldOptim", "poissonRatio"), 0.45);
    EXPECT_EQ(default_number("AttachProjectiveConstraint", "minDistance"), -1.0);
}

TEST(FieldAndConstraintComponents, ParticleSlidesDownItsLineAsImplicitEulerPredicts) {
    // line through the origin along (1, −1, 0)/√2: the gravity component along it is g/√2, and
    // implicit Euler without stiffness gives v_n = n h a, x_n = x_0 + h² a n(n+1)/2 along n
    auto s = build(
        particles("0 0 0  5 5 5", R"(<LineProjectiveConstraint indices="0" origin="0 0 0" direction="1 -1 0"/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("keeps 1 point on the line through (0, 0, 0)"));
    const int steps = 30;
    for (int i = 0; i < steps; ++i) s->step();
    const Vec3 n = Vec3(1, -1, 0).normalized();
    const double a = 10 / std::sqrt(2.0), h = 0.01;
    const Vec3Object& x = vec3_dofs(*s);
    EXPECT_NEAR((x.position[0] - n * (h * h * a * steps * (steps + 1) / 2)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((x.velocity[0] - n * (h * a * steps)).norm(), 0.0, 1e-12);
    EXPECT_NEAR(x.position[1].y(), 5 - h * h * 10 * steps * (steps + 1) / 2, 1e-11) << "the other point falls freely";
}

TEST(FieldAndConstraintComponents, PlaneAndPointConstraintsHoldTheirPoints) {
    auto s = build(particles("0 1 0  2 3 4  1 1 1",
                             R"(<PlaneProjectiveConstraint indices="0 1" origin="0 1 0" normal="0 1 0"/>
                                <PointProjectiveConstraint indices="2" point="1 1 1"/>)"));
    for (int i = 0; i < 10; ++i) s->step();
    const Vec3Object& x = vec3_dofs(*s);
    EXPECT_NEAR(x.position[0].y(), 1.0, 1e-15);
    EXPECT_NEAR(x.position[1].y(), 1.0, 1e-15) << "projected onto the plane at init";
    EXPECT_EQ(x.position[2], Vec3(1, 1, 1));
}

TEST(FieldAndConstraintComponents, LinearMovementLagsOneStepBehindTheStepsTime) {
    // SOFA projects after the solve at the context time, still the step's start: after step k
    // the point is at the movement of time (k − 1)·h
    auto s = build(particles(
        "1 0 0", R"(<LinearMovementProjectiveConstraint indices="0" keyTimes="0 1" movements="0 0 0  2 0 0"/>)"));
    const int steps = 10;
    for (int i = 0; i < steps; ++i) s->step();
    const Vec3Object& x = vec3_dofs(*s);
    EXPECT_NEAR(x.position[0].x(), 1 + 2 * 0.01 * (steps - 1), 1e-14);
    EXPECT_NEAR(x.position[0].y(), 0.0, 1e-15);
    EXPECT_NEAR(x.velocity[0].x(), 2.0, 1e-14);
}

TEST(FieldAndConstraintComponents, CantileverOfBeamsSagsAsThePointLoadsPredict) {
    // 4 beams along x, frame 0 fixed, 0.01 kg per frame under g = 10: a static tip deflection of
    // Σ_i P x_i² (3L − x_i)/(6EI) (each frame's weight P at x_i); long implicit steps reach it
    const std::string scene = R"(<Node name="root" dt="2" gravity="0 -10 0">
      <Node name="Beam"><EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
        <CGLinearSolver iterations="400" tolerance="1e-30" threshold="1e-30"/>
        <MeshTopology edges="0 1 1 2 2 3 3 4"/>
        <MechanicalObject template="Rigid3" name="frames" position="0 0 0 0 0 0 1  0.5 0 0 0 0 0 1  1 0 0 0 0 0 1  1.5 0 0 0 0 0 1  2 0 0 0 0 0 1"/>
        <FixedProjectiveConstraint indices="0"/>
        <UniformMass vertexMass="0.01"/>
        <BeamFEMForceField radius="0.05" youngModulus="1e8" poissonRatio="0.3"/>
      </Node>
    </Node>)";
    auto s = build(scene);
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("4 beams"));
    for (int i = 0; i < 60; ++i) s->step();
    const auto& frames = dynamic_cast<const Rigid3Object&>(*s.get()->states()[0].state);
    const double ei = 1e8 * std::numbers::pi * std::pow(0.05, 4) / 4, length = 2.0, p = 0.01 * 10;
    double tip = 0;
    for (double xi : {0.5, 1.0, 1.5, 2.0}) tip += p * xi * xi * (3 * length - xi) / (6 * ei);
    EXPECT_NEAR(frames.position[4].center.y(), -tip, 1e-4 * tip);
    EXPECT_NEAR(frames.position[0].center.norm(), 0.0, 0.0);
}

TEST(FieldAndConstraintComponents, JointSpringsBetweenMappedFramesRun) {
    // the shape of SOFA's JointSpringForceField.scn: the springs act on frames a RigidMapping
    // Rigid3 → Rigid3 makes; rigidIndexPerPoint of another length than the output means `index`
    const std::string scene = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
      <Node name="chain"><EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
        <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
        <MechanicalObject template="Rigid3" name="DOFs" position="0 0 0 0 0 0 1  2 0 0 0 0 0 1  4 0 0 0 0 0 1"/>
        <UniformMass vertexMass="1 1 [1 0 0,0 1 0,0 0 1]"/>
        <FixedProjectiveConstraint template="Rigid3" indices="0"/>
        <Node name="attaches">
          <MechanicalObject template="Rigid3" name="attaches" position="1 0 0 0 0 0 1  -1 0 0 0 0 0 1  1 0 0 0 0 0 1  -1 0 0 0 0 0 1"/>
          <RigidMapping template="Rigid3,Rigid3" input="@.." output="@." rigidIndexPerPoint="0 1 1 2"/>
          <JointSpringForceField template="Rigid3" spring="BEGIN_SPRING 0 1 FREE_AXIS 0 0 0 0 1 0 KS_T 0 30000 KS_R 0 200000 KD 1 R_LIM_Y -1.57 1.57 END_SPRING
             BEGIN_SPRING 2 3 END_SPRING"/>
        </Node>
      </Node>
    </Node>)";
    auto s = build(scene);
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("2 joint springs"));
    for (int i = 0; i < 50; ++i) s->step();
    const auto& dofs = dynamic_cast<const Rigid3Object&>(*s->states()[0].state);
    EXPECT_EQ(dofs.position[0].center, Vec3::Zero());
    // the hinges hold the chain together: frame 1's attach point stays on frame 0's (within the
    // springs' stretch under gravity, mg/k ~ 1e-3 m)
    const auto& attaches = dynamic_cast<const Rigid3Object&>(*s->states()[1].state);
    EXPECT_LT((attaches.position[0].center - attaches.position[1].center).norm(), 2e-2);
    EXPECT_LT(dofs.position[2].center.y(), -0.01) << "the chain swings down";
}

TEST(FieldAndConstraintComponents, NonUniformHexahedraOnAGridWithVirtualFinerLevels) {
    // the project's SOFA comparison scene: a box voxelised 4 times finer, condensed back
    auto s = scene::load_scene(penalty::test::source_dir() / "tests/scene/data/nonuniform_hexahedra.scn");
    const std::string text = scene::describe_scene(*s);
    EXPECT_THAT(text, HasSubstr("sparse grid 5 x 3 x 3 (from 2 virtual finer levels)"));
    EXPECT_THAT(text, HasSubstr("condensed from 2 virtual finer levels"));
    for (int i = 0; i < 20; ++i) s->step();
    const Vec3Object& two = vec3_dofs(*s, 0);
    // clamped at x = 0, the free end sags under gravity
    double lowest = 0;
    for (const Vec3& x : two.position) lowest = std::min(lowest, x.y());
    EXPECT_LT(lowest, -1e-3);
    const std::string error = error_of(R"(<Node name="root"><Node name="N"><EulerImplicitSolver/><CGLinearSolver/>
        <RegularGridTopology n="2 2 2" min="0 0 0" max="1 1 1"/><MechanicalObject/>
        <NonUniformHexahedronFEMForceFieldAndMass nbVirtualFinerLevels="1"/></Node></Node>)");
    EXPECT_THAT(error, HasSubstr("needs a SparseGridTopology in its node"));
}

TEST(FieldAndConstraintComponents, BoxRoiOrientedBoxSelectsThePointsInside) {
    // an oriented box spanning (1,0,0)–(3,0,0)–(3,1,0), depth 1: points with 1 ≤ x ≤ 3,
    // 0 ≤ y ≤ 1, |z| ≤ 0.5; no `box`: the default box is not added
    auto s = build(particles("0 0 0  2 0.5 0  2 0.5 0.7  2.9 0.9 -0.4  5 0 0",
                             R"(<BoxROI name="roi" orientedBox="1 0 0  3 0 0  3 1 0  1"/>
                                <FixedProjectiveConstraint indices="@roi.indices"/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("selects 2 of 5 points"));
}

TEST(FieldAndConstraintComponents, BoxRoiPositionLinkThatFindsNothingSelectsNothing) {
    auto s = build(particles("0 0 0  0.5 0.5 0.5", R"(<BoxROI name="roi" position="@../Volume.position"/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("selects 0 of 0 points"));
    bool warned = false;
    for (const std::string& w : s->warnings()) warned = warned || w.find("finds nothing") != std::string::npos;
    EXPECT_TRUE(warned);
}

TEST(FieldAndConstraintComponents, TaitPressureInflatesItsBoxWhileTheInjectionRamps) {
    // the project's SOFA comparison scene: 0.6 m³ injected at 12 m³/s (dt 0.01: 5 steps) into a
    // 2 m³ box; the quad box under a constant 20 Pa swells against its springs
    auto s = scene::load_scene(penalty::test::source_dir() / "tests/scene/data/tait_pressure.scn");
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("fluid in 12 surface triangles, rest volume 2 m^3"));
    // the balloon, pinned at one corner, swings down while it swells: its diagonal lengthens
    const auto diagonal = [&] { return (vec3_dofs(*s, 0).position[6] - vec3_dofs(*s, 0).position[0]).norm(); };
    const double diagonal0 = diagonal(), box0 = vec3_dofs(*s, 1).position[7].y();
    for (int i = 0; i < 30; ++i) s->step();
    EXPECT_GT(diagonal(), diagonal0 + 0.01) << "the balloon swells";
    EXPECT_GT(vec3_dofs(*s, 1).position[7].y(), box0 + 0.005) << "the box swells";
}

TEST(FieldAndConstraintComponents, MeshLoaderScaleThatIsNotOneNumberIsOneAsInSofa) {
    // SOFA's MeshLoader::parse reads `scale` with getAttributeAsFloat: "0.25 0.25 0.25" is not
    // read whole, so the scale stays 1 (TaitSurfacePressureForceField.scn relies on it)
    const auto box_top = [](const std::string& scale) {
        scene::BuildOptions options;
        options.data_dirs.push_back(penalty::test::source_dir() / "tests/scene/data");
        auto s = build(R"(<Node name="root"><Node name="N"><EulerImplicitSolver/><CGLinearSolver/>
            <MeshOBJLoader name="loader" filename="box_3x1x1.obj" )" +
                           scale + R"(/>
            <MeshTopology src="@loader"/><MechanicalObject src="@loader"/><UniformMass vertexMass="1"/></Node></Node>)",
                       options);
        return std::pair{vec3_dofs(*s).position[6], s->warnings()};
    };
    const auto [whole, no_notes] = box_top(R"(scale="0.5")");
    EXPECT_EQ(whole, Vec3(1.5, 0.5, 0.5));
    const auto [three, notes] = box_top(R"(scale="0.25 0.25 0.25")");
    EXPECT_EQ(three, Vec3(3, 1, 1));
    bool noted = false;
    for (const std::string& w : notes) noted = noted || w.find("is not one number: scale 1") != std::string::npos;
    EXPECT_TRUE(noted);
}

TEST(FieldAndConstraintComponents, BadAttributesNameFileLineComponentAndAttribute) {
    const auto expect_error = [](const std::string& components, const std::string& what) {
        const std::string message = error_of(particles("0 0 0  1 0 0", components));
        EXPECT_THAT(message, HasSubstr("test.scn:")) << message;
        const std::string type = components.substr(1, components.find(' ') - 1);
        EXPECT_THAT(message, HasSubstr("test.scn:6: " + type + ": ")) << message;
        EXPECT_THAT(message, HasSubstr(what)) << message;
    };
    expect_error(R"(<PartialFixedProjectiveConstraint indices="0" fixedDirections="1 0"/>)",
                 "attribute 'fixedDirections': expected 3 flags");
    expect_error(R"(<LinearMovementProjectiveConstraint keyTimes="0 2 1" movements="0 0 0 1 0 0 2 0 0"/>)",
                 "attribute 'keyTimes': must be in ascending order");
    expect_error(R"(<LinearMovementProjectiveConstraint keyTimes="0 1" movements="0 0 0 1 0"/>)",
                 "attribute 'movements': expected 3 numbers per key movement");
    expect_error(R"(<ParabolicProjectiveConstraint indices="0" P1="0 0 0" P2="0 0 0" P3="1 1 0" EndTime="1"/>)",
                 "attribute 'P2': P1, P2 and P3 must be three distinct points");
    expect_error(R"(<LineProjectiveConstraint indices="5" direction="1 0 0"/>)", "index 5 out of range");
    expect_error(R"(<FixedRotationProjectiveConstraint FixedZRotation="1"/>)", "acts on Rigid3d states only");
    expect_error(R"(<BoxROI orientedBox="0 0 0 1 0 0 1 1 0"/>)",
                 "attribute 'orientedBox': expected 10 numbers per box");
    expect_error(R"(<BoxROI orientedBox="0 0 0 1 0 0 2 0 0 1"/>)",
                 "attribute 'orientedBox': box 0: p0, p1 and p2 are aligned");
    expect_error(R"(<AttachProjectiveConstraint indices1="0" indices2="1" clamp="1"/>)",
                 "attribute 'clamp': only false is supported");
    expect_error(R"(<TriangularFEMForceFieldOptim poissonRatio="0.5"/>)",
                 "attribute 'poissonRatio': must be in [0, 0.5)");
    expect_error(R"(<FastTetrahedralCorotationalForceField method="qrs"/>)",
                 "attribute 'method': must be qr, large, polar");
    expect_error(R"(<FastTetrahedralCorotationalForceField youngModulus="30 -1"/>)",
                 "attribute 'youngModulus': must be > 0");
    expect_error(R"(<Mesh2PointTopologicalMapping copyEdges="1"/>)", "attribute 'copyEdges': only false is supported");
    expect_error(R"(<TaitSurfacePressureForceField B="-1"/>)", "attribute 'B'");
    expect_error(R"(<TaitSurfacePressureForceField maxInjectionRate="-2"/>)", "attribute 'maxInjectionRate'");
    expect_error(R"(<TaitSurfacePressureForceField p0="1"/>)", "needs a topology");
    expect_error(R"(<TaitSurfacePressureForceField p0="1"/><MeshTopology edges="0 1"/>)",
                 "its topology has no triangles or quads");
    const std::string rigid = R"(<Node name="root"><Node name="R"><EulerImplicitSolver/><CGLinearSolver/>
        <MechanicalObject template="Rigid3" position="0 0 0 0 0 0 1  1 0 0 0 0 0 1"/><UniformMass vertexMass="1"/>
        <MeshTopology edges="0 1"/>)";
    EXPECT_THAT(
        error_of(rigid + R"(<JointSpringForceField spring="BEGIN_SPRING 0 1 KS_Q 1 END_SPRING"/></Node></Node>)"),
        HasSubstr("attribute 'spring': unknown keyword 'KS_Q'"));
    EXPECT_THAT(
        error_of(rigid +
                 R"(<JointSpringForceField spring="BEGIN_SPRING 0 1 END_SPRING" outfile="log.txt"/></Node></Node>)"),
        HasSubstr("attribute 'outfile': files are not supported"));
    EXPECT_THAT(error_of(rigid + R"(<BeamFEMForceField radius="0.1" radiusInner="0.2"/></Node></Node>)"),
                HasSubstr("attribute 'radiusInner': must be smaller than radius"));
    EXPECT_THAT(error_of(rigid + R"(<BeamFEMForceField radius="0.1" poissonRatio="0.7"/></Node></Node>)"),
                HasSubstr("attribute 'poissonRatio': must be in (-1, 0.5)"));
}

}  // namespace

namespace {

/// Every DOF coordinate of every state of a scene after `steps` steps.
std::vector<double> coordinates_after(const std::string& xml, int steps) {
    auto s = build(xml);
    for (int k = 0; k < steps; ++k) s->step();
    std::vector<double> out;
    for (const auto& r : s->states())
        for (const Vec3& p : dynamic_cast<const Vec3Object&>(*r.state).position)
            out.insert(out.end(), {p.x(), p.y(), p.z()});
    return out;
}

}  // namespace

// SOFA's renamed components (ObjectFactory::createObject with renamedComponents): the names of
// before v24.06 build the components of the new names, the same bits, with a note; an old name
// whose new component penalty lacks stays an unknown component under its own name.
TEST(FieldAndConstraintComponents, SofasOlderNamesBuildTheRenamedComponents) {
    const std::string older = R"(<LinearMovementConstraint indices="0" keyTimes="0 1" movements="0 0 0  2 0 0"/>
        <StiffSpringForceField spring="1 2 50 0.5 0.3"/>
        <ProjectToPlaneConstraint indices="2" origin="0 0 0" normal="0 1 0"/>)";
    const std::string newer =
        R"(<LinearMovementProjectiveConstraint indices="0" keyTimes="0 1" movements="0 0 0  2 0 0"/>
        <SpringForceField spring="1 2 50 0.5 0.3"/>
        <PlaneProjectiveConstraint indices="2" origin="0 0 0" normal="0 1 0"/>)";
    const std::string positions = "1 0 0  0 1 0  0 0 1";
    const std::vector<double> a = coordinates_after(particles(positions, older), 20);
    const std::vector<double> b = coordinates_after(particles(positions, newer), 20);
    ASSERT_EQ(a.size(), 9u);
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << i;
    EXPECT_NE(a[0], 1.0);  // the prescribed motion moved point 0
    auto s = build(particles(positions, older));
    const std::vector<std::string> w = s->warnings();
    EXPECT_EQ(
        std::count_if(w.begin(), w.end(),
                      [](const std::string& m) { return m.find("SOFA's name before v24.06") != std::string::npos; }),
        3);
    EXPECT_THAT(error_of(particles(positions, R"(<UniformConstraint/>)")),
                HasSubstr("unknown component 'UniformConstraint'"));
}
