// The collision components of the scene builder (scene/builder/collision.cpp): the Data every
// collision model reads (a scene of spheres with per-sphere radii, both contact-distance names,
// per-model stiffness, a group shared with the floor and an inactive model, run 30 steps, is SOFA
// HEAD's state, 2a278d8, `sofa-head SCENE 30 OUT`, %.17g, bit for bit), the models' `penalty info`
// lines, the intersection methods' Data and SOFA's defaults, the beyond-SOFA switches, and the
// refusals naming the file, line, component and attribute.
#include "builder_scenes.hpp"

#include "penalty/collision/models.hpp"
#include "penalty/mechanics/state.hpp"

namespace {

using namespace penalty::test_builder_scenes;
using ::testing::ElementsAre;

/// Three spheres (radii 0.1, 0.12, 0.08 from listRadius; proximity 0.01 and contactDistance
/// 0.03, stiffness 500), a sphere of group 3 and a static floor of groups 3 and 4 (stiffness
/// 1000) beside an inactive point model; NewProximity 0.1 / 0.02.
const std::string kModelData = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <CollisionPipeline depth="4"/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <NewProximityIntersection alarmDistance="0.1" contactDistance="0.02"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Balls">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-12"/>
    <MechanicalObject name="dofs" position="0 0.15 0  0.5 0.2 0.1  1 0.12 -0.2"/>
    <UniformMass totalMass="0.6"/>
    <SphereCollisionModel name="balls" listRadius="0.1 0.12 0.08" proximity="0.01" contactDistance="0.03" contactStiffness="500"/>
  </Node>
  <Node name="Grouped">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-12"/>
    <MechanicalObject name="dofs" position="2 0.1 0"/>
    <UniformMass totalMass="0.2"/>
    <SphereCollisionModel name="grouped" radius="0.1" group="3" contactStiffness="800"/>
  </Node>
  <Node name="Floor">
    <MechanicalObject name="dofs" position="-3 0 -3  3 0 -3  3 0 3  -3 0 3"/>
    <MeshTopology triangles="0 2 1  0 3 2"/>
    <TriangleCollisionModel name="floor" simulated="0" moving="0" contactStiffness="1000" group="3 4"/>
    <PointCollisionModel name="corners" simulated="0" moving="0" active="0"/>
  </Node>
</Node>)";

const std::vector<Vec3>& collision_state_at(const scene::Scene& s, const std::string& node_path) {
    for (const auto& r : s.states())
        if (r.node_path == node_path) return dynamic_cast<const Vec3Object&>(*r.state).position;
    throw std::logic_error("no state at " + node_path);
}

const CollisionModel& model_named(const scene::Scene& s, const std::string& name) {
    for (const auto& m : s.collision_models())
        if (m.model->name() == name) return *m.model;
    throw std::logic_error("no model " + name);
}

TEST(CollisionComponents, ModelDataRunAsSofaHead) {
    auto s = build(kModelData);
    for (int k = 0; k < 30; ++k) s->step();
    // the balls rest on the floor, the grouped sphere falls through it
    EXPECT_THAT(collision_state_at(*s, "/Balls"),
                ElementsAre(Vec3(0, 0.12994405904050407, 0), Vec3(0.5, 0.14944350529644132, 0.099999999999999173),
                            Vec3(1, 0.10956757773994361, -0.1999999999999994)));
    EXPECT_THAT(collision_state_at(*s, "/Grouped"), ElementsAre(Vec3(2, -0.35616500000000029, 0)));
}

TEST(CollisionComponents, ModelsReadSofasCollisionModelData) {
    auto s = build(kModelData);
    const CollisionModelParams& balls = model_named(*s, "balls").params();
    EXPECT_EQ(balls.contact_distance, 0.01);  // its alias proximity over contactDistance (SOFA parses it last)
    EXPECT_EQ(balls.contact_stiffness, 500.0);
    EXPECT_TRUE(balls.active && balls.moving && balls.simulated);
    EXPECT_FALSE(balls.self_collision);
    const auto& spheres = dynamic_cast<const SphereModel&>(model_named(*s, "balls"));
    EXPECT_EQ(spheres.radius(0), 0.1);
    EXPECT_EQ(spheres.radius(1), 0.12);
    EXPECT_EQ(spheres.radius(2), 0.08);
    const CollisionModelParams& floor = model_named(*s, "floor").params();
    EXPECT_FALSE(floor.simulated);
    EXPECT_FALSE(floor.moving);
    EXPECT_THAT(floor.group, ElementsAre(3, 4));
    EXPECT_FALSE(model_named(*s, "corners").params().active);
    // SOFA's defaults, and the type as the name of an unnamed model
    auto d = build(R"(<Node name="root"><MechanicalObject position="0 0 0"/><PointCollisionModel proximity="0.2"
      selfCollision="1" bothSide="1" contactFriction="0.3" contactRestitution="0.4" contactResponse="PenalityContactForceField?damping=2"/></Node>)");
    const CollisionModelParams& p = d->collision_models()[0].model->params();
    EXPECT_EQ(p.name, "PointCollisionModel");
    EXPECT_EQ(p.contact_distance, 0.2);  // proximity alone
    EXPECT_EQ(p.contact_stiffness, 10.0);
    EXPECT_TRUE(p.self_collision);
    EXPECT_TRUE(p.both_side);
    EXPECT_EQ(p.contact_friction, 0.3);
    EXPECT_EQ(p.contact_restitution, 0.4);
    EXPECT_EQ(p.contact_response, "PenalityContactForceField?damping=2");
    EXPECT_TRUE(p.group.empty());
}

TEST(CollisionComponents, EachModelSaysWhatItIsInPenaltyInfo) {
    auto s = build(kModelData);
    const auto role_of = [&](const std::string& name) {
        for (const auto& m : s->collision_models())
            if (m.model->name() == name) return s->role(*m.component);
        return std::string("none");
    };
    EXPECT_EQ(role_of("balls"),
              "3 spheres, radii from listRadius, simulated, contactStiffness 500, contactDistance 0.01; pipeline "
              "CollisionPipeline");
    EXPECT_EQ(role_of("grouped"),
              "1 sphere, radius 0.1, simulated, contactStiffness 800, group 3; pipeline "
              "CollisionPipeline");
    EXPECT_EQ(role_of("floor"),
              "2 triangles, static obstacle (simulated=0, moving=0), contactStiffness 1000, group 3 4; pipeline "
              "CollisionPipeline");
    EXPECT_EQ(role_of("corners"),
              "4 points, static obstacle (simulated=0, moving=0), contactStiffness 10, inactive; pipeline "
              "CollisionPipeline");
    auto lone = build(R"(<Node name="root"><MechanicalObject position="0 0 0  1 0 0"/>
      <MeshTopology edges="0 1"/><LineCollisionModel simulated="0" selfCollision="1" contactResponse="nullptr"/>
      <PointCollisionModel moving="0"/></Node>)");
    EXPECT_EQ(lone->role(*lone->collision_models()[0].component),
              "1 edge, not simulated, contactStiffness 10, self-collision, contactResponse nullptr; in no collision "
              "pipeline: never collides");
    EXPECT_EQ(lone->role(*lone->collision_models()[1].component),
              "2 points, simulated, not moving, contactStiffness 10; in no collision pipeline: never collides");
}

const IntersectionParams& method_of(const scene::Scene& s) { return s.pipelines().at(0).pipeline->intersection(); }

/// A pipeline with the intersection `method` and one point model.
std::string with_method(const std::string& method) {
    return "<Node name=\"root\">\n  <CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/><CollisionResponse/>\n"
           "  " +
           method + "\n  <MechanicalObject position=\"0 0 0\"/><PointCollisionModel/>\n</Node>\n";
}

TEST(CollisionComponents, IntersectionMethodsReadTheirDataWithSofasDefaults) {
    const IntersectionParams np = method_of(*build(with_method("<NewProximityIntersection/>")));
    EXPECT_EQ(np.method, IntersectionMethod::NewProximity);
    EXPECT_EQ(np.alarm_distance, 1.0);
    EXPECT_EQ(np.contact_distance, 0.5);
    EXPECT_FALSE(np.use_line_line);
    const IntersectionParams mp = method_of(*build(with_method(
        R"(<MinProximityIntersection alarmDistance="0.3" contactDistance="0.1" useLineLine="0" useSphereTriangle="0" usePointPoint="0" useLinePoint="0" useSurfaceNormals="1"/>)")));
    EXPECT_EQ(mp.method, IntersectionMethod::MinProximity);
    EXPECT_EQ(mp.alarm_distance, 0.3);
    EXPECT_EQ(mp.contact_distance, 0.1);
    EXPECT_FALSE(mp.use_line_line || mp.use_sphere_triangle || mp.use_point_point || mp.use_line_point);
    EXPECT_TRUE(mp.use_surface_normals);
    const IntersectionParams md = method_of(*build(with_method("<MinProximityIntersection/>")));
    EXPECT_TRUE(md.use_line_line && md.use_sphere_triangle && md.use_point_point && md.use_line_point);
    EXPECT_FALSE(md.use_surface_normals);
    const IntersectionParams lmd = method_of(*build(with_method(
        R"(<LocalMinDistance filterIntersection="0" angleCone="0.2" coneFactor="0.7" useLMDFilters="1"/>)")));
    EXPECT_EQ(lmd.method, IntersectionMethod::LocalMinDistance);
    EXPECT_FALSE(lmd.filter_intersection);
    EXPECT_EQ(lmd.angle_cone, 0.2);
    EXPECT_EQ(lmd.cone_factor, 0.7);
    EXPECT_TRUE(lmd.use_lmd_filters);
    const IntersectionParams lmd0 = method_of(*build(with_method("<LocalMinDistance/>")));
    EXPECT_TRUE(lmd0.filter_intersection);
    EXPECT_EQ(lmd0.angle_cone, 0.0);
    EXPECT_EQ(lmd0.cone_factor, 0.5);
    const IntersectionParams discrete = method_of(*build(with_method("<DiscreteIntersection/>")));
    EXPECT_EQ(discrete.method, IntersectionMethod::Discrete);
    // beyond SOFA: the pairs SOFA has no intersector for, quirk fixes, the zero-distance normal
    const IntersectionParams beyond = method_of(*build(with_method(
        R"(<NewProximityIntersection beyondSofaPairs="1" fixSofaQuirks="all" zeroDistanceNormal="drop"/>)")));
    EXPECT_TRUE(beyond.enable_beyond_sofa_pairs);
    EXPECT_EQ(beyond.quirks.zero_distance_normal, ZeroDistanceNormal::Drop);
    EXPECT_EQ(enabled_sofa_quirk_fixes(beyond.quirks).size(), sofa_quirk_table().size());
    EXPECT_FALSE(np.enable_beyond_sofa_pairs);
    EXPECT_TRUE(enabled_sofa_quirk_fixes(np.quirks).empty());
    EXPECT_EQ(np.quirks.zero_distance_normal, ZeroDistanceNormal::FallbackX);
    // the command line's quirk fixes are added to every method's
    scene::BuildOptions o;
    ASSERT_TRUE(enable_sofa_quirk_fix(o.sofa_quirk_fixes, std::string(sofa_quirk_table()[0].name)));
    const IntersectionParams fixed = method_of(*build(with_method("<NewProximityIntersection/>"), o));
    EXPECT_THAT(enabled_sofa_quirk_fixes(fixed.quirks), ElementsAre(std::string(sofa_quirk_table()[0].name)));
}

TEST(CollisionComponents, BadIntersectionDataAreRefusedNamingTheAttribute) {
    EXPECT_EQ(error_of(with_method(R"(<NewProximityIntersection alarmDistance="0.1" contactDistance="0.2"/>)")),
              "test.scn:3: NewProximityIntersection: attribute 'contactDistance': must not exceed alarmDistance");
    EXPECT_THAT(error_of(with_method(R"(<MinProximityIntersection fixSofaQuirks="nosuch"/>)")),
                HasSubstr("test.scn:3: MinProximityIntersection: attribute 'fixSofaQuirks': unknown SOFA quirk "
                          "'nosuch' (known: all, "));
    EXPECT_EQ(error_of(with_method(R"(<LocalMinDistance zeroDistanceNormal="up"/>)")),
              "test.scn:3: LocalMinDistance: attribute 'zeroDistanceNormal': expected fallbackX, drop or sofaNaN");
    EXPECT_THAT(error_of(with_method(R"(<NewProximityIntersection alarmDistance="-1"/>)")),
                HasSubstr("test.scn:3: NewProximityIntersection: attribute 'alarmDistance'"));
}

/// A model's own response is checked when the model is built, not when its first contact is made
/// (that was an error at the step, exit 5: a fuzz finding, fuzz/regressions/unknown_model_response.scn).
TEST(CollisionComponents, AModelsUnknownResponseIsRefusedNamingTheAttribute) {
    const auto with_response = [](const std::string& response) {
        return "<Node name=\"root\">\n  <MechanicalObject position=\"0 0 0\"/>\n  <PointCollisionModel name=\"p\" "
               "contactResponse=\"" +
               response + "\"/>\n</Node>\n";
    };
    EXPECT_EQ(error_of(with_response("FrictionContactConstraint")),
              "test.scn:3: PointCollisionModel 'p': attribute 'contactResponse': unknown response "
              "'FrictionContactConstraint' (available: PenalityContactForceField, nullptr)");
    EXPECT_EQ(error_of(with_response("PenalityContactForceField?damping=-1")),
              "test.scn:3: PointCollisionModel 'p': attribute 'contactResponse': PenaltyParameters: damping = -1 "
              "must be finite and >= 0");
    EXPECT_EQ(error_of(with_response("PenalityContactForceField?friction=sticky")),
              "test.scn:3: PointCollisionModel 'p': attribute 'contactResponse': responseParams: parameter "
              "'friction': 'sticky' (expected ignored or coulomb)");
    for (const char* fine : {"", "nullptr", "PenalityContactForceField", "PenalityContactForceField?damping=2"})
        EXPECT_EQ(model_named(*build(with_response(fine)), "p").params().contact_response, fine);
}

TEST(CollisionComponents, ModelsRefuseAStateOfTheWrongKindAndBadRadii) {
    const std::string rigid = R"(<MechanicalObject template="Rigid3d" position="0 0 0 0 0 0 1"/>)";
    const std::string points = R"(<MechanicalObject name="dofs" position="0 0 0"/>)";
    const auto in_node = [](const std::string& state, const std::string& model) {
        return "<Node name=\"root\">\n  " + state + "\n  " + model + "\n</Node>\n";
    };
    EXPECT_EQ(error_of(in_node(rigid, "<PointCollisionModel/>")),
              "test.scn:3: PointCollisionModel: needs a Vec3d MechanicalObject");
    EXPECT_EQ(error_of(in_node(points, "<CylinderCollisionModel/>")),
              "test.scn:3: CylinderCollisionModel: needs a Rigid3d MechanicalObject");
    EXPECT_EQ(error_of(in_node(points, R"(<SphereCollisionModel template="Rigid3d"/>)")),
              "test.scn:3: SphereCollisionModel: template Rigid3d needs a Rigid3d MechanicalObject");
    EXPECT_EQ(error_of(in_node(points, R"(<SphereCollisionModel listRadius="0.1 0"/>)")),
              "test.scn:3: SphereCollisionModel: attribute 'listRadius': radii must be > 0");
    EXPECT_EQ(error_of(in_node(points, R"(<SphereCollisionModel radius="0"/>)"))
                  .rfind("test.scn:3: SphereCollisionModel: attribute 'radius': ", 0),
              0u);
    EXPECT_EQ(error_of("<Node name=\"root\">\n  " + points +
                       "\n  <SphereCollisionModel listRadius=\"@dofs.position\"/>\n</Node>\n"),
              "test.scn:3: SphereCollisionModel: attribute 'listRadius': must link to a SphereLoader's listRadius");
    // a Rigid3d state gives rigid spheres without a template
    auto r = build(in_node(rigid, R"(<SphereCollisionModel radius="0.3"/>)"));
    EXPECT_EQ(r->collision_models()[0].model->type(), ModelType::RigidSphere);
    EXPECT_EQ(r->role(*r->collision_models()[0].component),
              "1 rigid sphere, radius 0.3, simulated, contactStiffness 10; in no collision pipeline: never collides");
}

TEST(CollisionComponents, TriangleModelsComputeNormalsUnlessTold) {
    const std::string mesh = R"(<Node name="root"><MechanicalObject position="0 0 0  1 0 0  0 1 0"/>
      <MeshTopology triangles="0 1 2"/>)";
    auto on = build(mesh + "<TriangleCollisionModel/></Node>");
    EXPECT_TRUE(dynamic_cast<const TriangleModel&>(*on->collision_models()[0].model).compute_normals);
    auto off = build(mesh + "<TriangleCollisionModel computeNormals=\"0\"/></Node>");
    EXPECT_FALSE(dynamic_cast<const TriangleModel&>(*off->collision_models()[0].model).compute_normals);
    auto octree = build(mesh + "<TriangleOctreeCollisionModel computeNormals=\"0\"/></Node>");
    EXPECT_EQ(octree->collision_models()[0].model->type(), ModelType::Triangle);
    EXPECT_FALSE(dynamic_cast<const TriangleModel&>(*octree->collision_models()[0].model).compute_normals);
}

}  // namespace
