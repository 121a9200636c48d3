// Topological changes in built scenes (docs/topological-changes.md): each component after removals
// equals the same component built on the reduced mesh (masses, forces, stiffness; finite
// differences), fixed points stay the same points, a ball falls through a hole cut in a sheet,
// contacts on removed triangles end, a sphere tool carves exactly the elements within its reach,
// and bad input (change files, carving tools, components that cannot follow) is refused by name.
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/corotational_fem.hpp"
#include "penalty/mechanics/diagonal_mass.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/hyperelastic_fem.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/projective_constraints.hpp"
#include "penalty/mechanics/triangular_fem.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>

namespace penalty {
namespace {

using test::build;
using ::testing::HasSubstr;

/// The first object of type T in the graph (a mass, force field or constraint).
template <class T>
T* tchg_find(Node& n) {
    if (auto* m = dynamic_cast<T*>(n.mass())) return m;
    for (const auto& f : n.force_fields())
        if (auto* t = dynamic_cast<T*>(f.get())) return t;
    for (const auto& k : n.constraints())
        if (auto* t = dynamic_cast<T*>(k.get())) return t;
    for (const auto& child : n.children())
        if (T* t = tchg_find<T>(*child)) return t;
    return nullptr;
}

Vec3Object& tchg_state(scene::Scene& s, std::size_t k = 0) {
    auto* v = dynamic_cast<Vec3Object*>(s.states().at(k).state);
    EXPECT_NE(v, nullptr);
    return *v;
}

/// A tetrahedral body: container + modifier + state + `components`.
std::string tchg_body(const std::vector<Vec3>& points, const std::vector<Tetrahedron>& tets,
                      const std::string& components) {
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="body">
  <TetrahedronSetTopologyContainer name="volume" position=")" +
           test::points_text(points) + R"(" tetrahedra=")" + test::elements_text(tets) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  )" + components +
           "\n</Node></Node>\n";
}

Eigen::MatrixXd tchg_stiffness(const BaseForceField& ff, std::size_t dofs) {
    TripletList t;
    ff.add_stiffness(
        t, [](const BaseState*) { return Index(0); }, 1.0);
    SparseMatrix k(Eigen::Index(3 * dofs), Eigen::Index(3 * dofs));
    k.setFromTriplets(t.begin(), t.end());
    return Eigen::MatrixXd(k);
}

TEST(TopologicalChanges, FollowersEqualTheSameComponentsBuiltOnTheReducedMesh) {
    const test::TetraCube cube = test::tetra_cube(3, 0.3);
    const std::string components = R"(<DiagonalMass massDensity="1000"/>
  <TetrahedronFEMForceField youngModulus="5000" poissonRatio="0.3" method="large"/>)";
    auto changed = build(tchg_body(cube.points, cube.tetrahedra, components + R"(
  <FixedProjectiveConstraint indices="0 1 2 3 17 63"/>)"));
    // removals that leave points isolated (the corner tetrahedra) and that do not
    changed->remove_elements("volume", ElementType::tetrahedron, {0, 7, 33});
    changed->remove_elements("/body/volume", ElementType::tetrahedron, {127, 128, 129, 130, 131, 60});
    changed->remove_elements("/body", ElementType::tetrahedron, {2, 3, 4});
    // three tetrahedra removed and added again (new elements, on the points they had: found by
    // position, the removal may renumber them), then a removal that moves one of the new ones
    const TopologyContainer& c = changed->topology_container("volume");
    const Vec3Object& rest = tchg_state(*changed);
    std::vector<Vec3> corners;
    for (const std::size_t k : {5, 40, 77})
        for (const PointId v : c.mesh().tetrahedra()[k]) corners.push_back(rest.rest_position[std::size_t(v)]);
    changed->remove_elements("volume", ElementType::tetrahedron, {5, 40, 77});
    std::vector<PointId> again;
    for (const Vec3& p : corners) {
        const auto it = std::find(rest.rest_position.begin(), rest.rest_position.end(), p);
        ASSERT_NE(it, rest.rest_position.end());
        again.push_back(PointId(it - rest.rest_position.begin()));
    }
    changed->add_elements("volume", ElementType::tetrahedron, again);
    changed->remove_elements("volume", ElementType::tetrahedron, {10, 11});
    ASSERT_EQ(c.mesh().tetrahedra().size(), 135u - 12u - 2u);
    Vec3Object& x = tchg_state(*changed);
    ASSERT_EQ(x.num_dofs(), c.mesh().num_points());
    ASSERT_LT(x.num_dofs(), cube.points.size());  // some points went with their last tetrahedron

    // the same components built on the changed mesh: its lists, in its order, and its points
    auto fresh = build(tchg_body(x.rest_position, c.mesh().tetrahedra(), components));
    Vec3Object& y = tchg_state(*fresh);
    ASSERT_EQ(y.num_dofs(), x.num_dofs());

    // masses: SOFA's sums of element shares (up to their rounding)
    const auto& m1 = tchg_find<DiagonalMass>(changed->simulation().root())->vertex_masses();
    const auto& m2 = tchg_find<DiagonalMass>(fresh->simulation().root())->vertex_masses();
    ASSERT_EQ(m1.size(), m2.size());
    for (std::size_t i = 0; i < m1.size(); ++i) EXPECT_NEAR(m1[i], m2[i], 1e-12 * m2[i]) << i;
    EXPECT_NEAR(tchg_find<DiagonalMass>(changed->simulation().root())->total_mass(),
                tchg_find<DiagonalMass>(fresh->simulation().root())->total_mass(), 1e-9);

    // forces and stiffness at a deformed configuration: the same bits
    std::mt19937 rng(51);
    std::uniform_real_distribution<double> u(-0.01, 0.01);
    for (std::size_t i = 0; i < x.num_dofs(); ++i)
        x.position[i] = y.position[i] = x.rest_position[i] + Vec3(u(rng), u(rng), u(rng));
    auto* f1 = tchg_find<TetrahedronFEMForceField>(changed->simulation().root());
    auto* f2 = tchg_find<TetrahedronFEMForceField>(fresh->simulation().root());
    std::fill(x.force.begin(), x.force.end(), Vec3::Zero());
    std::fill(y.force.begin(), y.force.end(), Vec3::Zero());
    f1->accumulate_force();
    f2->accumulate_force();
    EXPECT_EQ(x.force, y.force);
    EXPECT_EQ(tchg_stiffness(*f1, x.num_dofs()), tchg_stiffness(*f2, y.num_dofs()));
    // df = K·dx through the element lane blocks of each kernel path this machine runs
    for (const KernelPath path : {KernelPath::scalar, KernelPath::avx, KernelPath::avx512}) {
        if (!kernel_path_supported(path)) continue;
        f1->set_kernel_path(path);
        f2->set_kernel_path(path);
        f1->accumulate_force();
        f2->accumulate_force();
        Vec3List dx(x.num_dofs()), df1(x.num_dofs(), Vec3::Zero()), df2(x.num_dofs(), Vec3::Zero());
        for (Vec3& d : dx) d = Vec3(u(rng), u(rng), u(rng));
        f1->add_dforce(df1, dx, 0.7, 0.0);
        f2->add_dforce(df2, dx, 0.7, 0.0);
        EXPECT_EQ(df1, df2) << to_string(path);
    }
    // K = −Rᵀ K^e R ignores the rotation's derivative: exact at rest and after a rigid motion
    const Mat3 r = Eigen::AngleAxisd(0.7, Vec3(1, 2, -1).normalized()).toRotationMatrix();
    for (std::size_t i = 0; i < x.num_dofs(); ++i) x.position[i] = r * x.rest_position[i] + Vec3(0.1, 0.2, 0.3);
    test::check_force_field_derivatives(*f1, x, {1e-6, 1e-12, std::nullopt});

    // the fixed points are the same points (those of the given ones that remain)
    std::set<std::array<double, 3>> fixed_changed, fixed_expected;
    for (const Index i : tchg_find<FixedProjectiveConstraint>(changed->simulation().root())->indices()) {
        const Vec3& p = x.rest_position[std::size_t(i)];
        fixed_changed.insert({p.x(), p.y(), p.z()});
    }
    for (const int i : {0, 1, 2, 3, 17, 63})
        for (const Vec3& p : x.rest_position)
            if (p == cube.points[std::size_t(i)]) fixed_expected.insert({p.x(), p.y(), p.z()});
    EXPECT_EQ(fixed_changed, fixed_expected);
    EXPECT_FALSE(fixed_expected.empty());
}

TEST(TopologicalChanges, CorotationalAndTriangleFemFollowAsIfBuiltAfresh) {
    // TetrahedralCorotationalFEMForceField and, on the border triangles a Tetra2Triangle mapping
    // keeps, TriangularFEMForceField
    const test::TetraCube cube = test::tetra_cube(2, 1.0);
    const std::string components = R"(<TetrahedralCorotationalFEMForceField youngModulus="300" poissonRatio="0.3"/>
  <Node name="surface">
    <TriangleSetTopologyContainer name="border"/>
    <TriangleSetTopologyModifier/>
    <Tetra2TriangleTopologicalMapping input="@../volume" output="@border"/>
    <TriangularFEMForceField youngModulus="60" poissonRatio="0.3"/>
  </Node>)";
    auto changed = build(tchg_body(cube.points, cube.tetrahedra, components));
    changed->remove_elements("volume", ElementType::tetrahedron, {1, 4, 9, 30});
    const MeshTopology& volume = changed->topology_container("volume").mesh();
    const MeshTopology& border = changed->topology_container("border").mesh();
    // the border is the changed volume's border (as a set of faces)
    std::map<std::array<PointId, 3>, int> count;
    for (const Tetrahedron& t : volume.tetrahedra())
        for (const auto& f : MeshTopology::kTetraFaces) {
            std::array<PointId, 3> k{t[std::size_t(f[0])], t[std::size_t(f[1])], t[std::size_t(f[2])]};
            std::sort(k.begin(), k.end());
            ++count[k];
        }
    std::set<std::array<PointId, 3>> expected, got;
    for (const auto& [k, n] : count)
        if (n == 1) expected.insert(k);
    for (Triangle t : border.triangles()) {
        std::sort(t.begin(), t.end());
        got.insert(t);
    }
    EXPECT_EQ(got, expected);

    Vec3Object& x = tchg_state(*changed);
    const std::string fresh_components =
        R"(<TetrahedralCorotationalFEMForceField youngModulus="300" poissonRatio="0.3"/>
  <Node name="surface">
    <TriangleSetTopologyContainer name="border" triangles=")" +
        test::elements_text(border.triangles()) + R"("/>
    <TriangularFEMForceField youngModulus="60" poissonRatio="0.3"/>
  </Node>)";
    auto fresh = build(tchg_body(x.rest_position, volume.tetrahedra(), fresh_components));
    Vec3Object& y = tchg_state(*fresh);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.02, 0.02);
    for (std::size_t i = 0; i < x.num_dofs(); ++i)
        x.position[i] = y.position[i] = x.rest_position[i] + Vec3(u(rng), u(rng), u(rng));
    auto* c1 = tchg_find<TetrahedralCorotationalFEMForceField>(changed->simulation().root());
    auto* c2 = tchg_find<TetrahedralCorotationalFEMForceField>(fresh->simulation().root());
    auto* t1 = tchg_find<TriangularFEMForceField>(changed->simulation().root());
    auto* t2 = tchg_find<TriangularFEMForceField>(fresh->simulation().root());
    ASSERT_TRUE(c1 && c2 && t1 && t2);
    for (const auto& [a, b] : {std::pair<BaseForceField*, BaseForceField*>{c1, c2}, {t1, t2}}) {
        std::fill(x.force.begin(), x.force.end(), Vec3::Zero());
        std::fill(y.force.begin(), y.force.end(), Vec3::Zero());
        a->accumulate_force();
        b->accumulate_force();
        EXPECT_EQ(x.force, y.force);
        EXPECT_EQ(tchg_stiffness(*a, x.num_dofs()), tchg_stiffness(*b, y.num_dofs()));
    }
    const Mat3 r = Eigen::AngleAxisd(-0.4, Vec3(0, 1, 1).normalized()).toRotationMatrix();
    for (std::size_t i = 0; i < x.num_dofs(); ++i) x.position[i] = r * x.rest_position[i];
    test::check_force_field_derivatives(*c1, x, {1e-6, 1e-12, std::nullopt});
}

TEST(TopologicalChanges, HyperelasticFemFollowsAsIfBuiltAfresh) {
    // TetrahedronHyperelasticityFEMForceField (createTetrahedronRestInformation for each element
    // left or added): after removals and an addition, the forces, stiffness and energy of the same
    // force field built on the changed mesh
    const test::TetraCube cube = test::tetra_cube(2, 1.0);
    const std::string ff =
        R"(<TetrahedronHyperelasticityFEMForceField ParameterSet="3448 31034" materialName="NeoHookean"/>)";
    auto changed = build(tchg_body(cube.points, cube.tetrahedra, ff));
    changed->remove_elements("volume", ElementType::tetrahedron, {2, 7, 11, 25});
    changed->add_elements("volume", ElementType::tetrahedron,
                          std::vector<PointId>(cube.tetrahedra[7].begin(), cube.tetrahedra[7].end()), 1);
    Vec3Object& x = tchg_state(*changed);
    const MeshTopology& volume = changed->topology_container("volume").mesh();
    ASSERT_EQ(volume.tetrahedra().size(), cube.tetrahedra.size() - 3);
    auto fresh = build(tchg_body(x.rest_position, volume.tetrahedra(), ff));
    Vec3Object& y = tchg_state(*fresh);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-0.03, 0.03);
    for (std::size_t i = 0; i < x.num_dofs(); ++i)
        x.position[i] = y.position[i] = x.rest_position[i] + Vec3(u(rng), u(rng), u(rng));
    auto* a = tchg_find<TetrahedronHyperelasticityFEMForceField>(changed->simulation().root());
    auto* b = tchg_find<TetrahedronHyperelasticityFEMForceField>(fresh->simulation().root());
    ASSERT_TRUE(a && b);
    std::fill(x.force.begin(), x.force.end(), Vec3::Zero());
    std::fill(y.force.begin(), y.force.end(), Vec3::Zero());
    a->accumulate_force();
    b->accumulate_force();
    EXPECT_EQ(x.force, y.force);
    EXPECT_EQ(a->potential_energy(), b->potential_energy());
    EXPECT_EQ(tchg_stiffness(*a, x.num_dofs()), tchg_stiffness(*b, y.num_dofs()));
    test::check_force_field_derivatives(*a, x,
                                        {.dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = 1e-6});
}

/// A ball (a sphere of radius r, UniformMass, implicit solver) above a fixed sheet of triangles
/// whose container can change.
std::string tchg_ball_over_sheet(const test::TriangleSheet& sheet, double radius, const Vec3& ball) {
    std::ostringstream b;
    b.precision(17);
    b << ball.x() << ' ' << ball.y() << ' ' << ball.z();
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.005">
  <CollisionPipeline/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <MinProximityIntersection alarmDistance="0.05" contactDistance="0.01"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="sheet">
    <TriangleSetTopologyContainer name="surface" position=")" +
           test::points_text(sheet.points) + R"(" triangles=")" + test::elements_text(sheet.triangles) + R"("/>
    <TriangleSetTopologyModifier/>
    <MechanicalObject name="sheetDofs"/>
    <TriangleCollisionModel moving="0" simulated="0" contactStiffness="2000"/>
  </Node>
  <Node name="ball">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-12"/>
    <MechanicalObject name="ballDofs" position=")" +
           b.str() + R"("/>
    <UniformMass totalMass="0.1"/>
    <SphereCollisionModel radius=")" +
           std::to_string(radius) + R"(" contactStiffness="2000"/>
  </Node>
</Node>
)";
}

double tchg_ball_height(scene::Scene& s) {
    for (const auto& r : s.states())
        if (r.state->state_name() == "ballDofs")
            if (const auto* ball = dynamic_cast<const Vec3Object*>(r.state); ball != nullptr && !ball->position.empty())
                return ball->position.front().y();
    ADD_FAILURE() << "no ball";
    return 0;
}

TEST(TopologicalChanges, ABallFallsThroughAHoleCutInASheet) {
    const test::TriangleSheet sheet = test::triangle_sheet(6, 0.1);  // 0.6 m square at y = 0
    const Vec3 start(0.31, 0.2, 0.33);  // inside a triangle (MinProximity finds no sphere on an edge)
    // the triangles within 0.15 m of the ball's axis (their centres)
    std::vector<ElementId> hole;
    for (std::size_t t = 0; t < sheet.triangles.size(); ++t) {
        Vec3 centre = Vec3::Zero();
        for (const PointId p : sheet.triangles[t]) centre += sheet.points[std::size_t(p)] / 3;
        if (std::hypot(centre.x() - start.x(), centre.z() - start.z()) < 0.15) hole.push_back(ElementId(t));
    }
    ASSERT_GT(hole.size(), 4u);
    auto whole = build(tchg_ball_over_sheet(sheet, 0.05, start));
    auto cut = build(tchg_ball_over_sheet(sheet, 0.05, start));
    cut->remove_elements("surface", ElementType::triangle, hole);
    EXPECT_EQ(cut->topology_container("surface").mesh().triangles().size(), sheet.triangles.size() - hole.size());
    for (int k = 0; k < 200; ++k) {
        whole->step();
        cut->step();
    }
    EXPECT_GT(tchg_ball_height(*whole), 0.0);  // it rests on the sheet
    EXPECT_LT(tchg_ball_height(*cut), -0.15);  // it fell through the hole (free fall: about −1.75 m)
}

TEST(TopologicalChanges, ContactsOnRemovedTrianglesEnd) {
    const test::TriangleSheet sheet = test::triangle_sheet(4, 0.1);
    auto s = build(tchg_ball_over_sheet(sheet, 0.05, Vec3(0.21, 0.06, 0.27)));
    for (int k = 0; k < 40; ++k) s->step();
    ASSERT_FALSE(s->contacts().empty());  // the ball rests on the sheet
    const double resting = tchg_ball_height(*s);
    std::vector<ElementId> all(sheet.triangles.size());
    for (std::size_t t = 0; t < all.size(); ++t) all[t] = ElementId(t);
    s->remove_elements("surface", ElementType::triangle, all);
    EXPECT_EQ(s->topology_container("surface").mesh().num_points(), 0u);  // the points went too
    EXPECT_EQ(s->states().front().state->num_dofs(), 0u);
    s->step();
    EXPECT_TRUE(s->contacts().empty());
    for (int k = 0; k < 20; ++k) s->step();
    EXPECT_LT(tchg_ball_height(*s), resting - 0.01);  // no force holds it any more
}

/// The scene's triangle collision models equal models built fresh on their changed topologies:
/// the same triangles in the same slots, the same flags (who owns each vertex and edge, the
/// border edges), the same counts.
void tchg_expect_triangle_models_fresh(const scene::Scene& s, const std::string& when) {
    std::size_t seen = 0;
    for (const scene::SceneCollisionModel& sm : s.collision_models()) {
        const auto* tm = dynamic_cast<const TriangleModel*>(sm.model.get());
        if (tm == nullptr) continue;
        ++seen;
        const TriangleModel fresh(tm->state(), tm->topology(), tm->params());
        ASSERT_EQ(tm->size(), fresh.size()) << when;
        EXPECT_EQ(tm->num_topology_triangles(), fresh.num_topology_triangles()) << when;
        EXPECT_EQ(tm->owns_every_feature(), fresh.owns_every_feature()) << when;
        for (std::size_t i = 0; i < fresh.size(); ++i) {
            ASSERT_EQ(tm->triangle(Index(i)), fresh.triangle(Index(i))) << when << ", triangle " << i;
            ASSERT_EQ(tm->flags(Index(i)), fresh.flags(Index(i))) << when << ", triangle " << i;
        }
    }
    EXPECT_GT(seen, 0u) << when;
}

TEST(TopologicalChanges, TriangleCollisionModelsFollowAsIfBuiltAfresh) {
    std::mt19937 rng(51);
    // a body's border through Tetra2Triangle: removals of tetrahedra uncover inner triangles,
    // remove border ones and renumber points
    const test::TetraCube cube = test::tetra_cube(4, 0.4);
    auto body = build(tchg_body(cube.points, cube.tetrahedra, R"(<DiagonalMass massDensity="1000"/>
  <Node name="border">
    <TriangleSetTopologyContainer name="surface"/>
    <TriangleSetTopologyModifier/>
    <Tetra2TriangleTopologicalMapping input="@../volume" output="@surface"/>
    <TriangleCollisionModel/>
  </Node>)"));
    tchg_expect_triangle_models_fresh(*body, "built");
    for (int round = 0; round < 12; ++round) {
        const std::size_t n = body->topology_container("volume").mesh().tetrahedra().size();
        std::set<ElementId> picked;
        while (picked.size() < std::min<std::size_t>(n, 1 + round % 4))
            picked.insert(ElementId(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng)));
        body->remove_elements("volume", ElementType::tetrahedron, {picked.begin(), picked.end()});
        tchg_expect_triangle_models_fresh(*body, "body, round " + std::to_string(round));
    }
    // a sheet: triangles removed, and removed ones added again on their points (found by position:
    // a removal may renumber them, or remove them with their last triangle)
    const test::TriangleSheet sheet = test::triangle_sheet(5, 0.1);
    auto s = build(tchg_ball_over_sheet(sheet, 0.05, Vec3(0.21, 0.3, 0.27)));
    const Vec3Object& sheet_dofs = tchg_state(*s, 0);
    ASSERT_EQ(sheet_dofs.num_dofs(), sheet.points.size());
    std::vector<std::array<Vec3, 3>> removed;
    std::size_t added = 0;
    for (int round = 0; round < 12; ++round) {
        const MeshTopology& mesh = s->topology_container("surface").mesh();
        const std::size_t n = mesh.triangles().size();
        if (round % 3 == 2) {
            std::vector<PointId> again;
            for (const auto& corners : removed) {
                std::vector<PointId> t;
                for (const Vec3& p : corners) {
                    const auto& x0 = sheet_dofs.rest_position;
                    const auto it = std::find(x0.begin(), x0.end(), p);
                    if (it != x0.end()) t.push_back(PointId(it - x0.begin()));
                }
                if (t.size() == 3) again.insert(again.end(), t.begin(), t.end());
            }
            removed.clear();
            if (again.empty()) continue;
            added += again.size() / 3;
            s->add_elements("surface", ElementType::triangle, again);
        } else {
            std::set<ElementId> picked;
            while (picked.size() < std::min<std::size_t>(n, 3))
                picked.insert(ElementId(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng)));
            for (const ElementId t : picked) {
                std::array<Vec3, 3> corners;
                for (std::size_t j = 0; j < 3; ++j)
                    corners[j] = sheet_dofs.rest_position[std::size_t(mesh.triangles()[std::size_t(t)][j])];
                removed.push_back(corners);
            }
            s->remove_elements("surface", ElementType::triangle, {picked.begin(), picked.end()});
        }
        tchg_expect_triangle_models_fresh(*s, "sheet, round " + std::to_string(round));
        s->step();
    }
    EXPECT_GT(added, 3u);  // the additions ran
}

}  // namespace
}  // namespace penalty

namespace penalty {
namespace {

/// The cube of tetrahedra with its border (Tetra2Triangle) tagged CarvingSurface, and a tool of
/// spheres (one per point of `tool`) tagged CarvingTool; no gravity.
std::string tchg_carving_scene(const test::TetraCube& cube, const std::vector<Vec3>& tool, double radius,
                               double carving) {
    return R"(<Node name="root" gravity="0 0 0" dt="0.01">
  <CollisionPipeline/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <MinProximityIntersection alarmDistance="0.1" contactDistance="0.01"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <CarvingManager active="1" carvingDistance=")" +
           std::to_string(carving) + R"("/>
  <Node name="body">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    <TetrahedronSetTopologyContainer name="volume" position=")" +
           test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/>
    <TetrahedronSetTopologyModifier/>
    <MechanicalObject name="dofs"/>
    <DiagonalMass massDensity="1000"/>
    <TetrahedralCorotationalFEMForceField youngModulus="5000" poissonRatio="0.3"/>
    <Node name="surface">
      <TriangleSetTopologyContainer name="border"/>
      <TriangleSetTopologyModifier/>
      <Tetra2TriangleTopologicalMapping input="@../volume" output="@border"/>
      <TriangleCollisionModel tags="CarvingSurface"/>
    </Node>
  </Node>
  <Node name="tool">
    <MechanicalObject name="toolDofs" position=")" +
           test::points_text(tool) + R"("/>
    <SphereCollisionModel radius=")" +
           std::to_string(radius) + R"(" tags="CarvingTool"/>
  </Node>
</Node>
)";
}

std::set<std::array<PointId, 4>> tchg_sorted(const std::vector<Tetrahedron>& tets, const std::vector<Vec3>& points,
                                             const std::vector<Vec3>& original) {
    // tetrahedra as sets of original point indices (points move by swap-and-pop: found by position)
    std::set<std::array<PointId, 4>> out;
    for (const Tetrahedron& t : tets) {
        std::array<PointId, 4> k{};
        for (std::size_t j = 0; j < 4; ++j)
            k[j] = PointId(std::find(original.begin(), original.end(), points[std::size_t(t[j])]) - original.begin());
        std::sort(k.begin(), k.end());
        out.insert(k);
    }
    return out;
}

TEST(TopologicalChanges, ASphereToolCarvesExactlyTheTetrahedraOfTheTrianglesWithinItsReach) {
    const test::TetraCube cube = test::tetra_cube(3, 0.3);  // top face at y = 0.3
    // two spheres within reach (distance 0.025 < radius 0.02 + contact distance 0.01: value < 0 =
    // carvingDistance), two within the alarm distance only (0.035: value 0.005 > 0), each above a
    // triangle's interior
    const double r = 0.02;
    const std::vector<Vec3> tool{Vec3(0.045, 0.325, 0.02), Vec3(0.23, 0.325, 0.115), Vec3(0.12, 0.335, 0.225),
                                 Vec3(0.255, 0.335, 0.23)};
    auto s = build(tchg_carving_scene(cube, tool, r, 0.0));
    const MeshTopology& border = s->topology_container("border").mesh();
    const Vec3Object& x = tchg_state(*s);
    // expected: the tetrahedron under each sphere within reach (the one holding the top face
    // triangle under its centre)
    std::set<std::array<PointId, 4>> expected = tchg_sorted(cube.tetrahedra, cube.points, cube.points);
    for (std::size_t k = 0; k < 2; ++k) {
        const Vec3& c = tool[k];
        int found = 0;
        for (const Triangle& t : border.triangles()) {
            const Vec3 a = x.position[std::size_t(t[0])], b = x.position[std::size_t(t[1])],
                       d = x.position[std::size_t(t[2])];
            if (std::abs(a.y() - 0.3) > 1e-12 || std::abs(b.y() - 0.3) > 1e-12 || std::abs(d.y() - 0.3) > 1e-12)
                continue;
            // barycentric coordinates of (c.x, c.z) in the triangle's xz projection
            const double det = (b.x() - a.x()) * (d.z() - a.z()) - (d.x() - a.x()) * (b.z() - a.z());
            const double u = ((c.x() - a.x()) * (d.z() - a.z()) - (d.x() - a.x()) * (c.z() - a.z())) / det;
            const double v = ((b.x() - a.x()) * (c.z() - a.z()) - (c.x() - a.x()) * (b.z() - a.z())) / det;
            if (u <= 0 || v <= 0 || u + v >= 1) continue;
            ++found;
            const std::set<PointId> face(t.begin(), t.end());
            for (const Tetrahedron& tet : cube.tetrahedra) {
                std::array<PointId, 4> key = tet;
                std::sort(key.begin(), key.end());
                if (std::includes(key.begin(), key.end(), face.begin(), face.end())) expected.erase(key);
            }
        }
        ASSERT_EQ(found, 1) << "sphere " << k << " is not above one triangle's interior";
    }
    ASSERT_EQ(expected.size(), cube.tetrahedra.size() - 2);
    s->step();  // detection at the step's start, carving at its end
    const Vec3Object& y = tchg_state(*s);
    EXPECT_EQ(tchg_sorted(s->topology_container("volume").mesh().tetrahedra(), y.rest_position, cube.points), expected);
}

/// A change file in a fresh folder (its path).
std::string tchg_change_file(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "penalty_topological_changes";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / name) << text;
    return (dir / name).string();
}

std::string tchg_processor_scene(const std::string& processor) {
    const test::TetraCube cube = test::tetra_cube(1, 1.0);
    return tchg_body(cube.points, cube.tetrahedra, R"(<EulerImplicitSolver/><CGLinearSolver/>
  <DiagonalMass massDensity="1"/>
  <TetrahedronFEMForceField youngModulus="500" poissonRatio="0.3"/>
  )" + processor);
}

TEST(TopologicalChanges, ProcessorFilesApplyAtTheirTimesAndBadOnesAreRefusedByLine) {
    const std::string good =
        tchg_change_file("good.txt", "T= 0.02\n  REMOVE= 2\n4 0\nT= 0.05\n  ADD= Tetrahedra 1\n0 1 2 3\n");
    auto s = build(tchg_processor_scene(R"(<TopologicalChangeProcessor filename=")" + good + R"("/>)"));
    const MeshTopology& m = s->topology_container("volume").mesh();
    for (int k = 0; k < 2; ++k) s->step();
    EXPECT_EQ(m.tetrahedra().size(), 5u);  // t = 0.01 at the start of the second step
    s->step();
    EXPECT_EQ(m.tetrahedra().size(), 3u);  // t = 0.02: removed
    for (int k = 0; k < 3; ++k) s->step();
    EXPECT_EQ(m.tetrahedra().size(), 4u);  // t = 0.05: added

    EXPECT_THAT(test::error_of(tchg_processor_scene(R"(<TopologicalChangeProcessor filename="/no/such/file.txt"/>)")),
                HasSubstr("attribute 'filename': cannot open /no/such/file.txt"));
    const std::string bad = tchg_change_file("bad.txt", "T= 0.01\n  REMOVE= 2\n1 x\n");
    EXPECT_THAT(test::error_of(tchg_processor_scene(R"(<TopologicalChangeProcessor filename=")" + bad + R"("/>)")),
                HasSubstr("bad.txt:3: 'x' is not an index"));
    const std::string keyword = tchg_change_file("keyword.txt", "T= 0.01\n  ADD= Prisms 1\n1 2 3 4 5 6\n");
    EXPECT_THAT(test::error_of(tchg_processor_scene(R"(<TopologicalChangeProcessor filename=")" + keyword + R"("/>)")),
                HasSubstr("keyword.txt:2: 'ADD= Prisms'"));

    // an element that does not exist (with the fix of SOFA's skipping, below), or one listed twice,
    // when the step comes: the error names the file and line, and nothing of the step is applied
    // (or a new element on a repeated vertex, or degenerate: four corners of the cube's bottom face)
    scene::BuildOptions refusing;
    refusing.sofa_quirk_fixes.fix_topology_removal_out_of_range = true;
    const std::pair<std::string, std::string> late_cases[] = {
        {"T= 0.01\n  REMOVE= 2\n0 9\n", "late.txt:3: tetrahedra 9 does not exist"},
        {"T= 0.01\n  REMOVE= 2\n1 1\n", "late.txt:3: tetrahedra 1 is listed twice"},
        {"T= 0.01\n  ADD= Tetrahedra 2\n0 1 2 7  0 1 2 2\n", "late.txt:3: new tetrahedra 1 uses vertex 2 twice"},
        {"T= 0.01\n  ADD= Tetrahedra 1\n0 1 2 3\n",
         "late.txt:3: the topology '/body/volume': new tetrahedron 0 (0 1 2 3) is degenerate"}};
    for (const auto& [text, expected] : late_cases) {
        const std::string late = tchg_change_file("late.txt", text);
        auto t = build(tchg_processor_scene(R"(<TopologicalChangeProcessor name="cuts" filename=")" + late + R"("/>)"),
                       refusing);
        t->step();
        try {
            t->step();
            ADD_FAILURE() << "no error";
        } catch (const io::SceneError& e) {
            EXPECT_THAT(e.what(), HasSubstr("TopologicalChangeProcessor 'cuts': "));
            EXPECT_THAT(e.what(), HasSubstr(expected));
        }
        EXPECT_EQ(t->topology_container("volume").mesh().tetrahedra().size(), 5u);
    }
}

TEST(TopologicalChanges, ProcessorSkipsRemovalsPastTheEndAsSofa) {
    // SOFA's TetrahedronSetTopologyModifier::removeTetrahedra skips an index past the end (a
    // warning) and removes the others: tetrahedron 9 of 5 is dropped, tetrahedron 0 removed
    const std::string late = tchg_change_file("past_end.txt", "T= 0.01\n  REMOVE= 3\n0 9 12\n");
    auto s = build(tchg_processor_scene(R"(<TopologicalChangeProcessor name="cuts" filename=")" + late + R"("/>)"));
    const MeshTopology& m = s->topology_container("volume").mesh();
    // the same mesh as a file removing tetrahedron 0 alone
    const std::string only = tchg_change_file("only_0.txt", "T= 0.01\n  REMOVE= 1\n0\n");
    auto reference = build(tchg_processor_scene(R"(<TopologicalChangeProcessor filename=")" + only + R"("/>)"));
    s->step();
    reference->step();
    testing::internal::CaptureStderr();
    s->step();
    const std::string warning = testing::internal::GetCapturedStderr();
    reference->step();
    ASSERT_EQ(m.tetrahedra().size(), 4u);
    EXPECT_EQ(m.tetrahedra(), reference->topology_container("volume").mesh().tetrahedra());
    EXPECT_EQ(m.num_points(), reference->topology_container("volume").mesh().num_points());
    EXPECT_THAT(
        warning,
        HasSubstr("past_end.txt:3: 2 tetrahedra index(es) past the end of '/body/volume' (5) not removed (9, 12)"));
    EXPECT_THAT(warning, HasSubstr("--fix-sofa-quirk topology_removal_out_of_range"));
}

TEST(TopologicalChanges, WhatCannotFollowIsRefusedByName) {
    // a SubsetMapping's points would lose their input points: no rule yet, the change is refused
    const test::TetraCube cube = test::tetra_cube(1, 1.0);
    const std::string file = tchg_change_file("one.txt", "T= 0.01\n  REMOVE= 1\n0\n");
    const std::string scene = tchg_body(cube.points, cube.tetrahedra, R"(<EulerImplicitSolver/><CGLinearSolver/>
  <UniformMass totalMass="1"/>
  <TopologicalChangeProcessor filename=")" + file + R"("/>
  <Node name="skin">
    <MechanicalObject name="skinDofs" position="0 0 0"/>
    <SubsetMapping name="attach" indices="0"/>
  </Node>)");
    EXPECT_THAT(test::error_of(scene), HasSubstr("SubsetMapping 'attach' (test.scn:"));
    EXPECT_THAT(test::error_of(scene), HasSubstr("does not follow topological changes"));
    // a component without a rule: a projective constraint with a target per point (SOFA's
    // PositionBasedDynamicsProjectiveConstraint has no topology data: its reinit does nothing)
    for (
        const auto& [component, named] : {std::pair<std::string, std::string>{
            R"(<UniformMass totalMass="1"/><PositionBasedDynamicsProjectiveConstraint name="pbd" stiffness="0.5" position=")" +
                test::points_text(cube.points) + "\"/>",
            "PositionBasedDynamicsProjectiveConstraint 'pbd' (test.scn:"}}) {
        const std::string text = tchg_body(cube.points, cube.tetrahedra, R"(<EulerImplicitSolver/><CGLinearSolver/>
  )" + component + R"(<TopologicalChangeProcessor filename=")" + file + R"("/>)");
        EXPECT_THAT(test::error_of(text), HasSubstr(named));
    }

    auto s = build(tchg_body(cube.points, cube.tetrahedra, "<UniformMass totalMass=\"1\"/>"));
    EXPECT_THROW(s->remove_elements("nothing", ElementType::tetrahedron, {0}), std::invalid_argument);
    EXPECT_THROW(s->remove_elements("volume", ElementType::tetrahedron, {5}), std::invalid_argument);
    EXPECT_THROW(s->remove_elements("volume", ElementType::quad, {0}), std::invalid_argument);
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 5u);

    // a carving tool needs a collision model
    EXPECT_THAT(test::error_of(R"(<Node name="root"><CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/>
  <MinProximityIntersection/><CollisionResponse/><CarvingManager active="1"/>
  <Node name="body"><TetrahedronSetTopologyContainer position="0 0 0 1 0 0 0 1 0 0 0 1" tetrahedra="0 1 2 3"/>
    <TetrahedronSetTopologyModifier/><MechanicalObject/><TetrahedronCollisionModel tags="CarvingSurface"/></Node></Node>)"),
                HasSubstr("CarvingManager: attribute 'toolModel': no tool"));
}

/// Volume of tetrahedron t at rest (m³).
double tchg_volume(const Vec3Object& x, const Tetrahedron& t) {
    const auto p = [&](std::size_t k) { return x.rest_position[std::size_t(t[k])]; };
    return std::abs((p(1) - p(0)).dot((p(2) - p(0)).cross(p(3) - p(0)))) / 6.0;
}

TEST(TopologicalChanges, ThousandsOfRemovalsAndAdditionsKeepEveryFollowerConsistent) {
    // 2 560 tetrahedra removed one to three at a time, with re-additions and steps between
    // (the run the asan preset checks); after each operation the state has the
    // topology's points and the lumped mass is ρ times the remaining volume
    const test::TetraCube cube = test::tetra_cube(8, 0.4);
    auto s = build(tchg_body(cube.points, cube.tetrahedra, R"(<EulerImplicitSolver/>
  <CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-12"/>
  <DiagonalMass massDensity="1000"/>
  <TetrahedronFEMForceField youngModulus="5000" poissonRatio="0.3" method="large"/>
  <FixedProjectiveConstraint indices="0 1 2 3 4 5 6 7 8"/>
  <Node name="border">
    <TriangleSetTopologyContainer name="surface"/>
    <TriangleSetTopologyModifier/>
    <Tetra2TriangleTopologicalMapping input="@../volume" output="@surface"/>
    <TriangleCollisionModel/>
  </Node>)"));
    const TopologyContainer& c = s->topology_container("volume");
    Vec3Object& x = tchg_state(*s);
    std::mt19937 rng(5151);
    std::size_t removals = 0, additions = 0;
    for (int round = 0; !c.mesh().tetrahedra().empty(); ++round) {
        const std::size_t n = c.mesh().tetrahedra().size();
        if (round % 7 == 6) {
            // a tetrahedron again on the vertices of one that exists (a duplicate element: allowed)
            const Tetrahedron t = c.mesh().tetrahedra()[std::uniform_int_distribution<std::size_t>(0, n - 1)(rng)];
            s->add_elements("volume", ElementType::tetrahedron, {t.begin(), t.end()});
            ++additions;
        } else {
            std::set<ElementId> picked;
            while (picked.size() < std::min<std::size_t>(n, 1 + std::size_t(round % 3)))
                picked.insert(ElementId(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng)));
            s->remove_elements("volume", ElementType::tetrahedron, {picked.begin(), picked.end()});
            removals += picked.size();
        }
        ASSERT_EQ(x.num_dofs(), c.mesh().num_points()) << "round " << round;
        if (round % 97 == 0) {
            double volume = 0;
            for (const Tetrahedron& t : c.mesh().tetrahedra()) volume += tchg_volume(x, t);
            EXPECT_NEAR(tchg_find<DiagonalMass>(s->simulation().root())->total_mass(), 1000.0 * volume, 1e-9)
                << "round " << round;
            tchg_expect_triangle_models_fresh(*s, "round " + std::to_string(round));
        }
        if (round % 50 == 0) {
            s->step();
            for (const Vec3& p : x.position) ASSERT_TRUE(p.allFinite()) << "round " << round;
        }
    }
    EXPECT_GT(removals, 2560u);
    EXPECT_GT(additions, 100u);
    EXPECT_EQ(x.num_dofs(), 0u);  // every point went with its last tetrahedron
    s->step();
}

TEST(TopologicalChanges, LinePlaneAndPointConstraintsKeepTheirPointsAndProjectAsIfBuiltOnThem) {
    // the same index list on a fixed, a line, a plane and a point constraint: after removals that
    // renumber points, each still names the same points (found by rest position), and the line's
    // projection acts on exactly those
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    const std::string indices = R"(indices="0 1 2 9 13 26")";
    auto s = build(tchg_body(cube.points, cube.tetrahedra,
                             "<UniformMass totalMass=\"1\"/>\n  <FixedProjectiveConstraint " + indices +
                                 "/>\n  <LineProjectiveConstraint direction=\"1 1 0\" " + indices +
                                 "/>\n  <PlaneProjectiveConstraint normal=\"0 0 1\" " + indices +
                                 "/>\n  <PointProjectiveConstraint point=\"0 0 0\" " + indices + "/>"));
    s->remove_elements("volume", ElementType::tetrahedron, {0, 38});  // the only ones on corners 0 and 26
    Node& root = s->simulation().root();
    const auto* fixed = tchg_find<FixedProjectiveConstraint>(root);
    const auto* line = tchg_find<LineProjectiveConstraint>(root);
    const auto* plane = tchg_find<PlaneProjectiveConstraint>(root);
    const auto* point = tchg_find<PointProjectiveConstraint>(root);
    ASSERT_TRUE(fixed && line && plane && point);
    const Vec3Object& x = tchg_state(*s);
    std::set<std::array<double, 3>> kept;
    for (const Index i : fixed->indices()) {
        const Vec3& p = x.rest_position[std::size_t(i)];
        kept.insert({p.x(), p.y(), p.z()});
    }
    EXPECT_EQ(kept.size(), 4u);  // 1, 2, 9, 13 at their rest positions
    EXPECT_EQ(line->indices(), fixed->indices());
    EXPECT_EQ(plane->indices(), fixed->indices());
    EXPECT_EQ(point->indices(), fixed->indices());
    std::vector<Index> sorted = fixed->indices();
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(line->projected_points(), sorted);
    Eigen::VectorXd v = Eigen::VectorXd::Ones(Eigen::Index(3 * x.num_dofs()));
    line->project_response(v);
    for (std::size_t i = 0; i < x.num_dofs(); ++i) {
        const bool on = std::binary_search(sorted.begin(), sorted.end(), Index(i));
        EXPECT_DOUBLE_EQ(v(Eigen::Index(3 * i + 2)), on ? 0.0 : 1.0) << i;  // z leaves the line (1, 1, 0)
    }
}

TEST(TopologicalChanges, ARebuildFromTheTextFollowsBeforeAChangeAndIsRefusedAfter) {
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    auto s = build(tchg_body(cube.points, cube.tetrahedra, R"(<EulerImplicitSolver/>
  <CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <DiagonalMass massDensity="1000"/>
  <TetrahedronFEMForceField youngModulus="5000" poissonRatio="0.3"/>)"));
    s->step();
    // no change yet: reset builds the scene again, and the new scene's components follow changes
    s->reset();
    const double before = tchg_find<DiagonalMass>(s->simulation().root())->total_mass();
    s->remove_elements("volume", ElementType::tetrahedron, {0});  // a corner tetrahedron: its corner point goes
    const TopologyContainer& c = s->topology_container("volume");
    EXPECT_EQ(tchg_state(*s).num_dofs(), c.mesh().num_points());
    EXPECT_EQ(c.mesh().num_points(), cube.points.size() - 1);
    const double after = tchg_find<DiagonalMass>(s->simulation().root())->total_mass();
    EXPECT_NEAR(after, before - 1000.0 * 0.1 * 0.1 * 0.1 / 6.0, 1e-9);  // a corner tetrahedron: a sixth of a cell
    s->step();
    // once changed: the text would undo the cut, so a rebuild is refused and the scene stands
    try {
        s->reset();
        ADD_FAILURE() << "reset after a topological change was accepted";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(), HasSubstr("undo the topological changes"));
    }
    EXPECT_EQ(tchg_state(*s).num_dofs(), cube.points.size() - 1);
    s->step();
    EXPECT_TRUE(std::isfinite(tchg_state(*s).position[0].x()));
}

}  // namespace
}  // namespace penalty
