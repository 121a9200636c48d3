// MeshMatrixMass, MeshSpringForceField and BarycentricMapping following tetrahedron removals
// (docs/topological-changes.md, "What follows"): the mass equals the same mass built on the
// remaining mesh, the springs are SOFA HEAD's (those on a removed point leave, the others stay
// with their points), and the mapping maps every output point again onto the remaining
// tetrahedra (SOFA's clear + init), which leaves the mapped positions where they were; a removal
// that would leave it no tetrahedron is refused beforehand.
#include "penalty/mechanics/diagonal_mass.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/mesh_matrix_mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <set>

namespace penalty {
namespace {

template <class T>
T* msm_find(Node& n) {
    if (auto* m = dynamic_cast<T*>(n.mass())) return m;
    for (const auto& f : n.force_fields())
        if (auto* t = dynamic_cast<T*>(f.get())) return t;
    if (auto* m = dynamic_cast<T*>(n.mapping())) return m;
    for (const auto& child : n.children())
        if (T* t = msm_find<T>(*child)) return t;
    return nullptr;
}

std::string msm_body(const std::vector<Vec3>& points, const std::vector<Tetrahedron>& tets,
                     const std::string& components) {
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="body">
  <EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-12"/>
  <TetrahedronSetTopologyContainer name="volume" position=")" +
           test::points_text(points) + R"(" tetrahedra=")" + test::elements_text(tets) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  )" + components +
           "\n</Node></Node>\n";
}

Vec3Object& msm_state(scene::Scene& s, std::size_t k = 0) { return *dynamic_cast<Vec3Object*>(s.states().at(k).state); }

/// Tetrahedra 0 and 38 hold corners 0 and 26 alone (their removal removes and renumbers points);
/// 5 and 17 are inside.
const std::vector<ElementId> kMsmRemoved{0, 38, 17, 5};

TEST(MassSpringMappingFollowers, MeshMatrixMassEqualsTheMassBuiltOnTheRemainingMesh) {
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    for (const std::string lumping : {"0", "1"}) {
        SCOPED_TRACE("lumping " + lumping);
        const std::string mass = R"(<MeshMatrixMass massDensity="1000" lumping=")" + lumping + R"("/>)";
        auto s = test::build(msm_body(cube.points, cube.tetrahedra, mass));
        s->remove_elements("volume", ElementType::tetrahedron, kMsmRemoved);
        const MeshTopology& mesh = s->topology_container("volume").mesh();
        const Vec3Object& x = msm_state(*s);
        auto fresh = test::build(msm_body(x.rest_position, mesh.tetrahedra(), mass));
        const auto* a = msm_find<MeshMatrixMass>(s->simulation().root());
        const auto* b = msm_find<MeshMatrixMass>(fresh->simulation().root());
        ASSERT_TRUE(a && b);
        ASSERT_EQ(a->vertex_masses().size(), b->vertex_masses().size());
        for (std::size_t i = 0; i < b->vertex_masses().size(); ++i)
            EXPECT_NEAR(a->vertex_masses()[i], b->vertex_masses()[i], 1e-13) << i;
        // edges by their vertices (the fresh container numbers them in its own order)
        const auto by_edge = [](const MeshTopology& m, const std::vector<double>& values) {
            std::map<std::pair<PointId, PointId>, double> out;
            for (std::size_t e = 0; e < values.size(); ++e)
                out[{std::min(m.edges()[e][0], m.edges()[e][1]), std::max(m.edges()[e][0], m.edges()[e][1])}] =
                    values[e];
            return out;
        };
        const auto ea = by_edge(mesh, a->edge_masses());
        const auto eb = by_edge(fresh->topology_container("volume").mesh(), b->edge_masses());
        ASSERT_EQ(ea.size(), eb.size());
        for (const auto& [edge, m] : eb) EXPECT_NEAR(ea.at(edge), m, 1e-13);
        // closed form: ρ × the remaining volume (the cube less four tetrahedra of 1/6 or 1/3 of a cell)
        double removed = 0;
        for (const ElementId t : kMsmRemoved) {
            const auto& tet = cube.tetrahedra[std::size_t(t)];
            const auto p = [&](int k) { return cube.points[std::size_t(tet[std::size_t(k)])]; };
            removed += std::abs((p(1) - p(0)).dot((p(2) - p(0)).cross(p(3) - p(0)))) / 6;
        }
        EXPECT_NEAR(a->total_mass(), 1000 * (0.008 - removed), 1e-12);
        EXPECT_NEAR(a->total_mass(), b->total_mass(), 1e-12);
    }
}

TEST(MassSpringMappingFollowers, DiagonalMassTakesItsTotalAndDensityFromItsVertexMassesAtTheNextStep) {
    // SOFA's DiagonalMass::doUpdateInternal: a point removal edits vertexMass after the callbacks,
    // so the next step's UpdateInternalDataVisitor runs initFromVertexMass: totalMass = Σ m_i,
    // ρ = totalMass / Σ(shares at ρ = 1); the masses stay
    const test::TetraCube cube = test::tetra_cube(2, 0.3);
    auto s = test::build(msm_body(cube.points, cube.tetrahedra, R"(<DiagonalMass massDensity="0.7"/>)"));
    auto* mass = dynamic_cast<DiagonalMass*>(s->simulation().root().children()[0]->mass());
    ASSERT_NE(mass, nullptr);
    s->remove_elements("volume", ElementType::tetrahedron, kMsmRemoved);
    const std::vector<double> masses = mass->vertex_masses();
    s->step();
    EXPECT_EQ(mass->vertex_masses(), masses);
    const double total = std::accumulate(masses.begin(), masses.end(), 0.0);
    EXPECT_EQ(mass->total_mass(), total);
    std::vector<double> unit;
    const Vec3Object& x = msm_state(*s);
    const double sum = lump_vertex_masses(s->topology_container("volume").mesh(), LumpedElementKind::tetrahedron,
                                          x.rest_position, 1.0, x.num_dofs(), unit);
    EXPECT_EQ(mass->mass_density(), total / sum);
    EXPECT_NEAR(mass->mass_density(), 0.7, 1e-14);
}

TEST(MassSpringMappingFollowers, MeshSpringsOnARemovedPointLeaveAndTheOthersKeepTheirPoints) {
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    auto s = test::build(msm_body(cube.points, cube.tetrahedra, R"(<UniformMass totalMass="1"/>
  <MeshSpringForceField tetrahedraStiffness="100" tetrahedraDamping="0.1"/>)"));
    auto* springs = msm_find<SpringForceField>(s->simulation().root());
    ASSERT_NE(springs, nullptr);
    const Vec3Object& x = msm_state(*s);
    using Ends = std::set<std::array<double, 3>>;
    const auto ends = [&](const Spring& sp) {
        const Vec3& a = x.rest_position[std::size_t(sp.a)];
        const Vec3& b = x.rest_position[std::size_t(sp.b)];
        return Ends{{a.x(), a.y(), a.z()}, {b.x(), b.y(), b.z()}};
    };
    std::vector<Ends> before_removal;
    for (const Spring& sp : springs->springs()) before_removal.push_back(ends(sp));
    const std::size_t before = springs->springs().size();
    s->remove_elements("volume", ElementType::tetrahedron, kMsmRemoved);
    // the points that remain (by rest position): corners 0, 2 and 26 went with their only tetrahedra
    std::set<std::array<double, 3>> remaining;
    for (const Vec3& p : x.rest_position) remaining.insert({p.x(), p.y(), p.z()});
    EXPECT_EQ(remaining.size(), 24u);
    std::multiset<Ends> expected;
    for (const Ends& e : before_removal)
        if (std::all_of(e.begin(), e.end(), [&](const auto& p) { return remaining.count(p) == 1; })) expected.insert(e);
    std::multiset<Ends> kept;
    for (const Spring& sp : springs->springs()) {
        EXPECT_LT(std::size_t(std::max(sp.a, sp.b)), x.num_dofs());
        kept.insert(ends(sp));
    }
    EXPECT_EQ(kept, expected);
    EXPECT_LT(kept.size(), before);
    for (int k = 0; k < 3; ++k) s->step();  // and the springs still act
    for (const Vec3& p : x.position) EXPECT_TRUE(p.allFinite());
}

TEST(MassSpringMappingFollowers, BarycentricMappingMapsItsPointsAgainOntoTheRemainingTetrahedra) {
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    // skin points: the centre of tetrahedron 0 (removed), of 17 (removed), of 20, and one outside
    std::vector<Vec3> skin;
    for (const int t : {0, 17, 20}) {
        Vec3 c = Vec3::Zero();
        for (const PointId p : cube.tetrahedra[std::size_t(t)]) c += cube.points[std::size_t(p)] / 4;
        skin.push_back(c);
    }
    skin.push_back(Vec3(0.25, 0.1, 0.1));
    auto s = test::build(msm_body(cube.points, cube.tetrahedra,
                                  R"(<DiagonalMass massDensity="1000"/>
  <TetrahedronFEMForceField youngModulus="5000" poissonRatio="0.3"/>
  <FixedProjectiveConstraint indices="0 1 2"/>
  <Node name="skin"><MechanicalObject name="skinDofs" position=")" +
                                      test::points_text(skin) + R"("/><BarycentricMapping name="attach"/></Node>)"));
    for (int k = 0; k < 5; ++k) s->step();
    auto* mapping = msm_find<BarycentricMapping>(s->simulation().root());
    ASSERT_NE(mapping, nullptr);
    const auto* in = dynamic_cast<const Vec3Object*>(mapping->from());
    auto* out = dynamic_cast<Vec3Object*>(mapping->to());
    ASSERT_TRUE(in && out);
    const std::vector<Vec3> mapped = out->position;

    s->remove_elements("volume", ElementType::tetrahedron, kMsmRemoved);
    // the rows are a fresh mapping of the current output positions onto the current tetrahedra
    BarycentricMapping fresh(const_cast<Vec3Object&>(*in), *out);
    fresh.map_on_set_tetrahedra(s->topology_container("volume").mesh(), in->position, mapped);
    ASSERT_EQ(mapping->weights().size(), fresh.weights().size());
    for (std::size_t i = 0; i < fresh.weights().size(); ++i) {
        ASSERT_EQ(mapping->weights()[i].count, fresh.weights()[i].count) << i;
        for (int k = 0; k < fresh.weights()[i].count; ++k) {
            EXPECT_EQ(mapping->weights()[i].entries[std::size_t(k)].index,
                      fresh.weights()[i].entries[std::size_t(k)].index);
            EXPECT_EQ(mapping->weights()[i].entries[std::size_t(k)].weight,
                      fresh.weights()[i].entries[std::size_t(k)].weight);
        }
    }
    // an affine map of the points it was made from: the mapped positions stay where they were
    std::vector<Vec3> again(mapped.size());
    mapping->apply(again, in->position);
    for (std::size_t i = 0; i < mapped.size(); ++i) EXPECT_NEAR((again[i] - mapped[i]).norm(), 0.0, 1e-14) << i;
    for (int k = 0; k < 5; ++k) s->step();
    for (const Vec3& p : out->position) EXPECT_TRUE(p.allFinite());
}

}  // namespace
}  // namespace penalty

namespace penalty {
namespace {

/// A 5-tetrahedron cube with a BarycentricMapping child and `changer` in the body's node.
std::string msm_mapped_cube(const std::string& changer) {
    const test::TetraCube cube = test::tetra_cube(1, 1.0);
    return msm_body(cube.points, cube.tetrahedra, R"(<DiagonalMass massDensity="1"/>
  )" + changer + R"(
  <Node name="skin"><MechanicalObject position="0.5 0.5 0.5  0.2 0.3 0.1"/><BarycentricMapping name="attach"/></Node>)");
}

std::string msm_change_file(const std::string& name, const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() / ("penalty_msm_" + name);
    std::ofstream(path) << text;
    return path.string();
}

TEST(MassSpringMappingFollowers, RemovingTheLastTetrahedraUnderABarycentricMappingIsRefusedBeforehand) {
    // SOFA's BarycentricMapperTopologyContainer::init over no element divides by zero (its hash
    // grid's cell size) and maps every point onto element -1: penalty refuses the removal, names the
    // mapping, and changes nothing, on every path a change comes by
    const std::string why = "the removal leaves no tetrahedra, and BarycentricMapping 'attach'";
    {  // the scene API (and Python's remove_elements, SofaPython3's removeTetrahedra through it)
        auto s = test::build(msm_mapped_cube(""));
        try {
            s->remove_elements("volume", ElementType::tetrahedron, {4, 3, 2, 1, 0});
            ADD_FAILURE() << "no error";
        } catch (const std::invalid_argument& e) {
            EXPECT_THAT(e.what(), ::testing::HasSubstr(why));
        }
        EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 5u);
        s->remove_elements("volume", ElementType::tetrahedron, {4, 3, 2, 0});  // one left: maps onto it
        EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 1u);
        s->step();
        for (std::size_t k = 0; k < 2; ++k) {
            const auto* state = dynamic_cast<const Vec3Object*>(s->states().at(k).state);
            ASSERT_NE(state, nullptr);
            for (const Vec3& p : state->position) EXPECT_TRUE(p.allFinite());
        }
    }
    // a change file: the second removal of the step takes the last ones (file and line named)
    const std::string file = msm_change_file("last.txt", "T= 0.01\n  REMOVE= 2\n4 3\n  REMOVE= 3\n0 1 2\n");
    const std::string dataInputs =
        R"(<TopologicalChangeProcessor useDataInputs="1" timeToRemove="0.005" tetrahedraToRemove="0 1 2 3 4"/>)";
    for (const std::string& changer : {R"(<TopologicalChangeProcessor filename=")" + file + R"("/>)", dataInputs}) {
        auto s = test::build(msm_mapped_cube(changer));
        s->step();
        try {
            s->step();
            ADD_FAILURE() << "no error";
        } catch (const io::SceneError& e) {
            EXPECT_THAT(e.what(), ::testing::HasSubstr(why));
            EXPECT_THAT(e.what(),
                        ::testing::HasSubstr(changer == dataInputs ? "TopologicalChangeProcessor: " : "last.txt:5: "));
        }
        EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 5u);
    }
    // useDataInputs: the second list names a tetrahedron the first one's removal leaves out of
    // range; nothing of the step is applied
    auto s = test::build(msm_mapped_cube(
        R"(<TopologicalChangeProcessor name="cuts" useDataInputs="1" timeToRemove="0.005" tetrahedraToRemove="0" trianglesToRemove="4"/>)"));
    s->step();
    try {
        s->step();
        ADD_FAILURE() << "no error";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(
            e.what(),
            ::testing::HasSubstr(
                "TopologicalChangeProcessor 'cuts': tetrahedra 4 does not exist (the topology '/body/volume' has 4)"));
    }
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 5u);
}

TEST(MassSpringMappingFollowers, CarvingTheLastTetrahedronUnderABarycentricMappingIsRefused) {
    // one tetrahedron with its border as the carving surface and a sphere tool touching its bottom
    // face: the carving of the step would remove it, and the mapped skin would have no element
    const std::string scene = R"(<Node name="root" gravity="0 0 0" dt="0.01">
  <CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/>
  <MinProximityIntersection alarmDistance="0.1" contactDistance="0.01"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <CarvingManager name="carver" active="1" carvingDistance="0"/>
  <Node name="body">
    <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    <TetrahedronSetTopologyContainer name="volume" position="0 0 0  1 0 0  0 1 0  0 0 1" tetrahedra="0 1 2 3"/>
    <TetrahedronSetTopologyModifier/><MechanicalObject/><UniformMass totalMass="1"/>
    <Node name="surface">
      <TriangleSetTopologyContainer name="border"/><TriangleSetTopologyModifier/>
      <Tetra2TriangleTopologicalMapping input="@../volume" output="@border"/>
      <TriangleCollisionModel tags="CarvingSurface"/>
    </Node>
    <Node name="skin"><MechanicalObject position="0.2 0.2 0.2"/><BarycentricMapping name="attach"/></Node>
  </Node>
  <Node name="tool"><MechanicalObject position="0.25 0.25 -0.025"/><SphereCollisionModel radius="0.02" tags="CarvingTool"/></Node>
</Node>)";
    auto s = test::build(scene);
    try {
        s->step();
        ADD_FAILURE() << "no error";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(),
                    ::testing::HasSubstr("CarvingManager 'carver': topology '/body/volume': the removal leaves no "
                                         "tetrahedra, and BarycentricMapping 'attach'"));
    }
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 1u);
}

TEST(MassSpringMappingFollowers, SetContainersMapOutsidePointsAsSofasHashGrid) {
    // two tetrahedra A (vertices 0-3) and B (4-7) and a point outside both, nearer A's centre but
    // in B's hash cell (Mapping.BarycentricOnSetTetrahedraKeepsAnElementOfThePointsHashCell); a
    // force on A's vertex 1. SOFA HEAD after one step (SofaPython3, the same scene): through a
    // TetrahedronSetTopologyContainer the point follows B (it does not move), through a
    // MeshTopology it follows A; both to the bit.
    const std::map<std::string, Vec3> sofa{
        {"TetrahedronSetTopologyContainer", Vec3(0.019999999999999962, 0.5, 0.45)},
        {"MeshTopology", Vec3(0.0199999999999999, 0.5566101694915254, 0.44999999999999996)}};
    for (const auto& [container, expected] : sofa) {
        auto s = test::build(R"(<Node name="root" gravity="0 0 0" dt="0.01"><Node name="body">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <)" + container + R"( name="volume" tetrahedra="0 1 2 3 4 5 6 7" position="-0.6 0.3 0.3  -0.01 0.3 0.3  -0.2 0.9 0.3
    -0.19 0.5 0.9  0.15 0.1 0.3  0.7 0.1 0.3  0.4 0.1 0.75  0.35 0.9 0.45"/>
  <MechanicalObject/><UniformMass totalMass="1"/><ConstantForceField indices="1" forces="0 100 0"/>
  <Node name="skin"><MechanicalObject position="0.02 0.5 0.45"/><BarycentricMapping/></Node>
</Node></Node>)");
        s->step();
        const auto* skin = dynamic_cast<const Vec3Object*>(s->states().at(1).state);
        ASSERT_TRUE(skin != nullptr && skin->position.size() == 1);
        const Vec3& p = skin->position[0];
        for (int k = 0; k < 3; ++k) EXPECT_EQ(p[k], expected[k]) << container << " coordinate " << k;
    }
}

}  // namespace
}  // namespace penalty
