// TriangularBiquadraticSpringsForceField, TriangularQuadraticSpringsForceField and
// TrianglePressureForceField following triangle removals (docs/topological-changes.md, "What
// follows"): after removals that also remove edges and points, each equals the same component
// built from scratch on the remaining mesh (per-edge rest lengths and stiffnesses, forces), and the
// pressure keeps exactly the selected triangles that remain.
#include "penalty/mechanics/pressure_loads.hpp"
#include "penalty/mechanics/triangular_biquadratic_springs.hpp"
#include "penalty/mechanics/triangular_quadratic_springs.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

namespace penalty {
namespace {

template <class T>
T* tsf_find(Node& n) {
    for (const auto& f : n.force_fields())
        if (auto* t = dynamic_cast<T*>(f.get())) return t;
    for (const auto& child : n.children())
        if (T* t = tsf_find<T>(*child)) return t;
    return nullptr;
}

std::string tsf_scene(const std::vector<Vec3>& points, const std::vector<Triangle>& triangles,
                      const std::string& components) {
    return R"(<Node name="root" gravity="0 0 0" dt="0.01"><Node name="sheet">
  <TriangleSetTopologyContainer name="surface" position=")" +
           test::points_text(points) + R"(" triangles=")" + test::elements_text(triangles) + R"("/>
  <TriangleSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  )" + components +
           "\n</Node></Node>\n";
}

Vec3Object& tsf_state(scene::Scene& s) { return *dynamic_cast<Vec3Object*>(s.states().at(0).state); }

using VertexPair = std::pair<PointId, PointId>;
VertexPair tsf_key(const Edge& e) { return {std::min(e[0], e[1]), std::max(e[0], e[1])}; }

/// Each edge's value by its vertices.
std::map<VertexPair, double> tsf_by_edge(const MeshTopology& mesh, const std::vector<double>& values) {
    std::map<VertexPair, double> out;
    for (std::size_t e = 0; e < mesh.edges().size(); ++e) out[tsf_key(mesh.edges()[e])] = values.at(e);
    return out;
}

void tsf_expect_same_edges(const std::map<VertexPair, double>& followed, const std::map<VertexPair, double>& fresh) {
    ASSERT_EQ(followed.size(), fresh.size());
    for (const auto& [edge, value] : fresh) {
        ASSERT_TRUE(followed.count(edge)) << edge.first << "-" << edge.second;
        EXPECT_NEAR(followed.at(edge), value, 1e-12 * std::abs(value)) << edge.first << "-" << edge.second;
    }
}

/// Removes triangles (with their isolated edges and points) from a sheet carrying the force field
/// of `components`, builds it again on what remains, and hands both scenes to `compare`.
template <class Compare>
void tsf_remove_and_rebuild(const std::string& components, Compare&& compare) {
    const test::TriangleSheet sheet = test::triangle_sheet(4, 0.5);
    auto followed = test::build(tsf_scene(sheet.points, sheet.triangles, components));
    followed->remove_elements("surface", ElementType::triangle, {0, 1, 9, 31, 20});
    followed->remove_elements("surface", ElementType::triangle, {3, 12});
    const MeshTopology& mesh = followed->topology_container("surface").mesh();
    const Vec3Object& x = tsf_state(*followed);
    ASSERT_EQ(mesh.triangles().size(), 25u);
    ASSERT_LT(x.num_dofs(), 25u);  // corners 0 and 24 went with their only triangles
    auto fresh = test::build(tsf_scene(x.rest_position, mesh.triangles(), components));
    compare(*followed, *fresh);
}

/// Both force fields' forces at the same perturbed positions.
template <class FF>
void tsf_expect_same_forces(scene::Scene& a, scene::Scene& b) {
    Vec3Object& xa = tsf_state(a);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.05, 0.05);
    std::vector<Vec3> x = xa.rest_position;
    for (Vec3& p : x) p += Vec3(jitter(rng), jitter(rng), jitter(rng));
    const std::vector<Vec3> v(x.size(), Vec3::Zero());
    std::vector<Vec3> fa(x.size(), Vec3::Zero()), fb(x.size(), Vec3::Zero());
    tsf_find<FF>(a.simulation().root())->add_force(fa, x, v);
    tsf_find<FF>(b.simulation().root())->add_force(fb, x, v);
    for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR((fa[i] - fb[i]).norm(), 0.0, 1e-9 * (1 + fb[i].norm())) << i;
}

TEST(TriangleSpringFollowers, BiquadraticSpringsEqualTheSameForceFieldBuiltOnTheRemainingMesh) {
    tsf_remove_and_rebuild(
        R"(<TriangularBiquadraticSpringsForceField youngModulus="15" poissonRatio="0.3" useAngularSprings="1"/>)",
        [](scene::Scene& a, scene::Scene& b) {
            using FF = TriangularBiquadraticSpringsForceField;
            const auto* fa = tsf_find<FF>(a.simulation().root());
            const auto* fb = tsf_find<FF>(b.simulation().root());
            ASSERT_TRUE(fa && fb);
            const MeshTopology& ma = a.topology_container("surface").mesh();
            const MeshTopology& mb = b.topology_container("surface").mesh();
            EXPECT_EQ(tsf_by_edge(ma, fa->rest_square_lengths()), tsf_by_edge(mb, fb->rest_square_lengths()));
            tsf_expect_same_edges(tsf_by_edge(ma, fa->edge_stiffness()), tsf_by_edge(mb, fb->edge_stiffness()));
            tsf_expect_same_forces<FF>(a, b);
        });
}

TEST(TriangleSpringFollowers, QuadraticSpringsEqualTheSameForceFieldBuiltOnTheRemainingMesh) {
    tsf_remove_and_rebuild(
        R"(<TriangularQuadraticSpringsForceField youngModulus="15" poissonRatio="0.3" useAngularSprings="1"/>)",
        [](scene::Scene& a, scene::Scene& b) {
            using FF = TriangularQuadraticSpringsForceField;
            const auto* fa = tsf_find<FF>(a.simulation().root());
            const auto* fb = tsf_find<FF>(b.simulation().root());
            ASSERT_TRUE(fa && fb);
            const MeshTopology& ma = a.topology_container("surface").mesh();
            const MeshTopology& mb = b.topology_container("surface").mesh();
            EXPECT_EQ(tsf_by_edge(ma, fa->rest_lengths()), tsf_by_edge(mb, fb->rest_lengths()));
            tsf_expect_same_edges(tsf_by_edge(ma, fa->edge_stiffness()), tsf_by_edge(mb, fb->edge_stiffness()));
            tsf_expect_same_forces<FF>(a, b);
        });
}

TEST(TriangleSpringFollowers, TrianglePressureKeepsTheSelectedTrianglesThatRemain) {
    // selected: 0 (removed), 5, 12 (removed), 17, 30, 31 (removed: its slot is taken by the last)
    const test::TriangleSheet sheet = test::triangle_sheet(4, 0.5);
    auto s = test::build(tsf_scene(sheet.points, sheet.triangles,
                                   R"(<TrianglePressureForceField triangleList="0 5 12 17 30 31" pressure="0 2 0"/>)"));
    const auto* p = tsf_find<TrianglePressureForceField>(s->simulation().root());
    ASSERT_NE(p, nullptr);
    const Vec3Object& x = tsf_state(*s);
    using Corners = std::set<std::array<double, 3>>;
    const auto corners = [&](const Triangle& t) {
        Corners c;
        for (const PointId v : t)
            c.insert({x.rest_position[std::size_t(v)].x(), x.rest_position[std::size_t(v)].y(),
                      x.rest_position[std::size_t(v)].z()});
        return c;
    };
    std::set<Corners> expected;
    for (const int k : {5, 17, 30}) expected.insert(corners(sheet.triangles[std::size_t(k)]));

    s->remove_elements("surface", ElementType::triangle, {0, 12, 31});
    const MeshTopology& mesh = s->topology_container("surface").mesh();
    std::set<Corners> kept;
    for (const Index t : p->triangles()) kept.insert(corners(mesh.triangles()[std::size_t(t)]));
    EXPECT_EQ(kept, expected);
    EXPECT_EQ(p->triangles().size(), 3u);
    EXPECT_DOUBLE_EQ(p->total_rest_area(), 3 * 0.5 * 0.25);  // three right triangles of legs 0.5
    // F = P·A₀ spread on the corners: Σf = (0, 2, 0)·Σ A₀
    std::vector<Vec3> f(x.num_dofs(), Vec3::Zero());
    const std::vector<Vec3> v(x.num_dofs(), Vec3::Zero());
    tsf_find<TrianglePressureForceField>(s->simulation().root())->add_force(f, x.position, v);
    Vec3 total = Vec3::Zero();
    for (const Vec3& fi : f) total += fi;
    EXPECT_NEAR((total - Vec3(0, 2 * 3 * 0.125, 0)).norm(), 0.0, 1e-15);
}

}  // namespace
}  // namespace penalty
