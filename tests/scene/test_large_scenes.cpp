// The generated scenes of the large-scene benchmarks (bench/bench_large_scenes.cpp,
// bench/bench_scaling.cpp), at small sizes: the soft body on the organ
// (tests/support/penalty_test/soft_body_on_organ.hpp) builds with the counts it announces, its
// organ is a closed surface with outward normals, and the body lands on the organ and slides down
// its side without going through it; the bowl at k = 16 (4 096 cubes) builds.
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/output/stats_csv.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/cubes_in_bowl.hpp"
#include "penalty_test/sanitizer.hpp"
#include "penalty_test/soft_body_on_organ.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <numbers>
#include <utility>

namespace {

using namespace penalty;
namespace organ = penalty::test::soft_body_on_organ;
namespace bowl = penalty::test::cubes_in_bowl;

organ::Setup small_setup() {
    organ::Setup s;
    s.cells = 8;                // 8 × 1 × 8 cells: 162 nodes, 384 tetrahedra
    s.organ_subdivisions = 16;  // 3 072 triangles
    return s;
}

std::unique_ptr<scene::Scene> build(const organ::Setup& s) {
    return scene::build_scene(io::parse_scene_string(organ::scene_xml(s), "soft_body_on_organ.scn"));
}

const Vec3Object& body_state(const scene::Scene& sc) {
    for (const auto& r : sc.states())
        if (r.node_path == "/Body") return dynamic_cast<const Vec3Object&>(*r.state);
    throw std::logic_error("no /Body state");
}

TEST(SoftBodyOnOrgan, CountsAreTheAnnouncedOnes) {
    for (const int n : {8, 16}) {
        organ::Setup s = small_setup();
        s.cells = n;
        EXPECT_EQ(organ::body_nodes(s), long(n + 1) * (n + 1) * (n / 8 + 1));
        EXPECT_EQ(organ::body_tetrahedra(s), 6L * n * n * (n / 8));
        const organ::Mesh body = organ::body_mesh(s);
        EXPECT_EQ(long(body.points.size()), organ::body_nodes(s));
        EXPECT_EQ(long(body.tetrahedra.size()), organ::body_tetrahedra(s));
        EXPECT_EQ(body.triangles.size(), std::size_t(4 * n * n + 8 * n * (n / 8)));  // 2 per boundary quad
        const organ::Mesh o = organ::organ_mesh(s);
        EXPECT_EQ(long(o.triangles.size()), organ::organ_triangles(s));
        EXPECT_EQ(o.points.size(), std::size_t(6 * 16 * 16 + 2));  // the cube's surface lattice
    }
    const organ::Setup s = small_setup();
    const auto sc = build(s);
    ASSERT_EQ(sc->collision_models().size(), 2u);
    EXPECT_EQ(long(sc->collision_models()[0].model->size()), organ::organ_triangles(s));
    EXPECT_EQ(body_state(*sc).position.size(), std::size_t(organ::body_nodes(s)));
}

// A closed, outward-oriented surface: every directed edge appears once and its reverse once;
// the enclosed volume (divergence theorem) is positive and near the smooth surface's, which the
// inscribed mesh approaches from below.
TEST(SoftBodyOnOrgan, OrganIsAClosedSurfaceWithOutwardNormals) {
    const organ::Setup s = small_setup();
    const organ::Mesh o = organ::organ_mesh(s);
    std::map<std::pair<int, int>, int> directed;
    double volume = 0;
    for (const auto& t : o.triangles) {
        for (int e = 0; e < 3; ++e) ++directed[{t[std::size_t(e)], t[std::size_t((e + 1) % 3)]}];
        const auto& a = o.points[std::size_t(t[0])];
        const auto& b = o.points[std::size_t(t[1])];
        const auto& c = o.points[std::size_t(t[2])];
        volume += bowl::detail::dot(a, bowl::detail::cross(b, c)) / 6.0;
    }
    for (const auto& [edge, count] : directed) {
        EXPECT_EQ(count, 1);
        EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
    }
    // V = abc·∫ s(d)³/3 dd over the unit sphere's directions d (the unit ball mapped by x ↦
    // s(x/|x|)·diag(a, b, c)·x), by a midpoint sum
    double smooth = 0;
    const int m = 400;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < 2 * m; ++j) {
            const double th = std::numbers::pi * (i + 0.5) / m, ph = std::numbers::pi * (j + 0.5) / m;
            const organ::P3 d = {std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)};
            smooth += s.organ_axes[0] * s.organ_axes[1] * s.organ_axes[2] * std::pow(organ::organ_scale(d), 3) / 3.0 *
                      std::sin(th) * (std::numbers::pi / m) * (std::numbers::pi / m);
        }
    EXPECT_GT(volume, 0.0);
    EXPECT_LT(volume, smooth);
    EXPECT_GT(volume, 0.97 * smooth);
    // ellipsoid of the same axes: 4/3·π·abc, the deformation changes it by a few percent
    const double ellipsoid = 4.0 / 3.0 * std::numbers::pi * s.organ_axes[0] * s.organ_axes[1] * s.organ_axes[2];
    EXPECT_NEAR(smooth / ellipsoid, 1.0, 0.05);
}

// The body starts 1 mm beyond the alarm distance above the organ's top; by 0.1 s it has landed (contacts, the springs
// hold its weight), at 0.4 s it has slid along −x down the organ's side, and no node has gone
// deeper into the organ's smooth surface than the contact distance.
TEST(SoftBodyOnOrgan, BodyLandsAndSlidesWithoutGoingThrough) {
    const organ::Setup s = small_setup();
    const auto sc = build(s);
    const auto centre = [&] {
        Vec3 c = Vec3::Zero();
        for (const Vec3& x : body_state(*sc).position) c += x;
        return Vec3(c / double(body_state(*sc).position.size()));
    };
    const Vec3 start = centre();
    sc->step();
    EXPECT_EQ(output::summarize_contacts(sc->contacts()).contacts, 0u);  // in the air
    double deepest = -1;
    for (int step = 1; step < 80; ++step) {
        sc->step();
        for (const Vec3& x : body_state(*sc).position) {
            ASSERT_TRUE(x.allFinite()) << "step " << step;
            deepest = std::max(deepest, organ::organ_depth(s, {x.x(), x.y(), x.z()}));
        }
        if (step == 20) {
            const output::ContactSummary c = output::summarize_contacts(sc->contacts());
            EXPECT_GT(c.active_contacts, 20u);
            EXPECT_LT(c.max_penetration, organ::contact_distance(s));
        }
    }
    EXPECT_LT(deepest, organ::contact_distance(s));
    const Vec3 now = centre();
    EXPECT_LT(now.x(), start.x() - 0.005);                                      // slid down the −x side
    EXPECT_GT(output::summarize_contacts(sc->contacts()).active_contacts, 0u);  // still on the organ
}

TEST(SoftBodyOnOrgan, BodyMeshFileGivesTheInlineScenesStatesToTheBit) {
    // The 10⁶-DOF size cannot write its body inline (an attribute holds at most 10⁶ values): its
    // mesh goes to a legacy VTK file read by MeshVTKLoader. The same scene both ways, 30 steps
    // (the body lands on the organ): the same states to the bit.
    const organ::Setup s = small_setup();
    EXPECT_FALSE(organ::body_needs_mesh_file(s));
    organ::Setup million = s;
    million.cells = 136;
    EXPECT_TRUE(organ::body_needs_mesh_file(million));
    const std::filesystem::path mesh =
        std::filesystem::path(::testing::TempDir()) / ("soft_body_mesh_" + std::to_string(::getpid()) + ".vtk");
    const auto inline_scene = build(s);
    const auto file_scene = scene::build_scene(io::parse_scene_string(organ::scene_xml(s, mesh), "from_file.scn"));
    ASSERT_EQ(body_state(*file_scene).position.size(), body_state(*inline_scene).position.size());
    for (int step = 0; step < 30; ++step) {
        inline_scene->step();
        file_scene->step();
    }
    const auto& a = body_state(*inline_scene).position;
    const auto& b = body_state(*file_scene).position;
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)));
    EXPECT_GT(inline_scene->contacts().size(), 0u);
    std::filesystem::remove(mesh);
}

// A body of 24 576 tetrahedra (16 335 DOFs in one state): its FEM force and product and the CG's
// vector passes split within the state on TBB's threads. The body's states after landing are
// the same bits at 1, 2 and 8 threads, in SOFA's reductions and in blocked ones. Under ASan +
// UBSan (about 20× slower on this test) the body has 10 368 tetrahedra, still split, at 1 and 8.
TEST(SoftBodyOnOrgan, OneLargeStateOnThreadsGivesTheBitsOfOneThread) {
    organ::Setup s = small_setup();
    s.cells = test::kUnderSanitizer ? 24 : 32;
    ASSERT_GE(organ::body_tetrahedra(s), 8192);  // detail::OrderedScatter::kMinElements
    for (const bool blocked : {false, true}) {
        std::vector<Vec3> one;
        for (const int threads : test::thread_counts_to_compare({1, 2, 8})) {
            scene::BuildOptions o;
            o.threads = threads;
            o.blocked_reductions = blocked;
            const auto sc =
                scene::build_scene(io::parse_scene_string(organ::scene_xml(s), "soft_body_on_organ.scn"), o);
            for (int step = 0; step < 25; ++step) sc->step();
            const std::vector<Vec3>& x = body_state(*sc).position;
            if (threads == 1) {
                ASSERT_GT(output::summarize_contacts(sc->contacts()).active_contacts, 0u);  // it has landed
                one = x;
                continue;
            }
            ASSERT_EQ(x.size(), one.size());
            EXPECT_EQ(std::memcmp(x.data(), one.data(), x.size() * sizeof(Vec3)), 0)
                << threads << " threads" << (blocked ? ", blocked reductions" : "");
        }
    }
}

TEST(CubesInBowl, LargestBenchmarkSizeBuilds) {
    bowl::Setup s;
    s.k = 16;
    const auto sc = scene::build_scene(io::parse_scene_string(bowl::scene_xml(s), "cubes_in_bowl_k16.scn"));
    EXPECT_EQ(sc->collision_models().size(), 4097u);
    std::size_t dofs = 0;
    for (const auto& r : sc->states())
        if (r.in_solver_subtree) dofs += r.state->scalar_size();
    EXPECT_EQ(dofs, 98304u);
}

}  // namespace
