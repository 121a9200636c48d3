// Large scenes (issue 54): a tetrahedral soft body of 10⁴ … 10⁶ DOFs dropped onto a static,
// curved, liver-sized triangle surface and sliding over it (tests/support/penalty_test/
// soft_body_on_organ.hpp), SOFA scene text built by the scene builder, so a step is the one
// `penalty run` takes. The k×k×k cubes in a bowl, the other large scene (k = 16: 98 304 DOFs), is
// bench_scaling.cpp.
//
// Sizes (body cells n × n/8 × n, organ subdivisions s):
//   n = 16  (2 601 DOFs,    3 072 tetrahedra), s = 32 (12 288 triangles)
//   n = 32  (16 335 DOFs,  24 576 tetrahedra), s = 48 (27 648 triangles)
//   n = 64  (114 075 DOFs, 196 608 tetrahedra), s = 64 (49 152 triangles)
//   n = 136 (1 010 394 DOFs, 1 886 592 tetrahedra), s = 96 (110 592 triangles)
//
// Method. Per size: the scene is built, one step is run (the body is still above the organ:
// no contact), then warmup_steps(n) steps (the body has landed on the organ and slides), then
// timed_steps(n) steps are timed one by one (manual time = wall time of Scene::step() alone).
// Threads: TBB's default or $PENALTY_BENCH_THREADS; $PENALTY_SCALING_SCENES=DIR writes
// DIR/soft_body_on_organ_n<n>.scn (n = 136: its body's mesh beside it, soft_body_on_organ_n136_body.vtk,
// since a scene attribute holds at most 10⁶ values); callgrind: bench/scene_probe.hpp.
//
// BM_SoftBodyElasticity/FIELD: the n = 64 body with another tetrahedral force field
// (TetrahedralCorotationalFEMForceField, FastTetrahedralCorotationalForceField,
// TetrahedronHyperelasticityFEMForceField: St Venant-Kirchhoff; MeshSpringForceField: the edges'
// springs). BM_Cloth/FIELD: a cloth of
// 200 × 200 quads (80 000 triangles, 121 203 DOFs) pinned at two corners, falling, with
// TriangularFEMForceFieldOptim, TriangularFEMForceField, TriangularBiquadraticSpringsForceField,
// TriangularQuadraticSpringsForceField or TriangularTensorMassForceField; 5 steps, then 20 timed.
// BM_ClothWithBending/TriangularFEMForceFieldOptim: the same cloth with FastTriangularBendingSprings
// too (119 600 bending elements, one per interior edge).
//
// Counters (per step, over the timed steps): dofs, tetrahedra, organ_triangles; contacts,
// active (springs with pen > 0); cg_its; kinetic_j; detect_ms, response_ms, solve_ms (Scene::last_timings);
// ns_per_dof_cg_it = solve time / (DOFs × CG iterations); sunk (body nodes deeper inside the
// organ's smooth surface than the contact distance at the end); heap_mb, bytes_per_dof,
// bytes_per_contact, peak_rss_mb (as in bench_scaling.cpp); build_s (parse and build, wall).
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/output/stats_csv.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/soft_body_on_organ.hpp"
#include "scene_probe.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <memory>
#include <string>

namespace penalty::scene {
namespace {

namespace organ = penalty::test::soft_body_on_organ;
using Clock = std::chrono::steady_clock;

struct Size {
    int cells;
    int organ_subdivisions;
    int warmup_steps;
    int timed_steps;
};
constexpr Size kSizes[] = {{16, 32, 40, 60}, {32, 48, 40, 40}, {64, 64, 40, 10}, {136, 96, 20, 3}};

organ::Setup setup(const Size& size, organ::Elasticity elasticity = organ::Elasticity::tetrahedron_fem) {
    organ::Setup s;
    s.cells = size.cells;
    s.organ_subdivisions = size.organ_subdivisions;
    s.elasticity = elasticity;
    return s;
}

/// The n = 64 body with another elastic force field (BM_SoftBodyElasticity).
struct ElasticityCase {
    const char* name;
    organ::Elasticity elasticity;
};
constexpr ElasticityCase kElasticities[] = {
    {"TetrahedralCorotationalFEMForceField", organ::Elasticity::tetrahedral_corotational},
    {"FastTetrahedralCorotationalForceField", organ::Elasticity::fast_tetrahedral_corotational},
    {"TetrahedronHyperelasticityFEMForceField", organ::Elasticity::hyperelastic},
    {"MeshSpringForceField", organ::Elasticity::mesh_springs}};

void BM_SoftBodyOnOrgan(benchmark::State& state, Size size, organ::Elasticity elasticity, std::string name) {
    const organ::Setup s = setup(size, elasticity);
    std::unique_ptr<Scene> scene;
    double heap_without_contacts = 0, build_seconds = 0;
    try {
        const auto t0 = Clock::now();
        {
            // Above 10⁶ values an attribute cannot hold the body's lists: its mesh goes to a .vtk
            // file beside the written scene ($PENALTY_SCALING_SCENES), else in the temporary folder.
            BuildOptions options = bench::build_options();
            std::filesystem::path mesh;
            if (organ::body_needs_mesh_file(s)) {
                const char* dir = std::getenv("PENALTY_SCALING_SCENES");
                const std::filesystem::path folder = dir != nullptr && *dir != '\0'
                                                         ? std::filesystem::path(dir)
                                                         : std::filesystem::temp_directory_path();
                std::filesystem::create_directories(folder);
                mesh = folder / (name + "_body.vtk");
                options.data_dirs.push_back(folder);
            }
            const std::string xml = organ::scene_xml(s, mesh, mesh.empty() ? "" : mesh.filename().string());
            bench::write_scene_if_asked(name, xml);
            scene = build_scene(io::parse_scene_string(xml, name), options);
        }
        build_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        scene->step();  // in the air: the heap of the scene and the solve's scratch
        heap_without_contacts = bench::live_heap_bytes();
        for (int i = 0; i < size.warmup_steps; ++i) scene->step();
    } catch (const std::exception& e) {
        bench::skip(state, "build or warm-up failed: " + std::string(e.what()));
        return;
    }
    bench::StepSums sums;
    if (!bench::run_timed_steps(state, *scene, sums)) return;
    int sunk = 0;
    for (const auto& r : scene->states()) {
        if (!r.in_solver_subtree) continue;  // the organ
        for (const Vec3& x : dynamic_cast<const Vec3Object&>(*r.state).position)
            if (organ::organ_depth(s, {x.x(), x.y(), x.z()}) > organ::contact_distance(s)) ++sunk;
    }
    bench::report_step_sums(state, *scene, sums, heap_without_contacts);
    const double dofs = state.counters["dofs"];
    state.counters["cells"] = size.cells;
    state.counters["tetrahedra"] = double(organ::body_tetrahedra(s));
    state.counters["organ_triangles"] = double(organ::organ_triangles(s));
    state.counters["ns_per_dof_cg_it"] = sums.cg > 0 ? 1e9 * sums.solve / (dofs * sums.cg) : 0.0;
    state.counters["sunk"] = sunk;
    state.counters["build_s"] = build_seconds;
}

/// A square cloth of n × n quads (2n² triangles, 1 m², 1 kg) pinned at two corners, falling
/// under gravity with the triangle force field `field` (E = 3 kPa, ν = 0.3), and, if `bending`,
/// FastTriangularBendingSprings (bendingStiffness 1e-4): the triangle FEMs' large scene (no
/// contact).
std::string cloth_xml(int n, const std::string& field, bool bending) {
    std::string points, triangles;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            points += std::to_string(double(i) / n) + " 0 " + std::to_string(double(j) / n) + "  ";
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            triangles += std::to_string(a) + ' ' + std::to_string(b) + ' ' + std::to_string(d) + "  " +
                         std::to_string(a) + ' ' + std::to_string(d) + ' ' + std::to_string(c) + "  ";
        }
    return "<?xml version=\"1.0\"?>\n<Node name=\"root\" dt=\"0.01\" gravity=\"0 -9.81 0\">\n"
           "  <DefaultAnimationLoop/>\n  <Node name=\"Cloth\">\n"
           "    <EulerImplicitSolver rayleighStiffness=\"0.1\" rayleighMass=\"0.1\"/>\n"
           "    <CGLinearSolver iterations=\"50\" tolerance=\"1e-9\" threshold=\"1e-12\"/>\n"
           "    <MeshTopology position=\"" +
           points + "\" triangles=\"" + triangles +
           "\"/>\n    <MechanicalObject name=\"cloth\"/>\n    <UniformMass totalMass=\"1\"/>\n    <" + field +
           " youngModulus=\"3000\" poissonRatio=\"0.3\"/>\n" +
           (bending ? "    <FastTriangularBendingSprings bendingStiffness=\"1e-4\"/>\n" : "") +
           "    <FixedConstraint indices=\"0 " + std::to_string(n) + "\"/>\n  </Node>\n</Node>\n";
}

void BM_Cloth(benchmark::State& state, std::string field, bool bending) {
    constexpr int kQuads = 200;  // 80 000 triangles, 121 203 DOFs
    std::unique_ptr<Scene> scene;
    try {
        const std::string name = "cloth_" + field + (bending ? "_bending" : "");
        const std::string xml = cloth_xml(kQuads, field, bending);
        bench::write_scene_if_asked(name, xml);
        scene = build_scene(io::parse_scene_string(xml, name), bench::build_options());
        for (int i = 0; i < 5; ++i) scene->step();
    } catch (const std::exception& e) {
        bench::skip(state, "build or warm-up failed: " + std::string(e.what()));
        return;
    }
    bench::StepSums sums;
    if (!bench::run_timed_steps(state, *scene, sums)) return;
    state.counters["triangles"] = 2.0 * kQuads * kQuads;
    state.counters["cg_its"] = sums.mean(sums.cg);
}

[[maybe_unused]] const bool registered = [] {
    const auto timed = [](benchmark::internal::Benchmark* b, int steps) {
        b->Iterations(steps)->UseManualTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
    };
    for (const Size& size : kSizes)
        timed(benchmark::RegisterBenchmark(("BM_SoftBodyOnOrgan/n:" + std::to_string(size.cells)).c_str(),
                                           BM_SoftBodyOnOrgan, size, organ::Elasticity::tetrahedron_fem,
                                           "soft_body_on_organ_n" + std::to_string(size.cells)),
              size.timed_steps);
    // the other tetrahedral force fields on the n = 64 body (196 608 tetrahedra)
    for (const ElasticityCase& c : kElasticities)
        timed(benchmark::RegisterBenchmark(("BM_SoftBodyElasticity/" + std::string(c.name)).c_str(), BM_SoftBodyOnOrgan,
                                           kSizes[2], c.elasticity, "soft_body_" + std::string(c.name)),
              kSizes[2].timed_steps);
    for (const char* field :
         {"TriangularFEMForceFieldOptim", "TriangularFEMForceField", "TriangularBiquadraticSpringsForceField",
          "TriangularQuadraticSpringsForceField", "TriangularTensorMassForceField"})
        timed(benchmark::RegisterBenchmark(("BM_Cloth/" + std::string(field)).c_str(), BM_Cloth, std::string(field),
                                           false),
              20);
    timed(benchmark::RegisterBenchmark("BM_ClothWithBending/TriangularFEMForceFieldOptim", BM_Cloth,
                                       std::string("TriangularFEMForceFieldOptim"), true),
          20);
    return true;
}();

}  // namespace
}  // namespace penalty::scene
