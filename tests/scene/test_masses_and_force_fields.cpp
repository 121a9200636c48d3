// Masses, gravity and force fields of the scene builder (scene/builder/masses_and_force_fields.cpp):
// Gravity, UniformMass (vertexMass, totalMass, a Rigid3d mass with its inertia), MeshSpringForceField
// (per-kind stiffness), RegularGridSpringForceField, TetrahedronFEMForceField and
// HexahedronFEMForceField: the states after 20 steps are SOFA HEAD's (2a278d8, `sofa-head SCENE
// 20 OUT`, %.17g), bit for bit (the hexahedron within 1e-15: penalty's hexahedra part from SOFA
// at rounding level). Which of several names of one Data wins (SOFA's
// alphabetical parse), the `penalty info` lines, and the refusals naming the file, line,
// component and attribute.
#include "builder_scenes.hpp"

#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/mechanics/state.hpp"

#include <functional>
#include <map>

namespace {

using namespace penalty::test_builder_scenes;
using ::testing::ElementsAre;

const std::string kMassesAndFields = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Springs">
    <Gravity gravity="0 0 -2"/>
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="50" tolerance="1e-15" threshold="1e-15"/>
    <MeshTopology position="0 0 0  1 0 0  0 1 0  1 1 0.2" edges="0 3" triangles="0 1 2  1 3 2"/>
    <MechanicalObject name="cloth"/>
    <UniformMass vertexMass="0.25"/>
    <MeshSpringForceField stiffness="30" trianglesStiffness="80" linesStiffness="40" damping="0.5"/>
    <FixedProjectiveConstraint indices="0"/>
  </Node>
  <Node name="Grid">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="50" tolerance="1e-15" threshold="1e-15"/>
    <RegularGridTopology n="2 2 2" min="0 0 0" max="1 1 1"/>
    <MechanicalObject name="grid"/>
    <UniformMass totalMass="2"/>
    <RegularGridSpringForceField stiffness="200"/>
    <FixedProjectiveConstraint indices="0 1"/>
  </Node>
  <Node name="Tetra">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="50" tolerance="1e-15" threshold="1e-15"/>
    <MechanicalObject name="tetra" position="0 0 0  1 0 0  0 1 0  0 0 1  1 1 1"/>
    <MeshTopology tetrahedra="0 1 2 3  1 2 3 4"/>
    <UniformMass totalMass="1"/>
    <TetrahedronFEMForceField youngModulus="2000" poissonRatio="0.35" method="large"/>
    <FixedProjectiveConstraint indices="0 1 2"/>
  </Node>
  <Node name="Hexa">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="50" tolerance="1e-15" threshold="1e-15"/>
    <MechanicalObject name="hexa" position="0 0 0  1 0 0  1 1 0  0 1 0  0 0 1  1 0 1  1 1 1  0 1 1"/>
    <MeshTopology hexahedra="0 1 2 3 4 5 6 7"/>
    <UniformMass totalMass="1"/>
    <HexahedronFEMForceField youngModulus="3000" poissonRatio="0.3" method="large"/>
    <FixedProjectiveConstraint indices="0 1 2 3"/>
  </Node>
  <Node name="Body">
    <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="50" tolerance="1e-15" threshold="1e-15"/>
    <MechanicalObject template="Rigid3d" name="body" position="0 0 0 0 0 0 1" velocity="0 0 0 1 2 0.5"/>
    <UniformMass vertexMass="2 1 [1 0 0,0 2 0,0 0 3]"/>
  </Node>
</Node>)";

const BaseState& field_state_at(const scene::Scene& s, const std::string& node_path) {
    for (const auto& r : s.states())
        if (r.node_path == node_path) return *r.state;
    throw std::logic_error("no state at " + node_path);
}
const std::vector<Vec3>& field_points_at(const scene::Scene& s, const std::string& node_path) {
    return dynamic_cast<const Vec3Object&>(field_state_at(s, node_path)).position;
}

TEST(MassesAndForceFields, TheyMoveTheirStatesAsSofaHead) {
    auto s = build(kMassesAndFields);
    for (int k = 0; k < 20; ++k) s->step();
    EXPECT_THAT(field_points_at(*s, "/Springs"),
                ElementsAre(Vec3(0, 0, 0), Vec3(0.99980117358219645, 0.00049874681586099248, -0.041284126691327444),
                            Vec3(0.00049874681586099248, 0.99980117358219645, -0.041284126691327444),
                            Vec3(1.0011826939626609, 1.0011826939626609, 0.15810866679679209)));
    EXPECT_THAT(field_points_at(*s, "/Grid"),
                ElementsAre(Vec3(0, 0, 0), Vec3(1, 0, 0),
                            Vec3(-0.00064601807601368812, 0.98622372571718997, 0.098400567511832446),
                            Vec3(1.0006460180760135, 0.98622372571718997, 0.098400567511832474),
                            Vec3(0.00046276251176732326, -0.11351948939505155, 0.9928737829857095),
                            Vec3(0.99953723748823275, -0.11351948939505155, 0.9928737829857095),
                            Vec3(-0.00042363269757986785, 0.88298048367482795, 1.09447527649482),
                            Vec3(1.0004236326975799, 0.88298048367482784, 1.09447527649482)));
    EXPECT_THAT(field_points_at(*s, "/Tetra"),
                ElementsAre(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
                            Vec3(-0.0037246616022582049, -0.011580355381452552, 0.99702631271442888),
                            Vec3(0.9958240794722405, 0.98398922423120883, 1.0084629707058335)));
    // HexahedronFEMForceField parts from SOFA HEAD at rounding level (a few ulps after 20 steps)
    const std::vector<Vec3> hexa = {Vec3(0, 0, 0),
                                    Vec3(1, 0, 0),
                                    Vec3(1, 1, 0),
                                    Vec3(0, 1, 0),
                                    Vec3(-0.00063201155758305528, -0.0063178181396910844, 0.99732953938358582),
                                    Vec3(1.0006320115575829, -0.006317818139691087, 0.99732953938358582),
                                    Vec3(0.99936684638724516, 0.99367286483485595, 1.002654510588131),
                                    Vec3(0.00063315361275472415, 0.99367286483485595, 1.002654510588131)};
    const std::vector<Vec3>& hexa_now = field_points_at(*s, "/Hexa");
    ASSERT_EQ(hexa_now.size(), hexa.size());
    for (std::size_t i = 0; i < hexa.size(); ++i) EXPECT_LT((hexa_now[i] - hexa[i]).norm(), 1e-15) << "point " << i;
    EXPECT_NE(hexa_now[4], hexa[0]);  // it moved: 6 mm down, 0.6 mm aside
    const RigidFrame& body = dynamic_cast<const Rigid3Object&>(field_state_at(*s, "/Body")).position.at(0);
    EXPECT_EQ(body.center, Vec3(0, -0.20601000000000003, 0));
    EXPECT_EQ(body.orientation.coeffs(),
              Eigen::Vector4d(0.099127294005998817, 0.19825458801199763, 0.049563647002999409, 0.97386464296174369));
}

TEST(MassesAndForceFields, EachSaysWhatItIsInPenaltyInfo) {
    auto s = build(kMassesAndFields);
    const io::SceneNode& root = *s->file().root;
    const auto role = [&](std::size_t node, std::size_t component) {
        return s->role(*root.children[node]->components[component]);
    };
    EXPECT_EQ(role(0, 0), "gravity (0, 0, -2) m/s^2 in this node and below");
    EXPECT_EQ(role(0, 5), "mass 0.25 kg per DOF, 1 kg in all");
    EXPECT_EQ(
        role(0, 6),
        "6 springs between the topology's vertex pairs (ks = stiffness / rest length, kd = damping / rest length)");
    EXPECT_EQ(role(1, 4), "mass 0.25 kg per DOF, 2 kg in all");
    EXPECT_EQ(role(2, 5), "2 tetrahedra, E = 2000 Pa, nu = 0.35, corotational (large)");
    EXPECT_EQ(role(3, 5), "1 hexahedron, E = 3000 Pa, nu = 0.3, corotational (large)");
    EXPECT_EQ(role(4, 3), "mass 2 kg per DOF, 2 kg in all");
}

TEST(MassesAndForceFields, OfSeveralNamesOfOneStiffnessTheLastInAlphabeticalOrderWins) {
    // two points on one edge of rest length 2: ks = stiffness / 2. linesStiffness and stiffness
    // both written: "stiffness" comes last in SOFA's alphabetical parse and wins.
    const auto springs = [](const std::string& attributes) {
        auto s = build(R"(<Node name="root">
  <MeshTopology position="0 0 0  2 0 0" edges="0 1"/>
  <MechanicalObject/>
  <MeshSpringForceField )" +
                       attributes + R"(/>
</Node>)");
        return dynamic_cast<const SpringForceField&>(*s->simulation().root().force_fields().at(0)).springs();
    };
    const auto spring = [&](const std::string& attributes) {
        const std::vector<Spring> all = springs(attributes);
        EXPECT_EQ(all.size(), 1u);
        return all.empty() ? Spring{} : all[0];
    };
    EXPECT_EQ(spring(R"(linesStiffness="40" stiffness="30")").ks, 15.0);
    EXPECT_EQ(spring(R"(linesStiffness="40")").ks, 20.0);
    EXPECT_EQ(spring(R"(linesStiffness="40" linesDamping="4" damping="1")").kd, 2.0);  // linesDamping after damping
    EXPECT_EQ(spring(R"(linesStiffness="40" damping="1")").kd, 0.5);
    EXPECT_TRUE(springs("").empty());  // MeshSpringForceField's default stiffness and damping 0: no spring
    // the tetrahedra's alias: tetrasStiffness (t-e-t-r-as) comes after tetrahedraStiffness
    auto t = build(R"(<Node name="root">
  <MeshTopology position="0 0 0  1 0 0  0 1 0  0 0 1" tetrahedra="0 1 2 3"/>
  <MechanicalObject/>
  <MeshSpringForceField tetrahedraStiffness="10" tetrasStiffness="20"/>
</Node>)");
    const auto& ff = dynamic_cast<const SpringForceField&>(*t->simulation().root().force_fields().at(0));
    ASSERT_EQ(ff.springs().size(), 6u);
    EXPECT_EQ(ff.springs()[0].ks, 20.0);  // edge 0-1, rest length 1
}

TEST(MassesAndForceFields, RigidMassesReadSofasRigid3MassText) {
    // two frames turning at ω = (1, 2, 0.5) and (1, 0, 0): ½·m·ωᵀJω each (J per unit mass)
    const auto scene_with = [](const std::string& attributes) {
        return build(R"(<Node name="root"><MechanicalObject template="Rigid3d" position="0 0 0 0 0 0 1  1 0 0 0 0 0 1"
velocity="0 0 0 1 2 0.5  0 0 0 1 0 0"/>
<UniformMass )" + attributes +
                     "/></Node>");
    };
    const auto full = scene_with(R"(vertexMass="2 1 [1 0 0,0 2 0,0 0 3]")");
    EXPECT_EQ(dynamic_cast<const UniformMass<Rigid3Types>&>(*full->simulation().root().mass()).vertex_mass(), 2.0);
    EXPECT_DOUBLE_EQ(full->kinetic_energy(), 0.5 * 2 * (1 + 2 * 4 + 3 * 0.25) + 0.5 * 2 * 1);
    const auto total = scene_with(R"(totalMass="3" inertiaMatrix="2 0 0 0 2 0 0 0 2")");
    EXPECT_EQ(dynamic_cast<const UniformMass<Rigid3Types>&>(*total->simulation().root().mass()).vertex_mass(), 1.5);
    EXPECT_DOUBLE_EQ(total->kinetic_energy(), 0.5 * 1.5 * 2 * (1 + 4 + 0.25) + 0.5 * 1.5 * 2 * 1);
    const auto plain = scene_with(R"(vertexMass="2")");  // one number: the mass, J = I
    EXPECT_DOUBLE_EQ(plain->kinetic_energy(), 0.5 * 2 * (1 + 4 + 0.25) + 0.5 * 2 * 1);
    EXPECT_EQ(error_of(R"(<Node name="root"><MechanicalObject template="Rigid3d" position="0 0 0 0 0 0 1"/>
<UniformMass vertexMass="2 1 3"/></Node>)"),
              "test.scn:2: UniformMass: attribute 'vertexMass': expected a mass, or mass volume and a 3x3 inertia "
              "matrix (11 numbers), found 3 numbers");
    EXPECT_EQ(error_of(R"(<Node name="root"><MechanicalObject template="Rigid3d" position="0 0 0 0 0 0 1"/>
<UniformMass vertexMass="2 x"/></Node>)"),
              "test.scn:2: UniformMass: attribute 'vertexMass': expected numbers (mass volume [inertia]), found 'x'");
    EXPECT_EQ(error_of(R"(<Node name="root"><MechanicalObject template="Rigid3d" position="0 0 0 0 0 0 1"/>
<UniformMass vertexMass="-2 1"/></Node>)"),
              "test.scn:2: UniformMass: attribute 'vertexMass': the mass must be > 0, found -2");
    EXPECT_EQ(error_of(R"(<Node name="root"><MechanicalObject template="Rigid3d" position="0 0 0 0 0 0 1"/>
<UniformMass totalMass="1" inertiaMatrix="1 2"/></Node>)"),
              "test.scn:2: UniformMass: attribute 'inertiaMatrix': expected 9 numbers");
}

TEST(MassesAndForceFields, BadDataAreRefusedNamingTheAttribute) {
    const auto in_node = [](const std::string& body) {
        return "<Node name=\"root\">\n  <MeshTopology position=\"0 0 0  1 0 0  0 1 0  0 0 1\" tetrahedra=\"0 1 2 "
               "3\"/>\n  <MechanicalObject/>\n  " +
               body + "\n</Node>\n";
    };
    EXPECT_EQ(error_of(in_node("<UniformMass/>")),
              "test.scn:4: UniformMass: needs vertexMass or totalMass (SOFA refuses a UniformMass without them)");
    EXPECT_EQ(error_of(in_node(R"(<UniformMass vertexMass="0"/>)")),
              "test.scn:4: UniformMass: attribute 'vertexMass': must be > 0, found '0'");
    EXPECT_EQ(error_of(in_node(R"(<TetrahedronFEMForceField poissonRatio="0.5"/>)")),
              "test.scn:4: TetrahedronFEMForceField: attribute 'poissonRatio': must be in (-1, 0.5)");
    EXPECT_EQ(error_of(in_node(R"(<TetrahedronFEMForceField method="corotated"/>)")),
              "test.scn:4: TetrahedronFEMForceField: attribute 'method': 'corotated' is not supported (small, large, "
              "polar or svd)");
    EXPECT_EQ(error_of(in_node(R"(<HexahedronFEMForceField method="svd"/>)")),
              "test.scn:4: HexahedronFEMForceField: attribute 'method': 'svd' is not supported (small, large or "
              "polar)");
    EXPECT_EQ(error_of(in_node(R"(<TetrahedronFEMForceField method="polar" updateStiffnessMatrix="1"/>)")),
              "test.scn:4: TetrahedronFEMForceField: attribute 'updateStiffnessMatrix': with method polar or svd is "
              "not supported (SOFA recomputes the strain-displacement matrix each step)");
    EXPECT_EQ(error_of(in_node(R"(<TetrahedronFEMForceField method="small" plasticMaxThreshold="0.1"/>)")),
              "test.scn:4: TetrahedronFEMForceField: attribute 'plasticMaxThreshold': plasticity is supported with "
              "method large only");
    EXPECT_EQ(error_of(in_node(R"(<TetrahedronFEMForceField method="small" localStiffnessFactor="1 2"/>)")),
              "test.scn:4: TetrahedronFEMForceField: attribute 'localStiffnessFactor': is supported with method large "
              "only");
    EXPECT_EQ(error_of(in_node(R"(<RegularGridSpringForceField/>)")),
              "test.scn:4: RegularGridSpringForceField: needs a RegularGridTopology in its node");
    // SOFA's defaults of the TetrahedronFEMForceField's plasticity: the floats 0.0001f and 0.9f
    auto s = build(in_node(R"(<TetrahedronFEMForceField plasticMaxThreshold="0.1"/>)"));
    const auto& fem = dynamic_cast<const TetrahedronFEMForceField&>(*s->simulation().root().force_fields().at(0));
    EXPECT_EQ(fem.plasticity().yield_threshold, double(0.0001f));
    EXPECT_EQ(fem.plasticity().creep, double(0.9f));
    EXPECT_EQ(fem.plasticity().max_threshold, 0.1);
}

// Which force fields are SOFA's interaction force fields (BaseInteractionForceField), as SOFA HEAD
// (2a278d8) lists its categories: BaseObject::getCategories of each component made in a node with
// a MechanicalObject holds "InteractionForceField" for exactly these (SpringForceField and the
// fields made of it, TriangleBendingSprings and QuadBendingSprings among them); SOFA's
// TriangularBendingSprings and QuadularBendingSprings are plain ForceFields. It decides the
// summation order of a node's fields (Node::for_each_force_field) and which fields of a node
// without solver are explicit: SOFA's SolveVisitor evaluates only the interaction fields there.
const std::string kEveryForceField = R"()" + std::string(R"SCN(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Tetra">
    <TetrahedronSetTopologyContainer position="0 0 0  1 0 0  0 1 0  0 0 1  1 1 1" tetrahedra="0 1 2 3  1 2 3 4"/>
    <MechanicalObject name="tetra"/>
    <TetrahedronFEMForceField youngModulus="2000" poissonRatio="0.35" method="large"/>
    <TetrahedralCorotationalFEMForceField youngModulus="2000" poissonRatio="0.35"/>
    <FastTetrahedralCorotationalForceField youngModulus="2000" poissonRatio="0.35"/>
    <TetrahedronHyperelasticityFEMForceField materialName="StVenantKirchhoff" ParameterSet="1000 100"/>
  </Node>
  <Node name="Triangles">
    <TriangleSetTopologyContainer position="0 0 0  1 0 0  0 1 0  1 1 0.2" triangles="0 1 2  1 3 2"/>
    <MechanicalObject name="cloth"/>
    <TriangularFEMForceField youngModulus="60" poissonRatio="0.3"/>
    <TriangularFEMForceFieldOptim youngModulus="60" poissonRatio="0.3"/>
    <TriangleFEMForceField youngModulus="60" poissonRatio="0.3"/>
    <TriangularBendingSprings stiffness="10"/>
    <FastTriangularBendingSprings bendingStiffness="10"/>
    <TriangularBiquadraticSpringsForceField youngModulus="60" poissonRatio="0.3"/>
    <TriangularQuadraticSpringsForceField youngModulus="60" poissonRatio="0.3"/>
    <TriangularTensorMassForceField youngModulus="60" poissonRatio="0.3"/>
    <TrianglePressureForceField pressure="0 0 1" triangleList="0"/>
    <TriangleBendingSprings stiffness="10"/>
    <MeshSpringForceField stiffness="30"/>
    <SpringForceField spring="0 3 10 0.1 1.2"/>
    <ConstantForceField indices="0" forces="0 1 0"/>
    <PlaneForceField normal="0 1 0" d="-1" stiffness="100"/>
    <RestShapeSpringsForceField stiffness="10"/>
    <ConicalForceField coneCenter="0 2 0" coneHeight="0 -1 0" coneAngle="10" stiffness="100"/>
    <SurfacePressureForceField pressure="1"/>
    <TaitSurfacePressureForceField p0="1" B="1" gamma="1"/>
  </Node>
  <Node name="Quads">
    <QuadSetTopologyContainer position="0 0 0  1 0 0  1 1 0  0 1 0  2 0 0  2 1 0" quads="0 1 2 3  1 4 5 2"/>
    <MechanicalObject name="sheet"/>
    <QuadBendingSprings stiffness="10"/>
    <QuadularBendingSprings stiffness="10"/>
    <QuadPressureForceField pressure="0 0 1" quadList="0"/>
    <QuadBendingFEMForceField youngModulus="60" poissonRatio="0.3" thickness="0.1"/>
  </Node>
  <Node name="Hexa">
    <HexahedronSetTopologyContainer position="0 0 0  1 0 0  1 1 0  0 1 0  0 0 1  1 0 1  1 1 1  0 1 1" hexahedra="0 1 2 3 4 5 6 7"/>
    <MechanicalObject name="hexa"/>
    <HexahedronFEMForceField youngModulus="3000" poissonRatio="0.3" method="large"/>
    <HexahedralFEMForceField youngModulus="3000" poissonRatio="0.3"/>
  </Node>
  <Node name="Grid">
    <RegularGridTopology n="2 2 2" min="0 0 0" max="1 1 1"/>
    <MechanicalObject name="grid"/>
    <RegularGridSpringForceField stiffness="200"/>
  </Node>
  <Node name="Edges">
    <EdgeSetTopologyContainer position="0 0 0  1 0 0  2 0 0" edges="0 1  1 2"/>
    <MechanicalObject name="wire"/>
    <EdgePressureForceField pressure="0 1 0" normal="0 0 1"/>
  </Node>
</Node>)SCN") + R"()";

TEST(MassesAndForceFields, InteractionFieldsAreSofasInteractionForceFields) {
    const std::map<std::string, bool> sofa_interaction = {
        {"TetrahedronFEMForceField", false},
        {"TetrahedralCorotationalFEMForceField", false},
        {"FastTetrahedralCorotationalForceField", false},
        {"TetrahedronHyperelasticityFEMForceField", false},
        {"TriangularFEMForceField", false},
        {"TriangularFEMForceFieldOptim", false},
        {"TriangleFEMForceField", false},
        {"TriangularBendingSprings", false},
        {"FastTriangularBendingSprings", false},
        {"TriangularBiquadraticSpringsForceField", false},
        {"TriangularQuadraticSpringsForceField", false},
        {"TriangularTensorMassForceField", false},
        {"TrianglePressureForceField", false},
        {"TriangleBendingSprings", true},
        {"MeshSpringForceField", true},
        {"SpringForceField", true},
        {"ConstantForceField", false},
        {"PlaneForceField", false},
        {"RestShapeSpringsForceField", false},
        {"ConicalForceField", false},
        {"SurfacePressureForceField", false},
        {"TaitSurfacePressureForceField", false},
        {"QuadBendingSprings", true},
        {"QuadularBendingSprings", false},
        {"QuadPressureForceField", false},
        {"QuadBendingFEMForceField", false},
        {"HexahedronFEMForceField", false},
        {"HexahedralFEMForceField", false},
        {"RegularGridSpringForceField", true},
        {"EdgePressureForceField", false},
    };
    auto s = build(kEveryForceField);
    std::map<std::string, bool> found;
    std::function<void(const Node&)> visit = [&](const Node& n) {
        for (const auto& ff : n.force_fields()) {
            const io::SceneComponent* c = s->component_of(ff.get());
            ASSERT_NE(c, nullptr);
            found[c->type] = ff->sofa_interaction();
            // `penalty info` says which are never evaluated (no solver in this scene)
            EXPECT_EQ(s->role(*c).find("never evaluated: no ODE solver above it") != std::string::npos,
                      !ff->sofa_interaction())
                << c->type << ": " << s->role(*c);
        }
        for (const auto& child : n.children()) visit(*child);
    };
    visit(s->simulation().root());
    EXPECT_EQ(found, sofa_interaction);

    // No node has a solver: the interaction fields are explicit, the others never evaluated;
    // nothing moves, and the steps run.
    const auto state_of = [&](const std::string& node_name) -> const Vec3Object& {
        for (const auto& child : s->simulation().root().children())
            if (child->name() == node_name) return dynamic_cast<const Vec3Object&>(*child->state());
        throw std::runtime_error("no node " + node_name);
    };
    const Vec3Object& cloth = state_of("Triangles");
    const std::vector<Vec3> start = cloth.position;
    for (int step = 0; step < 3; ++step) s->step();
    EXPECT_EQ(cloth.position, start);
    // the cloth's springs are explicit: their forces reach its external force; the tetrahedra's
    // state is read by plain fields only, which nothing evaluates: static
    EXPECT_FALSE(cloth.is_static());
    EXPECT_TRUE(state_of("Tetra").is_static());
}

}  // namespace
