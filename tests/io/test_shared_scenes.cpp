// Parses every SOFA scene of ../shared/sofa/scenes, validates it and loads every mesh its physics
// components use. Skipped when the shared folder is absent (the SOFA files are not part of
// this repository).

#include "penalty/io/scene_file.hpp"
#include "penalty/io/scene_mesh.hpp"
#include "penalty/scene/components.hpp"

#include <gtest/gtest.h>
#include "penalty_test/paths.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>

namespace penalty::io {
namespace {

const std::filesystem::path kShared = penalty::test::shared_dir();

struct Counts {
    std::size_t points, edges, triangles, quads, tetrahedra, hexahedra, radii;
    bool operator==(const Counts&) const = default;
};

std::ostream& operator<<(std::ostream& out, const Counts& c) {
    return out << c.points << " points, " << c.edges << " edges, " << c.triangles << " triangles, " << c.quads
               << " quads, " << c.tetrahedra << " tetrahedra, " << c.hexahedra << " hexahedra, " << c.radii << " radii";
}

Counts counts_of(const MeshData& m) {
    return {m.positions.size(),  m.edges.size(),     m.triangles.size(), m.quads.size(),
            m.tetrahedra.size(), m.hexahedra.size(), m.radii.size()};
}

// What SOFA's loaders give for each mesh file the scenes' physics components use (Gmsh with its
// default createSubelements: the missing tetrahedron faces and triangle edges are added).
const std::map<std::string, Counts> kExpected{
    {"mesh/floor.obj", {50, 0, 96, 0, 0, 0, 0}},
    {"mesh/SaladBowl.obj", {706, 0, 1408, 0, 0, 0, 0}},
    {"mesh/torus.obj", {800, 0, 1600, 0, 0, 0, 0}},
    {"mesh/torus_for_collision.obj", {200, 0, 400, 0, 0, 0, 0}},
    {"mesh/torus2_for_collision.obj", {200, 0, 400, 0, 0, 0, 0}},
    {"mesh/torus2_scale3.obj", {800, 0, 1600, 0, 0, 0, 0}},
    {"mesh/dragon.obj", {1190, 0, 2564, 0, 0, 0, 0}},
    {"mesh/frog-push25.obj", {588, 0, 1166, 0, 0, 0, 0}},
    {"mesh/floor2b.obj", {5, 0, 4, 0, 0, 0, 0}},
    {"mesh/torus_low_res.msh", {264, 1330, 1928, 0, 862, 0, 0}},
    {"mesh/torus2_low_res.msh", {264, 1330, 1928, 0, 862, 0, 0}},
    {"mesh/floor.sph", {2520, 0, 0, 0, 0, 0, 2520}},
    {"mesh/smCube27b.sph", {27, 0, 0, 0, 0, 0, 27}},
};

// scene -> number of physics components, of meshes loaded for them, and the ignored summary
struct SceneExpectation {
    std::size_t physics;
    std::size_t meshes;
    std::string summary;
};

const std::map<std::string, SceneExpectation> kScenes{
    {"AdvancedSolversMultipleGroupsSolver.scn",
     {37, 1, "ignored 12 components that do not change the numbers: RequiredPlugin x11, VisualStyle x1"}},
    {"CompositeCollisionPipeline.scn",
     {36, 1, "ignored 13 components that do not change the numbers: RequiredPlugin x12, VisualStyle x1"}},
    {"CompositeCollisionPipeline_none.scn",
     {30, 1, "ignored 13 components that do not change the numbers: RequiredPlugin x12, VisualStyle x1"}},
    {"Gravity.scn",
     {42, 4,
      "ignored 25 components that do not change the numbers: BarycentricMapping (visual output) x2, MeshOBJLoader "
      "(visual only) "
      "x4, OglModel x4, RequiredPlugin x15"}},
    {"MeshSpringForceField.scn",
     {49, 9,
      "ignored 27 components that do not change the numbers: BarycentricMapping (visual output) x4, MeshOBJLoader "
      "(visual only) "
      "x5, OglModel x5, RequiredPlugin x13"}},
    {"ModelizationSphereBased.scn",
     {16, 1, "ignored 12 components that do not change the numbers: RequiredPlugin x11, VisualStyle x1"}},
    {"ModelizationTriangleBased.scn",
     {18, 1, "ignored 12 components that do not change the numbers: RequiredPlugin x11, VisualStyle x1"}},
    {"MultipleObjectsTwoCubes.scn",
     {25, 1, "ignored 12 components that do not change the numbers: RequiredPlugin x11, VisualStyle x1"}},
    {"RegularGridSpringForceField.scn",
     {49, 5,
      "ignored 28 components that do not change the numbers: BarycentricMapping (visual output) x4, MeshOBJLoader "
      "(visual only) "
      "x5, OglModel x5, RequiredPlugin x14"}},
    {"SphereModel.scn",
     {17, 2,
      "ignored 21 components that do not change the numbers: MeshOBJLoader (visual only) x2, OglModel x2, "
      "RequiredPlugin x14, "
      "SubsetMapping (visual output) x1, VisualStyle x2"}},
    {"collisionMultiple.scn",
     {47, 4,
      "ignored 34 components that do not change the numbers: BarycentricMapping (visual output) x6, MeshOBJLoader "
      "(visual only) "
      "x7, OglModel x7, RequiredPlugin x14"}},
};

TEST(SharedScenes, EverySceneParsesValidatesAndLoadsItsMeshes) {
    const std::filesystem::path scenes = kShared / "sofa" / "scenes";
    if (!std::filesystem::is_directory(scenes)) GTEST_SKIP() << "no shared SOFA scenes at " << scenes;
    const std::vector<std::filesystem::path> data_dirs{kShared / "sofa"};

    std::size_t scene_count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(scenes)) {
        if (entry.path().extension() != ".scn") continue;
        ++scene_count;
        const std::string name = entry.path().filename().string();
        SCOPED_TRACE(name);
        const SceneFile scene = parse_scene_file(entry.path());
        const scene::SceneCheck check = scene::validate(scene);

        // meshes used by physics: linked loaders, and MeshTopology filename=
        std::vector<const SceneComponent*> mesh_sources = check.loaders;
        for (const SceneComponent* c : check.physics) {
            if (c->type == "MeshTopology" && c->has("filename")) mesh_sources.push_back(c);
        }
        for (const SceneComponent* c : mesh_sources) {
            const std::string file = *get_string(*c, "filename");
            SCOPED_TRACE(c->describe() + " " + file);
            const MeshData mesh = load_scene_mesh(*c, scene.directory(), data_dirs);
            const auto expected = kExpected.find(file);
            ASSERT_NE(expected, kExpected.end());
            EXPECT_EQ(counts_of(mesh), expected->second);
        }

        const auto expected = kScenes.find(name);
        ASSERT_NE(expected, kScenes.end()) << "new scene: " << check.physics.size() << " physics, "
                                           << mesh_sources.size() << " meshes, " << check.summary;
        EXPECT_EQ(check.physics.size(), expected->second.physics);
        EXPECT_EQ(mesh_sources.size(), expected->second.meshes);
        EXPECT_EQ(check.summary, expected->second.summary);
    }
    EXPECT_EQ(scene_count, kScenes.size());
}

TEST(SharedScenes, FloorGeometryMatchesTheSpecification) {
    const std::filesystem::path floor = kShared / "sofa" / "mesh" / "floor.obj";
    if (!std::filesystem::is_regular_file(floor)) GTEST_SKIP() << "no shared SOFA meshes";
    const MeshData m = load_obj(floor);
    // spec §12: a slab |x|, |z| <= 74.67 between y = -5.33 and the top face y = -1.32967
    double top = -1e300, bottom = 1e300, extent = 0.0;
    for (const Vec3& p : m.positions) {
        top = std::max(top, p.y());
        bottom = std::min(bottom, p.y());
        extent = std::max({extent, std::abs(p.x()), std::abs(p.z())});
    }
    EXPECT_NEAR(top, -1.32967, 1e-5);
    EXPECT_NEAR(bottom, -5.33, 5e-3);
    EXPECT_NEAR(extent, 74.67, 5e-3);
}

}  // namespace
}  // namespace penalty::io
