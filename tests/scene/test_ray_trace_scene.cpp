// A scene with SOFA's RayTraceNarrowPhase over TriangleOctreeCollisionModel surfaces (built by
// the scene builder; docs/components/ray_trace_narrow_phase.md): two spheres made here.
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace penalty {
namespace {

using test::build;
using testing::HasSubstr;

/// A unit UV sphere (poles and 7 rings of 12 points; outward triangles) centred at c: its
/// vertices and its triangles as attribute text.
struct SphereText {
    std::string positions, triangles;
};
SphereText sphere_at(double cx, double cy, double cz) {
    constexpr int kAround = 12, kRings = 7;
    const double pi = 3.141592653589793;
    SphereText out;
    const auto add_point = [&](double x, double y, double z) {
        out.positions += std::to_string(cx + x) + " " + std::to_string(cy + y) + " " + std::to_string(cz + z) + "  ";
    };
    add_point(0, 0, 1);  // 0: north pole
    for (int r = 1; r <= kRings; ++r) {
        const double polar = pi * r / (kRings + 1);
        for (int a = 0; a < kAround; ++a) {
            const double azimuth = 2 * pi * a / kAround;
            add_point(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth), std::cos(polar));
        }
    }
    const int south = 1 + kRings * kAround;
    add_point(0, 0, -1);
    const auto at = [&](int r, int a) { return 1 + (r - 1) * kAround + (a % kAround); };
    const auto add_triangle = [&](int i, int j, int k) {
        out.triangles += std::to_string(i) + " " + std::to_string(j) + " " + std::to_string(k) + "  ";
    };
    for (int a = 0; a < kAround; ++a) add_triangle(0, at(1, a), at(1, a + 1));
    for (int r = 1; r < kRings; ++r)
        for (int a = 0; a < kAround; ++a) {
            add_triangle(at(r, a), at(r + 1, a), at(r + 1, a + 1));
            add_triangle(at(r, a), at(r + 1, a + 1), at(r, a + 1));
        }
    for (int a = 0; a < kAround; ++a) add_triangle(south, at(kRings, a + 1), at(kRings, a));
    return out;
}

std::string scene_with(const std::string& narrow_phase) {
    const SphereText ground = sphere_at(0, 0, 0), body = sphere_at(0.1, 0.05, 1.7);
    return R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <CollisionPipeline/><BruteForceBroadPhase/><)" +
           narrow_phase + R"(/>
  <NewProximityIntersection alarmDistance="0.5" contactDistance="0.1"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Ground">
    <MeshTopology triangles=")" +
           ground.triangles + R"("/>
    <MechanicalObject position=")" +
           ground.positions + R"("/>
    <TriangleOctreeCollisionModel simulated="0" moving="0"/>
  </Node>
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-20"/>
    <MeshTopology triangles=")" +
           body.triangles + R"("/>
    <MechanicalObject name="body" position=")" +
           body.positions + R"("/>
    <UniformMass totalMass="1"/>
    <TriangleOctreeCollisionModel contactStiffness="100"/>
  </Node>
</Node>)";
}

TEST(RayTraceScene, OverlappingSpheresArePushedApart) {
    auto s = build(scene_with("RayTraceNarrowPhase"));
    const auto& body = dynamic_cast<const Vec3Object&>(*s->simulation().root().children()[1]->state());
    s->step();
    // contacts both ways: the body's bottom vertex in the ground, the ground's top vertex in the body
    ASSERT_EQ(s->contacts().size(), 2u);
    EXPECT_GT(s->contacts()[0].field->size(), 0u);
    EXPECT_GT(s->contacts()[1].field->size(), 0u);
    for (int k = 0; k < 20; ++k) s->step();
    double z = 0.0;
    for (const Vec3& p : body.position) z += p.z() / double(body.position.size());
    EXPECT_GT(z, 1.7 + 1e-3);                  // pushed up, no gravity
    EXPECT_GT(body.velocity.back().z(), 0.0);  // the south pole moves up
}

TEST(RayTraceScene, AnOctreeModelUnderBvhNarrowPhaseIsWarnedAbout) {
    auto s = build(scene_with("BVHNarrowPhase"));
    std::string all;
    for (const std::string& w : s->warnings()) all += w + "\n";
    EXPECT_THAT(all, HasSubstr("SOFA's single-cube tree for it reaches triangle 0 only"));
}

}  // namespace
}  // namespace penalty
