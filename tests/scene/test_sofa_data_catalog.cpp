// SOFA's catalog of Data (scene/sofa_data_catalog.cpp, read from src/scene/sofa_data_catalog.tsv):
// a type's rows in SOFA's order, its Rigid3d rows where SOFA's template changes them, the rows
// of types without a template (nodes, SofaPython3's classes), none for a type SOFA lacks; the
// values SOFA HEAD's SofaPython3 gives (2a278d8: `sofa-head-python`, getValueTypeString,
// getValueString and the value's Python type of UniformMass<Vec3d> and UniformMass<Rigid3d>,
// the links of UniformMass); the columns of SOFA's vector types and the names of the live writes.
#include "penalty/scene/live_data.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace {

using namespace penalty::scene;

const CatalogEntry* catalog_row(std::string_view type, bool rigid, std::string_view name) {
    const std::vector<CatalogEntry>& rows = sofa_data_catalog(type, rigid);
    const auto it = std::find_if(rows.begin(), rows.end(), [&](const CatalogEntry& e) { return e.name == name; });
    return it == rows.end() ? nullptr : &*it;
}

TEST(SofaDataCatalog, UniformMassRowsAreSofaHeadsForEachTemplate) {
    const CatalogEntry* vec3 = catalog_row("UniformMass", false, "vertexMass");
    ASSERT_NE(vec3, nullptr);
    EXPECT_EQ(vec3->sofa_type, "d");
    EXPECT_EQ(vec3->python_form, "float");
    EXPECT_EQ(vec3->default_text, "1");
    EXPECT_FALSE(vec3->link);
    const CatalogEntry* rigid = catalog_row("UniformMass", true, "vertexMass");
    ASSERT_NE(rigid, nullptr);
    EXPECT_EQ(rigid->sofa_type, "RigidMass3d");
    EXPECT_EQ(rigid->python_form, "str");
    EXPECT_EQ(rigid->default_text, "1 1 [1 0 0,0 1 0,0 0 1]");
    const CatalogEntry* range = catalog_row("UniformMass", false, "localRange");
    ASSERT_NE(range, nullptr);
    EXPECT_EQ(range->sofa_type, "Vec2i");
    EXPECT_EQ(range->python_form, "ndarray:int32:1");
    EXPECT_EQ(range->default_text, "-1 -1");
    // the links after the Data, in SOFA's order, the context's default "@./"
    std::vector<std::string> links;
    for (const CatalogEntry& e : sofa_data_catalog("UniformMass", false))
        if (e.link) links.push_back(e.name);
    EXPECT_THAT(links, ::testing::ElementsAre("context", "slaves", "master", "mechanicalStates", "mstate", "topology"));
    EXPECT_EQ(catalog_row("UniformMass", false, "context")->default_text, "@./");
    // the first rows: Base's Data in SOFA's order, the name's default the class name
    const std::vector<CatalogEntry>& rows = sofa_data_catalog("UniformMass", false);
    ASSERT_GE(rows.size(), 3u);
    EXPECT_EQ(rows[0].name, "name");
    EXPECT_EQ(rows[0].default_text, "UniformMass");
    EXPECT_EQ(rows[1].name, "printLog");
    EXPECT_EQ(rows[2].name, "tags");
    EXPECT_EQ(rows[2].default_text, "");  // an empty default: the line's last field is empty
}

TEST(SofaDataCatalog, ATypeWithoutRigidRowsGivesItsVec3RowsAndOneWithoutTemplateItsOwn) {
    // BoxROI has Vec3d rows only: asked for rigid, the Vec3d ones
    EXPECT_EQ(&sofa_data_catalog("BoxROI", true), &sofa_data_catalog("BoxROI", false));
    EXPECT_FALSE(sofa_data_catalog("BoxROI", false).empty());
    // UniformMass has both: two lists
    EXPECT_NE(&sofa_data_catalog("UniformMass", true), &sofa_data_catalog("UniformMass", false));
    // a node: rows without template, the root's name
    const CatalogEntry* name = catalog_row("Node", false, "name");
    ASSERT_NE(name, nullptr);
    EXPECT_EQ(name->default_text, "root");
    EXPECT_EQ(&sofa_data_catalog("Node", true), &sofa_data_catalog("Node", false));
    // a type SOFA does not have
    EXPECT_TRUE(sofa_data_catalog("NoSuchComponent", false).empty());
    EXPECT_TRUE(sofa_data_catalog("", true).empty());
}

TEST(SofaDataCatalog, VectorTypesHaveTheirColumns) {
    EXPECT_EQ(sofa_type_columns("vector<Vec3d>"), 3u);
    EXPECT_EQ(sofa_type_columns("vector<RigidCoord3d>"), 7u);
    EXPECT_EQ(sofa_type_columns("vector<RigidDeriv3d>"), 6u);
    EXPECT_EQ(sofa_type_columns("vector<Edge>"), 2u);
    EXPECT_EQ(sofa_type_columns("vector<Hexahedron>"), 8u);
    EXPECT_EQ(sofa_type_columns("vector<Pyramid>"), 5u);
    EXPECT_EQ(sofa_type_columns("vector<Mat3x3d>"), 9u);
    EXPECT_EQ(sofa_type_columns("BoundingBox"), 3u);
    EXPECT_EQ(sofa_type_columns("Mat4x4d"), 4u);
    EXPECT_EQ(sofa_type_columns("d"), 0u);          // a scalar
    EXPECT_EQ(sofa_type_columns("vector<I>"), 0u);  // a flat list
    EXPECT_EQ(sofa_type_columns("vector<Vec3"), 0u);
}

TEST(SofaDataCatalog, LiveWritesHaveTheirNames) {
    EXPECT_EQ(live_write_name(LiveWrite::state), "state");
    EXPECT_EQ(live_write_name(LiveWrite::next_step), "next step");
    EXPECT_EQ(live_write_name(LiveWrite::reinit), "at reinit");
    EXPECT_EQ(live_write_name(LiveWrite::no_effect), "no effect");
    EXPECT_EQ(live_write_name(LiveWrite::refused), "refused");
    EXPECT_EQ(live_write_name(LiveWrite::read_only), "read-only");
    EXPECT_EQ(live_write_name(static_cast<LiveWrite>(99)), "?");
}

}  // namespace
