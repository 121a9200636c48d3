// SubtreeSystem::FixedReaders: within one solve the contacts do not change, so the rows of a
// mapped state that the products map (the rows its contacts read, DxReaders) are found by the
// first product and kept. A spring cube slides over a floor of points; its bottom face is a
// triangle surface carried by a BarycentricMapping (which maps selected rows), and the contacts
// on it read a few of the surface's vertices, other ones at each step. The products under a
// FixedReaders made after each step must be the bits of products that find the rows each time;
// products with rows kept from before the step differ, which shows the rows do change (a
// FixedReaders that kept its rows from one solve to the next would fail the first check).
// The systems here do not fuse their contact products: the fused block applies the contacts'
// own mappings itself (test_fused_contact_block.cpp), and the stale products below, made
// across a step (outside FixedReaders' contract), would read contact lists of another size.
#include "penalty/io/scene_file.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/same_bits.hpp"
#include "penalty_test/sliding_cube.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>

namespace {

using namespace penalty;

TEST(FixedReaders, ProductsOfOneSolveKeepTheRowsTheFirstFoundAndTheNextSolveFindsThemAgain) {
    const auto scene = scene::build_scene(io::parse_scene_string(test::sliding_cube_xml(), "sliding_cube.scn"), {});
    Node& root = scene->simulation().root();
    Node* body = nullptr;
    for (const auto& child : root.children())
        if (child->name() == "Body") body = child.get();
    ASSERT_NE(body, nullptr);

    std::mt19937 rng(20261125);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const auto draw = [&](Eigen::Index n) {
        return Eigen::VectorXd(Eigen::VectorXd::NullaryExpr(n, [&] { return unit(rng); }));
    };
    const double m = 1.02, b = -0.01, k = -1.01e-4;  // an implicit-Euler operator
    std::unique_ptr<SubtreeSystem> kept;             // lives over steps, rebuilt when the graph changes
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
