// ContinuousDetection (collision/ccd_detection.hpp): crossings of collision models over a step's
// motion, per feature pair, against closed forms and against the exhaustive loop over every feature
// pair (the trees lose none).
#include "fixtures.hpp"

#include "penalty/collision/ccd_detection.hpp"
#include "penalty_test/random_draws.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <string>
#include <tuple>

namespace penalty {
namespace {

using test::named;

/// A 4 × 4-cell sheet in the plane z = 0, [0, 4]², two triangles a cell.
/// A flat square sheet [0, 4]² at height z of n × n cells, two triangles each.
std::unique_ptr<test::Mesh> ccd_sheet(double z = 0.0, int n = 4) {
    std::vector<Vec3> p;
    const double h = 4.0 / n;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) p.emplace_back(h * i, h * j, z);
    std::vector<Triangle> t;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const PointId a = PointId(i + (n + 1) * j), b = a + 1, c = a + PointId(n + 1), d = c + 1;
            t.push_back({a, b, d});
            t.push_back({a, d, c});
        }
    return test::triangle_mesh(p, t);
}

TEST(CcdDetection, PointThroughSheetIsOneCrossingWithItsTimeAndDepth) {
    auto sheet = ccd_sheet();
    TriangleModel tri(sheet->state, sheet->topo, named("sheet"));
    Vec3State ball = test::make_state({Vec3(1.25, 1.5, 1.0)});
    PointModel point(ball, nullptr, named("ball"));
    ContinuousDetection ccd;
    const ModelPair pair{&tri, &point};
    ccd.set_pairs({&pair, 1});
    ccd.record_start();
    ball.position[0] = Vec3(1.25, 1.5, -3.0);  // through z = 0 at t = 1/4, 3 m beyond
    const auto& c = ccd.detect();
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].kind, CrossingKind::point_triangle);
    EXPECT_EQ(c[0].model1, &point);
    EXPECT_EQ(c[0].model2, &tri);
    EXPECT_EQ(c[0].dofs1[0], 0);
    EXPECT_LE(c[0].toi, 0.25);
    EXPECT_NEAR(c[0].toi, 0.25, 1e-8);
    EXPECT_NEAR(c[0].depth, 3.0, 1e-12);
    EXPECT_NEAR(c[0].point.z(), 0.0, 1e-7);
    // the cell (1..2, 1..2): its triangles are 10 (a, b, d) and 11 (a, d, c); (1.25, 1.5) lies in 11
    EXPECT_EQ(c[0].element2, 11);
    EXPECT_NE(c[0].describe().find("vertex 0 of 'ball' through triangle 11 of 'sheet'"), std::string::npos);
    // stopping 1 mm short: nothing
    ball.position[0] = Vec3(1.25, 1.5, 1.0);
    ccd.record_start();
    ball.position[0] = Vec3(1.25, 1.5, 0.001);
    EXPECT_TRUE(ccd.detect().empty());
}

TEST(CcdDetection, AVertexOfSeveralModelsOfOneStateIsTestedOnce) {
    // a cube-like body described by a Triangle and a Point model on one state: its vertices cross
    // the sheet once each, not once per model
    auto sheet = ccd_sheet();
    TriangleModel tri(sheet->state, sheet->topo, named("sheet"));
    auto body = test::triangle_mesh({Vec3(1.3, 1.6, 0.5), Vec3(2.6, 1.4, 0.5), Vec3(1.7, 2.7, 0.5)}, {{0, 1, 2}});
    TriangleModel body_tri(body->state, body->topo, named("body_triangles"));
    PointModel body_points(body->state, &body->topo, named("body_points"));
    ContinuousDetection ccd;
    const ModelPair pairs[] = {{&tri, &body_tri}, {&tri, &body_points}};
    ccd.set_pairs(pairs, /*edge_edge=*/false);
    EXPECT_EQ(ccd.surface_count(), 2u);
    ccd.record_start();
    for (Vec3& x : body->state.position) x.z() = -0.5;
    const auto& c = ccd.detect();
    // the three body vertices through the sheet, each once (vertex 2 passes on a diagonal of the
    // sheet, through two triangles: one crossing), and the sheet's vertex (2, 2), inside the body
    // triangle, through it
    ASSERT_EQ(c.size(), 4u);
    std::multiset<std::pair<std::string, Index>> vertices;
    for (const Crossing& x : c) {
        EXPECT_EQ(x.kind, CrossingKind::point_triangle);
        vertices.insert({x.model1 == &tri ? "sheet" : "body", x.dofs1[0]});
    }
    EXPECT_EQ(vertices,
              (std::multiset<std::pair<std::string, Index>>{{"body", 0}, {"body", 1}, {"body", 2}, {"sheet", 12}}));
}

TEST(CcdDetection, EdgeEdgeOnlyWhereTheMethodMakesEdgeContacts) {
    // two triangles crossed like an X, no vertex through a face: only edges meet
    auto a = test::triangle_mesh({Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0, 0, 3)}, {{0, 1, 2}});
    auto b = test::triangle_mesh({Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(0, 0, -2)}, {{0, 1, 2}});
    TriangleModel ta(a->state, a->topo, named("a"));
    TriangleModel tb(b->state, b->topo, named("b"));
    std::vector<CollisionModel*> models{&ta, &tb};
    for (bool line_line : {false, true}) {
        IntersectionParams params = IntersectionParams::new_proximity();
        params.use_line_line = line_line;
        ContinuousDetection ccd;
        ccd.add_pipeline_pairs(params, models);
        a->state.position = {Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0, 0, 3)};
        ccd.record_start();
        for (Vec3& x : a->state.position) x.z() -= 2.0;  // a's lower edge passes b's upper edge at t = 1/2
        const auto& c = ccd.detect();
        if (!line_line) {
            EXPECT_TRUE(c.empty()) << "NewProximity without useLineLine makes no edge contact: not a tunnelling";
            continue;
        }
        ASSERT_EQ(c.size(), 1u);
        EXPECT_EQ(c[0].kind, CrossingKind::edge_edge);
        EXPECT_NEAR(c[0].toi, 0.5, 1e-8);
    }
}

TEST(CcdDetection, SpheresThroughTrianglesAndIntoSpheres) {
    auto sheet = ccd_sheet();
    TriangleModel tri(sheet->state, sheet->topo, named("sheet"));
    Vec3State balls = test::make_state({Vec3(0.5, 0.6, 0.5), Vec3(3.0, 3.0, 2.0)});
    SphereModel spheres(balls, 0.2, {}, named("balls"));
    Vec3State big = test::make_state({Vec3(3.0, 3.0, 0.9)});
    SphereModel big_sphere(big, 0.5, {}, named("big"));
    const ModelPair pairs[] = {{&tri, &spheres}, {&spheres, &big_sphere}};
    ContinuousDetection ccd;
    ccd.set_pairs(pairs);
    ccd.record_start();
    balls.position[0].z() = -0.5;  // its centre through the sheet at t = 1/2
    balls.position[1].z() = 1.0;   // its centre enters the big sphere (|u| = 0.5) at z = 1.4, t = 0.6
    const auto& c = ccd.detect();
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c[0].kind, CrossingKind::sphere_triangle);
    EXPECT_NEAR(c[0].toi, 0.5, 1e-8);
    EXPECT_EQ(c[0].element1, 0);
    EXPECT_EQ(c[1].kind, CrossingKind::sphere_sphere);
    EXPECT_NEAR(c[1].toi, 0.6, 1e-12);
    EXPECT_NEAR(c[1].depth, 0.5 - 0.1, 1e-12);
}

TEST(CcdDetection, SelfCollisionSkipsNeighboursAndNeedsTheSwitch) {
    // a strip of two triangles folding so that vertex 3 passes through triangle 0
    const std::vector<Vec3> start = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.2, 0.5)};
    auto strip = test::triangle_mesh(start, {{0, 1, 2}, {1, 2, 3}});
    for (bool self : {false, true}) {
        CollisionModelParams p = named("strip");
        p.self_collision = self;
        TriangleModel tri(strip->state, strip->topo, p);
        std::vector<CollisionModel*> models{&tri};
        ContinuousDetection ccd;
        ccd.add_pipeline_pairs(IntersectionParams::new_proximity(), models);
        strip->state.position = start;
        ccd.record_start();
        strip->state.position[3] = Vec3(0.2, 0.2, -0.5);
        const auto& c = ccd.detect();
        if (!self) {
            EXPECT_TRUE(c.empty());
            continue;
        }
        ASSERT_EQ(c.size(), 1u);  // vertex 3 through triangle 0 only (triangle 1 holds it)
        EXPECT_EQ(c[0].dofs1[0], 3);
        EXPECT_EQ(c[0].element2, 0);
    }
}

/// Points moving at random through a jittered sheet that moves too: the crossings found and the
/// crossings of point_triangle_ccd over every (point, triangle), and the candidates tested.
struct CloudThroughSheet {
    std::set<std::pair<Index, Index>> found, expected;
    std::size_t candidates = 0, all_pairs = 0;
};

CloudThroughSheet cloud_through_sheet(int cells, int points) {
    std::mt19937 g(7);
    auto sheet = ccd_sheet(0.0, cells);
    for (Vec3& x : sheet->state.position) x.z() += 0.2 * test::rand_vec(g, 1.0).z();
    TriangleModel tri(sheet->state, sheet->topo, named("sheet"));
    std::uniform_real_distribution<double> u(0.0, 4.0);
    std::vector<Vec3> start;
    for (int i = 0; i < points; ++i) {  // (draws in g++'s order of evaluation: z, y, x)
        const double z = 0.5 * test::rand_vec(g, 1.0).z(), y = u(g), x = u(g);
        start.emplace_back(x, y, z);
    }
    Vec3State cloud = test::make_state(start);
    PointModel cloud_model(cloud, nullptr, named("cloud"));
    const ModelPair pair{&tri, &cloud_model};
    ContinuousDetection ccd;
    ccd.set_pairs({&pair, 1});
    const std::vector<Vec3> sheet_start = sheet->state.position;
    ccd.record_start();
    for (Vec3& x : cloud.position) x += test::rand_vec(g, 0.6);
    for (Vec3& x : sheet->state.position) x += test::rand_vec(g, 0.05);
    CloudThroughSheet r;
    for (const Crossing& c : ccd.detect()) r.found.insert({c.dofs1[0], c.element2});
    for (std::size_t i = 0; i < start.size(); ++i)
        for (std::size_t t = 0; t < tri.size(); ++t) {
            const Triangle& k = tri.triangle(Index(t));
            const auto s0 = [&](int j) { return sheet_start[std::size_t(k[std::size_t(j)])]; };
            const auto s1 = [&](int j) { return sheet->state.position[std::size_t(k[std::size_t(j)])]; };
            if (point_triangle_ccd(start[i], s0(0), s0(1), s0(2), cloud.position[i], s1(0), s1(1), s1(2)).hit)
                r.expected.insert({Index(i), Index(t)});
        }
    r.candidates = ccd.stats().candidates;
    r.all_pairs = start.size() * tri.size();
    return r;
}

TEST(CcdDetection, TheTreesFindWhatTheLoopOverEveryFeaturePairFinds) {
    // a surface's kind of more than 32 features has a tree, fewer a list of boxes: the four
    // combinations (sheet of 32 or 128 triangles, 12 or 200 points) find the exhaustive loop's pairs
    for (const int cells : {4, 8})
        for (const int points : {12, 200}) {
            SCOPED_TRACE("cells " + std::to_string(cells) + ", points " + std::to_string(points));
            const CloudThroughSheet r = cloud_through_sheet(cells, points);
            EXPECT_EQ(r.found, r.expected);
            EXPECT_GT(r.expected.size(), std::size_t(points) / 10);  // the motion is a test: many points cross
            EXPECT_GE(r.candidates, r.expected.size());
            EXPECT_LT(r.candidates, r.all_pairs / 4);  // and the boxes prune
        }
}

TEST(CcdDetection, DetectNeedsAStart) {
    auto sheet = ccd_sheet();
    TriangleModel tri(sheet->state, sheet->topo, named("sheet"));
    Vec3State ball = test::make_state({Vec3(1, 1, 1)});
    PointModel point(ball, nullptr, named("ball"));
    const ModelPair pair{&tri, &point};
    ContinuousDetection ccd;
    ccd.set_pairs({&pair, 1});
    EXPECT_THROW((void)ccd.detect(), std::logic_error);
    ccd.record_start();
    ball.resize(2);
    EXPECT_THROW((void)ccd.detect(), std::logic_error);
}

}  // namespace
}  // namespace penalty
