// The bounding trees of the narrow phase (collision/bvh.cpp): a valid tree over the element boxes, refit against
// rebuild, non-finite positions named.
#include "pipeline_references.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <random>

namespace penalty {
namespace {

using namespace test_pipeline;

// ---------------------------------------------------------------------------------------------
// Bounding tree

TEST(Bvh, IsAValidTreeOverTheElementBoxes) {
    std::mt19937 g(7);
    Vec3State st = random_cloud(1000, 1.0, g);
    SphereModel m(st, 0.03, random_radii(1000, 0.01, 0.05, g), mp("s"));
    Bvh t;
    t.build(m, 4);
    ASSERT_FALSE(t.empty());
    EXPECT_EQ(t.build_count(), 1u);
    // permutation of the elements
    auto o = t.order();
    std::sort(o.begin(), o.end());
    for (std::uint32_t i = 0; i < 1000; ++i) ASSERT_EQ(o[i], i);
    // leaves of <= 4 elements, boxes contain their elements / children, counts add up
    std::size_t leaf_elems = 0;
    auto contains = [](const Aabb& outer, const Aabb& inner) {
        return (outer.min.array() <= inner.min.array()).all() && (outer.max.array() >= inner.max.array()).all();
    };
    for (std::size_t k = 0; k < t.nodes().size(); ++k) {
        const BvhNode& n = t.nodes()[k];
        if (n.leaf()) {
            EXPECT_LE(n.count, 4u);
            EXPECT_GE(n.count, 1u);
            leaf_elems += n.count;
            for (std::uint32_t s = n.first; s < n.first + n.count; ++s)
                ASSERT_TRUE(contains(n.box, t.element_boxes()[t.order()[s]]));
        } else {
            const BvhNode& l = t.nodes()[k + 1];
            const BvhNode& r = t.nodes()[n.right];
            EXPECT_EQ(l.count + r.count, n.count);
            EXPECT_EQ(l.first, n.first);
            EXPECT_EQ(r.first, n.first + l.count);
            ASSERT_TRUE(contains(n.box, l.box) && contains(n.box, r.box));
        }
    }
    EXPECT_EQ(leaf_elems, 1000u);
    // balanced median split: 1000 -> 500 -> 250 -> 125 -> 62/63 -> 31/32 -> 15/16 -> 7/8 -> 3/4
    EXPECT_EQ(t.depth(), 9);
    EXPECT_EQ(t.nodes().size(), 2 * 256u - 1);
    for (std::uint32_t i = 0; i < 1000; ++i)
        ASSERT_TRUE(same_bits(t.element_boxes()[i].min, m.element_box(Index(i)).min));
}

TEST(Bvh, RefitKeepsTheTreeForSmallMotionAndRebuildsWhenDegraded) {
    std::mt19937 g(8);
    Vec3State st = random_cloud(2000, 1.0, g);
    SphereModel m(st, 0.02, {}, mp("s"));
    Bvh t;
    t.build(m);
    for (auto& p : st.position) p += test::rand_vec(g, 0.001);
    EXPECT_FALSE(t.refit(m));
    EXPECT_EQ(t.build_count(), 1u);
    EXPECT_TRUE(same_bits(t.root_box().max, m.model_box().max));
    EXPECT_TRUE(same_bits(t.root_box().min, m.model_box().min));
    // scramble: every element moves across the box -> the refitted tree is far worse
    st.position = random_cloud(2000, 1.0, g).position;
    EXPECT_TRUE(t.refit(m));
    EXPECT_EQ(t.build_count(), 2u);
}

TEST(Bvh, NonFinitePositionNamesModelAndElement) {
    std::mt19937 g(9);
    Vec3State st = random_cloud(100, 1.0, g);
    st.position[17].y() = std::numeric_limits<double>::quiet_NaN();
    SphereModel m(st, 0.02, {}, mp("cloud"));
    Bvh t;
    try {
        t.build(m);
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        const std::string w = e.what();
        EXPECT_NE(w.find("cloud"), std::string::npos) << w;
        EXPECT_NE(w.find("element 17"), std::string::npos) << w;
        EXPECT_NE(w.find("not finite"), std::string::npos) << w;
    }
}

// ---------------------------------------------------------------------------------------------
// Broad phase

}  // namespace
}  // namespace penalty
