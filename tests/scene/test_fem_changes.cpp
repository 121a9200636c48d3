// The FEM force fields follow topological changes (mechanics/topology/fem_changes.cpp): corotational,
// triangle and hyperelastic FEM equal the same force fields built afresh on the changed mesh.
#include "topological_change_scenes.hpp"

namespace penalty {
namespace {

using namespace test_topology_scenes;

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

}  // namespace
}  // namespace penalty
