// SOFA's read of a one-number Data (number_prefix_quirk.cpp): Data<T>::read extracts the value
// with `istringstream >> value` and ignores the text after it, so `tolerance="1e-12abc"` reads
// 1e-12. The prefix `>>` reads, form by form; the notes naming file, line, component and
// attribute; what is left alone (numbers, links, other kinds, the attributes SOFA reads in
// parse()); the quirk fix; and a scene of such numbers stepping as SOFA HEAD's (2a278d8,
// `sofa-head SCENE 20 OUT`, %.17g), bit for bit, as the same scene written plainly.
#include "penalty/io/scene_file.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using namespace penalty;

/// A CGLinearSolver whose tolerance is `value` (line 3 of "prefix.scn").
io::SceneFile tolerance_scene(const std::string& value) {
    return io::parse_scene_string(R"(<Node name="root">
  <Node name="Body">
    <CGLinearSolver name="cg" iterations="25" tolerance=")" +
                                      value + R"("/>
  </Node>
</Node>)",
                                  "prefix.scn");
}

/// The tolerance `value` reads as (the attribute after read_number_prefixes) and the notes.
std::pair<std::string, std::vector<std::string>> prefix_of(const std::string& value, bool fix = false) {
    io::SceneFile file = tolerance_scene(value);
    SofaQuirkFixes fixes;
    fixes.fix_number_trailing_text = fix;
    std::vector<std::string> notes = scene::read_number_prefixes(file, fixes);
    const auto& solver = *file.root->children[0]->components[0];
    for (const io::SceneAttribute& a : solver.attributes)
        if (a.name == "tolerance") return {a.value, notes};
    return {"(none)", notes};
}

TEST(NumberPrefixQuirk, ReadsThePrefixThatAnIstreamReads) {
    // [sign] digits [. digits] [(e|E) [sign] digits], the longest such prefix
    const std::pair<const char*, const char*> cases[] = {
        {"10-3", "10"},       {"0.2.5", "0.2"}, {"2.5e1kg", "2.5e1"}, {"+.5e+2x", "+.5e+2"}, {"1.N", "1."},
        {"-7E-3 m", "-7E-3"}, {"3,5", "3"},     {"1e5e5", "1e5"},     {".25.", ".25"},       {"42abc12", "42"},
    };
    for (const auto& [text, read] : cases) {
        const auto [value, notes] = prefix_of(text);
        EXPECT_EQ(value, read) << text;
        EXPECT_EQ(notes.size(), 1u) << text;
    }
}

TEST(NumberPrefixQuirk, WhatIsNoNumberOrIsOneIsLeftAlone) {
    // an exponent mark without digits fails the whole read (libstdc++ hands "1e" to strtod): no
    // prefix, the builder's error; no digit at all likewise; a number (spaces around it) is one
    for (const char* text : {"1e", "1e+x", "abc", "-", ".", "e5", " 3.5 ", "1e-3"}) {
        const auto [value, notes] = prefix_of(text);
        EXPECT_EQ(value, text) << text;
        EXPECT_TRUE(notes.empty()) << text;
    }
}

TEST(NumberPrefixQuirk, TheNoteNamesFileLineComponentAndAttribute) {
    const auto [value, notes] = prefix_of("1e-12abc");
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_EQ(notes[0],
              "prefix.scn:3: CGLinearSolver 'cg': attribute 'tolerance' = '1e-12abc' read as 1e-12, as SOFA's "
              "Data<T>::read does (it ignores the text after a number; --fix-sofa-quirk number_trailing_text makes "
              "it an error)");
    // with the fix the value stays, for the builder to refuse
    const auto [fixed, none] = prefix_of("1e-12abc", true);
    EXPECT_EQ(fixed, "1e-12abc");
    EXPECT_TRUE(none.empty());
}

TEST(NumberPrefixQuirk, LinksOtherKindsAndTheAttributesSofaParsesItselfAreNotRead) {
    // a link; a string attribute (name); MechanicalObject's dx, read by its parse() with
    // getAttributeAsFloat (the builder's own rule); an unknown component
    io::SceneFile file = io::parse_scene_string(R"(<Node name="root">
  <MechanicalObject name="3x" dx="1.5cm" position="0 0 0"/>
  <UniformMass totalMass="@other.mass"/>
  <NoSuchComponent value="2kg"/>
</Node>)",
                                                "other.scn");
    EXPECT_TRUE(scene::read_number_prefixes(file, {}).empty());
    for (const io::SceneAttribute& a : file.root->components[0]->attributes) {
        if (a.name == "dx") {
            EXPECT_EQ(a.value, "1.5cm");
        }
    }
}

const char* const kQuirkyNumbers = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <DefaultAnimationLoop/>
  <Node name="Body">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="RAYLEIGH_MASS"/>
    <CGLinearSolver iterations="25" tolerance="TOLERANCE" threshold="1e-12"/>
    <MeshTopology name="topo" position="0 0 0  1 0 0" edges="0 1"/>
    <MechanicalObject name="dofs"/>
    <FixedProjectiveConstraint indices="0"/>
    <UniformMass totalMass="TOTAL_MASS"/>
    <ConstantForceField totalForce="0 -10 0"/>
    <MeshSpringForceField stiffness="STIFFNESS" damping="DAMPING"/>
  </Node>
</Node>)";

std::string quirky_numbers(const std::vector<std::pair<std::string, std::string>>& values) {
    std::string xml = kQuirkyNumbers;
    for (const auto& [key, value] : values) xml.replace(xml.find(key), key.size(), value);
    return xml;
}

TEST(NumberPrefixQuirk, ASceneOfSuchNumbersStepsAsSofaHeads) {
    auto quirky = test::build(quirky_numbers({{"RAYLEIGH_MASS", "0.2.5"},
                                              {"TOLERANCE", "1e-12abc"},
                                              {"TOTAL_MASS", "2.5e1kg"},
                                              {"STIFFNESS", "+.5e+2x"},
                                              {"DAMPING", "1.N"}}));
    auto plain = test::build(quirky_numbers({{"RAYLEIGH_MASS", "0.2"},
                                             {"TOLERANCE", "1e-12"},
                                             {"TOTAL_MASS", "25"},
                                             {"STIFFNESS", "50"},
                                             {"DAMPING", "1"}}));
    EXPECT_EQ(quirky->warnings().size(), plain->warnings().size() + 5);
    for (int k = 0; k < 20; ++k) {
        quirky->step();
        plain->step();
    }
    const auto& x = dynamic_cast<const Vec3Object&>(*quirky->data({"/Body/dofs", false}, "position").state).position;
    const auto& y = dynamic_cast<const Vec3Object&>(*plain->data({"/Body/dofs", false}, "position").state).position;
    // SOFA HEAD reads the quirky scene so (with a warning for the two MeshSpringForceField Data)
    EXPECT_EQ(x[1], Vec3(0.99999909316164759, -0.0082781977760901671, 0));
    EXPECT_EQ(x, y);
}

}  // namespace
