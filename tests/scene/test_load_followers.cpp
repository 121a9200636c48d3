// SurfacePressureForceField with index lists, TaitSurfacePressureForceField and
// RestShapeSpringsForceField with recompute_indices="0" following a topological change with SOFA's
// rules (docs/topological-changes.md, "What follows"): SOFA's triangleIndices / quadIndices are
// plain Data (each index names the element now in its slot), Tait's updateFromTopology takes the
// new surface and corrects the volume by volumeAfterTC − initialVolume, and without
// recompute_indices init's springs stay by index. Each is checked against the same component
// built fresh on the reduced mesh (forces, add_dforce, the assembled matrix) or against the
// closed form, and by finite differences after the change.
#include "penalty/mechanics/pressure_loads.hpp"
#include "penalty/mechanics/rest_shape_springs.hpp"
#include "penalty/mechanics/tait_surface_pressure.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/same_forces.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace penalty {
namespace {

template <class T>
T* lf_find(Node& n) {
    for (const auto& f : n.force_fields())
        if (auto* t = dynamic_cast<T*>(f.get())) return t;
    for (const auto& child : n.children())
        if (T* t = lf_find<T>(*child)) return t;
    return nullptr;
}

Vec3Object& lf_state(scene::Scene& s) { return dynamic_cast<Vec3Object&>(*s.states().at(0).state); }

/// The surface of the unit cube, 2×2 squares per face, two triangles each, normals outward
/// (26 points, 48 triangles).
struct LfSurface {
    std::vector<Vec3> points;
    std::vector<Triangle> triangles;
};

LfSurface lf_cube_surface() {
    LfSurface s;
    std::map<std::array<int, 3>, PointId> ids;  // corners in half units
    const auto point = [&](std::array<int, 3> h) {
        const auto [it, added] = ids.emplace(h, PointId(s.points.size()));
        if (added) s.points.push_back(Vec3(h[0], h[1], h[2]) * 0.5);
        return it->second;
    };
    // each face: origin o, directions u, v with u × v outward
    static constexpr int kFaces[6][3][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}, {{0, 0, 2}, {1, 0, 0}, {0, 1, 0}},
                                            {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 2, 0}, {0, 0, 1}, {1, 0, 0}},
                                            {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {{2, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    for (const auto& f : kFaces)
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) {
                const auto corner = [&](int a, int b) {
                    return point({f[0][0] + f[1][0] * a + f[2][0] * b, f[0][1] + f[1][1] * a + f[2][1] * b,
                                  f[0][2] + f[1][2] * a + f[2][2] * b});
                };
                const PointId a = corner(i, j), b = corner(i + 1, j), c = corner(i + 1, j + 1), d = corner(i, j + 1);
                s.triangles.push_back({a, b, c});
                s.triangles.push_back({a, c, d});
            }
    return s;
}

std::string lf_surface_scene(const std::vector<Vec3>& points, const std::vector<Triangle>& triangles,
                             const std::string& load) {
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="body">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <TriangleSetTopologyContainer name="surface" position=")" +
           test::points_text(points) + R"(" triangles=")" + test::elements_text(triangles) + R"("/>
  <TriangleSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="0.05"/>
  <MeshSpringForceField stiffness="200" damping="0.1"/>
  <FixedProjectiveConstraint indices="0"/>
  )" + load +
           "\n</Node></Node>\n";
}

TEST(LoadFollowers, SurfacePressureListsNameTheElementsNowInTheirSlotsAsSofa) {
    // SOFA's triangleIndices is plain Data: after removing triangles 5 and 17 (17 <- 47, 5 <- 46)
    // the list stays; 5 and 17 name the moved triangles, 46 and 47 are past the end (SOFA HEAD
    // crashes there): they press nothing, with a warning
    const LfSurface cube = lf_cube_surface();
    const std::string listed = "1 5 17 20 33 40 46 47";
    auto s = test::build(lf_surface_scene(
        cube.points, cube.triangles,
        R"(<SurfacePressureForceField name="listed" pressure="30" triangleIndices=")" + listed + R"("/>)"));
    auto* ff = lf_find<SurfacePressureForceField>(s->simulation().root());
    ASSERT_NE(ff, nullptr);
    s->step();
    testing::internal::CaptureStderr();
    s->remove_elements("surface", ElementType::triangle, {5, 17});
    const std::string warning = testing::internal::GetCapturedStderr();
    EXPECT_THAT(warning, testing::HasSubstr("SurfacePressureForceField 'listed' (test.scn:"));
    EXPECT_THAT(warning, testing::HasSubstr("2 of its listed triangleIndices / quadIndices are past"));
    EXPECT_EQ(ff->parameters().triangle_indices, (std::vector<Index>{1, 5, 17, 20, 33, 40, 46, 47}));
    const auto& triangles = s->topology_container("surface").mesh().triangles();
    ASSERT_EQ(triangles.size(), 46u);
    EXPECT_EQ(triangles[5], cube.triangles[46]);
    EXPECT_EQ(triangles[17], cube.triangles[47]);

    Vec3Object& x = lf_state(*s);
    auto fresh = test::build(lf_surface_scene(
        x.rest_position, triangles, R"(<SurfacePressureForceField pressure="30" triangleIndices="1 5 17 20 33 40"/>)"));
    auto* ref = lf_find<SurfacePressureForceField>(fresh->simulation().root());
    test::expect_same_forces(*ff, x, *ref, lf_state(*fresh));
    test::check_force_field_derivatives(
        *ff, x, {.dforce_vs_fd = 1e-7, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt});
    s->step();  // the body steps on (no read past the topology)
    for (const Vec3& p : x.position) EXPECT_TRUE(p.allFinite());
}

TEST(LoadFollowers, SurfacePressureKeepsItsDefaultVolumeThroughAChangeAsSofa) {
    // volumeConservationMode: defaultVolume is taken at the first addForce and kept; after the change
    // p·V_default/V uses the listed triangles now in their slots: as a fresh load given that volume
    const LfSurface cube = lf_cube_surface();
    const std::string options = R"(pressure="30" volumeConservationMode="1" mainDirection="0 1 0")";
    auto s = test::build(lf_surface_scene(
        cube.points, cube.triangles, "<SurfacePressureForceField " + options + R"( triangleIndices="0 3 9 30"/>)"));
    auto* ff = lf_find<SurfacePressureForceField>(s->simulation().root());
    ASSERT_NE(ff, nullptr);
    s->step();
    const double default_volume = ff->parameters().default_volume;
    ASSERT_NE(default_volume, -1.0);
    s->remove_elements("surface", ElementType::triangle, {3, 30, 12});
    EXPECT_EQ(ff->parameters().default_volume, default_volume);
    Vec3Object& x = lf_state(*s);
    std::ostringstream volume;
    volume.precision(17);
    volume << default_volume;
    auto fresh =
        test::build(lf_surface_scene(x.rest_position, s->topology_container("surface").mesh().triangles(),
                                     "<SurfacePressureForceField " + options + R"( triangleIndices="0 3 9 30" )" +
                                         "defaultVolume=\"" + volume.str() + "\"/>"));
    test::expect_same_forces(*ff, x, *lf_find<SurfacePressureForceField>(fresh->simulation().root()), lf_state(*fresh));
    EXPECT_EQ(ff->last_pressure(), lf_find<SurfacePressureForceField>(fresh->simulation().root())->last_pressure());
}

TEST(LoadFollowers, TaitPressureCorrectsItsVolumeByTheRestVolumeAfterTheChangeAsSofa) {
    // TaitSurfacePressureForceField::updateFromTopology: the new surface's rest volume about the
    // mean rest point (0.5, 0.5, 0.5) loses 1/48 per face triangle (area 1/8, height 1/2): 46/48
    // (SOFA HEAD: volumeAfterTC 0.9583333333333334); the area 6 − 2/8. addForce then uses
    // V − (V_TC − V_rest) with V0 = V_rest + the injected volume.
    const LfSurface cube = lf_cube_surface();
    const std::string tait =
        R"(<TaitSurfacePressureForceField name="tait" p0="50" B="400" gamma="1" injectedVolume="0.1" maxInjectionRate="2"/>)";
    auto s = test::build(lf_surface_scene(cube.points, cube.triangles, tait));
    auto* ff = lf_find<TaitSurfacePressureForceField>(s->simulation().root());
    ASSERT_NE(ff, nullptr);
    for (int i = 0; i < 3; ++i) s->step();
    EXPECT_EQ(ff->rest_volume(), 1.0);
    EXPECT_EQ(ff->volume_after_change(), 1.0);
    s->remove_elements("surface", ElementType::triangle, {5, 17});
    EXPECT_EQ(ff->rest_volume(), 1.0);
    EXPECT_DOUBLE_EQ(ff->volume_after_change(), 46.0 / 48.0);
    EXPECT_DOUBLE_EQ(ff->surface_area_after_change(), 6.0 - 2.0 / 8.0);
    EXPECT_DOUBLE_EQ(ff->rest_surface_area(), 6.0);
    const auto& triangles = s->topology_container("surface").mesh().triangles();
    EXPECT_EQ(ff->triangles(), triangles);

    // the same surface built fresh: its rest volume is the follower's volumeAfterTC, to the bit
    Vec3Object& x = lf_state(*s);
    auto fresh = test::build(lf_surface_scene(x.rest_position, triangles, tait));
    auto* ref = lf_find<TaitSurfacePressureForceField>(fresh->simulation().root());
    EXPECT_EQ(ff->volume_after_change(), ref->rest_volume());

    s->step();  // the 4th step: injected 0.08 of 0.1
    const double v = ff->current_volume() - (ff->volume_after_change() - ff->rest_volume());
    EXPECT_DOUBLE_EQ(ff->injected_volume(), 0.08);
    EXPECT_DOUBLE_EQ(ff->current_pressure(), 50.0 - 400.0 * (v / (ff->rest_volume() + ff->injected_volume()) - 1.0));
    // (an open surface: SOFA's p·∇V is not the gradient of its volume about the moving mean point,
    // so the finite-difference check is made on a closed one below)
}

TEST(LoadFollowers, TaitPressureOnAClosedSurfaceStaysAGradientAfterTheChange) {
    // the Tetra2Triangle surface of the tetrahedral cube (2×2×2 cells) stays closed when the corner
    // tetrahedra 0 and 38 go (SOFA HEAD: volumeAfterTC 0.9583333333333334 = 1 − 2·(1/2)³/6); its
    // area loses 6 right triangles of 1/8 and gains 2 equilateral ones of side √2/2
    const test::TetraCube cube = test::tetra_cube(2, 1.0);
    const std::string tait =
        R"(<TaitSurfacePressureForceField name="tait" p0="50" B="400" gamma="1" injectedVolume="0.1" maxInjectionRate="2"/>)";
    auto s = test::build(R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="body">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <TetrahedronSetTopologyContainer name="volume" position=")" +
                         test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) +
                         R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="0.04"/>
  <TetrahedronFEMForceField youngModulus="3000" poissonRatio="0.3" method="large"/>
  <Node name="skin">
    <TriangleSetTopologyContainer name="surface"/>
    <TriangleSetTopologyModifier/>
    <Tetra2TriangleTopologicalMapping input="@../volume" output="@surface"/>
    )" + tait + "\n  </Node>\n</Node></Node>\n");
    auto* ff = lf_find<TaitSurfacePressureForceField>(s->simulation().root());
    ASSERT_NE(ff, nullptr);
    for (int i = 0; i < 3; ++i) s->step();
    s->remove_elements("volume", ElementType::tetrahedron, {0, 38});
    EXPECT_EQ(ff->rest_volume(), 1.0);
    EXPECT_DOUBLE_EQ(ff->volume_after_change(), 46.0 / 48.0);
    EXPECT_DOUBLE_EQ(ff->surface_area_after_change(), 6.0 - 6.0 / 8.0 + 2.0 * std::sqrt(3.0) / 8.0);
    const auto& triangles = s->topology_container("surface").mesh().triangles();
    EXPECT_EQ(ff->triangles(), triangles);
    Vec3Object& x = lf_state(*s);
    ASSERT_EQ(x.num_dofs(), 25u);
    auto fresh = test::build(lf_surface_scene(x.rest_position, triangles, tait));
    EXPECT_EQ(ff->volume_after_change(),
              lf_find<TaitSurfacePressureForceField>(fresh->simulation().root())->rest_volume());
    s->step();
    test::check_force_field_derivatives(*ff, x,
                                        {.dforce_vs_fd = 1e-7, .assembled_vs_dforce = 1e-12, .force_vs_energy = 1e-7});
}

TEST(LoadFollowers, RestShapeSpringsWithoutRecomputedIndicesKeepInitsSpringsByIndexAsSofa) {
    // recompute_indices="0": SOFA's m_indices stay "0 2 6 7" while `points` follows (-> "2 6 0").
    // Removing tetrahedron 0 removes corner 0 and moves corner 7 (the last) into index 0: spring 0
    // (stiffness 10) now holds the old corner 7 at its rest position, spring 3 (index 7) is past the
    // end and acts on nothing, with a warning; springs 1, 2 are unchanged
    const test::TetraCube cube = test::tetra_cube(1, 1.0);
    const auto body =
        [](const std::vector<Vec3>& points, const std::vector<Tetrahedron>& tets, const std::string& springs) {
            return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="body">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <TetrahedronSetTopologyContainer name="volume" position=")" +
                   test::points_text(points) + R"(" tetrahedra=")" + test::elements_text(tets) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="0.04"/>
  )" + springs + "\n</Node></Node>\n";
        };
    auto s = test::build(body(
        cube.points, cube.tetrahedra,
        R"(<RestShapeSpringsForceField name="kept" points="0 2 6 7" stiffness="10 20 30 40" recompute_indices="0"/>)"));
    auto* ff = lf_find<RestShapeSpringsForceField<Vec3Types>>(s->simulation().root());
    ASSERT_NE(ff, nullptr);
    s->step();
    testing::internal::CaptureStderr();
    s->remove_elements("volume", ElementType::tetrahedron, {0});
    const std::string warning = testing::internal::GetCapturedStderr();
    EXPECT_THAT(warning, testing::HasSubstr("RestShapeSpringsForceField 'kept' (test.scn:"));
    EXPECT_THAT(warning, testing::HasSubstr("1 of its springs"));
    ASSERT_EQ(lf_state(*s).num_dofs(), 7u);
    EXPECT_EQ(ff->point_list(), (std::vector<Index>{2, 6, 0}));
    EXPECT_EQ(ff->points(), (std::vector<Index>{0, 2, 6, 7}));
    EXPECT_EQ(ff->springs_past_end(), 1u);
    EXPECT_EQ(lf_state(*s).rest_position[0], cube.points[7]);

    Vec3Object& x = lf_state(*s);
    auto fresh = test::build(
        body(x.rest_position, s->topology_container("volume").mesh().tetrahedra(),
             R"(<RestShapeSpringsForceField points="0 2 6" stiffness="10 20 30" assembleAsAddDForce="1"/>)"));
    ff->set_sofa_assembly(false);  // stiffness by spring in both matrices
    test::expect_same_forces(*ff, x, *lf_find<RestShapeSpringsForceField<Vec3Types>>(fresh->simulation().root()),
                             lf_state(*fresh));
    test::check_force_field_derivatives(*ff, x,
                                        {.dforce_vs_fd = 1e-7, .assembled_vs_dforce = 1e-12, .force_vs_energy = 1e-7});
    ff->set_sofa_assembly(true);
    s->step();
    for (const Vec3& p : x.position) EXPECT_TRUE(p.allFinite());
}

}  // namespace
}  // namespace penalty
