// ContinuousDetection's surfaces (ccd_surfaces.cpp): models grouped by their state and named by
// their models, each feature once per surface, the recorded start of the motion, the swept boxes
// (a sphere's grown by its radius), and the errors naming the model.
#include "fixtures.hpp"

#include "penalty/collision/ccd_detection.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace penalty {
namespace {

using test::named;

/// The message of the std::invalid_argument `f` throws ("" when none).
template <class F>
std::string ccd_surface_error(F&& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

/// Two triangles over the square [0, 2]² at height z.
std::unique_ptr<test::Mesh> ccd_square(double z) {
    return test::triangle_mesh({{0, 0, z}, {2, 0, z}, {2, 2, z}, {0, 2, z}}, {{0, 1, 2}, {0, 2, 3}});
}

TEST(CcdSurfaces, ModelsOfOneStateAreOneSurfaceNamedByItsModels) {
    auto square = ccd_square(0.0);
    TriangleModel triangles(square->state, square->topo, named("skin"));
    LineModel lines(square->state, square->topo, named("edges"));
    Vec3State ball = test::make_state({{0.5, 1.5, 1.0}});
    PointModel point(ball, nullptr, named("ball"));
    // a tetrahedron model has no feature the guard tests: its pairs make no surface
    Vec3State corners = test::make_state({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
    MeshTopology tetra_topo;
    tetra_topo.set_tetrahedra({{0, 1, 2, 3}});
    TetrahedronModel tetra(corners, tetra_topo, named("tetra"));
    const ModelPair pairs[] = {{&triangles, &point}, {&lines, &point}, {&tetra, &point}};
    ContinuousDetection ccd;
    ccd.set_pairs(pairs);
    ASSERT_EQ(ccd.surface_count(), 2u);
    ASSERT_TRUE(ccd.surface_of(triangles).has_value());
    EXPECT_EQ(ccd.surface_of(triangles), ccd.surface_of(lines));
    EXPECT_EQ(ccd.surface_name(*ccd.surface_of(triangles)), "skin+edges");
    EXPECT_EQ(ccd.surface_name(*ccd.surface_of(point)), "ball");
    EXPECT_FALSE(ccd.surface_of(tetra).has_value());
    // through the square: the point crosses one triangle once, though two models hold the surface
    ccd.record_start();
    ball.position[0] = Vec3(0.5, 1.5, -1.0);
    const auto& crossings = ccd.detect();
    ASSERT_EQ(crossings.size(), 1u);
    EXPECT_EQ(crossings[0].kind, CrossingKind::point_triangle);
    EXPECT_EQ(crossings[0].model2, &triangles);
    EXPECT_EQ(crossings[0].element2, 1);  // (0.5, 1.5) lies in (0, 2, 3)
    EXPECT_NEAR(crossings[0].toi, 0.5, 1e-8);
    EXPECT_EQ(ccd.stats().surfaces, 2u);
}

TEST(CcdSurfaces, ATriangleHeldByTwoModelsOfOneStateIsTestedOnce) {
    // two Triangle models over one state and topology: the point through them is one crossing
    // (triangles kept once by their DOFs), of the first model; a second pair with the same
    // models adds nothing
    auto square = ccd_square(0.0);
    TriangleModel first(square->state, square->topo, named("first"));
    TriangleModel second(square->state, square->topo, named("second"));
    Vec3State ball = test::make_state({{1.5, 0.5, 0.5}});
    PointModel point(ball, nullptr, named("ball"));
    const ModelPair pairs[] = {{&first, &point}, {&second, &point}, {&point, &second}};
    ContinuousDetection ccd;
    ccd.set_pairs(pairs);
    EXPECT_EQ(ccd.surface_count(), 2u);
    ccd.record_start();
    ball.position[0] = Vec3(1.5, 0.5, -0.5);
    const auto& crossings = ccd.detect();
    ASSERT_EQ(crossings.size(), 1u);
    EXPECT_EQ(crossings[0].model2, &first);
    EXPECT_EQ(crossings[0].element2, 0);
    EXPECT_EQ(crossings[0].dofs2, (std::array<Index, 3>{0, 1, 2}));
    // the point against the square's two triangles (both boxes hold it), not four
    EXPECT_EQ(ccd.stats().candidates, 2u);
}

TEST(CcdSurfaces, TheStartIsWhereTheMotionWasRecorded) {
    auto square = ccd_square(0.25);
    TriangleModel triangles(square->state, square->topo, named("skin"));
    Rigid3State frames = test::make_rigid_state({RigidFrame{Vec3(3, 4, 5), Quat::Identity()}});
    RigidSphereModel sphere(frames, 0.5);
    Vec3State other = test::make_state({{0, 0, 0}});
    PointModel untested(other, nullptr, named("untested"));
    const ModelPair pair{&triangles, &sphere};
    ContinuousDetection ccd;
    ccd.set_pairs({&pair, 1});
    ccd.record_start();
    square->state.position[2] = Vec3(9, 9, 9);
    frames.position[0].center = Vec3(-1, -1, -1);
    // the positions at record_start, a rigid DOF's centre
    EXPECT_EQ(ccd.start_position(triangles, 2), Vec3(2, 2, 0.25));
    EXPECT_EQ(ccd.start_position(sphere, 0), Vec3(3, 4, 5));
    EXPECT_EQ(ccd_surface_error([&] { (void)ccd.start_position(triangles, 4); }),
              "ContinuousDetection::start_position: DOF 4 outside the state of 'skin'");
    EXPECT_EQ(ccd_surface_error([&] { (void)ccd.start_position(triangles, -1); }),
              "ContinuousDetection::start_position: DOF -1 outside the state of 'skin'");
    EXPECT_EQ(ccd_surface_error([&] { (void)ccd.start_position(untested, 0); }),
              "ContinuousDetection::start_position: model 'untested' is not tested");
    const ModelPair with_null{&triangles, nullptr};
    EXPECT_EQ(ccd_surface_error([&] {
                  ccd.set_pairs({&with_null, 1});
              }),
              "ContinuousDetection::set_pairs: a null model");
}

TEST(CcdSurfaces, ASpheresSweptBoxIsGrownByItsRadius) {
    // sphere A (r 0.5) at rest at the origin, sphere B (r 0.1) from (2,0,0) to (0.3,0,0): B's
    // centre enters A at x = 0.5, t = 1.5/1.7; the centres' swept boxes ({0} and [0.3, 2]) meet
    // only once grown by the radii. Depth max(r1, r2) − |c2 − c1| = 0.2 at the end
    Vec3State a = test::make_state({{0, 0, 0}});
    Vec3State b = test::make_state({{2, 0, 0}});
    SphereModel big(a, 0.5, {}, named("big"));
    SphereModel small(b, 0.1, {}, named("small"));
    const ModelPair pair{&big, &small};
    ContinuousDetection ccd;
    ccd.set_pairs({&pair, 1});
    ccd.record_start();
    b.position[0] = Vec3(0.3, 0, 0);
    const auto& crossings = ccd.detect();
    ASSERT_EQ(crossings.size(), 1u);
    EXPECT_EQ(crossings[0].kind, CrossingKind::sphere_sphere);
    EXPECT_LE(crossings[0].toi, 1.5 / 1.7);
    EXPECT_GT(crossings[0].toi, 1.5 / 1.7 - 1e-6);
    EXPECT_NEAR(crossings[0].depth, 0.2, 1e-12);
    EXPECT_EQ(ccd.stats().candidates, 1u);
}

}  // namespace
}  // namespace penalty
