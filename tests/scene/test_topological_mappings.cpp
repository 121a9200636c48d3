// The topological mappings wired between dynamic topologies (src/scene/topology/
// topological_mappings.cpp): Tetra2Triangle with its flipNormals and noNewTriangles (against SOFA
// HEAD), Hexa2Quad then Quad2Triangle in a chain, each output equal to the border of what is left;
// a mapping without a rule (Hexa2Tetra) blocks its input, named; a mapping whose output has no
// modifier leaves the output as built while its input changes alone.
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace penalty {
namespace {

Vec3Object& tm_state(scene::Scene& s) { return dynamic_cast<Vec3Object&>(*s.states().at(0).state); }

/// A file of `text` in a fresh folder (its path).
std::string tm_file(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "penalty_topological_mappings";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / name) << text;
    return (dir / name).string();
}

/// The 2×2×2-cell tetrahedral cube (side 0.2 m) fixed at x = 0, a processor removing tetrahedra
/// 0, 4 and 13 at t = 0.02, and a pressure of 50 Pa on its border (Tetra2Triangle with `options`).
std::string tm_pressed_cube(const std::string& options) {
    const std::string file = tm_file("three.txt", "T= 0.02\n  REMOVE= 3\n0 4 13\n");
    return test::fixed_tetra_cube_head("0 0 0") + R"(  <TopologicalChangeProcessor filename=")" + file + R"("/>
  <Node name="border">
    <TriangleSetTopologyContainer name="surface"/>
    <TriangleSetTopologyModifier/>
    <Tetra2TriangleTopologicalMapping input="@../volume" output="@surface" )" +
           options + R"(/>
    <SurfacePressureForceField pressure="50"/>
  </Node>
</Node></Node>
)";
}

/// The faces (sorted vertices) of `elements` that belong to one element only, each with the
/// element's other vertices' centre (to tell the outward side).
template <std::size_t N, std::size_t F>
std::map<std::array<PointId, F>, Vec3> tm_border(const std::vector<std::array<PointId, N>>& elements,
                                                 const std::vector<std::array<int, F>>& faces,
                                                 const std::vector<Vec3>& x) {
    std::map<std::array<PointId, F>, std::pair<int, Vec3>> count;
    for (const auto& e : elements) {
        Vec3 centre = Vec3::Zero();
        for (const PointId p : e) centre += x[std::size_t(p)] / double(N);
        for (const auto& f : faces) {
            std::array<PointId, F> key{};
            for (std::size_t k = 0; k < F; ++k) key[k] = e[std::size_t(f[k])];
            std::sort(key.begin(), key.end());
            auto& [n, c] = count[key];
            ++n;
            c = centre;
        }
    }
    std::map<std::array<PointId, F>, Vec3> out;
    for (const auto& [key, value] : count)
        if (value.first == 1) out.emplace(key, value.second);
    return out;
}

/// +1 when every triangle's normal (right hand) points away from `inside[its vertices]`, −1 when
/// every one points towards it, 0 otherwise.
int tm_orientation(const std::vector<Triangle>& triangles, const std::map<std::array<PointId, 3>, Vec3>& inside,
                   const std::vector<Vec3>& x) {
    int outward = 0, inward = 0;
    for (const Triangle& t : triangles) {
        std::array<PointId, 3> key = t;
        std::sort(key.begin(), key.end());
        const Vec3& a = x[std::size_t(t[0])];
        const Vec3 n = (x[std::size_t(t[1])] - a).cross(x[std::size_t(t[2])] - a);
        (n.dot(a - inside.at(key)) > 0 ? outward : inward) += 1;
    }
    return inward == 0 ? 1 : outward == 0 ? -1 : 0;
}

const std::vector<std::array<int, 3>> kTetraFaces{{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};

// SOFA HEAD (2a278d8), each scene, `sofa-head SCENE 15 OUT --every 1`: point 13 (the centre, which
// every border triangle added by the removal presses) after step 15. The pressure is summed in
// another order than SOFA's: within 1.1e-11 of SOFA HEAD at every step, while the three options
// part by 2.8e-3 to 5.4e-3.
TEST(TopologicalMappingFollowers, Tetra2TriangleFollowsItsInputWithItsOptionsAsSofaHead) {
    struct Case {
        std::string options;
        Vec3 sofa;  // point 13 after step 15
        int orientation;
    };
    const std::vector<Case> cases{
        {"", Vec3(0.10252626148536438, 0.0999343045377387, 0.09997484703712013), 1},
        {R"(flipNormals="1")", Vec3(0.0975086467107494, 0.10007060090130719, 0.1000325211283072), -1},
        {R"(noNewTriangles="1")", Vec3(0.10286886190947228, 0.099930141185445, 0.10028314492761813), 1}};
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    for (const Case& c : cases) {
        auto s = test::build(tm_pressed_cube(c.options));
        const MeshTopology& volume = s->topology_container("volume").mesh();
        const MeshTopology& surface = s->topology_container("surface").mesh();
        const Vec3Object& x = tm_state(*s);
        for (int k = 0; k < 15; ++k) s->step();
        ASSERT_EQ(volume.tetrahedra().size(), 37u) << c.options;
        ASSERT_EQ(x.num_dofs(), 26u) << c.options;  // point 0 went with tetrahedron 0
        EXPECT_LT((x.position[13] - c.sofa).lpNorm<Eigen::Infinity>(), 1.1e-11) << c.options;
        // the output: the border of the tetrahedra left, or (noNewTriangles) the border as built
        // less the removed tetrahedra's faces; outward, or inward with flipNormals
        const auto now = tm_border<4, 3>(volume.tetrahedra(), kTetraFaces, x.rest_position);
        std::set<std::array<PointId, 3>> expected, got;
        for (const auto& face : now) expected.insert(face.first);
        if (c.options.find("noNewTriangles") != std::string::npos) {
            // the border as built less the removed tetrahedra's faces (original indices), renamed:
            // point 26 took point 0's index
            expected.clear();
            std::set<std::array<PointId, 3>> removed;
            for (const std::size_t e : {0, 4, 13})
                for (const auto& f : kTetraFaces) {
                    std::array<PointId, 3> key{};
                    for (std::size_t k = 0; k < 3; ++k) key[k] = cube.tetrahedra[e][std::size_t(f[k])];
                    std::sort(key.begin(), key.end());
                    removed.insert(key);
                }
            for (const auto& face : tm_border<4, 3>(cube.tetrahedra, kTetraFaces, cube.points)) {
                if (removed.count(face.first) != 0) continue;
                std::array<PointId, 3> renamed = face.first;
                for (PointId& p : renamed) p = p == 26 ? 0 : p;
                std::sort(renamed.begin(), renamed.end());
                expected.insert(renamed);
            }
            EXPECT_EQ(expected.size(), 48u - 3u - 1u);  // tetrahedron 0's three faces, 13's one
        }
        for (const Triangle& t : surface.triangles()) {
            std::array<PointId, 3> key = t;
            std::sort(key.begin(), key.end());
            got.insert(key);
        }
        EXPECT_EQ(got, expected) << c.options;
        EXPECT_EQ(got.size(), surface.triangles().size()) << c.options;  // none twice
        if (c.options.find("noNewTriangles") == std::string::npos) {
            EXPECT_EQ(tm_orientation(surface.triangles(), now, x.rest_position), c.orientation) << c.options;
        }
    }
}

TEST(TopologicalMappingFollowers, Hexa2QuadThenQuad2TriangleFollowTheHexahedraInAChain) {
    // two unit cubes side by side: 10 border quads, 20 triangles; the first cube goes with its
    // four own points: 6 quads (outward, or inward with flipNormals), 12 triangles
    for (const bool flip : {false, true}) {
        auto s = test::build(std::string(R"(<Node name="root" gravity="0 0 0"><Node name="body">
  <HexahedronSetTopologyContainer name="bricks" position="0 0 0  1 0 0  2 0 0  0 1 0  1 1 0  2 1 0  0 0 1  1 0 1  2 0 1  0 1 1  1 1 1  2 1 1"
    hexahedra="0 1 4 3 6 7 10 9  1 2 5 4 7 8 11 10"/>
  <HexahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="1"/>
  <Node name="skin">
    <QuadSetTopologyContainer name="quads"/>
    <QuadSetTopologyModifier/>
    <Hexa2QuadTopologicalMapping input="@../bricks" output="@quads" flipNormals=")") +
                             (flip ? "1" : "0") + R"("/>
    <Node name="split">
      <TriangleSetTopologyContainer name="triangles"/>
      <TriangleSetTopologyModifier/>
      <Quad2TriangleTopologicalMapping input="@../quads" output="@triangles"/>
    </Node>
  </Node>
</Node></Node>)");
        const MeshTopology& quads = s->topology_container("quads").mesh();
        const MeshTopology& triangles = s->topology_container("triangles").mesh();
        ASSERT_EQ(quads.quads().size(), 10u);
        ASSERT_EQ(triangles.triangles().size(), 20u);
        s->remove_elements("bricks", ElementType::hexahedron, {0});
        const Vec3Object& x = tm_state(*s);
        ASSERT_EQ(x.num_dofs(), 8u);
        ASSERT_EQ(quads.quads().size(), 6u) << flip;
        EXPECT_EQ(triangles.triangles().size(), 12u) << flip;
        // each quad a face of the brick left (x in [1, 2]), its normal along ±(its centre − (1.5, 0.5, 0.5))
        for (const Quad& q : quads.quads()) {
            Vec3 centre = Vec3::Zero();
            for (const PointId p : q) centre += x.rest_position[std::size_t(p)] / 4;
            const Vec3 n = (x.rest_position[std::size_t(q[1])] - x.rest_position[std::size_t(q[0])])
                               .cross(x.rest_position[std::size_t(q[2])] - x.rest_position[std::size_t(q[0])]);
            const Vec3 out = centre - Vec3(1.5, 0.5, 0.5);
            EXPECT_DOUBLE_EQ(out.norm(), 0.5);
            EXPECT_DOUBLE_EQ(n.dot(out), flip ? -0.5 : 0.5);
        }
        // every quad split in two triangles on its vertices
        for (const Quad& q : quads.quads()) {
            std::set<PointId> corners(q.begin(), q.end()), covered;
            int halves = 0;
            for (const Triangle& t : triangles.triangles())
                if (std::all_of(t.begin(), t.end(), [&](PointId p) { return corners.count(p) != 0; })) {
                    ++halves;
                    covered.insert(t.begin(), t.end());
                }
            EXPECT_EQ(halves, 2) << flip;
            EXPECT_EQ(covered, corners) << flip;
        }
    }
}

TEST(TopologicalMappingFollowers, AMappingWithoutARuleBlocksItsInputByName) {
    // Hexa2Tetra between two dynamic topologies: no rule makes its output follow the input
    const std::string text = R"(<Node name="root"><Node name="body">
  <HexahedronSetTopologyContainer name="bricks" position="0 0 0  1 0 0  0 1 0  1 1 0  0 0 1  1 0 1  0 1 1  1 1 1"
    hexahedra="0 1 3 2 4 5 7 6"/>
  <HexahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="1"/>
  <Node name="cut">
    <TetrahedronSetTopologyContainer name="tetrahedra"/>
    <TetrahedronSetTopologyModifier/>
    <Hexa2TetraTopologicalMapping name="split" input="@../bricks" output="@tetrahedra"/>
  </Node>
</Node></Node>)";
    auto s = test::build(text);
    EXPECT_EQ(s->topology_container("tetrahedra").mesh().tetrahedra().size(), 6u);
    try {
        s->remove_elements("bricks", ElementType::hexahedron, {0});
        ADD_FAILURE() << "the removal was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(),
                     "topology '/body/bricks' cannot change: Hexa2TetraTopologicalMapping 'split' (test.scn:10) does "
                     "not follow topological changes");
    }
    EXPECT_EQ(s->topology_container("bricks").mesh().hexahedra().size(), 1u);
    // the output alone may change (nothing maps it on)
    s->remove_elements("tetrahedra", ElementType::tetrahedron, {0});
    EXPECT_EQ(s->topology_container("tetrahedra").mesh().tetrahedra().size(), 5u);
}

TEST(TopologicalMappingFollowers, AnOutputWithoutModifierStaysAsBuiltWhileItsInputChanges) {
    // Tetra2Triangle onto a container without modifier in its node or above (SOFA: no modifier, no
    // change): the input loses an inner tetrahedron, the output keeps its 48 triangles, and only
    // the input is dynamic
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    auto s =
        test::build(R"(<Node name="root"><Node name="body">
  <TetrahedronSetTopologyContainer name="volume" position=")" +
                    test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="1"/>
</Node>
<Node name="border">
  <TriangleSetTopologyContainer name="surface"/>
  <Tetra2TriangleTopologicalMapping input="@/body/volume" output="@surface"/>
  <MechanicalObject name="skin" position="@/body/volume.position"/>
  <TriangleCollisionModel/>
</Node></Node>)");
    EXPECT_EQ(s->dynamic_topologies(), std::vector<std::string>{"/body/volume"});
    s->remove_elements("volume", ElementType::tetrahedron, {4});  // the centre of cell 0: no point goes
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 39u);
    // the collision model on the output reads its 48 triangles still (the cube's border as built)
    ASSERT_EQ(s->collision_models().size(), 1u);
    EXPECT_EQ(s->collision_models()[0].model->size(), 48u);
    EXPECT_EQ((tm_border<4, 3>(cube.tetrahedra, kTetraFaces, cube.points).size()), 48u);
}

}  // namespace
}  // namespace penalty
