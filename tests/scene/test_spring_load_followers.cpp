// Springs and loads following a topological change with SOFA's rules (docs/topological-changes.md,
// "What follows"): RestShapeSpringsForceField's points are a TopologySubsetIndices (a removed point
// leaves, the last point's entry takes its index; `stiffness` stays by slot), its springs resolved
// again as addForce's recomputeIndices does; a SpringForceField between two states follows each
// end's topology (SOFA HEAD's applyRemovedPoints per end). After each change the follower equals
// the same component built fresh on the reduced mesh with the followed lists (forces, add_dforce,
// the assembled matrix, the next step), and its derivatives pass the finite-difference check.
#include "penalty/mechanics/pressure_loads.hpp"
#include "penalty/mechanics/rest_shape_springs.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/same_forces.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

namespace penalty {
namespace {

template <class T>
T* slf_find(Node& n) {
    for (const auto& f : n.force_fields())
        if (auto* t = dynamic_cast<T*>(f.get())) return t;
    for (const auto& child : n.children())
        if (T* t = slf_find<T>(*child)) return t;
    return nullptr;
}

std::string slf_body(const std::vector<Vec3>& points, const std::vector<Tetrahedron>& tets,
                     const std::string& components) {
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="body">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <TetrahedronSetTopologyContainer name="volume" position=")" +
           test::points_text(points) + R"(" tetrahedra=")" + test::elements_text(tets) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="0.04"/>
  )" + components +
           "\n</Node></Node>\n";
}

Vec3Object& slf_state(scene::Scene& s) { return dynamic_cast<Vec3Object&>(*s.states().at(0).state); }

std::string slf_list(const std::vector<Index>& v) {
    std::ostringstream out;
    for (const Index i : v) out << i << ' ';
    return out.str();
}

TEST(SpringLoadFollowers, RestShapeSpringsKeepTheirPointsAndStiffnessBySlotAsIfBuiltAfresh) {
    // tetrahedra 0 and 38 hold corners 0 and 26 alone: points 26 (the last) and 0 go, 25 takes
    // index 0. SOFA's TopologySubsetIndices::remove on "0 1 2 25 9 26 13": 26 leaves; 0 leaves and
    // the entry 25 becomes 0 -> "1 2 0 9 13"; the stiffness list stays by slot (10 20 30 ...)
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    const std::string stiffness = R"(stiffness="10 20 30 40 50 60 70")";
    for (const std::string assembly : {"0", "1"}) {
        SCOPED_TRACE("assembleAsAddDForce " + assembly);
        const auto springs = [&](const std::string& points) {
            return R"(<RestShapeSpringsForceField name="anchor" )" + points + " " + stiffness +
                   R"( assembleAsAddDForce=")" + assembly + R"("/>)";
        };
        auto s = test::build(slf_body(cube.points, cube.tetrahedra, springs(R"(points="0 1 2 25 9 26 13")")));
        s->remove_elements("volume", ElementType::tetrahedron, {0, 38});
        auto* ff = slf_find<RestShapeSpringsForceField<Vec3Types>>(s->simulation().root());
        ASSERT_NE(ff, nullptr);
        Vec3Object& x = slf_state(*s);
        ASSERT_EQ(x.num_dofs(), 25u);
        EXPECT_EQ(ff->point_list(), (std::vector<Index>{1, 2, 0, 9, 13}));
        EXPECT_EQ(x.rest_position[0], Vec3(0.1, 0.2, 0.2));  // old point 25
        ASSERT_TRUE(ff->resolve_after_change());
        EXPECT_EQ(ff->points(), (std::vector<Index>{1, 2, 0, 9, 13}));

        const MeshTopology& mesh = s->topology_container("volume").mesh();
        auto fresh = test::build(
            slf_body(x.rest_position, mesh.tetrahedra(), springs("points=\"" + slf_list(ff->point_list()) + "\"")));
        auto* ref = slf_find<RestShapeSpringsForceField<Vec3Types>>(fresh->simulation().root());
        ASSERT_NE(ref, nullptr);
        test::expect_same_forces(*ff, x, *ref, slf_state(*fresh));
        if (assembly == "1") {
            const test::DerivativeTolerances tol{1e-7, 1e-14, 1e-7};
            (void)test::check_force_field_derivatives(*ff, x, tol);
        }
    }
}

TEST(SpringLoadFollowers, RestShapeSpringsOnEveryPointFollowTheStateAndStepAsSofa) {
    // no `points`: every point of the state, resolved again after the change (recomputeIndices);
    // the step after the change equals the step of the scene built on the reduced mesh
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    const std::string springs = R"(<RestShapeSpringsForceField stiffness="5"/>)";
    auto s = test::build(slf_body(cube.points, cube.tetrahedra, springs));
    s->remove_elements("volume", ElementType::tetrahedron, {0, 38, 17});
    Vec3Object& x = slf_state(*s);
    auto fresh = test::build(slf_body(x.rest_position, s->topology_container("volume").mesh().tetrahedra(), springs));
    auto* ff = slf_find<RestShapeSpringsForceField<Vec3Types>>(s->simulation().root());
    auto* ref = slf_find<RestShapeSpringsForceField<Vec3Types>>(fresh->simulation().root());
    ASSERT_TRUE(ff && ref);
    for (int k = 0; k < 2; ++k) {
        s->step();
        fresh->step();
    }
    EXPECT_EQ(ff->points().size(), x.num_dofs());
    EXPECT_EQ(x.position, slf_state(*fresh).position);
    EXPECT_EQ(x.velocity, slf_state(*fresh).velocity);
    EXPECT_NE(x.position, x.rest_position);  // it moved under gravity
}

TEST(SpringLoadFollowers, RestShapeSpringsGoOffWhenTheirExternalPointsNoLongerMatchAsSofa) {
    // external_points is no topology data: after the change it names point 25, past the end, and
    // SOFA's checkOutOfBoundsIndices clears the springs (an error each step); so does penalty, with
    // a warning naming the component
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    auto s = test::build(slf_body(
        cube.points, cube.tetrahedra,
        R"(<RestShapeSpringsForceField name="anchor" points="0 1 2 25 9 26 13" external_points="0 1 2 25 9 26 13" stiffness="10"/>)"));
    auto* ff = slf_find<RestShapeSpringsForceField<Vec3Types>>(s->simulation().root());
    ASSERT_NE(ff, nullptr);
    EXPECT_EQ(ff->points().size(), 7u);
    testing::internal::CaptureStderr();
    s->remove_elements("volume", ElementType::tetrahedron, {0, 38});
    const std::string warning = testing::internal::GetCapturedStderr();
    EXPECT_THAT(warning, testing::HasSubstr("RestShapeSpringsForceField 'anchor' (test.scn:"));
    EXPECT_THAT(warning, testing::HasSubstr("external point 25 is out of range (25 rest positions)"));
    EXPECT_FALSE(ff->active());
    EXPECT_TRUE(ff->points().empty());
    Vec3Object& x = slf_state(*s);
    x.position[1] += Vec3(0.1, 0, 0);
    std::fill(x.force.begin(), x.force.end(), Vec3::Zero());
    ff->accumulate_force();
    for (const Vec3& f : x.force) EXPECT_EQ(f, Vec3::Zero());
}

TEST(SpringLoadFollowers, RestShapeSpringsWhoseListsAreEmptiedHoldEveryPointAsSofa) {
    // removing every listed point empties d_points, which recomputeIndices reads as "all points"
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    auto s = test::build(
        slf_body(cube.points, cube.tetrahedra, R"(<RestShapeSpringsForceField points="26" stiffness="3"/>)"));
    auto* ff = slf_find<RestShapeSpringsForceField<Vec3Types>>(s->simulation().root());
    ASSERT_NE(ff, nullptr);
    EXPECT_EQ(ff->points(), (std::vector<Index>{26}));
    s->remove_elements("volume", ElementType::tetrahedron, {38});
    EXPECT_TRUE(ff->point_list().empty());
    ASSERT_TRUE(ff->resolve_after_change());
    EXPECT_EQ(ff->points().size(), 26u);
}

/// A tetrahedral body (its own topology and modifier) and a fixed anchor state of 6 points, joined
/// by `springs` (a SpringForceField at the root, `object1`/`object2` naming the ends).
std::string slf_two_states(const std::vector<Vec3>& points, const std::vector<Tetrahedron>& tets,
                           const std::string& springs) {
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <Node name="body">
    <TetrahedronSetTopologyContainer name="volume" position=")" +
           test::points_text(points) + R"(" tetrahedra=")" + test::elements_text(tets) + R"("/>
    <TetrahedronSetTopologyModifier/>
    <MechanicalObject name="dofs"/>
    <UniformMass vertexMass="0.04"/>
  </Node>
  <Node name="anchor">
    <MechanicalObject name="ref" position="0 0.5 0  0.1 0.5 0  0.2 0.5 0  0.3 0.5 0  0.4 0.5 0  0.5 0.5 0"/>
    <UniformMass vertexMass="0.04"/><FixedProjectiveConstraint indices="0 1 2 3 4 5"/>
  </Node>
  )" + springs +
           "\n</Node>\n";
}

std::string slf_spring_list(const std::vector<Spring>& springs) {
    std::ostringstream out;
    out.precision(17);
    for (const Spring& s : springs)
        out << s.a << ' ' << s.b << ' ' << s.ks << ' ' << s.kd << ' ' << s.rest_length << "  ";
    return out.str();
}

TEST(SpringLoadFollowers, SpringsBetweenTwoStatesFollowTheirEndsTopologyAsIfBuiltAfresh) {
    // removing tetrahedra 0 and 38 removes points 26 (the last) and 0, and 25 takes index 0.
    // applyRemovedPoints on the body's ends: the spring on 26 leaves, the one on 0 leaves, the
    // ends on 25 become 0; the anchor's ends stay
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    const std::string body = "0 1 25 26 13 25 2", anchor = "0 1 2 3 4 5 0";
    for (const bool body_first : {true, false}) {
        SCOPED_TRACE(body_first ? "the body's ends first" : "the body's ends second");
        const std::string ends =
            body_first
                ? R"(object1="@body/dofs" object2="@anchor/ref" indices1=")" + body + R"(" indices2=")" + anchor + "\""
                : R"(object1="@anchor/ref" object2="@body/dofs" indices1=")" + anchor + R"(" indices2=")" + body + "\"";
        auto s = test::build(slf_two_states(
            cube.points, cube.tetrahedra,
            "<SpringForceField " + ends + R"( stiffness="50 60 70 80 90 100 110" damping="1" lengths="0.3"/>)"));
        s->remove_elements("volume", ElementType::tetrahedron, {0, 38});
        auto* ff = slf_find<SpringForceField>(s->simulation().root());
        ASSERT_NE(ff, nullptr);
        std::vector<std::array<Index, 2>> kept;  // (body end, anchor end)
        std::vector<double> ks;
        for (const Spring& sp : ff->springs()) {
            kept.push_back(body_first ? std::array<Index, 2>{sp.a, sp.b} : std::array<Index, 2>{sp.b, sp.a});
            ks.push_back(sp.ks);
        }
        EXPECT_EQ(kept, (std::vector<std::array<Index, 2>>{{1, 1}, {0, 2}, {13, 4}, {0, 5}, {2, 0}}));
        EXPECT_EQ(ks, (std::vector<double>{60, 70, 90, 100, 110}));

        const Vec3Object& x = dynamic_cast<const Vec3Object&>(*ff->states()[body_first ? 0 : 1]);
        const std::string fresh_ends = body_first ? R"(object1="@body/dofs" object2="@anchor/ref")"
                                                  : R"(object1="@anchor/ref" object2="@body/dofs")";
        auto fresh = test::build(
            slf_two_states(x.rest_position, s->topology_container("volume").mesh().tetrahedra(),
                           "<SpringForceField " + fresh_ends + " spring=\"" + slf_spring_list(ff->springs()) + "\"/>"));
        for (int k = 0; k < 3; ++k) {
            s->step();
            fresh->step();
        }
        ASSERT_EQ(s->states().size(), fresh->states().size());
        for (std::size_t k = 0; k < s->states().size(); ++k) {
            const auto& a = dynamic_cast<const Vec3Object&>(*s->states()[k].state);
            const auto& b = dynamic_cast<const Vec3Object&>(*fresh->states()[k].state);
            EXPECT_EQ(a.position, b.position) << k;
            EXPECT_EQ(a.velocity, b.velocity) << k;
        }
        EXPECT_NE(x.position, x.rest_position);
    }
}

TEST(SpringLoadFollowers, SpringsBetweenTwoChangingBodiesFollowBothEnds) {
    // each end on its own changing topology: the first ends follow the body's removals, the second
    // the other body's, in one spring list
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    const auto other = [&] {
        std::vector<Vec3> p = cube.points;
        for (Vec3& v : p) v.x() += 0.4;
        return p;
    }();
    const std::string text =
        R"(<Node name="root" gravity="0 -9.81 0" dt="0.01">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <Node name="a"><TetrahedronSetTopologyContainer name="va" position=")" +
        test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/>
    <TetrahedronSetTopologyModifier/><MechanicalObject name="xa"/><UniformMass vertexMass="0.04"/></Node>
  <Node name="b"><TetrahedronSetTopologyContainer name="vb" position=")" +
        test::points_text(other) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/>
    <TetrahedronSetTopologyModifier/><MechanicalObject name="xb"/><UniformMass vertexMass="0.04"/></Node>
  <SpringForceField object1="@a/xa" object2="@b/xb" indices1="0 1 25 26 13 25 2 24" indices2="26 0 1 25 24 3 26 2" stiffness="50"/>
</Node>)";
    auto s = test::build(text);
    auto* ff = slf_find<SpringForceField>(s->simulation().root());
    ASSERT_NE(ff, nullptr);
    s->remove_elements("va", ElementType::tetrahedron, {0, 38});
    // first ends: (0,26) and (26,25) leave, 25 -> 0
    std::vector<std::array<Index, 2>> ends;
    for (const Spring& sp : ff->springs()) ends.push_back({sp.a, sp.b});
    EXPECT_EQ(ends, (std::vector<std::array<Index, 2>>{{1, 0}, {0, 1}, {13, 24}, {0, 3}, {2, 26}, {24, 2}}));
    s->remove_elements("vb", ElementType::tetrahedron, {38, 0});
    // second ends: (2,26) and (1,0) leave (26 the last, then 0), 25 -> 0
    ends.clear();
    for (const Spring& sp : ff->springs()) ends.push_back({sp.a, sp.b});
    EXPECT_EQ(ends, (std::vector<std::array<Index, 2>>{{0, 1}, {13, 24}, {0, 3}, {24, 2}}));
}

/// A 4×4 sheet of quads in the plane y = 0 (25 points, 10 cm cells) with `load` on it.
std::string slf_quad_sheet(const std::vector<Vec3>& points, const std::vector<Quad>& quads, const std::string& load) {
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="sheet">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <QuadSetTopologyContainer name="surface" position=")" +
           test::points_text(points) + R"(" quads=")" + test::elements_text(quads) + R"("/>
  <QuadSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="0.01"/>
  <MeshSpringForceField stiffness="100" damping="0.1"/>
  )" + load +
           "\n</Node></Node>\n";
}

struct SlfSheet {
    std::vector<Vec3> points;
    std::vector<Quad> quads;
};

SlfSheet slf_sheet() {
    SlfSheet s;
    for (int z = 0; z <= 4; ++z)
        for (int x = 0; x <= 4; ++x) s.points.push_back(Vec3(0.1 * x, 0, 0.1 * z));
    for (int z = 0; z < 4; ++z)
        for (int x = 0; x < 4; ++x) {
            const PointId a = PointId(x + 5 * z);
            s.quads.push_back({a, a + 1, a + 6, a + 5});
        }
    return s;
}

std::string slf_quad_list(const std::vector<Index>& v) { return R"(quadList=")" + slf_list(v) + R"(")"; }

TEST(SpringLoadFollowers, QuadPressureEntriesFollowTheirQuadsAsIfBuiltAfresh) {
    // quads 15 and 0 hold corners 24 and 0 alone. QuadSubsetData::remove on "0 3 5 15 9 14": 15
    // leaves; 0 leaves and 14 (the last then) becomes 0 -> "3 5 9 0"; then quads 8, 7, 2 go (none listed)
    const SlfSheet sheet = slf_sheet();
    const std::string pressure = R"(pressure="0 -2 0.5")";
    auto s = test::build(slf_quad_sheet(sheet.points, sheet.quads,
                                        R"(<QuadPressureForceField quadList="0 3 5 15 9 14" )" + pressure + "/>"));
    auto* ff = slf_find<QuadPressureForceField>(s->simulation().root());
    ASSERT_NE(ff, nullptr);
    s->remove_elements("surface", ElementType::quad, {15, 0});
    EXPECT_EQ(ff->quads(), (std::vector<Index>{3, 5, 9, 0}));
    for (const std::vector<ElementId>& removed : {std::vector<ElementId>{}, std::vector<ElementId>{2, 7, 8}}) {
        if (!removed.empty()) s->remove_elements("surface", ElementType::quad, removed);
        EXPECT_EQ(ff->quads(), (std::vector<Index>{3, 5, 9, 0}));
        Vec3Object& x = slf_state(*s);
        auto fresh = test::build(
            slf_quad_sheet(x.rest_position, s->topology_container("surface").mesh().quads(),
                           "<QuadPressureForceField " + slf_quad_list(ff->quads()) + " " + pressure + "/>"));
        auto* ref = slf_find<QuadPressureForceField>(fresh->simulation().root());
        ASSERT_NE(ref, nullptr);
        EXPECT_EQ(ff->total_rest_area(), ref->total_rest_area());
        test::expect_same_forces(*ff, x, *ref, slf_state(*fresh));
    }
}

TEST(SpringLoadFollowers, QuadPressureKeepsSofasStaleLastIndexOrTheFixedRule) {
    // SOFA's QuadSubsetData keeps its last index from init (15): after the first removal
    // ("0 3 5 15 9 14 13 12" -> "3 5 9 0 13 12"), removing 8, 7, 2 renames 13 to 2 (quad 13 went
    // to 8) and leaves 12 past the end (11 quads; SOFA HEAD crashes): dropped with a warning.
    // --fix-sofa-quirk subset_data_last_index: the current last quads 13, 12, 11 -> 8, 7, 2
    const SlfSheet sheet = slf_sheet();
    const std::string load =
        R"(<QuadPressureForceField name="push" quadList="0 3 5 15 9 14 13 12" pressure="0 -2 0.5"/>)";
    for (const bool fixed : {false, true}) {
        SCOPED_TRACE(fixed ? "fixed" : "SOFA");
        scene::BuildOptions options;
        options.sofa_quirk_fixes.fix_subset_data_last_index = fixed;
        auto s = test::build(slf_quad_sheet(sheet.points, sheet.quads, load), options);
        auto* ff = slf_find<QuadPressureForceField>(s->simulation().root());
        ASSERT_NE(ff, nullptr);
        s->remove_elements("surface", ElementType::quad, {15, 0});
        EXPECT_EQ(ff->quads(), (std::vector<Index>{3, 5, 9, 0, 13, 12}));
        testing::internal::CaptureStderr();
        s->remove_elements("surface", ElementType::quad, {2, 7, 8});
        const std::string warning = testing::internal::GetCapturedStderr();
        ASSERT_EQ(s->topology_container("surface").mesh().quads().size(), 11u);
        if (!fixed) {
            EXPECT_EQ(ff->quads(), (std::vector<Index>{3, 5, 9, 0, 2}));
            EXPECT_THAT(warning, testing::HasSubstr("QuadPressureForceField 'push' (test.scn:"));
            EXPECT_THAT(warning, testing::HasSubstr("1 pressure entries name elements past the topology's end"));
            continue;
        }
        EXPECT_EQ(warning, "");
        EXPECT_EQ(ff->quads(), (std::vector<Index>{3, 5, 9, 0, 8, 7}));
        Vec3Object& x = slf_state(*s);
        auto fresh =
            test::build(slf_quad_sheet(x.rest_position, s->topology_container("surface").mesh().quads(),
                                       R"(<QuadPressureForceField quadList="3 5 9 0 8 7" pressure="0 -2 0.5"/>)"));
        test::expect_same_forces(*ff, x, *slf_find<QuadPressureForceField>(fresh->simulation().root()),
                                 slf_state(*fresh));
    }
}

TEST(SpringLoadFollowers, SurfacePressurePressesTheRemainingQuadsAsIfBuiltAfresh) {
    // no topology data: addForce presses the topology's current quads (with index lists:
    // test_load_followers.cpp)
    const SlfSheet sheet = slf_sheet();
    const std::string load = R"(<SurfacePressureForceField pressure="3" useTangentStiffness="1"/>)";
    auto s = test::build(slf_quad_sheet(sheet.points, sheet.quads, load));
    auto* ff = slf_find<SurfacePressureForceField>(s->simulation().root());
    ASSERT_NE(ff, nullptr);
    s->step();
    s->remove_elements("surface", ElementType::quad, {15, 0, 6});
    Vec3Object& x = slf_state(*s);
    auto fresh = test::build(slf_quad_sheet(x.rest_position, s->topology_container("surface").mesh().quads(), load));
    test::expect_same_forces(*ff, x, *slf_find<SurfacePressureForceField>(fresh->simulation().root()),
                             slf_state(*fresh));
}

}  // namespace
}  // namespace penalty
