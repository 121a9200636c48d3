// The .scn parser, typed attributes, SOFA links, the component registry, data path resolution
// and the loading of component meshes, on a small scene written for these tests.

#include "io_test_util.hpp"

#include "penalty/io/data_path.hpp"
#include "penalty/io/scene_file.hpp"
#include "penalty/io/scene_mesh.hpp"
#include "penalty/scene/components.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>

namespace penalty::io {
namespace {

using test::data_dir;
using test::message_of;
using test::node_at;
using test::tiny_path;
using ::testing::ElementsAre;

// ---------------------------------------------------------------------------------------------
// tree

TEST(SceneParser, BuildsTheTreeWithLinesAndTemplates) {
    const SceneFile s = parse_scene_file(tiny_path());
    ASSERT_TRUE(s.root);
    EXPECT_EQ(s.root->name, "root");
    EXPECT_EQ(s.root->line, 3);
    EXPECT_EQ(s.root->path(), "/");
    EXPECT_EQ(s.directory(), data_dir() / "scenes");
    ASSERT_EQ(s.root->children.size(), 4u);
    EXPECT_EQ(s.root->children[0]->name, "Body");
    EXPECT_EQ(s.root->children[3]->name, "Cube");
    ASSERT_EQ(s.root->components.size(), 9u);
    EXPECT_EQ(s.root->components[0]->type, "RequiredPlugin");
    EXPECT_EQ(s.root->components[8]->type, "MeshOBJLoader");
    EXPECT_EQ(s.root->components[8]->name, "shared_loader");
    EXPECT_EQ(s.root->components[8]->line, 12);

    const SceneNode& collision = node_at(s, {"Body", "Collision"});
    EXPECT_EQ(collision.path(), "/Body/Collision");
    EXPECT_EQ(collision.line, 18);
    const SceneComponent* rigid = node_at(s, {"Body"}).component("rigid");
    ASSERT_NE(rigid, nullptr);
    EXPECT_EQ(rigid->template_name, "Rigid3d");
    EXPECT_EQ(rigid->line, 16);
    EXPECT_EQ(rigid->file, tiny_path().string());
    EXPECT_EQ(rigid->index, 2u);
    EXPECT_FALSE(rigid->has("template"));  // name and template have their own fields
    ASSERT_EQ(rigid->attributes.size(), 1u);
    EXPECT_EQ(rigid->attributes[0].name, "position");
    EXPECT_EQ(rigid->attributes[0].line, 16);

    int count = 0;
    for_each_component(*s.root, [&](const SceneComponent&) { ++count; });
    EXPECT_EQ(count, 30);
}

TEST(SceneParser, ObjectSyntaxAndUnnamedNodes) {
    const SceneFile s = parse_scene_string(
        "<Node name='r'>\n  <Node>\n    <Object type='MechanicalObject' name='m' position='1 2 3'/>\n  "
        "</Node>\n</Node>\n",
        "inline.scn");
    ASSERT_EQ(s.root->children.size(), 1u);
    const SceneNode& n = *s.root->children[0];
    EXPECT_EQ(n.name, "");
    ASSERT_EQ(n.components.size(), 1u);
    EXPECT_EQ(n.components[0]->type, "MechanicalObject");
    EXPECT_FALSE(n.components[0]->has("type"));
    EXPECT_EQ(get_vec3_list(*n.components[0], "position"), std::vector<Vec3>{Vec3(1, 2, 3)});
}

TEST(SceneParser, MissingFile) {
    const auto p = data_dir() / "scenes" / "no_such.scn";
    EXPECT_EQ(message_of<SceneError>([&] { (void)parse_scene_file(p); }),
              p.string() + ": cannot read: the path does not exist");
}

TEST(SceneParser, UnclosedTagNamesTheLine) {
    const std::string xml = "<Node name='root'>\n  <Node name='A'>\n    <MechanicalObject/>\n</Node>\n";
    EXPECT_EQ(message_of<SceneError>([&] { (void)parse_scene_string(xml, "unclosed.scn"); }),
              "unclosed.scn:1: XML error: unclosed element or malformed document");
}

TEST(SceneParser, MismatchedClosingTag) {
    const std::string xml = "<Node name='root'>\n  <Node name='A'>\n  </Nod>\n</Node>\n";
    EXPECT_EQ(message_of<SceneError>([&] { (void)parse_scene_string(xml, "mismatch.scn"); }),
              "mismatch.scn:2: XML error: element closed by a mismatched tag");
}

TEST(SceneParser, MalformedXmlAttribute) {
    const std::string xml = "<Node name='root'>\n\n  <UniformMass totalMass=1/>\n</Node>\n";
    EXPECT_EQ(message_of<SceneError>([&] { (void)parse_scene_string(xml, "attr.scn"); }),
              "attr.scn:3: XML error: malformed attribute");
}

TEST(SceneParser, EmptyAndWrongRoot) {
    EXPECT_EQ(message_of<SceneError>([&] { (void)parse_scene_string("", "empty.scn"); }),
              "empty.scn: XML error: empty document");
    EXPECT_EQ(
        message_of<SceneError>([&] { (void)parse_scene_string("<?xml version='1.0'?>\n<Scene/>\n", "root.scn"); }),
        "root.scn:2: root element must be <Node>, found <Scene>");
    EXPECT_EQ(
        message_of<SceneError>([&] { (void)parse_scene_string("<Node>\n<Object name='x'/>\n</Node>", "obj.scn"); }),
        "obj.scn:2: <Object> without a 'type' attribute");
}

// ---------------------------------------------------------------------------------------------
// typed attributes

TEST(SceneAttributes, ReadsSofaValues) {
    const SceneFile s = parse_scene_file(tiny_path());
    EXPECT_EQ(get_double(*s.root, "dt"), 0.02);
    EXPECT_EQ(get_vec3(*s.root, "gravity"), Vec3(0, -9.81, 0));
    EXPECT_EQ(get_double(*s.root, "time"), std::nullopt);
    EXPECT_EQ(get_double_or(*s.root, "time", 7.0), 7.0);

    const SceneNode& body = node_at(s, {"Body"});
    EXPECT_EQ(get_int(*body.components[1], "iterations"), 25);
    EXPECT_EQ(get_double(*body.components[1], "tolerance"), 1e-9);
    const auto frames = get_rigid_list(*body.component("rigid"), "position");
    ASSERT_EQ(frames.size(), 1u);
    EXPECT_EQ(frames[0].center, Vec3(0, 1, 0));
    EXPECT_EQ(frames[0].orientation.w(), 1.0);

    const SceneNode& floor = node_at(s, {"Floor"});
    EXPECT_EQ(get_bool(*floor.components[2], "simulated"), false);
    EXPECT_EQ(get_bool(*floor.components[2], "moving"), false);
    EXPECT_EQ(get_bool_or(*floor.components[2], "selfCollision", true), true);

    const SceneComponent* hexa = node_at(s, {"Cube"}).component("hexa");
    EXPECT_THAT(get_elements<8>(*hexa, "hexas"), ElementsAre(Hexahedron{0, 4, 6, 2, 1, 5, 7, 3}));
}

// one attribute value per malformed case, with the message it must give
struct MalformedCase {
    const char* xml_attribute;
    std::function<void(const SceneComponent&)> read;
    const char* message;
};

TEST(SceneAttributes, IndexRangesAsSofa) {
    // SOFA's vector<unsigned int>::read: "A-B" every index from A to B, down when B < A; "A-B-S"
    // steps by S, whose sign wins (A and B swap); the last index of a downward range always ends it.
    const SceneFile s = parse_scene_string(
        "<Node name='root'><Thing a='4 0-3 9' b='5-2' c='0-10-4' d='10-0-3' e='0-9--4'/></Node>", "r.scn");
    const SceneComponent& c = *s.root->components[0];
    EXPECT_EQ(get_indices(c, "a"), (std::vector<PointId>{4, 0, 1, 2, 3, 9}));
    EXPECT_EQ(get_indices(c, "b"), (std::vector<PointId>{5, 4, 3, 2}));
    EXPECT_EQ(get_indices(c, "c"), (std::vector<PointId>{0, 4, 8}));
    EXPECT_EQ(get_indices(c, "d"), (std::vector<PointId>{0, 3, 6, 9}));
    EXPECT_EQ(get_indices(c, "e"), (std::vector<PointId>{9, 5, 1, 0}));
}

TEST(SceneAttributes, MalformedValuesNameFileLineComponentAndAttribute) {
    const std::vector<MalformedCase> cases{
        {"totalMass='abc'", [](const SceneComponent& c) { (void)get_double(c, "totalMass"); },
         "attribute 'totalMass': expected a number, found 'abc'"},
        {"totalMass='1 2'", [](const SceneComponent& c) { (void)get_double(c, "totalMass"); },
         "attribute 'totalMass': expected one number, found '1 2'"},
        {"iterations='2.5'", [](const SceneComponent& c) { (void)get_int(c, "iterations"); },
         "attribute 'iterations': expected an integer, found '2.5'"},
        {"moving='yes'", [](const SceneComponent& c) { (void)get_bool(c, "moving"); },
         "attribute 'moving': expected a boolean (0, 1, true or false), found 'yes'"},
        {"gravity='0 -9.81'", [](const SceneComponent& c) { (void)get_vec3(c, "gravity"); },
         "attribute 'gravity': expected 3 numbers, found 2"},
        {"position='0 0 1 1 0'", [](const SceneComponent& c) { (void)get_vec3_list(c, "position"); },
         "attribute 'position': expected a multiple of 3 numbers, found 5"},
        {"position='0 0 1 0 0 0'", [](const SceneComponent& c) { (void)get_rigid_list(c, "position"); },
         "attribute 'position': expected a multiple of 7 numbers (x y z qx qy qz qw), found 6"},
        {"position='0 0 0 0 0 0 0'", [](const SceneComponent& c) { (void)get_rigid_list(c, "position"); },
         "attribute 'position': rigid frame 0 has a zero quaternion"},
        {"hexas='0 4 6 2 1 5 7'", [](const SceneComponent& c) { (void)get_elements<8>(c, "hexas"); },
         "attribute 'hexas': expected a multiple of 8 indices, found 7"},
        {"hexas='0 -4 6'", [](const SceneComponent& c) { (void)get_indices(c, "hexas"); },
         "attribute 'hexas': expected a non-negative integer index, found '-4'"},
        {"indices='3-'", [](const SceneComponent& c) { (void)get_indices(c, "indices"); },
         "attribute 'indices': expected a non-negative integer index, found '3-'"},
        {"indices='0-3-x'", [](const SceneComponent& c) { (void)get_indices(c, "indices"); },
         "attribute 'indices': expected a range A-B or A-B-STEP, found '0-3-x'"},
        {"indices='0-2000000000'", [](const SceneComponent& c) { (void)get_indices(c, "indices"); },
         "attribute 'indices': the range '0-2000000000' gives more than 10^8 indices"},
        {"totalMass='@../mass'", [](const SceneComponent& c) { (void)get_double(c, "totalMass"); },
         "attribute 'totalMass': expected a value, found the link '@../mass' (resolve it first)"},
    };
    for (const MalformedCase& k : cases) {
        const std::string xml = std::string("<Node name='root'>\n  <Node name='A'>\n\n    <Thing name='t'\n        ") +
                                k.xml_attribute + "/>\n  </Node>\n</Node>\n";
        const SceneFile s = parse_scene_string(xml, "bad.scn");
        const SceneComponent& c = *s.root->children[0]->components[0];
        EXPECT_EQ(message_of<SceneError>([&] { k.read(c); }), std::string("bad.scn:5: Thing 't': ") + k.message);
    }
}

// ---------------------------------------------------------------------------------------------
// links

TEST(SceneLinks, ResolveAsSofa) {
    const SceneFile s = parse_scene_file(tiny_path());
    const SceneNode& body = node_at(s, {"Body"});
    const SceneNode& collision = node_at(s, {"Body", "Collision"});
    const SceneComponent& mapping = *collision.components[2];

    const LinkTarget input = resolve_link(mapping, "input");  // @../rigid
    EXPECT_EQ(input.component, body.component("rigid"));
    EXPECT_EQ(input.node, nullptr);
    EXPECT_EQ(input.data, "");
    EXPECT_EQ(resolve_link(mapping, "output").component, collision.component("points"));  // @points

    const SceneNode& visu = node_at(s, {"Body", "Visu"});
    const LinkTarget parent = resolve_link(*visu.components[2], "input");  // @..
    EXPECT_EQ(parent.node, &body);
    EXPECT_EQ(parent.component, nullptr);

    const SceneNode& balls = node_at(s, {"Balls"});
    const LinkTarget previous = resolve_link(*balls.components[1], "position");  // @[-1].position
    EXPECT_EQ(previous.component, balls.components[0].get());
    EXPECT_EQ(previous.data, "position");
    const LinkTarget two_back = resolve_link(*balls.components[2], "listRadius");  // @[-2].listRadius
    EXPECT_EQ(two_back.component, balls.components[0].get());
    EXPECT_EQ(two_back.data, "listRadius");

    const SceneComponent& floor_topology = *node_at(s, {"Floor"}).components[0];
    const SceneComponent* shared = s.root->component("shared_loader");
    EXPECT_EQ(resolve_link(floor_topology, "src").component, shared);  // @../shared_loader

    // an unbased name is searched in the node, then its ancestors; an absolute path from the root
    EXPECT_EQ(resolve_link_text(mapping, "@shared_loader.position", "x").component, shared);
    EXPECT_EQ(resolve_link_text(mapping, "@shared_loader.position", "x").data, "position");
    EXPECT_EQ(resolve_link_text(floor_topology, "@/Body/Collision/spheres", "x").component,
              collision.component("spheres"));
    EXPECT_EQ(resolve_link_text(floor_topology, "@Body/Collision", "x").node, &collision);
}

TEST(SceneLinks, SeveralLinksInOneAttribute) {
    const SceneFile s = parse_scene_string(
        "<Node name='root'>\n<Node name='A'><PointCollisionModel name='p'/></Node>\n"
        "<Node name='B'><LineCollisionModel name='l'/></Node>\n"
        "<SubCollisionPipeline name='sub' collisionModels='@/A/p\n   @B/l'/>\n</Node>\n",
        "multi.scn");
    const auto targets = resolve_links(*s.root->components[0], "collisionModels");
    ASSERT_EQ(targets.size(), 2u);
    EXPECT_EQ(targets[0].component, s.root->children[0]->components[0].get());
    EXPECT_EQ(targets[1].component, s.root->children[1]->components[0].get());
}

TEST(SceneLinks, BrokenLinksNameTheAttribute) {
    const SceneFile s = parse_scene_file(tiny_path());
    const std::string file = tiny_path().string();
    const SceneComponent& mapping = *node_at(s, {"Body", "Collision"}).components[2];  // line 21
    EXPECT_EQ(message_of<SceneError>([&] { (void)resolve_link_text(mapping, "@../rigidx", "input"); }),
              file +
                  ":21: IdentityMapping: attribute 'input': broken link '@../rigidx': no node or component named "
                  "'rigidx' in node '/Body'");
    EXPECT_EQ(message_of<SceneError>([&] { (void)resolve_link_text(mapping, "@nowhere", "input"); }),
              file +
                  ":21: IdentityMapping: attribute 'input': broken link '@nowhere': no node or component named "
                  "'nowhere' in node '/Body/Collision' or its ancestors");
    EXPECT_EQ(message_of<SceneError>([&] { (void)resolve_link_text(mapping, "@../../..", "input"); }),
              file + ":21: IdentityMapping: attribute 'input': broken link '@../../..': '..' goes above the root node");
    EXPECT_EQ(message_of<SceneError>([&] { (void)resolve_link_text(mapping, "@[-5].position", "input"); }),
              file +
                  ":21: IdentityMapping: attribute 'input': broken link '@[-5].position': only 2 component(s) "
                  "before it in node '/Body/Collision'");
    EXPECT_EQ(message_of<SceneError>([&] { (void)resolve_link_text(mapping, "@points/x", "input"); }),
              file +
                  ":21: IdentityMapping: attribute 'input': broken link '@points/x': 'MechanicalObject 'points'' "
                  "is a component, it has no child 'x'");
    EXPECT_EQ(message_of<SceneError>([&] { (void)resolve_link(mapping, "template"); }),
              file + ":21: IdentityMapping: attribute 'template': missing (a link was expected)");
}

// ---------------------------------------------------------------------------------------------
// registry and validation

TEST(SceneValidation, ClassifiesComponentsAndSummarizesIgnoredOnes) {
    const SceneFile s = parse_scene_file(tiny_path());
    const scene::SceneCheck check = scene::validate(s);
    EXPECT_EQ(check.physics.size(), 22u);
    ASSERT_EQ(check.loaders.size(), 3u);
    EXPECT_EQ(check.loaders[0]->name, "shared_loader");
    EXPECT_EQ(check.loaders[1]->type, "SphereLoader");
    EXPECT_EQ(check.loaders[2]->type, "MeshGmshLoader");
    EXPECT_EQ(check.ignored.size(), 5u);
    EXPECT_EQ(check.summary,
              "ignored 5 components that do not change the numbers: BarycentricMapping (visual output) x1, "
              "MeshOBJLoader (visual only) x1, "
              "OglModel x1, RequiredPlugin x1, VisualStyle x1");
    EXPECT_EQ(scene::component_category("TriangleCollisionModel"), scene::ComponentCategory::physics);
    EXPECT_EQ(scene::component_category("OglModel"), scene::ComponentCategory::ignored);
    EXPECT_EQ(scene::component_category("MeshGmshLoader"), scene::ComponentCategory::loader);
    EXPECT_EQ(scene::component_category("FancyForceField"), std::nullopt);
}

TEST(SceneValidation, UnknownComponentIsAnError) {
    const SceneFile s = parse_scene_string(
        "<Node name='root'>\n  <VisualStyle/>\n  <Node name='A'>\n    <MechanicalObject/>\n"
        "    <FancyForceField stiffness='3'/>\n  </Node>\n</Node>\n",
        "unknown.scn");
    EXPECT_EQ(message_of<SceneError>([&] { (void)scene::validate(s); }),
              "unknown.scn:5: unknown component 'FancyForceField' (not supported by penalty)");
}

TEST(SceneValidation, BrokenLinkOfAPhysicsComponentIsAnError) {
    const SceneFile s = parse_scene_string(
        "<Node name='root'>\n  <Node name='A'>\n    <MechanicalObject name='m'/>\n"
        "    <IdentityMapping input='@../m' output='@m'/>\n  </Node>\n</Node>\n",
        "broken.scn");
    EXPECT_EQ(message_of<SceneError>([&] { (void)scene::validate(s); }),
              "broken.scn:4: IdentityMapping: attribute 'input': broken link '@../m': no node or component named 'm' "
              "in node '/'");
}

TEST(SceneValidation, NoIgnoredComponent) {
    const SceneFile s = parse_scene_string("<Node name='root'><DefaultAnimationLoop/></Node>", "plain.scn");
    EXPECT_EQ(scene::validate(s).summary, "ignored 0 components that do not change the numbers");
}

// ---------------------------------------------------------------------------------------------
// data path and component meshes

}  // namespace
}  // namespace penalty::io
