// The generated scene of the scaling benchmark (tests/support/penalty_test/cubes_in_bowl.hpp,
// bench/bench_scaling.cpp): it builds as described, and k = 2 (8 one-cell FEM cubes of 0.1 m, 1 kg
// each) falls into the bowl and comes to rest there as a pile: finite states, every node inside
// the bowl and below its rim, cubes resting on the bowl and on each other, penetrations small.
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/output/stats_csv.hpp"
#include "penalty/response/penalty_force_field.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/cubes_in_bowl.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace {

using namespace penalty;
namespace bowl = penalty::test::cubes_in_bowl;

std::unique_ptr<scene::Scene> bowl_scene(const bowl::Setup& s) {
    return scene::build_scene(io::parse_scene_string(bowl::scene_xml(s), "cubes_in_bowl.scn"));
}

bowl::Setup setup(int k) {
    bowl::Setup s;
    s.k = k;
    return s;
}

TEST(CubesInBowl, BuildsOneStatePerCubeAndAStaticBowl) {
    for (const int k : {1, 3}) {
        const bowl::Setup s = setup(k);
        const auto scene = bowl_scene(s);
        int cubes = 0;
        std::size_t dofs = 0;
        for (const auto& r : scene->states()) {
            if (r.node_path == "/Bowl") {
                EXPECT_FALSE(r.in_solver_subtree);
                continue;
            }
            ++cubes;
            EXPECT_TRUE(r.in_solver_subtree) << r.node_path;
            dofs += r.state->scalar_size();
        }
        EXPECT_EQ(cubes, k * k * k);
        EXPECT_EQ(dofs, std::size_t(k * k * k) * 8 * 3);  // one cell: 8 nodes per cube
        // one triangle model per cube (12 triangles: 2 per face) and the bowl's
        ASSERT_EQ(scene->collision_models().size(), std::size_t(k * k * k) + 1);
        EXPECT_EQ(scene->collision_models()[1].model->size(), 12u);
        // every lattice node starts inside the bowl's sphere (clearance 0.02 m from it)
        const auto c = bowl::bowl_centre(s);
        const double R = bowl::bowl_radius(s);
        for (const auto& r : scene->states()) {
            if (r.node_path == "/Bowl") continue;
            for (const Vec3& x : dynamic_cast<const Vec3Object&>(*r.state).position)
                EXPECT_LT((x - Vec3(c[0], c[1], c[2])).norm(), R - s.clearance + 1e-12) << r.node_path;
        }
    }
}

TEST(CubesInBowl, BowlMeshIsTheCapWithInwardNormals) {
    const bowl::Setup s = setup(4);
    const auto m = bowl::detail::bowl_mesh(s);
    const int rings = bowl::bowl_rings(s);
    // 1 + Σ 6r points, Σ 6(2r − 1) = 6·rings² triangles
    EXPECT_EQ(m.points.size(), std::size_t(1 + 3 * rings * (rings + 1)));
    EXPECT_EQ(m.triangles.size(), std::size_t(6 * rings * rings));
    const double R = bowl::bowl_radius(s);
    double area = 0;
    for (const auto& t : m.triangles) {
        const auto& a = m.points[std::size_t(t[0])];
        const auto& b = m.points[std::size_t(t[1])];
        const auto& d = m.points[std::size_t(t[2])];
        const Vec3 pa(a[0], a[1], a[2]), pb(b[0], b[1], b[2]), pd(d[0], d[1], d[2]);
        const Vec3 n = (pb - pa).cross(pd - pa);
        const Vec3 to_centre = Vec3(0, R, 0) - (pa + pb + pd) / 3.0;
        EXPECT_GT(n.dot(to_centre), 0.0);  // normal toward the sphere's centre
        area += 0.5 * n.norm();
    }
    // the cap's area 2πR²(1 − cos θ_max), approached from below by the inscribed triangles
    const double cap = 2.0 * std::numbers::pi * R * R * (1.0 - std::cos(s.bowl_cap_deg * std::numbers::pi / 180.0));
    EXPECT_LT(area, cap);
    EXPECT_GT(area, 0.98 * cap);
}

// k = 2: 8 cubes fall a few centimetres, slide to the bottom (slowly: the drag holds them near
// 1 m/s) and pile up in 600 steps (3 s). Measured on this build (contacts in SOFA's order): the
// kinetic energy is 1.3e-2 J at step 400, still settling, and below 1e-4 J from step 550 on
// (with the contacts in ascending element order the pile had settled by step 400: a pile's
// last moves depend on the order of its contacts); about 85 contact springs, 60 of them active.
TEST(CubesInBowl, EightCubesComeToRestAsAPileInsideTheBowl) {
    const bowl::Setup s = setup(2);
    const auto scene = bowl_scene(s);
    const auto c = bowl::bowl_centre(s);
    const Vec3 centre(c[0], c[1], c[2]);
    const double R = bowl::bowl_radius(s);
    double peak_kinetic = 0;
    for (int step = 0; step < 600; ++step) {
        scene->step();
        peak_kinetic = std::max(peak_kinetic, scene->kinetic_energy());
        for (const auto& r : scene->states())
            for (const Vec3& x : dynamic_cast<const Vec3Object&>(*r.state).position)
                ASSERT_TRUE(x.allFinite()) << "step " << step << ", " << r.node_path;
    }
    // at rest: the kinetic energy has fallen below 1 % of its peak
    EXPECT_GT(peak_kinetic, 0.1);
    EXPECT_LT(scene->kinetic_energy(), 1e-2 * peak_kinetic);

    // every cube is inside the bowl: its centre (mean of its 8 nodes) at least half an edge
    // inside the sphere and below the rim; every node inside the sphere up to the contact
    // distance; the pile's lowest node near the bottom
    double lowest = 1e9, mean_centre_y = 0;
    int cubes = 0;
    for (const auto& r : scene->states()) {
        if (r.node_path == "/Bowl") continue;
        Vec3 cube_centre = Vec3::Zero();
        const auto& x = dynamic_cast<const Vec3Object&>(*r.state).position;
        for (const Vec3& p : x) {
            EXPECT_LT((p - centre).norm(), R + s.contact_distance) << r.node_path;
            lowest = std::min(lowest, p.y());
            cube_centre += p;
        }
        cube_centre /= double(x.size());
        EXPECT_LT((cube_centre - centre).norm(), R - 0.5 * s.cube_size) << r.node_path;
        EXPECT_LT(cube_centre.y(), bowl::bowl_rim_height(s)) << r.node_path;
        mean_centre_y += cube_centre.y();
        ++cubes;
    }
    mean_centre_y /= cubes;
    EXPECT_GT(lowest, -s.contact_distance);
    EXPECT_LT(lowest, 0.05);
    // 8 cubes of 0.1 m: the mean centre height lies above one cube resting at the bottom
    // (0.05 m) and below a single column of 8 (0.4 m)
    EXPECT_GT(mean_centre_y, 0.05);
    EXPECT_LT(mean_centre_y, 0.4);

    // contacts: with the bowl and between cubes, each cube held by at least 3 active springs
    const output::ContactSummary summary = output::summarize_contacts(scene->contacts());
    EXPECT_GE(summary.active_contacts, 3u * 8u);
    EXPECT_GT(summary.contacts, summary.active_contacts);  // springs inside the alarm distance
    EXPECT_LT(summary.max_penetration, 0.01);
    std::size_t cube_cube_active = 0, cube_bowl_active = 0;
    for (const auto& rec : scene->contacts())
        (rec.name.find("bowl") == std::string::npos ? cube_cube_active : cube_bowl_active) += rec.field->active_count();
    EXPECT_GT(cube_cube_active, 0u);
    EXPECT_GT(cube_bowl_active, 0u);
}

}  // namespace
