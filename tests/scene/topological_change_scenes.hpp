#pragma once
// The scenes and checks of the topological-change tests (test_topological_changes.cpp,
// test_fem_changes.cpp, test_triangle_model_changes.cpp, test_carving_manager.cpp,
// test_topological_change_processor.cpp, test_wiring.cpp): tetrahedral bodies, a ball over a sheet,
// the carving scene, change files, and comparisons with components built afresh.
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

namespace penalty::test_topology_scenes {

using test::build;
using ::testing::HasSubstr;

/// The first object of type T in the graph (a mass, force field or constraint).
template <class T>
inline T* tchg_find(Node& n) {
    if (auto* m = dynamic_cast<T*>(n.mass())) return m;
    for (const auto& f : n.force_fields())
        if (auto* t = dynamic_cast<T*>(f.get())) return t;
    for (const auto& k : n.constraints())
        if (auto* t = dynamic_cast<T*>(k.get())) return t;
    for (const auto& child : n.children())
        if (T* t = tchg_find<T>(*child)) return t;
    return nullptr;
}

inline Vec3Object& tchg_state(scene::Scene& s, std::size_t k = 0) {
    auto* v = dynamic_cast<Vec3Object*>(s.states().at(k).state);
    EXPECT_NE(v, nullptr);
    return *v;
}

/// A tetrahedral body: container + modifier + state + `components`.
inline std::string tchg_body(const std::vector<Vec3>& points, const std::vector<Tetrahedron>& tets,
                             const std::string& components) {
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="body">
  <TetrahedronSetTopologyContainer name="volume" position=")" +
           test::points_text(points) + R"(" tetrahedra=")" + test::elements_text(tets) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  )" + components +
           "\n</Node></Node>\n";
}

inline Eigen::MatrixXd tchg_stiffness(const BaseForceField& ff, std::size_t dofs) {
    TripletList t;
    ff.add_stiffness(
        t, [](const BaseState*) { return Index(0); }, 1.0);
    SparseMatrix k(Eigen::Index(3 * dofs), Eigen::Index(3 * dofs));
    k.setFromTriplets(t.begin(), t.end());
    return Eigen::MatrixXd(k);
}

/// A ball (a sphere of radius r, UniformMass, implicit solver) above a fixed sheet of triangles
/// whose container can change.
inline std::string tchg_ball_over_sheet(const test::TriangleSheet& sheet, double radius, const Vec3& ball) {
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

inline double tchg_ball_height(scene::Scene& s) {
    for (const auto& r : s.states())
        if (r.state->state_name() == "ballDofs")
            if (const auto* ball = dynamic_cast<const Vec3Object*>(r.state); ball != nullptr && !ball->position.empty())
                return ball->position.front().y();
    ADD_FAILURE() << "no ball";
    return 0;
}

/// The scene's triangle collision models equal models built fresh on their changed topologies:
/// the same triangles in the same slots, the same flags (who owns each vertex and edge, the
/// border edges), the same counts.
inline void tchg_expect_triangle_models_fresh(const scene::Scene& s, const std::string& when) {
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

/// The cube of tetrahedra with its border (Tetra2Triangle) tagged CarvingSurface, and a tool of
/// spheres (one per point of `tool`) tagged CarvingTool; no gravity.
inline std::string tchg_carving_scene(const test::TetraCube& cube, const std::vector<Vec3>& tool, double radius,
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

inline std::set<std::array<PointId, 4>> tchg_sorted(const std::vector<Tetrahedron>& tets,
                                                    const std::vector<Vec3>& points,
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

/// A change file in a fresh folder (its path).
inline std::string tchg_change_file(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "penalty_topological_changes";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / name) << text;
    return (dir / name).string();
}

inline std::string tchg_processor_scene(const std::string& processor) {
    const test::TetraCube cube = test::tetra_cube(1, 1.0);
    return tchg_body(cube.points, cube.tetrahedra, R"(<EulerImplicitSolver/><CGLinearSolver/>
  <DiagonalMass massDensity="1"/>
  <TetrahedronFEMForceField youngModulus="500" poissonRatio="0.3"/>
  )" + processor);
}

/// Volume of tetrahedron t at rest (m³).
inline double tchg_volume(const Vec3Object& x, const Tetrahedron& t) {
    const auto p = [&](std::size_t k) { return x.rest_position[std::size_t(t[k])]; };
    return std::abs((p(1) - p(0)).dot((p(2) - p(0)).cross(p(3) - p(0)))) / 6.0;
}

}  // namespace penalty::test_topology_scenes
