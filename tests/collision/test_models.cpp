// Collision models (collision/models.cpp): triangle and line flags and ownership, the quad split,
// self-collision neighbours.
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace penalty {
namespace {

using test::make_state;

// probes: one point just outside every vertex and every edge midpoint of a closed mesh
struct Probes {
    std::vector<Vec3> points;
    std::size_t n_vertices = 0;
};

Probes make_probes(const test::Mesh& m, double delta) {
    Probes p;
    const auto& x = m.state.position;
    const Vec3 c = Vec3::Zero();
    for (const Vec3& v : x) p.points.push_back(v + delta * (v - c).normalized());
    p.n_vertices = x.size();
    for (const Edge& e : m.topo.edges()) {
        const Vec3 mid = 0.5 * (x[std::size_t(e[0])] + x[std::size_t(e[1])]);
        p.points.push_back(mid + delta * (mid - c).normalized());
    }
    return p;
}

TEST(TriangleFlags, ClosedMeshEachVertexAndEdgeOwnedOnce) {
    auto mesh = test::octahedron();
    TriangleModel tri(mesh->state, mesh->topo);
    ASSERT_EQ(tri.size(), 8u);
    std::vector<int> vertex_owner(6, 0);
    std::map<std::pair<int, int>, int> edge_owner;
    for (std::size_t t = 0; t < tri.size(); ++t) {
        const Triangle& tr = tri.triangle(Index(t));
        const std::uint32_t f = tri.flags(Index(t));
        EXPECT_EQ(f & (TriangleModel::kBE12 | TriangleModel::kBE23 | TriangleModel::kBE31), 0u);  // closed
        for (int j = 0; j < 3; ++j) {
            if (f & (TriangleModel::kP1 << j)) vertex_owner[std::size_t(tr[std::size_t(j)])]++;
            if (f & (TriangleModel::kE23 << j)) {
                int a = tr[std::size_t((j + 1) % 3)], b = tr[std::size_t((j + 2) % 3)];
                edge_owner[{std::min(a, b), std::max(a, b)}]++;
            }
        }
    }
    for (int c : vertex_owner) EXPECT_EQ(c, 1);
    EXPECT_EQ(edge_owner.size(), 12u);
    for (const auto& [e, c] : edge_owner) EXPECT_EQ(c, 1);
}

TEST(TriangleFlags, NewProximityEachVertexAndEdgeContactsFromExactlyOneTriangle) {
    auto mesh = test::octahedron();
    TriangleModel tri(mesh->state, mesh->topo);
    const Probes probes = make_probes(*mesh, 0.05);
    Vec3State ps = make_state(probes.points);
    PointModel pts(ps);
    auto params = IntersectionParams::new_proximity();
    params.alarm_distance = 0.1;
    params.contact_distance = 0.02;
    const auto det = detect_model_pair(params, tri, pts);
    std::vector<std::set<Index>> triangles_per_probe(probes.points.size());
    std::vector<int> count(probes.points.size(), 0);
    for (const auto& o : det.outputs) {
        count[o.elem2.slot()]++;
        triangles_per_probe[o.elem2.slot()].insert(o.elem1.value());
        EXPECT_EQ(o.id, o.elem2.value());
        EXPECT_NEAR(o.value, 0.05 - 0.02, 1e-12);
    }
    ASSERT_EQ(probes.points.size(), 6u + 12u);
    for (std::size_t i = 0; i < probes.points.size(); ++i) EXPECT_EQ(count[i], 1) << "probe " << i;
    // the same with spheres of radius 0 and the quirk fixed (SOFA's Triangle–Sphere checks the
    // wrong edge flags, so some edges are reported twice or never)
    SphereModel sph(ps, 0.0);
    params.quirks.fix_newproximity_triangle_sphere_edge_flags = true;
    const auto det2 = detect_model_pair(params, tri, sph);
    std::vector<int> count2(probes.points.size(), 0);
    for (const auto& o : det2.outputs) count2[o.elem2.slot()]++;
    for (std::size_t i = 0; i < probes.points.size(); ++i) EXPECT_EQ(count2[i], 1) << "probe " << i;
    params.quirks.fix_newproximity_triangle_sphere_edge_flags = false;
    const auto det3 = detect_model_pair(params, tri, sph);
    std::vector<int> count3(probes.points.size(), 0);
    for (const auto& o : det3.outputs) count3[o.elem2.slot()]++;
    int edge_miscount = 0;
    for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(count3[i], 1);
    for (std::size_t i = 6; i < probes.points.size(); ++i) edge_miscount += count3[i] != 1;
    EXPECT_GT(edge_miscount, 0);  // the quirk is visible on this mesh
}

TEST(TriangleModel, QuadsSplitAsSofaWithZeroFlags) {
    auto m = std::make_unique<test::Mesh>();
    m->state = make_state({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}});
    m->topo.set_num_points(5);
    m->topo.set_triangles({{1, 4, 2}});
    m->topo.set_quads({{0, 1, 2, 3}});
    TriangleModel tri(m->state, m->topo);
    ASSERT_EQ(tri.size(), 3u);
    EXPECT_EQ(tri.num_topology_triangles(), 1u);
    EXPECT_EQ(tri.triangle(1), (Triangle{1, 2, 0}));
    EXPECT_EQ(tri.triangle(2), (Triangle{3, 0, 2}));
    EXPECT_EQ(tri.flags(1), 0u);
    EXPECT_EQ(tri.flags(2), 0u);
    EXPECT_NE(tri.flags(0), 0u);
    tri.update();
    EXPECT_NEAR((tri.normal(1) - Vec3(0, 0, 1)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((tri.normal(2) - Vec3(0, 0, 1)).norm(), 0.0, 1e-15);
    // a point above a quad vertex gets no vertex contact from the split triangles
    Vec3State ps = make_state({{0, 0, 0.1}, {0.3, 0.6, 0.1}});
    PointModel pts(ps);
    auto params = IntersectionParams::new_proximity();
    params.alarm_distance = 0.2;  // the topology triangle (1,4,2) is out of range
    const auto det = detect_model_pair(params, tri, pts);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].elem2, ElementIndex(1));
    EXPECT_EQ(det.outputs[0].elem1, ElementIndex(2));
}

TEST(TriangleModel, NonMovingModelKeepsFirstNormals) {
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    CollisionModelParams p;
    p.moving = false;
    TriangleModel tri(mesh->state, mesh->topo, p);
    tri.update();
    mesh->state.position[2] = Vec3(0, 0, 1);
    tri.update();
    EXPECT_EQ(tri.normal(0), Vec3(0, 0, 1));
}

TEST(LineModel, FlagsFirstEdgeAndBoundaryVertex) {
    auto m = std::make_unique<test::Mesh>();
    m->state = make_state({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
    m->topo.set_num_points(3);
    m->topo.set_edges({{0, 1}, {1, 2}});
    LineModel l(m->state, m->topo);
    ASSERT_EQ(l.size(), 2u);
    EXPECT_EQ(l.flags(0), std::uint32_t(LineModel::kP1 | LineModel::kP2 | LineModel::kBP1));
    EXPECT_EQ(l.flags(1), std::uint32_t(LineModel::kP2 | LineModel::kBP2));
}

TEST(SelfCollision, PointModelSkipsNeighboursAndVisitsEachPairOnce) {
    auto m = std::make_unique<test::Mesh>();
    m->state = make_state({{0, 0, 0}, {0.1, 0, 0}, {0.2, 0, 0}});
    m->topo.set_num_points(3);
    m->topo.set_edges({{0, 1}});
    PointModel p(m->state, &m->topo);
    p.params().self_collision = true;
    const auto det = detect_model_pair(IntersectionParams::new_proximity(), p, p);
    // pairs (1,0) neighbours -> skipped; (2,0) and (2,1) kept
    ASSERT_EQ(det.outputs.size(), 2u);
    for (const auto& o : det.outputs) EXPECT_GT(o.elem1, o.elem2);
    p.params().self_collision = false;
    EXPECT_TRUE(detect_model_pair(IntersectionParams::new_proximity(), p, p).skipped);
}

TEST(SelfCollision, TriangleIgnoresItsOwnVerticesInTheSameNode) {
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 0.1}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo);
    PointModel pts(mesh->state, &mesh->topo);
    tri.params().node = pts.params().node = 7;
    tri.params().self_collision = pts.params().self_collision = true;
    const auto det = detect_model_pair(IntersectionParams::new_proximity(), tri, pts);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].elem2, ElementIndex(3));
}

}  // namespace
}  // namespace penalty
