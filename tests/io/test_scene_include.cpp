// `<include href=... />` in scene files, with SOFA's semantics (sofa::simulation::xml::includeNode):
// the included root as a child (or spliced in when named Group), `name` renaming it, the other
// attributes replacing the values of included components that have them, nested includes, the
// search path, and the errors (missing file, loop, depth, errors inside included files).
// Data: tests/io/data/include/ (written for these tests).

#include "io_test_util.hpp"

#include "penalty/io/scene_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace penalty::io {
namespace {

using test::data_dir;
using test::message_of;
using test::write_temp;
using ::testing::HasSubstr;

std::filesystem::path include_dir() { return data_dir() / "include"; }

std::string value_of(const SceneComponent& c, std::string_view attribute) {
    const SceneAttribute* a = c.find(attribute);
    return a == nullptr ? std::string("<absent>") : a->value;
}

const SceneComponent& component_named(const SceneNode& node, std::string_view name) {
    const SceneComponent* c = node.component(name);
    if (c == nullptr) throw std::runtime_error("no component " + std::string(name) + " in " + node.path());
    return *c;
}

TEST(SceneInclude, IncludedNodeBecomesAChildRenamedWithReplacedAttributes) {
    const std::filesystem::path scene_path = include_dir() / "child.scn";
    const SceneFile s = parse_scene_file(scene_path);
    ASSERT_EQ(s.root->children.size(), 2u);
    ASSERT_EQ(s.root->components.size(), 2u);
    EXPECT_EQ(s.root->components[1]->name, "after");
    EXPECT_EQ(s.root->components[1]->index, 1u);

    // first include: name="Moved" dx="2.5" rx="90" scale="3" contactStiffness="500" gravity="0 0 0"
    const SceneNode& moved = *s.root->children[0];
    EXPECT_EQ(moved.name, "Moved");
    EXPECT_EQ(moved.parent, s.root.get());
    EXPECT_EQ(moved.path(), "/Moved");
    // nodes keep their attributes (NodeElement::initNode ignores the replacements)
    ASSERT_NE(moved.find("gravity"), nullptr);
    EXPECT_EQ(moved.find("gravity")->value, "0 -1 0");
    const SceneComponent& dofs = component_named(moved, "dofs");
    EXPECT_EQ(value_of(dofs, "dx"), "2.5");
    EXPECT_EQ(value_of(dofs, "rx"), "90");
    EXPECT_EQ(value_of(dofs, "scale"), "3");
    EXPECT_EQ(value_of(dofs, "dy"), "0");  // not on the include: unchanged
    EXPECT_EQ(dofs.template_name, "Rigid3d");
    EXPECT_EQ(dofs.node, &moved);
    EXPECT_EQ(dofs.line, 3);
    EXPECT_EQ(dofs.file, (include_dir() / "Objects/Body.xml").string());
    EXPECT_EQ(dofs.included_from, " (included from " + scene_path.string() + ":4)");
    // an attribute is replaced only where it is written, never added
    const SceneComponent& mass = *moved.components[2];
    EXPECT_EQ(mass.type, "UniformMass");
    EXPECT_EQ(mass.find("dx"), nullptr);
    EXPECT_EQ(mass.find("contactStiffness"), nullptr);
    EXPECT_EQ(value_of(mass, "totalMass"), "1");
    // ... at any depth of the included tree
    const SceneNode& surf = *moved.child("Surf");
    EXPECT_EQ(surf.path(), "/Moved/Surf");
    EXPECT_EQ(value_of(component_named(surf, "Surf"), "scale"), "3");
    EXPECT_EQ(value_of(component_named(surf, "Surf"), "dx"), "2.5");
    EXPECT_EQ(value_of(*surf.components[2], "contactStiffness"), "500");

    // second include: Surf__scale="0.5" (only elements named Surf) and template="Vec3d"
    const SceneNode& body = *s.root->children[1];
    EXPECT_EQ(body.name, "Body");
    EXPECT_EQ(value_of(component_named(body, "dofs"), "scale"), "1");
    EXPECT_EQ(component_named(body, "dofs").template_name, "Vec3d");
    EXPECT_EQ(body.components[0]->template_name, "");  // the solver has no template: none added
    EXPECT_EQ(value_of(component_named(*body.child("Surf"), "Surf"), "scale"), "0.5");
    EXPECT_EQ(value_of(*body.child("Surf")->components[2], "contactStiffness"), "10");
}

TEST(SceneInclude, RootNamedGroupIsSplicedIntoTheIncludingNode) {
    const SceneFile s = parse_scene_file(include_dir() / "group.scn");
    const SceneNode& cloth = *s.root->child("Cloth");
    ASSERT_EQ(cloth.components.size(), 4u);
    const char* names[] = {"loader", "Container", "Modifier", "dofs"};
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(cloth.components[i]->name, names[i]);
        EXPECT_EQ(cloth.components[i]->index, i);
        EXPECT_EQ(cloth.components[i]->node, &cloth);
    }
    const SceneComponent& container = *cloth.components[1];
    EXPECT_EQ(value_of(container, "src"), "@loader");
    EXPECT_EQ(value_of(container, "tags"), " ");
    EXPECT_EQ(value_of(container, "fileTopology"), "");
    EXPECT_EQ(cloth.components[2]->find("src"), nullptr);
    // the link now resolves in the including node, as in SOFA
    const LinkTarget target = resolve_link(container, "src");
    EXPECT_EQ(target.component, cloth.components[0].get());
    // child nodes of the group join the including node too
    ASSERT_EQ(cloth.children.size(), 1u);
    EXPECT_EQ(cloth.children[0]->name, "Edges");
    EXPECT_EQ(cloth.children[0]->parent, &cloth);
    EXPECT_EQ(cloth.children[0]->path(), "/Cloth/Edges");
    EXPECT_EQ(s.root->child("Group"), nullptr);
}

TEST(SceneInclude, NestedIncludesApplyTheOuterReplacementLast) {
    const SceneFile s = parse_scene_file(include_dir() / "nested.scn");
    const SceneNode& outer = *s.root->child("Outer");
    ASSERT_EQ(outer.children.size(), 1u);
    const SceneNode& inner = *outer.children[0];
    EXPECT_EQ(inner.name, "Renamed");
    const SceneComponent& mass = *inner.components[1];
    EXPECT_EQ(value_of(mass, "totalMass"), "7");   // outer include
    EXPECT_EQ(value_of(mass, "vertexMass"), "2");  // inner include
    EXPECT_EQ(mass.file, (include_dir() / "Objects" / "Inner.xml").string());
    EXPECT_THAT(mass.included_from, HasSubstr("Outer.xml:2, included from "));
    EXPECT_THAT(mass.included_from, HasSubstr("nested.scn:3)"));
}

TEST(SceneInclude, IncludedComponentRootIsAddedToTheNode) {
    const SceneFile s = parse_scene_file(include_dir() / "component.scn");
    ASSERT_EQ(s.root->components.size(), 2u);
    const SceneComponent& mass = *s.root->components[1];
    EXPECT_EQ(mass.type, "UniformMass");
    EXPECT_EQ(mass.name, "mass");
    EXPECT_EQ(mass.index, 1u);
    EXPECT_EQ(value_of(mass, "totalMass"), "4");
}

TEST(SceneInclude, FilesAreLookedForInTheDataDirectoriesAfterTheIncludingFolder) {
    const std::filesystem::path scene = write_temp(
        "include_from_data_dir.scn", "<Node name=\"root\">\n  <include href=\"Objects/Mass.xml\"/>\n</Node>\n");
    EXPECT_THAT(
        message_of<SceneError>([&] { (void)parse_scene_file(scene); }),
        HasSubstr("include_from_data_dir.scn:2: <include>: cannot find data file 'Objects/Mass.xml'; looked in: "));
    const SceneFile s = parse_scene_file(scene, {include_dir()});
    ASSERT_EQ(s.root->components.size(), 1u);
    EXPECT_EQ(s.root->components[0]->name, "massFromFile");
    EXPECT_EQ(s.root->components[0]->file, (include_dir() / "Objects/Mass.xml").string());
    // parse_scene_string takes the same data directories
    const SceneFile t =
        parse_scene_string("<Node><include href=\"Objects/Mass.xml\"/></Node>", "text.scn", {include_dir()});
    EXPECT_EQ(t.root->components.at(0)->type, "UniformMass");
}

TEST(SceneInclude, ErrorsNameFileAndLine) {
    const std::string missing = message_of<SceneError>([] { (void)parse_scene_file(include_dir() / "missing.scn"); });
    EXPECT_THAT(missing, HasSubstr("missing.scn:3: <include>: cannot find data file 'Objects/NoSuchFile.xml'"));

    const std::string loop = message_of<SceneError>([] { (void)parse_scene_file(include_dir() / "loop.scn"); });
    EXPECT_THAT(loop, HasSubstr("LoopB.xml:3: <include>: include loop: "));
    EXPECT_THAT(loop, HasSubstr("LoopA.xml includes "));
    EXPECT_THAT(loop, HasSubstr("LoopB.xml includes "));
    EXPECT_THAT(loop, HasSubstr("(included from "));

    const std::filesystem::path self =
        write_temp("include_self.scn", "<Node>\n<include href=\"include_self.scn\"/>\n</Node>\n");
    EXPECT_THAT(message_of<SceneError>([&] { (void)parse_scene_file(self); }),
                HasSubstr("include_self.scn:2: <include>: include loop: "));

    const std::filesystem::path no_href = write_temp("include_no_href.scn", "<Node>\n\n<include dx=\"1\"/>\n</Node>\n");
    EXPECT_THAT(message_of<SceneError>([&] { (void)parse_scene_file(no_href); }),
                HasSubstr("include_no_href.scn:3: <include>: no 'href' attribute"));

    const std::string inside = message_of<SceneError>([] { (void)parse_scene_file(include_dir() / "bad_inside.scn"); });
    EXPECT_THAT(inside, HasSubstr("Broken.xml:2: <Object> without a 'type' attribute (included from "));
    EXPECT_THAT(inside, HasSubstr("bad_inside.scn:2)"));
}

TEST(SceneInclude, AttributeErrorsInIncludedComponentsSayWhereTheyWereIncluded) {
    const SceneFile s = parse_scene_file(include_dir() / "nested.scn");
    const SceneComponent& mass = *s.root->child("Outer")->children[0]->components[1];
    const std::string message = message_of<SceneError>([&] { throw_attribute_error(mass, "totalMass", "bad"); });
    EXPECT_THAT(message, HasSubstr("Inner.xml:3: UniformMass: attribute 'totalMass': bad (included from "));
}

TEST(SceneInclude, NestingIsLimited) {
    // chain_0.xml includes chain_1.xml ... : 17 levels of includes, one more than the limit
    for (int i = 0; i <= 17; ++i) {
        const std::string body =
            i < 17 ? "<include href=\"chain_" + std::to_string(i + 1) + ".xml\"/>" : "<MechanicalObject/>";
        (void)write_temp("chain_" + std::to_string(i) + ".xml",
                         "<Node name=\"n" + std::to_string(i) + "\">" + body + "</Node>\n");
    }
    const std::filesystem::path deep = write_temp("chain.scn", "<Node><include href=\"chain_0.xml\"/></Node>\n");
    EXPECT_THAT(message_of<SceneError>([&] { (void)parse_scene_file(deep); }),
                HasSubstr("chain_15.xml:1: <include>: includes nested more than 16 levels deep"));
    // 16 levels are accepted
    const std::filesystem::path ok = write_temp("chain_ok.scn", "<Node><include href=\"chain_2.xml\"/></Node>\n");
    const SceneFile s = parse_scene_file(ok);
    const SceneNode* n = s.root.get();
    int depth = 0;
    while (!n->children.empty()) {
        n = n->children[0].get();
        ++depth;
    }
    EXPECT_EQ(depth, 16);
    EXPECT_EQ(n->components.at(0)->type, "MechanicalObject");
}

}  // namespace
}  // namespace penalty::io
