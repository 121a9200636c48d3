// SparseGridMultipleTopology and SparseGridRamificationTopology in a scene: two nested cubes
// (OBJ files written here) on unit cells over [0, 6]³, their stiffness and mass coefficients in
// HexahedronFEMForceFieldAndMass (total mass in closed form), a BarycentricMapping onto the grid,
// and the errors naming file, line, component and attribute.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/hexahedral_fem.hpp"
#include "penalty/scene/scene.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {

using namespace penalty;

struct NestedCubesFolder {
    std::filesystem::path dir;
    explicit NestedCubesFolder(const std::string& name)
        : dir(std::filesystem::temp_directory_path() /
              ("penalty_sparse_grid_multiple_" + name + "_" +
               std::to_string(::testing::UnitTest::GetInstance()->random_seed()))) {
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
        write_cube("outer.obj", 0.5, 5.0);
        write_cube("inner.obj", 1.5, 3.0);
    }
    NestedCubesFolder(const NestedCubesFolder&) = delete;
    NestedCubesFolder& operator=(const NestedCubesFolder&) = delete;
    ~NestedCubesFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(dir, ignored);
    }
    void write_cube(const char* file, double corner, double size) const {
        std::ofstream out(dir / file);
        for (int k = 0; k < 8; ++k)
            out << "v " << corner + size * (k & 1) << ' ' << corner + size * ((k >> 1) & 1) << ' '
                << corner + size * ((k >> 2) & 1) << '\n';
        out << "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 "
               "8 6\n";
    }
    [[nodiscard]] std::filesystem::path scene(const std::string& grid) const {
        std::ofstream(dir / "scene.scn") << R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <Node name="Cubes">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    )" << grid << R"(
    <MechanicalObject name="grid"/>
    <HexahedronFEMForceFieldAndMass youngModulus="1000" poissonRatio="0.3" density="2"/>
    <Node name="Points">
      <MechanicalObject name="points" position="0.7 0.55 0.71  3 3 3  5.2 1.5 4.5"/>
      <BarycentricMapping/>
    </Node>
  </Node>
</Node>
)";
        return dir / "scene.scn";
    }
};

const std::string kNestedCubesGrid =
    R"(<SparseGridMultipleTopology min="0 0 0" max="6 6 6" fileTopologies="outer.obj inner.obj" )"
    R"(stiffnessCoefs="10 0.2" massCoefs="3 5" finestConnectivity="0" )";

std::string nested_cubes_build_error(const std::filesystem::path& scene) {
    try {
        (void)scene::build_scene(io::parse_scene_file(scene));
    } catch (const std::exception& e) {
        return e.what();
    }
    return "no error";
}

TEST(SparseGridMultipleComponents, MassCoefficientsGiveTheClosedFormTotalMassOnEveryLevel) {
    const NestedCubesFolder folder("mass");
    // unit cells: 152 outer-BOUNDARY cells (mass coefficient 3/2), 56 cells on the inner cube's
    // boundary ((3 + 5)/2), 8 inside it (5): total density·(228 + 224 + 40) = 984; a coarser level
    // averages 8 children over a cell 8 times bigger, the same total
    for (const std::string levels : {R"(n="7 7 7"/>)", R"(n="4 4 4" nbVirtualFinerLevels="1"/>)"}) {
        auto scene = scene::build_scene(io::parse_scene_file(folder.scene(kNestedCubesGrid + levels)));
        const Node& cubes = *scene->simulation().root().children().at(0);
        auto* mass = dynamic_cast<HexahedronElementMass*>(cubes.mass());
        ASSERT_NE(mass, nullptr) << levels;
        EXPECT_NEAR(mass->total_mass(), 984.0, 1e-9) << levels;
        // the stiffness factors are the stiffness coefficients, not the mass ones
        auto* ff = dynamic_cast<HexahedronFEMForceField*>(cubes.force_fields().at(0).get());
        ASSERT_NE(ff, nullptr);
        double stiffness_sum = 0;
        for (const double f : ff->stiffness_factors()) stiffness_sum += f;
        const double unit_cells_sum = 152 * 5.0 + 56 * double((10.0f + 0.2f) * 0.5f) + 8 * double(0.2f);
        EXPECT_NEAR(stiffness_sum * (ff->stiffness_factors().size() == 27 ? 8 : 1), unit_cells_sum, 1e-4) << levels;
        const Node& points = *cubes.children().at(0);
        auto* mapped = dynamic_cast<Vec3Object*>(points.state());
        ASSERT_NE(mapped, nullptr);
        const std::vector<Vec3> given{{0.7, 0.55, 0.71}, {3, 3, 3}, {5.2, 1.5, 4.5}};
        for (std::size_t i = 0; i < given.size(); ++i)
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(mapped->position[i][k], given[i][k], 1e-12) << i << levels;
        for (int i = 0; i < 3; ++i) scene->step();
        auto* grid = dynamic_cast<Vec3Object*>(cubes.state());
        ASSERT_NE(grid, nullptr);
        for (const Vec3& p : grid->position) EXPECT_TRUE(p.allFinite());
        EXPECT_LT(grid->position[0].y(), 0.0);  // falling
    }
}

TEST(SparseGridMultipleComponents, RamifiedGridsBuildWithFinestConnectivity) {
    const NestedCubesFolder folder("ramified");
    // the outer cube's 12 triangles have their edges on the cube's edges and diagonals: most faces
    // between its BOUNDARY cells are crossed by none, so the finest cells come apart
    auto plain = scene::build_scene(io::parse_scene_file(folder.scene(kNestedCubesGrid + R"(n="7 7 7"/>)")));
    auto ramified = scene::build_scene(io::parse_scene_file(folder.scene(
        R"(<SparseGridRamificationTopology min="0 0 0" max="6 6 6" n="7 7 7" fileTopology="outer.obj"/>)")));
    const auto points_of = [](scene::Scene& s) { return s.simulation().root().children().at(0)->state()->num_dofs(); };
    EXPECT_EQ(points_of(*plain), 343u);
    EXPECT_GT(points_of(*ramified), 343u);
    EXPECT_LE(points_of(*ramified), 8u * 216u);
    ramified->step();
}

TEST(SparseGridMultipleComponents, BadAttributesNameFileLineComponentAndAttribute) {
    const NestedCubesFolder folder("errors");
    const auto error_of = [&](const std::string& grid) { return nested_cubes_build_error(folder.scene(grid)); };
    const std::string no_files = error_of(R"(<SparseGridMultipleTopology n="4 4 4" fileTopologies=""/>)");
    EXPECT_THAT(no_files, ::testing::HasSubstr("scene.scn:5: SparseGridMultipleTopology"));
    EXPECT_THAT(no_files, ::testing::HasSubstr("SparseGridMultipleTopology"));
    EXPECT_THAT(no_files, ::testing::HasSubstr("fileTopologies"));
    EXPECT_THAT(
        error_of(
            R"(<SparseGridMultipleTopology n="4 4 4" fileTopologies="outer.obj" stiffnessCoefs="-1" finestConnectivity="0"/>)"),
        ::testing::HasSubstr("stiffnessCoefs"));
    EXPECT_THAT(
        error_of(
            R"(<SparseGridMultipleTopology n="4 4 4" fileTopologies="outer.obj missing.obj" finestConnectivity="0"/>)"),
        ::testing::AllOf(::testing::HasSubstr("fileTopologies"), ::testing::HasSubstr("missing.obj")));
    // finestConnectivity (SOFA's default) tests faces against fileTopology's surface
    EXPECT_THAT(error_of(R"(<SparseGridMultipleTopology n="4 4 4" fileTopologies="outer.obj"/>)"),
                ::testing::HasSubstr("finestConnectivity"));
    EXPECT_THAT(
        error_of(R"(<SparseGridRamificationTopology n="4 4 4" fileTopology="outer.obj" nbVirtualFinerLevels="9"/>)"),
        ::testing::HasSubstr("nbVirtualFinerLevels"));
}

}  // namespace
