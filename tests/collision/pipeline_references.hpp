#pragma once
// The references of the detection pipeline's tests (test_bvh, test_broad_phase,
// test_candidate_cache, test_narrow_phase): model parameters, the exhaustive detection of every
// element pair, output comparisons and the sphere and mesh scenes.
#include "detection_scenes.hpp"
#include "fixtures.hpp"
#include "penalty/collision/collision_pipeline.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <tuple>

namespace penalty::test_pipeline {

using test::same_bits;

using test::random_cloud;
using test::random_radii;

inline CollisionModelParams mp(const char* name, int node = -1, bool self = false, std::vector<int> group = {},
                               double cd = 0.0) {
    CollisionModelParams p;
    p.name = name;
    p.node = node;
    p.self_collision = self;
    p.group = std::move(group);
    p.contact_distance = cd;
    return p;
}

// A static obstacle's parameters: not moving, not simulated (its candidate-cache slack is 0).
inline CollisionModelParams static_mp(const char* name) {
    CollisionModelParams p = mp(name);
    p.moving = false;
    p.simulated = false;
    return p;
}

inline IntersectionParams method_params(IntersectionMethod m) {
    IntersectionParams p;
    switch (m) {
        case IntersectionMethod::Discrete:
            p = IntersectionParams::discrete();
            break;
        case IntersectionMethod::NewProximity:
            p = IntersectionParams::new_proximity();
            break;
        case IntersectionMethod::MinProximity:
            p = IntersectionParams::min_proximity();
            break;
        case IntersectionMethod::LocalMinDistance:
            p = IntersectionParams::local_min_distance();
            break;
    }
    if (m != IntersectionMethod::Discrete) {
        p.alarm_distance = 0.05;
        p.contact_distance = 0.02;
    }
    return p;
}

inline bool same_output(const DetectionOutput& a, const DetectionOutput& b) {
    return a.elem1 == b.elem1 && a.elem2 == b.elem2 && a.id == b.id && same_bits(a.point[0], b.point[0]) &&
           same_bits(a.point[1], b.point[1]) && same_bits(a.normal, b.normal) && same_bits(a.value, b.value);
}

/// Same pairs, keys and outputs, in the same order, bit for bit.
inline void expect_identical(const SceneDetection& got, const SceneDetection& ref) {
    ASSERT_EQ(got.size(), ref.size());
    for (std::size_t k = 0; k < ref.size(); ++k) {
        ASSERT_EQ(got[k].model1, ref[k].model1) << "pair " << k;
        ASSERT_EQ(got[k].model2, ref[k].model2) << "pair " << k;
        ASSERT_EQ(got[k].outputs.size(), ref[k].outputs.size())
            << got[k].model1->name() << "-" << got[k].model2->name();
        for (std::size_t i = 0; i < ref[k].outputs.size(); ++i) {
            ASSERT_TRUE(same_output(got[k].outputs[i], ref[k].outputs[i]))
                << got[k].model1->name() << "-" << got[k].model2->name() << " output " << i << " elems ("
                << got[k].outputs[i].elem1 << "," << got[k].outputs[i].elem2 << ") vs (" << ref[k].outputs[i].elem1
                << "," << ref[k].outputs[i].elem2 << ")";
        }
    }
}

/// A detection's pairs against broad_phase()'s, without the pipeline's root-box test: the listed
/// pairs come in broad_phase()'s order, each with every pair's outputs of the exhaustive loop
/// over its element pairs (detect_model_pair), and every pair not listed has none. Returns the
/// number of pairs broad_phase() keeps.
inline std::size_t expect_listed_pairs_hold_every_output(const SceneDetection& got, const IntersectionParams& params,
                                                         const std::vector<CollisionModel*>& models) {
    std::vector<ModelPair> pairs;
    broad_phase(params, models, pairs);
    std::size_t listed = 0;
    for (const ModelPair& pair : pairs) {
        const ModelPairDetection every = detect_model_pair(params, *pair.model1, *pair.model2);
        const bool is_listed =
            listed < got.size() && got[listed].model1 == pair.model1 && got[listed].model2 == pair.model2;
        if (!is_listed) {
            EXPECT_TRUE(every.outputs.empty()) << pair.model1->name() << "-" << pair.model2->name() << " not listed";
            continue;
        }
        const ModelPairDetection& d = got[listed++];
        EXPECT_TRUE(d.narrow_phase);
        EXPECT_EQ(d.outputs.size(), every.outputs.size()) << d.model1->name() << "-" << d.model2->name();
    }
    EXPECT_EQ(listed, got.size()) << "listed pairs not in broad_phase()'s order";
    return pairs.size();
}

inline std::size_t count_outputs(const SceneDetection& d) {
    std::size_t n = 0;
    for (const auto& p : d) n += p.outputs.size();
    return n;
}

/// The pair (a, b) if it has outputs, else nullptr.
inline const ModelPairDetection* find_pair(const SceneDetection& d, const CollisionModel* a, const CollisionModel* b) {
    for (const auto& p : d)
        if (p.model1 == a && p.model2 == b && !p.outputs.empty()) return &p;
    return nullptr;
}

/// Outputs in ascending (elem1, elem2): comparable between pipelines made at different steps
/// (SOFA's order depends on the positions at a model's first detection, see SofaOrder below).
inline CollisionPipelineOptions canonical_order() {
    CollisionPipelineOptions o;
    o.sofa_output_order = false;
    return o;
}

/// The reference: the same driver with the exhaustive all-element-pairs narrow phase.
inline SceneDetection detect_scene_exhaustive(const IntersectionParams& params, std::vector<CollisionModel*> models) {
    CollisionPipeline pipe(params, canonical_order(), ContactDetection::exhaustive);
    pipe.set_models(std::move(models));
    return pipe.detect();
}

// ---------------------------------------------------------------------------------------------
// Scenes

/// Sphere clouds: self-collision on and off, groups, a rigid sphere model, per-model skins.
struct SphereScene {
    Vec3State sa, sb, sc;
    Rigid3State sr;
    std::unique_ptr<SphereModel> a, b, c;
    std::unique_ptr<RigidSphereModel> r;
    std::vector<CollisionModel*> models;

    explicit SphereScene(std::uint32_t seed) {
        std::mt19937 g(seed);
        sa = random_cloud(400, 1.0, g);
        sb = random_cloud(300, 1.0, g, Vec3(0.3, 0, 0));
        sc = random_cloud(300, 1.0, g, Vec3(0, 0.3, 0));
        sr.resize(150);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (auto& f : sr.position) f.center = Vec3(u(g), u(g), u(g));
        a = std::make_unique<SphereModel>(sa, 0.05, random_radii(400, 0.02, 0.07, g), mp("A", 0, true, {}, 0.01));
        b = std::make_unique<SphereModel>(sb, 0.04, std::vector<double>{}, mp("B", 1, false, {1}));
        c = std::make_unique<SphereModel>(sc, 0.04, random_radii(100, 0.03, 0.05, g), mp("C", 2, true, {1, 2}));
        r = std::make_unique<RigidSphereModel>(sr, 0.06, std::vector<double>{}, mp("R", 3, false, {3}, 0.005));
        models = {a.get(), b.get(), c.get(), r.get()};
    }
    void jiggle(std::mt19937& g, double s) {
        for (auto* st : {&sa, &sb, &sc})
            for (auto& p : st->position) p += test::rand_vec(g, s);
        for (auto& f : sr.position) f.center += test::rand_vec(g, s);
    }
};

/// Triangle meshes with their edges and vertices in the same node (self-collision filters),
/// a second torus, and a point cloud.
struct MeshScene {
    std::unique_ptr<test::TorusMesh> t1, t2;
    Vec3State cloud;
    std::unique_ptr<TriangleModel> tri1, tri2;
    std::unique_ptr<LineModel> line1;
    std::unique_ptr<PointModel> pts1, pts2, free_pts;
    std::unique_ptr<SphereModel> balls;
    std::vector<CollisionModel*> models;

    MeshScene(std::uint32_t seed, bool self) {
        std::mt19937 g(seed);
        t1 = test::make_torus(28, 12, 0.5, 0.18, Vec3::Zero(), g, 0.3);
        t2 = test::make_torus(20, 10, 0.4, 0.15, Vec3(0.35, 0.1, 0.12), g, 0.3);
        cloud = random_cloud(500, 0.8, g);
        tri1 = std::make_unique<TriangleModel>(t1->state, t1->topo, mp("torus1", 1, self, {}, 0.005));
        line1 = std::make_unique<LineModel>(t1->state, t1->topo, mp("torus1-edges", 1, self));
        pts1 = std::make_unique<PointModel>(t1->state, &t1->topo, mp("torus1-points", 1, self));
        tri2 = std::make_unique<TriangleModel>(t2->state, t2->topo, mp("torus2", 2, false));
        pts2 = std::make_unique<PointModel>(t2->state, &t2->topo, mp("torus2-points", 2, false));
        free_pts = std::make_unique<PointModel>(cloud, nullptr, mp("cloud", 3, false, {}, 0.01));
        balls = std::make_unique<SphereModel>(cloud, 0.03, std::vector<double>{}, mp("balls", 4, false));
        models = {tri1.get(), line1.get(), pts1.get(), tri2.get(), pts2.get(), free_pts.get(), balls.get()};
    }
    void jiggle(std::mt19937& g, double s) {
        for (auto* st : {&t1->state, &t2->state, &cloud})
            for (auto& p : st->position) p += test::rand_vec(g, s);
    }
};

constexpr IntersectionMethod kMethods[] = {IntersectionMethod::Discrete, IntersectionMethod::NewProximity,
                                           IntersectionMethod::MinProximity, IntersectionMethod::LocalMinDistance};

}  // namespace penalty::test_pipeline
