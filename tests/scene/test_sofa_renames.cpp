// SOFA's renamed components (scene/sofa_renames.cpp; ObjectFactory::createObject with
// renamedComponents): the names of before v24.06 build the components of the new names, the same
// bits, with a note; an old name whose new component penalty lacks stays an unknown component.
#include "field_and_constraint_scenes.hpp"

namespace {

using namespace penalty;
using namespace penalty::test_field_scenes;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

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

}  // namespace
