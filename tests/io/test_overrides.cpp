// Attribute overrides (`--set PATH.attribute=value`) on a parsed scene: parsing, path
// resolution (root, nodes, components, the root's own name), replacement in place, additions
// through the caller's filter, and the messages for what does not exist.

#include "io_test_util.hpp"

#include "penalty/io/overrides.hpp"
#include "penalty/io/scene_file.hpp"

#include <gtest/gtest.h>

namespace penalty::io {
namespace {

using test::message_of;

constexpr const char* kScene = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
    <EulerImplicitSolver name="solver" rayleighMass="0.1"/>
    <Node name="Floor">
        <MechanicalObject name="dofs" position="0 0 0"/>
        <TriangleCollisionModel name="FloorTri1" contactStiffness="10"/>
        <Node name="Inner">
            <UniformMass name="mass" totalMass="2"/>
        </Node>
    </Node>
</Node>
)";

SceneFile scene() { return parse_scene_string(kScene, "s.scn"); }

TEST(Overrides, ParsesPathAttributeAndValue) {
    const Override o = parse_override("/Floor/FloorTri1.contactStiffness=200");
    EXPECT_EQ(o.path, "/Floor/FloorTri1");
    EXPECT_EQ(o.attribute, "contactStiffness");
    EXPECT_EQ(o.value, "200");
    // The value keeps blanks and further '=' signs; an empty path is the root.
    const Override v = parse_override("/Floor/dofs.position=0 1 0=x");
    EXPECT_EQ(v.value, "0 1 0=x");
    EXPECT_EQ(parse_override(".dt=0.5").path, "/");
    EXPECT_EQ(parse_override("/.dt=0.5").path, "/");
    // A dot in a node name before the last '/' is part of the path.
    const Override d = parse_override("/a.b/c.k=1");
    EXPECT_EQ(d.path, "/a.b/c");
    EXPECT_EQ(d.attribute, "k");
}

TEST(Overrides, MalformedTextIsASyntaxError) {
    EXPECT_EQ(message_of<OverrideSyntaxError>([] { (void)parse_override("/Floor/FloorTri1.contactStiffness"); }),
              "--set '/Floor/FloorTri1.contactStiffness': expected PATH.attribute=value (no '=')");
    EXPECT_EQ(message_of<OverrideSyntaxError>([] { (void)parse_override("/Floor/FloorTri1=3"); }),
              "--set '/Floor/FloorTri1=3': expected PATH.attribute=value (no '.attribute' before '=')");
    EXPECT_EQ(message_of<OverrideSyntaxError>([] { (void)parse_override("/a.b/c=3"); }),
              "--set '/a.b/c=3': expected PATH.attribute=value (no '.attribute' before '=')");
    EXPECT_EQ(message_of<OverrideSyntaxError>([] { (void)parse_override("/Floor.=3"); }),
              "--set '/Floor.=3': '' is not an attribute name");
    EXPECT_EQ(message_of<OverrideSyntaxError>([] { (void)parse_override("/Floor.a b=3"); }),
              "--set '/Floor.a b=3': 'a b' is not an attribute name");
}

TEST(Overrides, ReplacesAttributesInPlaceKeepingTheirLine) {
    SceneFile s = scene();
    apply_overrides(s, {parse_override("/Floor/FloorTri1.contactStiffness=200"), parse_override("/root.dt=0.005"),
                        parse_override("/Floor/Inner/mass.totalMass=3"), parse_override("/.gravity=0 0 -1"),
                        parse_override("/Floor/Inner/mass.totalMass=4")});
    const SceneComponent* tri = s.root->child("Floor")->component("FloorTri1");
    ASSERT_NE(tri, nullptr);
    ASSERT_NE(tri->find("contactStiffness"), nullptr);
    EXPECT_EQ(tri->find("contactStiffness")->value, "200");
    EXPECT_EQ(tri->find("contactStiffness")->line, 5);
    EXPECT_EQ(s.root->find("dt")->value, "0.005");
    EXPECT_EQ(s.root->find("gravity")->value, "0 0 -1");
    // A later override wins.
    EXPECT_EQ(s.root->child("Floor")->child("Inner")->component("mass")->find("totalMass")->value, "4");
    EXPECT_EQ(s.root->child("Floor")->child("Inner")->component("mass")->attributes.size(), 1U);
}

TEST(Overrides, AddsAnAbsentAttributeOnlyWhenTheFilterAcceptsIt) {
    SceneFile s = scene();
    const Override o = parse_override("/Floor/FloorTri1.contactFriction=0.3");
    EXPECT_EQ(message_of<SceneError>([&] { apply_overrides(s, {o}); }),
              "s.scn:5: TriangleCollisionModel 'FloorTri1': --set '/Floor/FloorTri1.contactFriction=0.3': "
              "no attribute 'contactFriction' in the file");
    const AttributeFilter only_friction = [](const SceneElement&, std::string_view a) {
        return a == "contactFriction";
    };
    apply_overrides(s, {o}, only_friction);
    const SceneComponent* tri = s.root->child("Floor")->component("FloorTri1");
    ASSERT_NE(tri->find("contactFriction"), nullptr);
    EXPECT_EQ(tri->find("contactFriction")->value, "0.3");
    EXPECT_EQ(tri->find("contactFriction")->line, 5);  // the element's line
    EXPECT_EQ(message_of<SceneError>([&] {
                  apply_overrides(s, {parse_override("/Floor/FloorTri1.contactFricton=0.3")}, only_friction,
                                  [](const SceneElement&) { return std::string("it reads: contactFriction"); });
              }),
              "s.scn:5: TriangleCollisionModel 'FloorTri1': --set '/Floor/FloorTri1.contactFricton=0.3': no attribute "
              "'contactFricton' in the file, and penalty does not read it for TriangleCollisionModel "
              "(it reads: contactFriction)");
}

TEST(Overrides, UnknownPathsNameTheMissingSegment) {
    SceneFile s = scene();
    EXPECT_EQ(
        message_of<SceneError>([&] { apply_overrides(s, {parse_override("/Flor/FloorTri1.contactStiffness=1")}); }),
        "s.scn: --set '/Flor/FloorTri1.contactStiffness=1': no node 'Flor' in '/' (it has: Floor/, solver)");
    EXPECT_EQ(message_of<SceneError>([&] { apply_overrides(s, {parse_override("/Floor/Tri.contactStiffness=1")}); }),
              "s.scn: --set '/Floor/Tri.contactStiffness=1': no node or component 'Tri' in '/Floor' "
              "(it has: Inner/, dofs, FloorTri1)");
    EXPECT_EQ(message_of<SceneError>([&] { apply_overrides(s, {parse_override("/Floor.name=x")}); }),
              "s.scn:3: Node 'Floor': --set '/Floor.name=x': the name cannot be overridden (paths use it)");
}

TEST(Overrides, TemplateIsTheComponentsTemplate) {
    SceneFile s = scene();
    apply_overrides(s, {parse_override("/Floor/dofs.template=Rigid3d")});
    EXPECT_EQ(s.root->child("Floor")->component("dofs")->template_name, "Rigid3d");
    EXPECT_EQ(message_of<SceneError>([&] { apply_overrides(s, {parse_override("/Floor.template=Vec3d")}); }),
              "s.scn:3: Node 'Floor': --set '/Floor.template=Vec3d': a node has no template");
}

}  // namespace
}  // namespace penalty::io
