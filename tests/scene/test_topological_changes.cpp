// Topological changes in built scenes (docs/topological-changes.md): each component after removals
// equals the same component built on the reduced mesh (masses, forces, stiffness; finite
// differences), fixed points stay the same points, a ball falls through a hole cut in a sheet,
// contacts on removed triangles end, thousands of removals and additions keep every follower
// consistent, a rebuild from the text follows before a change.
#include "topological_change_scenes.hpp"

namespace penalty {
namespace {

using namespace test_topology_scenes;

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
