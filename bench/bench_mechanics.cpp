// Step time of an implicit (EulerImplicit + matrix-free CG, 25 iterations) tetrahedral FEM block
// and of a spring grid, about 10^4 DOFs each, reported per step and per DOF.

#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/grid_meshes.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>

namespace {

using namespace penalty;

using penalty::test::kuhn_tetrahedra;

enum class Model { TetraFem, SpringGrid };

void run(benchmark::State& state, Model model) {
    const int n = static_cast<int>(state.range(0));
    RegularGridTopology grid({n, n, n}, Vec3(0, 0, 0), Vec3(1, 1, 1));
    Simulation sim;
    Node& body = sim.root().add_child("block");
    auto& solver = body.set_ode_solver<EulerImplicitSolver>();
    solver.cg.iterations = 25;
    solver.cg.tolerance = 1e-12;  // run all 25 iterations: a fixed amount of work per step
    solver.cg.threshold = 1e-30;
    auto& x = body.add_state<Vec3Types>();
    x.position = grid.points();
    body.set_mass<UniformMass<Vec3Types>>(x).set_total_mass(10.0);
    if (model == Model::TetraFem) {
        body.add_force_field<TetrahedronFEMForceField>(x, kuhn_tetrahedra(grid), 1e5, 0.3, FemMethod::Large);
    } else {
        auto& springs = body.add_force_field<SpringForceField>(x);
        for (const Spring& s : regular_grid_springs(grid, MeshSpringParameters::uniform(1e3, 0.0))) springs.add_spring(s);
    }
    std::vector<Index> bottom;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) bottom.push_back(grid.point_index(i, j, 0));
    body.add_constraint<FixedProjectiveConstraint>(x).set_indices(bottom);
    sim.init();
    for (auto _ : state) sim.step();
    const double dofs = 3.0 * static_cast<double>(grid.num_points());
    state.counters["dofs"] = dofs;
    state.counters["s_per_dof"] = benchmark::Counter(dofs, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    state.counters["cg_iterations"] = solver.last_cg_stats().iterations;
}

void BM_TetraFemBlockStep(benchmark::State& state) { run(state, Model::TetraFem); }
void BM_SpringGridStep(benchmark::State& state) { run(state, Model::SpringGrid); }

}  // namespace

// n³ points, 3n³ DOFs: n = 15 -> 10125 DOFs.
BENCHMARK(BM_TetraFemBlockStep)->Arg(8)->Arg(15)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SpringGridStep)->Arg(8)->Arg(15)->Unit(benchmark::kMillisecond);
