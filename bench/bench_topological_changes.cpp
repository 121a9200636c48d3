// Topological changes (issue 51, docs/topological-changes.md): the cost of cutting a liver-sized
// tetrahedral body (about 10⁵ tetrahedra) against the cost of an unchanged step.
//
// The body: a cube of n³ cells, 5 tetrahedra each (n = 27: 98 415 tetrahedra, 21 952 points),
// TetrahedronSetTopologyContainer + Modifier, DiagonalMass, TetrahedronFEMForceField (large),
// its bottom fixed through a BoxROI, and its border surface in a child node through a
// Tetra2TriangleTopologicalMapping with a TriangleCollisionModel; implicit Euler, 25 CG iterations.
//
//   BM_UnchangedStep            one Scene::step() of the whole body
//   BM_CarveOnePercentPerStep   per iteration: remove 1 % of the initial tetrahedra (the ones whose
//                               centroid is nearest a tool point moving through the body, as a
//                               carving tool's reach would pick them; the picking is not timed),
//                               then one step. Counters: removal_ms (the removal with everything
//                               following: mass, FEM, constraint, mapping, surface, collision
//                               model, state), step_ms (the step after it), unchanged_step_ms
//                               (a step of the same scene without a change, measured before),
//                               ratio = (removal + step) / unchanged step.
//   BM_RemoveOneTetrahedron/N   the removal of one tetrahedron from a body of N cells per side
//                               (no step): it grows with what the tetrahedron touches, not with
//                               the mesh (compare N = 12 and N = 27).
#include "penalty/io/scene_file.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

namespace penalty::scene {
namespace {

using Clock = std::chrono::steady_clock;

std::string body_scene(int n) {
    const test::TetraCube cube = test::tetra_cube(n, 0.2);
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <Node name="Liver">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="25" tolerance="1e-30" threshold="1e-30"/>
    <TetrahedronSetTopologyContainer name="volume" position=")" +
           test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/>
    <TetrahedronSetTopologyModifier/>
    <MechanicalObject name="dofs"/>
    <DiagonalMass massDensity="1000"/>
    <TetrahedronFEMForceField youngModulus="3000" poissonRatio="0.45" method="large"/>
    <BoxROI name="bottom" box="-0.01 -0.01 -0.01 0.21 0.001 0.21"/>
    <FixedProjectiveConstraint indices="@bottom.indices"/>
    <Node name="Surface">
      <TriangleSetTopologyContainer name="surface"/>
      <TriangleSetTopologyModifier/>
      <Tetra2TriangleTopologicalMapping input="@../volume" output="@surface"/>
      <TriangleCollisionModel name="surfaceModel"/>
    </Node>
  </Node>
</Node>
)";
}

std::unique_ptr<Scene> build(int n) { return build_scene(io::parse_scene_string(body_scene(n), "liver.scn")); }

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

/// The `count` tetrahedra whose centroids are nearest to `tool`.
std::vector<ElementId> nearest(const Scene& s, const Vec3& tool, std::size_t count) {
    const TopologyContainer& c = s.topology_container("volume");
    const auto* dofs = dynamic_cast<const Vec3Object*>(s.states().front().state);
    const auto& tets = c.mesh().tetrahedra();
    std::vector<std::pair<double, ElementId>> d(tets.size());
    for (std::size_t i = 0; i < tets.size(); ++i) {
        Vec3 centre = Vec3::Zero();
        for (const PointId v : tets[i]) centre += dofs->position[std::size_t(v)];
        d[i] = {(centre / 4 - tool).squaredNorm(), ElementId(i)};
    }
    count = std::min(count, d.size());
    std::partial_sort(d.begin(), d.begin() + std::ptrdiff_t(count), d.end());
    std::vector<ElementId> out(count);
    for (std::size_t k = 0; k < count; ++k) out[k] = d[k].second;
    return out;
}

void BM_UnchangedStep(benchmark::State& state) {
    auto s = build(int(state.range(0)));
    s->step();
    for (auto _ : state) s->step();
    state.counters["tetrahedra"] = double(s->topology_container("volume").mesh().tetrahedra().size());
}
BENCHMARK(BM_UnchangedStep)->Arg(27)->Unit(benchmark::kMillisecond)->Iterations(10);

void BM_CarveOnePercentPerStep(benchmark::State& state) {
    const int n = int(state.range(0));
    auto s = build(n);
    s->step();
    auto t0 = Clock::now();
    constexpr int kUnchanged = 5;
    for (int k = 0; k < kUnchanged; ++k) s->step();
    const double unchanged = seconds(Clock::now() - t0) / kUnchanged;
    const std::size_t initial = s->topology_container("volume").mesh().tetrahedra().size();
    const std::size_t per_step = initial / 100;
    double removal = 0, stepping = 0;
    int iterations = 0;
    for (auto _ : state) {
        state.PauseTiming();
        // the tool moves down through the body's top half
        const Vec3 tool(0.1, 0.2 - 0.004 * iterations, 0.1);
        const std::vector<ElementId> picked = nearest(*s, tool, per_step);
        state.ResumeTiming();
        t0 = Clock::now();
        s->remove_elements("volume", ElementType::tetrahedron, picked);
        const auto t1 = Clock::now();
        s->step();
        removal += seconds(t1 - t0);
        stepping += seconds(Clock::now() - t1);
        ++iterations;
    }
    state.counters["tetrahedra_removed_per_step"] = double(per_step);
    state.counters["tetrahedra_left"] = double(s->topology_container("volume").mesh().tetrahedra().size());
    state.counters["removal_ms"] = 1e3 * removal / iterations;
    state.counters["step_ms"] = 1e3 * stepping / iterations;
    state.counters["unchanged_step_ms"] = 1e3 * unchanged;
    state.counters["ratio"] = (removal + stepping) / iterations / unchanged;
}
BENCHMARK(BM_CarveOnePercentPerStep)->Arg(27)->Unit(benchmark::kMillisecond)->Iterations(20);

void BM_RemoveOneTetrahedron(benchmark::State& state) {
    auto s = build(int(state.range(0)));
    s->step();
    const std::size_t initial = s->topology_container("volume").mesh().tetrahedra().size();
    ElementId next = 0;
    for (auto _ : state) {
        s->remove_elements("volume", ElementType::tetrahedron, {next});
        next = (next + 7919) % ElementId(initial / 2);  // spread over the body, always in range
    }
    state.counters["tetrahedra"] = double(initial);
}
BENCHMARK(BM_RemoveOneTetrahedron)->Arg(12)->Arg(27)->Unit(benchmark::kMicrosecond)->Iterations(2000);

}  // namespace
}  // namespace penalty::scene
