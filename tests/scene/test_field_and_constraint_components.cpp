// The components of issue 52 built from .scn text: the registry's defaults agree with the library, a
// MeshLoader scale that is not one number is one as in SOFA, and bad attribute values are scene errors
// naming the file, line, component and attribute.
#include "field_and_constraint_scenes.hpp"

namespace {

using namespace penalty;
using namespace penalty::test_field_scenes;
using penalty::test::build;
using penalty::test::default_number;
using penalty::test::error_of;
using ::testing::HasSubstr;

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
