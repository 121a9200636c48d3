// penalty against Bullet 3.24 (issue 17), part of penalty_bench_detection (built only when CMake
// finds Bullet's double-precision libraries): the `spheres` scene (spheres_scene.hpp: the same
// cloud, radius and alarm distance as BM_Pipeline/spheres), every sphere moved slightly before
// each detection, n = 1e3 … 1e6, registered side by side per n so that one run compares them.
//
// Motion (the same numbers for both): at step k, centre_i = rest_i + s_k·offset_i with
// s_k = +1 (k even) or −1 (k odd) and offset_i a fixed random vector of length ≤ kMotion, so
// both libraries see moving objects (penalty refits its tree, Bullet updates its AABBs) while
// the pair set barely changes (compared at s = +1: 660 pairs against 661 at rest for 10³).
// Writing the positions is part of the timed step for both.
//
// What "a pair" is: penalty (NewProximity Sphere–Sphere, np_sphere_sphere) reports spheres i, j
// when |c_i − c_j| < r_i + r_j + alarm distance. Bullet's btSphereSphereCollisionAlgorithm adds a
// contact point when |c_i − c_j| ≤ R_i + R_j (its m_closestPointDistanceThreshold is 0 in
// discrete detection), at distance |c_i − c_j| − R_i − R_j. Bullet spheres of radius
// R = r + alarm/2 therefore find the same pairs; a Bullet pair is a manifold holding a point of
// distance ≤ 0 (the manifold keeps one point per sphere pair). The two sets differ only for
// centres exactly at the threshold (strict vs. non-strict comparison, never met by this cloud).
//
// Bullet runs in two unit systems (the same cloud either way):
//   bullet        — every length multiplied by kBulletScale = 2^7 (exact in binary floating point:
//                   the same comparisons, hence the same pairs), so that the 7.5 mm spheres become
//                   0.96 "units", the size Bullet's fixed tolerances are made for (objects of
//                   0.05–10 units: gContactBreakingThreshold = 0.02 added to every AABB,
//                   gDbvtMargin = 0.05 added to moving leaves of the broad-phase tree). This is
//                   the comparison;
//   bullet_metres — in metres as penalty, Bullet's tolerances unchanged: the 5 cm leaf margin
//                   is 7 sphere spacings, so nearly every sphere pair of 10³ spheres becomes a
//                   broad-phase pair (counter bp_pairs) with its manifold. Run at 10³ only, to
//                   show why the scaling is needed (10⁴ would need gigabytes of manifolds).
// Both: btCollisionWorld + btDbvtBroadphase + btDefaultCollisionConfiguration +
// btCollisionDispatcher, one shared btSphereShape, performDiscreteCollisionDetection(), then the
// contact points of distance ≤ 0 counted over the manifolds (inside the timed step). One thread.
// penalty: CollisionPipeline::detect() with ContactDetection::bvh (the path `penalty run` takes),
// 1 and 2 threads.
//
// Counters: pairs (found per step, at the configuration s = +1), and for Bullet bp_pairs (its
// broad-phase pairs = manifolds) and pair_set_diff (the size of the symmetric difference between
// Bullet's and penalty's pair sets at s = +1; 0 expected, an error message otherwise).
#include "penalty/collision/collision_pipeline.hpp"
#include "spheres_scene.hpp"

#include <benchmark/benchmark.h>
#include <btBulletCollisionCommon.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace penalty {
namespace {

constexpr double kMotion = 1e-5;  ///< largest distance of a centre from its rest position, m (0.2 % of r)
/// Untimed steps, so that both libraries are timed in their steady state: trees built, Bullet's
/// pair cache and manifolds created, penalty's kept candidates collected and sorted into SOFA's
/// order (PairCandidates' rent-or-buy rule sorts them once the outputs sorted since the
/// collection outnumber them: at the 6th step at 10⁶ spheres, 3.2·10⁶ kept pairs against
/// 0.70·10⁶ outputs a step).
constexpr int kWarmupSteps = 8;
constexpr double kBulletScale = 128.0;  ///< Bullet's length unit = 1/128 m (2^7: exact scaling)

/// A sphere pair (i < j).
using SpherePair = std::pair<std::int64_t, std::int64_t>;

/// The rest positions of the cloud and the fixed offsets of the motion.
struct SphereMotion {
    std::vector<Vec3> rest;
    std::vector<Vec3> offset;

    explicit SphereMotion(std::size_t n) : rest(bench::sphere_cloud(n).position), offset(n) {
        std::mt19937 g(2000);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (auto& o : offset) o = Vec3(u(g), u(g), u(g)) * (kMotion / std::sqrt(3.0));
    }
    /// s_k of step k: +1 (even) or −1 (odd).
    static double sign(std::int64_t step) { return step % 2 == 0 ? 1.0 : -1.0; }
};

// ---- penalty ----

/// penalty's CollisionPipeline over the cloud, as BM_Pipeline/spheres builds it.
struct PenaltySpheres {
    Vec3State state;
    SphereModel model;
    CollisionPipeline pipe;

    PenaltySpheres(const SphereMotion& motion, bool candidate_cache)
        : state(cloud(motion)),
          model(state, bench::kSphereRadius, {}, bench::sphere_model_params()),
          pipe(bench::sphere_intersection_params(), options(candidate_cache)) {
        pipe.set_models({&model});
    }
    static CollisionPipelineOptions options(bool candidate_cache) {
        CollisionPipelineOptions o;
        o.candidate_cache = candidate_cache;
        return o;
    }
    static Vec3State cloud(const SphereMotion& motion) {
        Vec3State s;
        s.resize(motion.rest.size());
        s.position = motion.rest;
        return s;
    }
    /// Moves the spheres to step k and detects; returns the outputs found.
    std::size_t step(const SphereMotion& motion, std::int64_t k) {
        const double s = SphereMotion::sign(k);
        for (std::size_t i = 0; i < state.position.size(); ++i)
            state.position[i] = motion.rest[i] + s * motion.offset[i];
        std::size_t found = 0;
        for (const auto& d : pipe.detect()) found += d.outputs.size();
        return found;
    }
    [[nodiscard]] std::vector<SpherePair> pairs() const {
        std::vector<SpherePair> out;
        for (const auto& d : pipe.detections())
            for (const auto& o : d.outputs)
                out.emplace_back(std::min(o.elem1, o.elem2).value(), std::max(o.elem1, o.elem2).value());
        std::sort(out.begin(), out.end());
        return out;
    }
};

// ---- Bullet ----

/// Bullet's collision world over the cloud, lengths multiplied by `scale` (Bullet units per
/// metre). Members in construction order (the world is destroyed first and removes the objects'
/// proxies).
struct BulletSpheres {
    double scale;
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    btSphereShape shape{scale * (bench::kSphereRadius + 0.5 * bench::kSphereAlarmDistance)};  // R = r + alarm/2
    std::vector<std::unique_ptr<btCollisionObject>> objects;
    btCollisionWorld world{&dispatcher, &broadphase, &config};

    BulletSpheres(const SphereMotion& motion, double units_per_metre) : scale(units_per_metre) {
        objects.reserve(motion.rest.size());
        for (std::size_t i = 0; i < motion.rest.size(); ++i) {
            auto o = std::make_unique<btCollisionObject>();
            o->setCollisionShape(&shape);
            o->setCollisionFlags(0);  // not static: a moving body
            o->setUserIndex(int(i));
            const Vec3 p = scale * motion.rest[i];
            o->getWorldTransform().setIdentity();
            o->getWorldTransform().setOrigin(btVector3(p.x(), p.y(), p.z()));
            world.addCollisionObject(o.get());
            objects.push_back(std::move(o));
        }
    }
    /// Removes the broad-phase pairs one by one from the end of the pair array (O(1) each) before
    /// the world goes: ~btCollisionWorld cleans each proxy's pairs with a scan of the whole pair
    /// array (btHashedOverlappingPairCache::cleanProxyFromPairs), O(objects × pairs), hours at 10⁶.
    ~BulletSpheres() {
        btOverlappingPairCache* cache = broadphase.getOverlappingPairCache();
        btBroadphasePairArray& pairs = cache->getOverlappingPairArray();
        while (pairs.size() > 0) {
            const btBroadphasePair& last = pairs[pairs.size() - 1];
            cache->removeOverlappingPair(last.m_pProxy0, last.m_pProxy1, &dispatcher);
        }
    }
    BulletSpheres(const BulletSpheres&) = delete;
    BulletSpheres& operator=(const BulletSpheres&) = delete;

    /// Moves the spheres to step k and detects; returns the contact points of distance ≤ 0.
    std::size_t step(const SphereMotion& motion, std::int64_t k) {
        const double s = SphereMotion::sign(k);
        for (std::size_t i = 0; i < objects.size(); ++i) {
            const Vec3 p = scale * (motion.rest[i] + s * motion.offset[i]);  // as penalty's, then scaled
            objects[i]->getWorldTransform().setOrigin(btVector3(p.x(), p.y(), p.z()));
        }
        world.performDiscreteCollisionDetection();
        std::size_t found = 0;
        const int manifolds = dispatcher.getNumManifolds();
        for (int m = 0; m < manifolds; ++m) {
            const btPersistentManifold* mf = dispatcher.getManifoldByIndexInternal(m);
            for (int c = 0; c < mf->getNumContacts(); ++c) found += mf->getContactPoint(c).getDistance() <= 0.0;
        }
        return found;
    }
    [[nodiscard]] std::vector<SpherePair> pairs() {
        std::vector<SpherePair> out;
        const int manifolds = dispatcher.getNumManifolds();
        for (int m = 0; m < manifolds; ++m) {
            const btPersistentManifold* mf = dispatcher.getManifoldByIndexInternal(m);
            for (int c = 0; c < mf->getNumContacts(); ++c) {
                if (mf->getContactPoint(c).getDistance() > 0.0) continue;
                const std::int64_t i = mf->getBody0()->getUserIndex();
                const std::int64_t j = mf->getBody1()->getUserIndex();
                out.emplace_back(std::min(i, j), std::max(i, j));
            }
        }
        std::sort(out.begin(), out.end());
        return out;
    }
};

std::size_t symmetric_difference_size(const std::vector<SpherePair>& a, const std::vector<SpherePair>& b) {
    std::vector<SpherePair> d;
    std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
    return d.size();
}

// ---- the benchmarks ----

void BM_SpheresPenalty(benchmark::State& state) {
    const auto n = std::size_t(state.range(0));
    const int threads = int(state.range(1));
    const bool candidate_cache = state.range(2) != 0;
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    tbb::task_arena arena(threads);
    const SphereMotion motion(n);
    PenaltySpheres scene(motion, candidate_cache);
    std::int64_t k = 0;
    arena.execute([&] {
        for (; k < kWarmupSteps; ++k) scene.step(motion, k);
    });
    for (auto _ : state) {
        arena.execute([&] { benchmark::DoNotOptimize(scene.step(motion, k++)); });
    }
    std::size_t pairs = 0;
    arena.execute([&] { pairs = scene.step(motion, 0); });
    state.counters["pairs"] = double(pairs);
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(n));
}

void BM_SpheresBullet(benchmark::State& state, double units_per_metre) {
    const auto n = std::size_t(state.range(0));
    const SphereMotion motion(n);
    BulletSpheres scene(motion, units_per_metre);
    std::int64_t k = 0;
    for (; k < kWarmupSteps; ++k) scene.step(motion, k);
    for (auto _ : state) benchmark::DoNotOptimize(scene.step(motion, k++));
    const std::size_t pairs = scene.step(motion, 0);
    state.counters["pairs"] = double(pairs);
    state.counters["bp_pairs"] = double(scene.dispatcher.getNumManifolds());

    // the same pairs as penalty at the same positions (penalty's detection, untimed)
    PenaltySpheres reference(motion, false);
    reference.step(motion, 0);
    const auto bullet_pairs = scene.pairs();
    const auto penalty_pairs = reference.pairs();
    const std::size_t diff = symmetric_difference_size(bullet_pairs, penalty_pairs);
    state.counters["pair_set_diff"] = double(diff);
    if (diff != 0)
        state.SkipWithError(("Bullet found " + std::to_string(bullet_pairs.size()) + " pairs, penalty " +
                             std::to_string(penalty_pairs.size()) + ", " + std::to_string(diff) + " not in both")
                                .c_str());
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(n));
}

// Side by side per n: Bullet (in metres at 10³ only, then scaled), penalty (1, 2 threads). 10⁶
// runs a fixed 3 iterations so that the whole comparison takes a few minutes.
const bool registered = [] {
    for (const long n : {1000L, 10000L, 100000L, 1000000L}) {
        auto timing = [n](benchmark::internal::Benchmark* b) {
            b->Unit(benchmark::kMillisecond)->UseRealTime();
            if (n >= 1000000L) b->Iterations(3);
            else b->MinTime(0.5);
        };
        if (n == 1000L)
            timing(benchmark::RegisterBenchmark("BM_Against_Bullet/bullet_metres", BM_SpheresBullet, 1.0)->Arg(n));
        timing(benchmark::RegisterBenchmark("BM_Against_Bullet/bullet", BM_SpheresBullet, kBulletScale)->Arg(n));
        // third argument: the candidate cache on (1, the default) or off (0: the trees traversed at
        // every step, as before the cache)
        for (const long threads : {1L, 2L})
            timing(benchmark::RegisterBenchmark("BM_Against_Bullet/penalty", BM_SpheresPenalty)->Args({n, threads, 1}));
        timing(benchmark::RegisterBenchmark("BM_Against_Bullet/penalty", BM_SpheresPenalty)->Args({n, 1, 0}));
    }
    return true;
}();

}  // namespace
}  // namespace penalty
