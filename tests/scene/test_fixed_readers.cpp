// SubtreeSystem::FixedReaders: within one solve the contacts do not change, so the rows of a
// mapped state that the products map (the rows its contacts read, DxReaders) are found by the
// first product and kept. A spring cube slides over a floor of points; its bottom face is a
// triangle surface carried by a BarycentricMapping (which maps selected rows), and the contacts
// on it read a few of the surface's vertices, other ones at each step. The products under a
// FixedReaders made after each step must be the bits of products that find the rows each time;
// products with rows kept from before the step differ, which shows the rows do change (a
// FixedReaders that kept its rows from one solve to the next would fail the first check).
// The systems here do not fuse their contact products: the fused block applies the contacts'
// own mappings itself (test_fused_contact_products.cpp), and the stale products below, made
// across a step (outside FixedReaders' contract), would read contact lists of another size.
#include "penalty/io/scene_file.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <sstream>
#include <string>

namespace {

using namespace penalty;

// Cube: 0.4 m, 8 points, springs on its hexahedron, 2 m/s along x; its bottom face (y = 0.02)
// a 5 × 5 vertex grid of 32 triangles facing down. Floor: two lines of static points 0.13 m
// apart, under a few of the face's triangles at a time.
std::string sliding_cube_xml() {
    std::ostringstream s;
    s << R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <CollisionPipeline/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <MinProximityIntersection alarmDistance="0.05" contactDistance="0.02"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Body">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    <MechanicalObject position="0 0.02 0  0.4 0.02 0  0 0.42 0  0.4 0.42 0  0 0.02 0.4  0.4 0.02 0.4  0 0.42 0.4  0.4 0.42 0.4"
                      velocity="2 0 0  2 0 0  2 0 0  2 0 0  2 0 0  2 0 0  2 0 0  2 0 0"/>
    <MeshTopology hexas="0 1 3 2 4 5 7 6"/>
    <UniformMass totalMass="1"/>
    <MeshSpringForceField stiffness="500" damping="1"/>
    <Node name="Surface">
      <MeshTopology position=")";
    for (int k = 0; k <= 4; ++k)
        for (int i = 0; i <= 4; ++i) s << 0.1 * i << " 0.02 " << 0.1 * k << "  ";
    s << R"(" triangles=")";
    const auto v = [](int i, int k) { return 5 * k + i; };
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 4; ++i)
            s << v(i, k) << ' ' << v(i + 1, k) << ' ' << v(i, k + 1) << "  " << v(i + 1, k) << ' ' << v(i + 1, k + 1) << ' '
              << v(i, k + 1) << "  ";
    s << R"("/>
      <MechanicalObject/>
      <TriangleCollisionModel contactStiffness="200"/>
      <BarycentricMapping/>
    </Node>
  </Node>
  <Node name="Floor">
    <MechanicalObject position=")";
    for (const double z : {0.11, 0.29})
        for (int i = 0; i < 25; ++i) s << -0.2 + 0.13 * i << " 0 " << z << "  ";
    s << R"("/>
    <PointCollisionModel simulated="0" moving="0" contactStiffness="200"/>
  </Node>
</Node>
)";
    return s.str();
}

TEST(FixedReaders, ProductsOfOneSolveKeepTheRowsTheFirstFoundAndTheNextSolveFindsThemAgain) {
    const auto scene = scene::build_scene(io::parse_scene_string(sliding_cube_xml(), "sliding_cube.scn"), {});
    Node& root = scene->simulation().root();
    Node* body = nullptr;
    for (const auto& child : root.children())
        if (child->name() == "Body") body = child.get();
    ASSERT_NE(body, nullptr);

    std::mt19937 rng(20261125);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const auto draw = [&](Eigen::Index n) { return Eigen::VectorXd(Eigen::VectorXd::NullaryExpr(n, [&] { return unit(rng); })); };
    const double m = 1.02, b = -0.01, k = -1.01e-4;  // an implicit-Euler operator
    std::unique_ptr<SubtreeSystem> kept;              // lives over steps, rebuilt when the graph changes
    std::uint64_t version = 0;
    int steps_with_contacts = 0, differing = 0, stale_compared = 0, stale_differing = 0;
    for (int step = 0; step < 60; ++step) {
        // rows found before the step, kept over it (what a FixedReaders must not do)
        Eigen::VectorXd stale_dx, stale_q;
        std::unique_ptr<SubtreeSystem::FixedReaders> stale;
        if (kept) {
            stale_dx = draw(kept->size());
            stale = std::make_unique<SubtreeSystem::FixedReaders>(*kept);
            kept->apply_mbk(stale_dx, stale_q, m, b, k, true);
        }
        scene->step();
        const bool same_graph = kept && root.structure_version() == version;
        if (same_graph) kept->apply_mbk(stale_dx, stale_q, m, b, k, true);
        stale.reset();
        if (!same_graph) {
            kept = std::make_unique<SubtreeSystem>(*body, false, /*fuse_contact_products=*/false);
            version = root.structure_version();
        }
        std::size_t contacts = 0;
        for (const auto& c : scene->contacts()) contacts += c.field->size();
        steps_with_contacts += contacts > 0 ? 1 : 0;

        // reference: a system whose products find the rows each time (no FixedReaders)
        SubtreeSystem fresh(*body, false, /*fuse_contact_products=*/false);
        if (same_graph) {
            Eigen::VectorXd ref;
            fresh.apply_mbk(stale_dx, ref, m, b, k, true);
            ++stale_compared;
            bool same = true;
            for (Eigen::Index i = 0; i < ref.size(); ++i) same = same && test::same_bits(stale_q[i], ref[i]);
            stale_differing += same ? 0 : 1;
        }
        const Eigen::VectorXd dx1 = draw(kept->size()), dx2 = draw(kept->size());
        Eigen::VectorXd ref1, ref2, q1, q2;
        fresh.apply_mbk(dx1, ref1, m, b, k, true);
        fresh.apply_mbk(dx2, ref2, m, b, k, true);
        {
            const SubtreeSystem::FixedReaders fixed(*kept);
            kept->apply_mbk(dx1, q1, m, b, k, true);
            kept->apply_mbk(dx2, q2, m, b, k, true);  // with the rows the product above found
        }
        ASSERT_EQ(q1.size(), ref1.size());
        for (Eigen::Index i = 0; i < q1.size(); ++i) {
            differing += test::same_bits(q1[i], ref1[i]) ? 0 : 1;
            differing += test::same_bits(q2[i], ref2[i]) ? 0 : 1;
        }
    }
    // the cube slides on the points: contacts at most steps, the same graph at most steps,
    // and at most of those the rows read changed over the step
    EXPECT_GE(steps_with_contacts, 40);
    EXPECT_GE(stale_compared, 30);
    EXPECT_GE(stale_differing, stale_compared / 4);  // 22 of 59
    EXPECT_EQ(differing, 0);
}

}  // namespace
