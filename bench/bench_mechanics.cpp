// Step time of an implicit (EulerImplicit + matrix-free CG, 25 iterations) tetrahedral FEM block
// and of a spring grid, about 10^4 DOFs each, reported per step and per DOF; and the product the
// CG repeats (add_dforce) alone, for SphereModel's FEM grid and a spring set of
// MeshSpringForceField's size, with the flops it does (docs/performance.md, "How far from the
// machine's limits", against penalty_bench_machine's rates); and a large RestShapeSpringsForceField's
// product (a soft robot held at rest on every point), a large BarycentricMapping's J and Jᵀ and
// RigidMapping's apply and J, springs between two states and a cable of beams on 1 and 2 threads.

#include "penalty/mechanics/beam_fem_force_field.hpp"
#include "penalty/mechanics/corotational_fem.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/rest_shape_springs.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/mechanics/triangular_fem.hpp"
#include "penalty/mechanics/triangular_quadratic_springs.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/grid_meshes.hpp"

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

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
        for (const Spring& s : regular_grid_springs(grid, MeshSpringParameters::uniform(1e3, 0.0)))
            springs.add_spring(s);
    }
    std::vector<Index> bottom;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) bottom.push_back(grid.point_index(i, j, 0));
    body.add_constraint<FixedProjectiveConstraint>(x).set_indices(bottom);
    sim.init();
    for (auto _ : state) sim.step();
    const double dofs = 3.0 * static_cast<double>(grid.num_points());
    state.counters["dofs"] = dofs;
    state.counters["s_per_dof"] =
        benchmark::Counter(dofs, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    state.counters["cg_iterations"] = solver.last_cg_stats().iterations;
}

// Flops of one element in TetrahedronFEMForceField::add_dforce, method large (fem.cpp,
// large_dforce_avx): R·dx 60, Jᵀδ 66 (4, 4, 4, 8, 8, 8 terms), M·ε 18, the k factor 6, J·σ 60
// (3 terms a row), Rᵀ·F 60, df −= 12.
constexpr double kFemLargeDForceFlops = 282.0;
// Flops of one spring in SpringForceField::add_dforce: u = dx_b − dx_a 3, K·u 15, ·k 3, df += 3, df −= 3.
constexpr double kSpringDForceFlops = 27.0;

/// The force at x once, then the timed products (m = 0, k = −0.25) of a fixed dx.
template <class Field>
void time_products(benchmark::State& state, Field& fem, const Vec3Object& x) {
    std::vector<Vec3> f(x.position.size(), Vec3::Zero()), df(x.position.size(), Vec3::Zero()), dx(x.position.size());
    fem.add_force(f, x.position, x.velocity);
    for (std::size_t i = 0; i < dx.size(); ++i) dx[i] = Vec3(1e-3 * double(i % 7), -1e-3, 2e-3);
    for (auto _ : state) {
        fem.add_dforce(df, dx, -0.25, 0.0);
        benchmark::DoNotOptimize(df.data());
    }
}

/// The counters of an element product: its elements and the time a product takes per element.
void count_elements(benchmark::State& state, std::size_t elements) {
    state.counters["elements"] = double(elements);
    state.counters["ns_per_element"] = benchmark::Counter(
        double(elements), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// The benchmark skipped with a message when this CPU cannot run `path`.
bool skipped_unsupported(benchmark::State& state, KernelPath path) {
    if (kernel_path_supported(path)) return false;
    state.SkipWithError((std::string("kernel path ") + to_string(path) + " not supported by this CPU").c_str());
    for (auto _ : state) {
    }
    return true;
}

// The product of a method-large tetrahedral field over n³ grid points on SphereModel's cube (n = 5:
// its 5 × 5 × 5 grid), SOFA's grid tetrahedra, on kernel path range(1); `make_field(state, grid)`
// adds the field to the node.
template <class MakeField>
void tetra_large_dforce(benchmark::State& state, const MakeField& make_field) {
    const int n = static_cast<int>(state.range(0));
    RegularGridTopology grid({n, n, n}, Vec3(-3.5, -3.5, -3.5), Vec3(3.5, 3.5, 3.5));
    Simulation sim;
    Node& body = sim.root().add_child("block");
    auto& x = body.add_state<Vec3Types>();
    x.position = grid.points();
    auto& fem = make_field(body, x, grid);
    const auto path = static_cast<KernelPath>(state.range(1));
    if (skipped_unsupported(state, path)) return;
    fem.set_kernel_path(path);
    sim.init();
    // a deformed state, so that the rotations are not the identity
    for (std::size_t i = 0; i < x.position.size(); ++i)
        x.position[i] += 0.1 * Vec3(std::sin(double(i)), std::cos(double(i)), 0.5);
    time_products(state, fem, x);
    const double elements = double(fem.tetrahedra().size());
    state.counters["elements"] = elements;
    state.counters["flops"] =
        benchmark::Counter(elements * kFemLargeDForceFlops, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_TetraFemLargeDForce(benchmark::State& state) {
    tetra_large_dforce(
        state, [](Node & body, Vec3Object & x, const RegularGridTopology& grid) -> auto& {
            return body.add_force_field<TetrahedronFEMForceField>(x, grid, 25.0, 0.3, FemMethod::Large);
        });
}

// TetrahedralCorotationalFEMForceField (its SOFA path) on TetrahedronFEMForceField's tetrahedra of
// the same grid: the same element operations.
void BM_TetraCorotationalLargeDForce(benchmark::State& state) {
    tetra_large_dforce(
        state, [](Node & body, Vec3Object & x, const RegularGridTopology& grid) -> auto& {
            const TetrahedronFEMForceField split(x, grid, 25.0, 0.3, FemMethod::Large);
            return body.add_force_field<TetrahedralCorotationalFEMForceField>(x, split.tetrahedra(), 25.0, 0.3);
        });
}

// The springs of an n × n × (n + 1) grid (regular_grid_springs, diagonals included); n = 6: 2 306
// springs over 252 points, in cache as one of MeshSpringForceField's tori (1 330 springs over 264
// points).
void BM_SpringDForce(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    RegularGridTopology grid({n, n, n + 1}, Vec3(0, 0, 0), Vec3(1, 1, 1));
    Simulation sim;
    Node& body = sim.root().add_child("springs");
    auto& x = body.add_state<Vec3Types>();
    x.position = grid.points();
    auto& springs = body.add_force_field<SpringForceField>(x);
    for (const Spring& s : regular_grid_springs(grid, MeshSpringParameters::uniform(1e3, 0.0))) springs.add_spring(s);
    sim.init();
    for (std::size_t i = 0; i < x.position.size(); ++i)
        x.position[i] += 0.01 * Vec3(std::sin(double(i)), 0.3, std::cos(double(i)));
    std::vector<Vec3> f(x.position.size(), Vec3::Zero()), df(x.position.size(), Vec3::Zero()), dx(x.position.size());
    springs.add_force(f, f, x.position, x.position, x.velocity, x.velocity);
    for (std::size_t i = 0; i < dx.size(); ++i) dx[i] = Vec3(1e-3 * double(i % 5), -1e-3, 2e-3);
    for (auto _ : state) {
        springs.add_dforce(df, df, dx, dx, -0.25, 0.0);
        benchmark::DoNotOptimize(df.data());
    }
    const double count = double(springs.springs().size());
    state.counters["springs"] = count;
    state.counters["flops"] =
        benchmark::Counter(count * kSpringDForceFlops, benchmark::Counter::kIsIterationInvariantRate);
}

// The springs of an n × n × (n + 1) grid's tetrahedra (first argument) between two copies of it,
// 1 cm apart, their force and product in an arena of the second
// argument's threads: OrderedScatter over both states' points (the same bits at any count).
void BM_SpringsBetweenTwoStates(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    RegularGridTopology grid({n, n, n + 1}, Vec3(0, 0, 0), Vec3(1, 1, 1));
    Vec3Object a, b;
    a.position = grid.points();
    b.position = grid.points();
    for (Vec3& p : b.position) p += Vec3(0.01, 0.0, 0.0);
    a.init();
    b.init();
    SpringForceField springs(a, b);
    // the springs of the grid's tetrahedra in element order (MeshSpringForceField's): neighbours in
    // the list are neighbours in space, so few ends are deferred
    for (const Spring& s :
         mesh_springs(test::kuhn_tetrahedra(grid), grid.points(), MeshSpringParameters::uniform(1e3, 0.0)))
        springs.add_spring(s);
    springs.init();
    for (std::size_t i = 0; i < a.dx.size(); ++i) a.dx[i] = Vec3(1e-3 * double(i % 5), -1e-3, 2e-3);
    tbb::task_arena arena(static_cast<int>(state.range(1)));
    for (auto _ : state) {
        arena.execute([&] {
            springs.accumulate_force();
            springs.accumulate_dforce(-0.25, 0.0);
        });
        benchmark::DoNotOptimize(a.df.data());
    }
    state.counters["springs"] = double(springs.springs().size());
    state.counters["threads"] = double(state.range(1));
}

// A cable of BeamFEMForceField beams (first argument), bent and twisted a little, its force and
// product in an arena of the second argument's threads (OrderedScatter over the frames).
void BM_BeamCable(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0));
    Rigid3Object frames;
    for (std::size_t i = 0; i <= n; ++i) {
        const double t = double(i);
        frames.position.push_back(RigidFrame{Vec3(0.01 * t, 0.001 * std::sin(t), 0.0),
                                             Quat(Eigen::AngleAxisd(0.01 * std::sin(0.1 * t), Vec3::UnitY()))});
    }
    frames.init();
    for (std::size_t i = 0; i <= n; ++i) frames.position[i].center.z() = 1e-4 * std::cos(double(i));
    std::vector<std::array<Index, 2>> beams;
    for (std::size_t i = 0; i < n; ++i) beams.push_back({Index(i), Index(i + 1)});
    BeamParameters p;
    p.radius = 0.002;
    BeamFEMForceField cable(frames, std::move(beams), p);
    cable.init();
    for (RigidDeriv& d : frames.dx) d = {Vec3(1e-3, -1e-3, 2e-3), Vec3(1e-2, 0.0, -1e-2)};
    tbb::task_arena arena(static_cast<int>(state.range(1)));
    for (auto _ : state) {
        arena.execute([&] {
            cable.accumulate_force();
            cable.accumulate_dforce(-0.25, 0.0);
        });
        benchmark::DoNotOptimize(frames.df.data());
    }
    state.counters["beams"] = double(n);
    state.counters["threads"] = double(state.range(1));
}

// A RestShapeSpringsForceField on every point of a state of 10^5 points (the first argument),
// its product in an arena of the second argument's threads: ranges of springs on TBB's threads,
// each point's row its own (the same bits at any count).
void BM_RestShapeSpringsDForce(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0));
    Vec3Object x;
    x.position.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        x.position[i] = Vec3(std::sin(double(i)), 0.3 * double(i % 7), std::cos(double(i)));
    x.init();
    RestShapeSpringsForceField<Vec3Types> springs(x);
    springs.set_stiffness({1e3});
    springs.init();
    std::vector<Vec3> df(n, Vec3::Zero()), dx(n);
    for (std::size_t i = 0; i < n; ++i) dx[i] = Vec3(1e-3 * double(i % 5), -1e-3, 2e-3);
    tbb::task_arena arena(static_cast<int>(state.range(1)));
    for (auto _ : state) {
        arena.execute([&] { springs.add_dforce(df, dx, -0.25, 0.0); });
        benchmark::DoNotOptimize(df.data());
    }
    state.counters["springs"] = double(n);
    state.counters["threads"] = double(state.range(1));
}

// A BarycentricMapping of the first argument's rows (four entries each, on a parent of half as
// many points), J·dx then Jᵀ·f with every third argument's row forced (1: every row, the full
// gather; 100: a collision surface with few contacts, the forced rows' scatter after a search of
// the inputs for a −0 start), in an arena of the second argument's threads: ranges of rows and of
// inputs on TBB's threads.
void BM_BarycentricMappingProducts(benchmark::State& state) {
    const auto rows = static_cast<std::size_t>(state.range(0));
    const std::size_t inputs = rows / 2;
    Vec3Object in, out;
    in.position.resize(inputs);
    for (std::size_t i = 0; i < inputs; ++i) in.position[i] = Vec3(std::sin(double(i)), 0.1 * double(i % 9), 1.0);
    in.init();
    std::vector<BarycentricRow> weights(rows);
    for (std::size_t i = 0; i < rows; ++i)
        for (std::size_t k = 0; k < 4; ++k) weights[i].push(Index((i / 2 + 37 * k) % inputs), 0.25 + 0.01 * double(k));
    BarycentricMapping map(in, out);
    map.set_rows(std::move(weights));
    map.init();
    for (std::size_t i = 0; i < inputs; ++i) in.dx[i] = Vec3(1e-3 * double(i % 5), -1e-3, 2e-3);
    const auto forced_every = static_cast<std::size_t>(state.range(2));
    for (std::size_t i = 0; i < rows; ++i)
        out.df[i] = i % forced_every == 0 ? Vec3(0.5, -1.0 + 1e-4 * double(i % 11), 0.25) : Vec3::Zero();
    tbb::task_arena arena(static_cast<int>(state.range(1)));
    for (auto _ : state) {
        arena.execute([&] {
            map.apply_dx();
            map.apply_jt_df();
        });
        benchmark::DoNotOptimize(in.df.data());
    }
    state.counters["rows"] = double(rows);
    state.counters["threads"] = double(state.range(1));
}

// A RigidMapping of the first argument's points on one frame (a rigid body's collision surface),
// its positions (apply) then J·v in an arena of the second argument's threads: ranges of points.
void BM_RigidMappingProducts(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0));
    Rigid3Object frame;
    frame.position = {RigidFrame{Vec3(0.1, 0.2, 0.3), Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()))}};
    frame.init();
    frame.velocity[0] = {Vec3(0.1, -0.2, 0.05), Vec3(0.3, 0.1, -0.2)};
    Vec3Object points;
    RigidMapping map(frame, points);
    std::vector<Vec3> local(n);
    for (std::size_t i = 0; i < n; ++i)
        local[i] = Vec3(std::sin(double(i)), std::cos(double(i)), 0.001 * double(i % 97));
    map.set_points(std::move(local));
    map.init();
    tbb::task_arena arena(static_cast<int>(state.range(1)));
    for (auto _ : state) {
        arena.execute([&] {
            map.apply_position();
            map.apply_velocity();
        });
        benchmark::DoNotOptimize(points.velocity.data());
    }
    state.counters["points"] = double(n);
    state.counters["threads"] = double(state.range(1));
}

// HexahedronFEMForceField method large: the product over an n³-point grid of (n − 1)³ hexahedra
// (n = 8: 343, HexahedronFEMForceField.scn's size), on kernel path range(1) (0 scalar, 1 avx).
void BM_HexahedronFemLargeDForce(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    const auto path = static_cast<KernelPath>(state.range(1));
    if (skipped_unsupported(state, path)) return;
    RegularGridTopology grid({n, n, n}, Vec3(-3.5, -3.5, -3.5), Vec3(3.5, 3.5, 3.5));
    Simulation sim;
    Node& body = sim.root().add_child("block");
    auto& x = body.add_state<Vec3Types>();
    x.position = grid.points();
    auto& fem = body.add_force_field<HexahedronFEMForceField>(x, grid.mesh(), 25.0, 0.3, FemMethod::Large);
    fem.set_kernel_path(path);
    sim.init();
    for (std::size_t i = 0; i < x.position.size(); ++i)
        x.position[i] += 0.1 * Vec3(std::sin(double(i)), std::cos(double(i)), 0.5);
    time_products(state, fem, x);
    count_elements(state, fem.element_stiffness().size());
}

// An m×m sheet of 2(m − 1)² triangles (m = 28: 1 458, the size of SOFA's square3.msh examples),
// its points in `x`, its triangles in `topology`.
void sheet_of_triangles(std::size_t m, Vec3Object& x, MeshTopology& topology) {
    std::vector<Triangle> triangles;
    for (std::size_t i = 0; i < m; ++i)
        for (std::size_t j = 0; j < m; ++j) x.position.emplace_back(double(i), double(j), 0.0);
    for (std::size_t i = 0; i + 1 < m; ++i)
        for (std::size_t j = 0; j + 1 < m; ++j) {
            const auto v = [m](std::size_t a, std::size_t b) { return static_cast<PointId>(a * m + b); };
            triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
            triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
        }
    topology.set_num_points(m * m);
    topology.set_triangles(std::move(triangles));
}

/// Crumpled, so that the frames are not the identity and every edge is stretched or compressed.
void crumple(Vec3Object& x) {
    for (std::size_t i = 0; i < x.position.size(); ++i)
        x.position[i] += 0.2 * Vec3(std::sin(double(i)), std::cos(double(3 * i)), std::sin(double(7 * i)));
}

// TriangularFEMForceField "large" (SOFA's order): the product of the crumpled sheet.
void BM_TriangularFemLargeDForce(benchmark::State& state) {
    Simulation sim;
    Node& sheet = sim.root().add_child("sheet");
    auto& x = sheet.add_state<Vec3Types>();
    MeshTopology topology;
    sheet_of_triangles(static_cast<std::size_t>(state.range(0)), x, topology);
    auto& fem = sheet.add_force_field<TriangularFEMForceField>(x, topology, 60.0, 0.3, FemMethod::Large);
    sim.init();
    crumple(x);
    time_products(state, fem, x);
    count_elements(state, fem.triangles().size());
}

// TriangularQuadraticSpringsForceField with angular springs (one 3×3 block per triangle edge,
// the product of TriangularBiquadraticSprings too): the product of the crumpled sheet, one
// thread, on kernel path range(1) (0 scalar, 1 avx).
void BM_TriangleEdgeBlocksDForce(benchmark::State& state) {
    Simulation sim;
    Node& sheet = sim.root().add_child("sheet");
    auto& x = sheet.add_state<Vec3Types>();
    MeshTopology topology;
    sheet_of_triangles(static_cast<std::size_t>(state.range(0)), x, topology);
    auto& springs = sheet.add_force_field<TriangularQuadraticSpringsForceField>(
        x, topology, QuadraticSpringParameters{.young_modulus = 60.0, .use_angular_springs = true});
    sim.init();
    crumple(x);
    const auto path = static_cast<KernelPath>(state.range(1));
    if (skipped_unsupported(state, path)) return;
    springs.set_kernel_path(path);
    tbb::task_arena one(1);  // the one-thread product (the kernel's)
    one.execute([&] { time_products(state, springs, x); });
    count_elements(state, topology.triangles().size());
}

void BM_TetraFemBlockStep(benchmark::State& state) { run(state, Model::TetraFem); }
void BM_SpringGridStep(benchmark::State& state) { run(state, Model::SpringGrid); }

}  // namespace

// n³ points, 3n³ DOFs: n = 15 -> 10125 DOFs.
BENCHMARK(BM_TetraFemBlockStep)->Arg(8)->Arg(15)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SpringGridStep)->Arg(8)->Arg(15)->Unit(benchmark::kMillisecond);
// second argument: the KernelPath (0 scalar, 1 avx, 2 avx512), side by side in one run
BENCHMARK(BM_TetraFemLargeDForce)->ArgsProduct({{5}, {0, 1, 2}});
BENCHMARK(BM_TetraCorotationalLargeDForce)->ArgsProduct({{5}, {0, 1, 2}});
BENCHMARK(BM_SpringDForce)->Arg(6);
BENCHMARK(BM_TriangularFemLargeDForce)->Arg(28)->Arg(200);
BENCHMARK(BM_TriangleEdgeBlocksDForce)->ArgsProduct({{28, 200}, {0, 1}});
BENCHMARK(BM_HexahedronFemLargeDForce)->ArgsProduct({{8, 20}, {0, 1}});
// 10^5 and 10^6 points on 1 and 2 threads, side by side in one run
BENCHMARK(BM_RestShapeSpringsDForce)->ArgsProduct({{100'000, 1'000'000}, {1, 2}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SpringsBetweenTwoStates)->ArgsProduct({{30}, {1, 2}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BeamCable)->ArgsProduct({{100'000}, {1, 2}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BarycentricMappingProducts)
    ->ArgsProduct({{100'000, 1'000'000}, {1, 2}, {1, 100}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RigidMappingProducts)->ArgsProduct({{100'000, 1'000'000}, {1, 2}})->Unit(benchmark::kMicrosecond);
