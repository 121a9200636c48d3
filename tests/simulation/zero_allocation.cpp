// Steady-state steps allocate nothing on the heap in the contact path (issue 14 item 5).
//
// Its own executable (penalty_tests_zero_allocation, CTest label `simulation`): it replaces the
// global operator new / delete with counting versions, which must not leak into the other suites.
// The project scenes whose bodies rest on (or slide along) static bodies from step 50 on (persistent
// contact pairs; together they cover 15 model pairs: spheres, points, lines, cylinders, tetrahedra)
// are built by the scene builder, as `penalty run` does, with both detections, and run for 50
// steps; then steps 50–100 are counted. (Not here: triangle_pairs.scn, whose box is still settling
// then — its contact count reaches new maxima, so buffers grow — and damped_bounce.scn, which
// bounces: pairs are destroyed and recreated.)
//   - the contact path: everything the collision hook runs (every ContactPipeline::update():
//     detection by CollisionPipeline, CollisionResponse::set_detections, contact tracking,
//     contact mappers and penalty springs rebuilt, contact-point states resized): must be zero;
//   - the whole step (collision + solvers): asserted in WholeStep, skipped (with the count) while
//     the implicit solver still rebuilds its SubtreeSystem at every solve.
// Only C++ allocations (operator new) are counted: TBB's own task and thread-local storage go
// through its allocator (malloc), outside the contact code's control.
#include "penalty/collision/models.hpp"
#include "penalty/collision/sofa_traversal_order.hpp"
#include "penalty/core/pair_key.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/function_stage.hpp"
#include "penalty_test/paths.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>
#include <string>
#include <tuple>

namespace {

std::atomic<bool> counting{false};
std::atomic<long> allocations{0};

void* counted_alloc(std::size_t n) {
    if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
    throw std::bad_alloc();
}

void* counted_aligned_alloc(std::size_t n, std::align_val_t al) {
    if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
    const auto a = static_cast<std::size_t>(al);
    const std::size_t size = ((n == 0 ? 1 : n) + a - 1) / a * a;  // aligned_alloc: size a multiple of a
    if (void* p = std::aligned_alloc(a, size)) return p;
    throw std::bad_alloc();
}

}  // namespace

void* operator new(std::size_t n) { return counted_alloc(n); }
void* operator new[](std::size_t n) { return counted_alloc(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
    try {
        return counted_alloc(n);
    } catch (...) {
        return nullptr;
    }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
    try {
        return counted_alloc(n);
    } catch (...) {
        return nullptr;
    }
}
void* operator new(std::size_t n, std::align_val_t a) { return counted_aligned_alloc(n, a); }
void* operator new[](std::size_t n, std::align_val_t a) { return counted_aligned_alloc(n, a); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace penalty {
namespace {

/// Allocations counted while `f` runs.
template <class F>
long count_allocations(const F& f) {
    allocations.store(0);
    counting.store(true);
    f();
    counting.store(false);
    return allocations.load();
}

struct Counts {
    long contact_path = 0;  ///< inside the collision hook (every pipeline's update())
    long whole_step = 0;    ///< Scene::step()
    std::size_t live_pairs = 0;
    std::size_t contacts = 0;
};

/// Runs `file` for 50 steps, then counts steps 50–100 (`bvh`: the BVH detection, `penalty
/// run`'s default; else the exhaustive one, `--exhaustive`).
Counts run_scene(const std::string& file, bool bvh) {
    scene::BuildOptions options;
    options.exhaustive_detection = !bvh;
    auto scene = scene::load_scene(penalty::test::source_dir() / "scenes" / file, options);
    Simulation& sim = scene->simulation();
    // the contact path: the scene's contact stages, counted on their own
    long in_hook = 0;
    const std::vector<ContactStage*> stages = sim.contact_stages();
    for (ContactStage* s : stages) sim.remove_contact_stage(*s);
    const test::FunctionStage counted(sim, [&in_hook, &stages] {
        const long before = allocations.load();
        for (ContactStage* s : stages) s->detect();
        for (ContactStage* s : stages) s->respond();
        in_hook += allocations.load() - before;
    });
    for (int step = 0; step < 50; ++step) scene->step();
    Counts c;
    c.whole_step = count_allocations([&] {
        for (int step = 50; step < 100; ++step) scene->step();
    });
    c.contact_path = in_hook;
    for (const scene::ScenePipeline& p : scene->pipelines()) {
        c.live_pairs += p.pipeline->graph_entries().size();
        for (const ContactGraphEntry& e : p.pipeline->graph_entries()) c.contacts += e.contact->force_field().size();
    }
    return c;
}

class ZeroAllocation : public ::testing::TestWithParam<std::tuple<std::string, bool>> {};

TEST_P(ZeroAllocation, ContactPathAllocatesNothingInSteadyState) {
    const auto& [file, bvh] = GetParam();
    const Counts c = run_scene(file, bvh);
    // not vacuous: the bodies rest on their beds, so contact pairs stay alive
    ASSERT_GT(c.live_pairs, 0u);
    ASSERT_GT(c.contacts, 0u);
    EXPECT_EQ(c.contact_path, 0) << file << ": the contact path allocated over steps 50-100";
}

TEST_P(ZeroAllocation, WholeStep) {
    const auto& [file, bvh] = GetParam();
    const Counts c = run_scene(file, bvh);
    ASSERT_GT(c.live_pairs, 0u);
    EXPECT_EQ(c.whole_step, 0) << file << ": a step allocated over steps 50-100 (contact path: " << c.contact_path
                               << ")";
}

// The sort into SOFA's order keeps its buffers (SofaOrderScratch) from call to call: once they
// have grown, sorting the same number of outputs, or of keys, allocates nothing. 3000 outputs
// go through the radix sort (512 or more), 300 through std::sort.
TEST(ZeroAllocationSofaOrder, SortsAllocateNothingOnceTheScratchHasGrown) {
    std::mt19937 g(23);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Vec3State s1, s2;
    for (int i = 0; i < 300; ++i) s1.position.emplace_back(u(g), u(g), u(g));
    for (int i = 0; i < 120; ++i) s2.position.emplace_back(u(g), u(g), u(g));
    CollisionModelParams p1, p2;
    p1.name = "a";
    p2.name = "b";
    p2.node = 1;
    const PointModel m1(s1, nullptr, p1), m2(s2, nullptr, p2);
    SofaCubeTree t1, t2;
    t1.build(m1, 6);
    t2.build(m2, 6);
    for (const int count : {300, 3000}) {
        DetectionOutputList outputs;
        std::vector<std::uint64_t> keys;
        std::uniform_int_distribution<int> e1(0, 299), e2(0, 119);
        for (int k = 0; k < count; ++k) {
            DetectionOutput o;
            o.elem1 = ElementIndex(e1(g));
            o.elem2 = ElementIndex(e2(g));
            outputs.push_back(o);
            keys.push_back(pair_key::make(k % 300, k % 120));  // distinct pairs
        }
        const std::vector<std::uint64_t> unsorted_keys = keys;
        SofaOrderScratch scratch;
        DetectionOutputList first = outputs;
        std::vector<std::uint64_t> first_keys = keys;
        sort_in_sofa_order(t1, t2, first, scratch);  // the scratch grows
        sort_keys_in_sofa_order(t1, t2, first_keys, scratch);
        const long n = count_allocations([&] {
            sort_in_sofa_order(t1, t2, outputs, scratch);
            sort_keys_in_sofa_order(t1, t2, keys, scratch);
        });
        EXPECT_EQ(n, 0) << count << " outputs";
        // the same order both times (not vacuous: the sorts ran)
        ASSERT_EQ(outputs.size(), first.size());
        for (std::size_t i = 0; i < outputs.size(); ++i) ASSERT_EQ(outputs[i].elem1, first[i].elem1);
        EXPECT_EQ(keys, first_keys);
        EXPECT_NE(keys, unsorted_keys);  // the keys were given in element order, not SOFA's
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, ZeroAllocation,
                         ::testing::Combine(::testing::Values("sphere_pairs.scn", "line_pairs.scn", "cylinders.scn",
                                                              "tetra_point.scn", "friction_incline.scn"),
                                            ::testing::Bool()),
                         [](const auto& test_info) {
                             std::string name = std::get<0>(test_info.param);
                             name = name.substr(0, name.find('.'));
                             return name + (std::get<1>(test_info.param) ? "_bvh" : "_exhaustive");
                         });

}  // namespace
}  // namespace penalty
