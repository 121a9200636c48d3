// `--reduction blocked` (src/simulation/blocked_reductions.hpp, beyond SOFA): the CG's dot products
// summed in fixed blocks of 4 096 Vec3 DOFs (runs of whole small states, or parts of a large
// one), each block's sum SOFA's chain over its states, the blocks' sums added in order. Checked
// against that rule computed here, at one and two threads (the same bits), and a whole run: the
// same state files at 1, 2 and 8 threads, within rounding of SOFA's chains, and SOFA's bits for a
// solver of one block.
#include "penalty/io/scene_file.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace penalty;

/// A grid beam of nx × ny × nz points, springs along the grid, its x = 0 end fixed; under
/// gravity. `small`: also a 2×2×2 grid in its own node under the same solver.
std::string reduction_beam(int nx, int ny, int nz, bool small) {
    std::ostringstream s;
    s << R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="beams">
  <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/><CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-14"/>
  <Node name="big">
    <RegularGridTopology nx=")"
      << nx << R"(" ny=")" << ny << R"(" nz=")" << nz << R"(" min="0 0 0" max=")" << nx - 1 << " " << ny - 1 << " "
      << nz - 1 << R"("/>
    <MechanicalObject/><UniformMass totalMass="10"/><RegularGridSpringForceField stiffness="500"/>
    <BoxROI name="end" box="-0.1 -0.1 -0.1 0.1 100 100"/><FixedProjectiveConstraint indices="@end.indices"/>
  </Node>)";
    if (small)
        s << R"(
  <Node name="small"><RegularGridTopology nx="2" ny="2" nz="2" min="0 -3 0" max="1 -2 1"/>
    <MechanicalObject/><UniformMass totalMass="1"/><RegularGridSpringForceField stiffness="100"/></Node>)";
    s << "\n</Node></Node>\n";
    return s.str();
}

std::unique_ptr<scene::Scene> reduction_scene(const std::string& text, bool blocked, int threads) {
    scene::BuildOptions o;
    o.blocked_reductions = blocked;
    o.threads = threads;
    return scene::build_scene(io::parse_scene_string(text, "beam.scn"), o);
}

std::vector<double> reduction_positions(const scene::Scene& s) {
    std::vector<double> out;
    for (const auto& r : s.states())
        if (const auto* v = dynamic_cast<const Vec3Object*>(r.state))
            for (const Vec3& p : v->position) out.insert(out.end(), {p.x(), p.y(), p.z()});
    return out;
}

/// SOFA's chain over the DOFs [begin, end) of a Vec3 state: ((a0b0 + a1b1) + a2b2) per DOF, added from 0.
double reduction_chain(const Eigen::VectorXd& a, const Eigen::VectorXd& b, Eigen::Index begin, Eigen::Index end) {
    double sum = 0.0;
    for (Eigen::Index i = begin; i < end; i += 3) sum += (a[i] * b[i] + a[i + 1] * b[i + 1]) + a[i + 2] * b[i + 2];
    return sum;
}

TEST(BlockedReductions, DotIsTheSumOfTheBlocksChainsAtAnyThreadCount) {
    // the big state: 9 × 10 × 100 = 9 000 DOFs = 27 000 values: blocks [0, 12 288), [12 288,
    // 24 576), [24 576, 27 000); the small state (24 values) starts a block of its own
    auto s = reduction_scene(reduction_beam(9, 10, 100, true), true, 0);
    Node& beams = *s->simulation().root().children().at(0);
    SubtreeSystem system(beams);
    ASSERT_EQ(system.size(), 27024);
    std::mt19937 rng(2026);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    Eigen::VectorXd a(system.size()), b(system.size());
    for (Eigen::Index i = 0; i < a.size(); ++i) a[i] = unit(rng), b[i] = unit(rng);
    const double sofa = reduction_chain(a, b, 0, 27000) + reduction_chain(a, b, 27000, 27024);
    const double blocks = ((reduction_chain(a, b, 0, 12288) + reduction_chain(a, b, 12288, 24576)) +
                           reduction_chain(a, b, 24576, 27000)) +
                          reduction_chain(a, b, 27000, 27024);
    EXPECT_TRUE(test::same_bits(system.dot(a, b), 0.0 + sofa));
    system.set_blocked_reductions(true);
    for (const int threads : {1, 2}) {
        tbb::task_arena arena(threads);
        double dot = 0.0;
        arena.execute([&] { dot = system.dot(a, b); });
        EXPECT_TRUE(test::same_bits(dot, blocks)) << threads << " threads: " << dot << " vs " << blocks;
    }
    EXPECT_NE(blocks, sofa);  // the seed gives sums whose rounding differs: the test sees the blocks
    // the update x += α·p, r −= α·q: every entry as the serial pass, r·r as the blocks sum it
    Eigen::VectorXd x0 = a, r0 = b, x1 = a, r1 = b;
    const Eigen::VectorXd p = b * 0.5, q = a * 0.25;
    system.set_blocked_reductions(false);
    (void)system.update_and_residual(0.3, p, q, x0, r0);
    system.set_blocked_reductions(true);
    const double rr = system.update_and_residual(0.3, p, q, x1, r1);
    for (Eigen::Index i = 0; i < x0.size(); ++i)
        ASSERT_TRUE(test::same_bits(x0[i], x1[i]) && test::same_bits(r0[i], r1[i])) << i;
    EXPECT_TRUE(test::same_bits(rr, ((reduction_chain(r1, r1, 0, 12288) + reduction_chain(r1, r1, 12288, 24576)) +
                                     reduction_chain(r1, r1, 24576, 27000)) +
                                        reduction_chain(r1, r1, 27000, 27024)));
}

TEST(BlockedReductions, RunsAreTheSameBitsAtAnyThreadCountAndWithinRoundingOfSofas) {
    const std::string text = reduction_beam(5, 5, 180, false);  // 4 500 DOFs: two blocks
    std::vector<std::vector<double>> runs;
    for (const auto& [blocked, threads] : {std::pair{false, 1}, {true, 1}, {true, 2}, {true, 8}}) {
        auto s = reduction_scene(text, blocked, threads);
        for (int k = 0; k < 5; ++k) s->step();
        runs.push_back(reduction_positions(*s));
    }
    double largest = 0.0;
    for (std::size_t i = 0; i < runs[0].size(); ++i) {
        ASSERT_TRUE(test::same_bits(runs[1][i], runs[2][i]) && test::same_bits(runs[1][i], runs[3][i])) << i;
        largest = std::max(largest, std::abs(runs[1][i] - runs[0][i]));
    }
    EXPECT_GT(largest, 0.0);    // the blocks sum in another order than SOFA's chain
    EXPECT_LT(largest, 1e-10);  // at rounding level (the beam sags about 0.1 m)
    // a solver of one block: SOFA's bits
    const std::string one = reduction_beam(5, 5, 40, false);
    auto sofa = reduction_scene(one, false, 1), blocked = reduction_scene(one, true, 2);
    for (int k = 0; k < 5; ++k) sofa->step(), blocked->step();
    const std::vector<double> x = reduction_positions(*sofa), y = reduction_positions(*blocked);
    for (std::size_t i = 0; i < x.size(); ++i) ASSERT_TRUE(test::same_bits(x[i], y[i])) << i;
}

}  // namespace
