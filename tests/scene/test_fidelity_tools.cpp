// Issue 13's tools in the scene layer: SOFA's default names of unnamed components (exported file
// names line up with SOFA's), LocalMinDistance with SOFA's Data, and the SOFA-quirk switches from
// a scene attribute and from the build options (the command line).
#include "penalty/io/error.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using ::testing::HasSubstr;

using penalty::test::build;

const char* const kTwoSpheres = R"(<Node name="root">
      <CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/><CollisionResponse/>
      %INTERSECTION%
      <Node name="A"><MechanicalObject position="0 0 0"/><SphereCollisionModel simulated="0"/></Node>
      <Node name="B"><MechanicalObject name="ball" position="5 0 0"/><SphereCollisionModel/></Node>
      <Node name="C"><MechanicalObject position="9 0 0"/><SphereCollisionModel/></Node>
    </Node>)";

std::string two_spheres(const std::string& intersection) {
    std::string xml = kTwoSpheres;
    xml.replace(xml.find("%INTERSECTION%"), 14, intersection);
    return xml;
}

// SOFA's XML loader names an unnamed component <class><n>, n counting the unnamed components of
// that class in the node (ComponentNameHelper, xml convention): every node's one unnamed
// MechanicalObject is "MechanicalObject1", as in SOFA's trajectory files.
TEST(FidelityTools, UnnamedStatesGetSofaDefaultNames) {
    auto s = build(two_spheres("<NewProximityIntersection/>"));
    ASSERT_EQ(s->states().size(), 3u);
    EXPECT_EQ(s->states()[0].name, "MechanicalObject1");
    EXPECT_EQ(s->states()[1].name, "ball");
    EXPECT_EQ(s->states()[2].name, "MechanicalObject1");
}

TEST(FidelityTools, LocalMinDistanceReadsSofaData) {
    auto s = build(two_spheres(R"(<LocalMinDistance alarmDistance="2" contactDistance="0.5" angleCone="0.1"
                                     coneFactor="0.7" filterIntersection="0" useLMDFilters="1"/>)"));
    ASSERT_EQ(s->pipelines().size(), 1u);
    EXPECT_EQ(s->pipelines()[0].intersection, IntersectionMethod::LocalMinDistance);
    const IntersectionParams& p = s->pipelines()[0].pipeline->intersection();
    EXPECT_EQ(p.method, IntersectionMethod::LocalMinDistance);
    EXPECT_DOUBLE_EQ(p.alarm_distance, 2.0);
    EXPECT_DOUBLE_EQ(p.contact_distance, 0.5);
    EXPECT_DOUBLE_EQ(p.angle_cone, 0.1);
    EXPECT_DOUBLE_EQ(p.cone_factor, 0.7);
    EXPECT_FALSE(p.filter_intersection);
    EXPECT_TRUE(p.use_lmd_filters);
    EXPECT_TRUE(s->warnings().empty() ||
                std::none_of(s->warnings().begin(), s->warnings().end(), [](const std::string& w) {
                    return w.find("LocalMinDistance: attribute") != std::string::npos;
                }));
    // SOFA's defaults (LocalMinDistance's constructor and BaseProximityIntersection's).
    auto d = build(two_spheres("<LocalMinDistance/>"));
    const IntersectionParams& q = d->pipelines()[0].pipeline->intersection();
    EXPECT_DOUBLE_EQ(q.alarm_distance, 1.0);
    EXPECT_DOUBLE_EQ(q.contact_distance, 0.5);
    EXPECT_DOUBLE_EQ(q.angle_cone, 0.0);
    EXPECT_DOUBLE_EQ(q.cone_factor, 0.5);
    EXPECT_TRUE(q.filter_intersection);
    EXPECT_FALSE(q.use_lmd_filters);
}

TEST(FidelityTools, QuirkFixesFromSceneAttributeAndBuildOptions) {
    auto none = build(two_spheres("<NewProximityIntersection/>"));
    EXPECT_TRUE(enabled_sofa_quirk_fixes(none->pipelines()[0].pipeline->intersection().quirks).empty());

    auto one = build(two_spheres(
        R"(<NewProximityIntersection fixSofaQuirks="newproximity_triangle_sphere_edge_flags" zeroDistanceNormal="drop"/>)"));
    const SofaQuirkFixes& q = one->pipelines()[0].pipeline->intersection().quirks;
    EXPECT_TRUE(q.fix_newproximity_triangle_sphere_edge_flags);
    EXPECT_FALSE(q.fix_minproximity_line_sphere_mirror);
    EXPECT_EQ(q.zero_distance_normal, ZeroDistanceNormal::Drop);
    EXPECT_THAT(one->role(*one->file().root->components[4]), HasSubstr("newproximity_triangle_sphere_edge_flags"));

    scene::BuildOptions cli;  // --fix-sofa-quirk minproximity_line_sphere_mirror
    ASSERT_TRUE(enable_sofa_quirk_fix(cli.sofa_quirk_fixes, "minproximity_line_sphere_mirror"));
    auto both = build(
        two_spheres(R"(<NewProximityIntersection fixSofaQuirks="newproximity_triangle_sphere_edge_flags"/>)"), cli);
    EXPECT_EQ(enabled_sofa_quirk_fixes(both->pipelines()[0].pipeline->intersection().quirks),
              (std::vector<std::string>{"minproximity_line_sphere_mirror", "newproximity_triangle_sphere_edge_flags"}));

    auto all = build(two_spheres(R"(<MinProximityIntersection fixSofaQuirks="all"/>)"));
    EXPECT_EQ(enabled_sofa_quirk_fixes(all->pipelines()[0].pipeline->intersection().quirks).size(),
              sofa_quirk_table().size());
}

TEST(FidelityTools, UnknownQuirkOrPolicyIsAnErrorNamingTheAttribute) {
    try {
        (void)build(two_spheres(R"(<NewProximityIntersection fixSofaQuirks="no_such_quirk"/>)"));
        FAIL() << "no error";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(), HasSubstr("test.scn:3"));
        EXPECT_THAT(e.what(), HasSubstr("fixSofaQuirks"));
        EXPECT_THAT(e.what(), HasSubstr("unknown SOFA quirk 'no_such_quirk'"));
    }
    try {
        (void)build(two_spheres(R"(<NewProximityIntersection zeroDistanceNormal="maybe"/>)"));
        FAIL() << "no error";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(), HasSubstr("zeroDistanceNormal"));
    }
    SofaQuirkFixes fixes;
    EXPECT_FALSE(enable_sofa_quirk_fix(fixes, "nope"));
    EXPECT_TRUE(enabled_sofa_quirk_fixes(fixes).empty());
}

}  // namespace
