// The proximity kernels' early outs (penalty/collision/separation.hpp): a plane holding one
// element rules out a pair only when the other element is beyond R and the rounding allowance,
// and the kernels keep every output near R with the early outs in place.
#include "fixtures.hpp"
#include "penalty/collision/collision_pipeline.hpp"
#include "penalty/collision/separation.hpp"
#include "penalty_test/random_draws.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace penalty::test {
// The reference distances are long double computed from the kernels' doubles: every double is
// promoted on purpose (clang's -Wdouble-promotion would name each one).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdouble-promotion"

namespace {

using detail::plane_separates;
using detail::worth_separating;

// |n·(q − o)| / |n|, n = u × v, in long double from the same doubles (64-bit mantissa on x86-64)
long double plane_distance(const Vec3& o, const Vec3& u, const Vec3& v, const Vec3& q) {
    const long double n[3] = {(long double)u.y() * v.z() - (long double)u.z() * v.y(),
                              (long double)u.z() * v.x() - (long double)u.x() * v.z(),
                              (long double)u.x() * v.y() - (long double)u.y() * v.x()};
    long double s = 0.0L, n2 = 0.0L;
    for (int i = 0; i < 3; ++i) {
        s += n[i] * ((long double)q[i] - (long double)o[i]);
        n2 += n[i] * n[i];
    }
    return std::fabs(s) / std::sqrt(n2);
}

TEST(Separation, RejectsOnlyBeyondRAndTheAllowanceAndFindsTheFarOnes) {
    std::mt19937 rng(20261124);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double scales[] = {1e-3, 1.0, 1e3};
    int far = 0, far_rejected = 0, near = 0, near_rejected = 0, between_rejected = 0, band_rejected = 0, rejected = 0;
    for (int trial = 0; trial < 30000; ++trial) {
        const double scale = scales[trial % 3];
        const double R = scale * (0.01 + unit(rng));
        const Vec3 o = rand_vec(rng, 100.0 * scale);
        const Vec3 u = rand_vec(rng, 50.0 * R);
        const Vec3 v = rand_vec(rng, 50.0 * R);
        const Vec3 n = u.cross(v).normalized();
        // a point over the plane at a height around R: just inside, at R, just beyond, far
        const double rel[] = {-0.5, -1e-3, -1e-9, 0.0, 1e-12, 1e-9, 1e-4, 4e-4, 1e-3, 0.01, 1.0};
        const double h = R * (1.0 + rel[trial % 11]) * (trial % 2 == 0 ? 1.0 : -1.0);
        const Vec3 q = o + unit(rng) * u + unit(rng) * v + h * n;
        const bool reliable = u.cross(v).squaredNorm() > 1e-6 * u.squaredNorm() * v.squaredNorm();
        const long double d = plane_distance(o, u, v, q);
        const bool rejects = plane_separates(o, u, v, R, q);
        rejected += rejects;
        if (rejects) {
            // beyond R by far more than any kernel's rounding (1e-14 of the coordinates)
            EXPECT_GT(d, 1.0004L * R) << "trial " << trial;
        }
        if (d <= R) {
            ++near;
            near_rejected += rejects;
        } else if (d < 1.0004L * R) {
            between_rejected += rejects;
        } else if (d > 1.001L * R && reliable) {
            ++far;
            far_rejected += rejects;
        } else if (d <= 1.001L * R) {
            band_rejected += rejects;  // (1.0004 R, 1.001 R]: the allowance's edge, either answer
        }
    }
    EXPECT_EQ(near_rejected, 0);
    EXPECT_EQ(between_rejected, 0);
    EXPECT_GT(near, 8000);
    EXPECT_GT(far, 5000);
    // the test finds the separated points (the hit rate), not just never errs
    EXPECT_GE(far_rejected, far * 99 / 100) << far_rejected << " of " << far;
    // an unreliable plane is never used: every rejection is of a far point or one at the edge
    EXPECT_EQ(rejected, far_rejected + band_rejected);
}

TEST(Separation, EveryPointOnOneSide) {
    const Vec3 o(0, 0, 0), u(10, 0, 0), v(0, 10, 0);
    const Vec3 up(1, 1, 2), up2(3, -4, 5), down(1, 1, -2), close(1, 1, 0.5);
    EXPECT_TRUE(plane_separates(o, u, v, 1.0, up, up2));
    EXPECT_TRUE(plane_separates(o, u, v, 1.0, down));
    EXPECT_FALSE(plane_separates(o, u, v, 1.0, up, down));   // the element crosses the plane
    EXPECT_FALSE(plane_separates(o, u, v, 1.0, up, close));  // one point within R
    EXPECT_TRUE(plane_separates(o, u, v, 1.0, up, up2, Vec3(0, 0, 1.01)));
    EXPECT_FALSE(plane_separates(o, u, v, 1.0, up, up2, Vec3(0, 0, 1.0003)));  // within the allowance
}

TEST(Separation, UnreliableOrNonFiniteInputsAreNeverRejected) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const Vec3 o(0, 0, 0), u(10, 0, 0), v(0, 10, 0), far(0, 0, 100);
    EXPECT_TRUE(plane_separates(o, u, v, 1.0, far));
    EXPECT_FALSE(plane_separates(o, u, Vec3(10, 1e-3, 0), 1.0, far));  // nearly parallel: 1e-4 rad
    EXPECT_FALSE(plane_separates(o, u, Vec3::Zero(), 1.0, far));       // a degenerate triangle
    EXPECT_FALSE(plane_separates(o, u, v, nan, far));
    EXPECT_FALSE(plane_separates(o, u, v, 1.0, Vec3(0, 0, nan)));
    EXPECT_FALSE(plane_separates(Vec3(nan, 0, 0), u, v, 1.0, far));
    EXPECT_FALSE(plane_separates(o, Vec3(inf, 0, 0), v, 1.0, far));
    EXPECT_FALSE(plane_separates(o, u, v, inf, far));
    // tiny coordinates: the products underflow, no decision
    EXPECT_FALSE(plane_separates(o, 1e-150 * u, 1e-150 * v, 1e-150, 1e-150 * far));
    // large coordinates: no rejection within R, rejection far beyond it; from lengths of about
    // 1e50 on, the products (length⁶) overflow and there is no decision
    EXPECT_FALSE(plane_separates(Vec3(1e45, 0, 0), 1e39 * u, 1e39 * v, 1e40, Vec3(1e45, 0, 0.5e40)));
    EXPECT_TRUE(plane_separates(Vec3(1e45, 0, 0), 1e39 * u, 1e39 * v, 1e40, Vec3(1e45, 0, 3e40)));
    EXPECT_FALSE(plane_separates(Vec3(1e150, 0, 0), 1e140 * u, 1e140 * v, 1e140, Vec3(1e150, 0, 3e140)));
    EXPECT_FALSE(worth_separating(1.0, nan));
    EXPECT_FALSE(worth_separating(nan, 1.0));
    EXPECT_FALSE(worth_separating(15.9, 1.0));
    EXPECT_TRUE(worth_separating(16.1, 1.0));
}

// ---------------------------------------------------------------------------------------------
// ElementPlanes: whole boxes against a triangle's plane or a segment's three axis-parallel planes
// (the traversal's row mode).

using detail::ElementPlanes;

// The smallest |n·(x − o)| / |n| over the corners x of `box` grown by `pad`, in long double, if
// all corners are on one side of the plane; 0 if they straddle it.
long double box_clearance(const long double n[3], const Vec3& o, const Aabb& box, double pad) {
    long double lo = std::numeric_limits<long double>::infinity(), hi = -lo, n2 = 0.0L;
    for (int i = 0; i < 3; ++i) n2 += n[i] * n[i];
    for (int corner = 0; corner < 8; ++corner) {
        long double d = 0.0L;
        for (int i = 0; i < 3; ++i) {
            const long double x = (corner >> i) & 1 ? (long double)box.max[i] + pad : (long double)box.min[i] - pad;
            d += n[i] * (x - (long double)o[i]);
        }
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
    if (lo <= 0.0L && hi >= 0.0L) return 0.0L;
    return std::min(std::fabs(lo), std::fabs(hi)) / std::sqrt(n2);
}

TEST(Separation, ElementPlanesClearOnlyBoxesBeyondRAndFindTheFarOnes) {
    std::mt19937 rng(20261125);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double scales[] = {1e-3, 1.0, 1e3};
    const double rel[] = {-0.5, -1e-3, -1e-9, 0.0, 1e-12, 1e-9, 1e-4, 4e-4, 1e-3, 0.01, 1.0};
    int far = 0, far_cleared = 0, near = 0, near_cleared = 0, between_cleared = 0, cleared = 0, band_cleared = 0;
    for (int trial = 0; trial < 40000; ++trial) {
        const double scale = scales[trial % 3];
        const double R = scale * (0.01 + unit(rng));
        const bool triangle = trial % 2 == 0;
        const Vec3 p1 = rand_vec(rng, 100.0 * scale);
        const Vec3 u = rand_vec(rng, 50.0 * R), v = rand_vec(rng, 50.0 * R);
        const Vec3 p2 = p1 + u, p3 = p1 + v;
        const ElementPlanes planes =
            triangle ? ElementPlanes::triangle(p1, p2, p3, R) : ElementPlanes::segment(p1, p2, R);
        // the exact normals of the element's planes (from the stored vertices), in long double
        std::vector<std::array<long double, 3>> normals;
        const long double du[3] = {(long double)p2.x() - p1.x(), (long double)p2.y() - p1.y(),
                                   (long double)p2.z() - p1.z()};
        const long double dv[3] = {(long double)p3.x() - p1.x(), (long double)p3.y() - p1.y(),
                                   (long double)p3.z() - p1.z()};
        if (triangle) {
            normals.push_back(
                {du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2], du[0] * dv[1] - du[1] * dv[0]});
        } else {
            normals.push_back({0.0L, du[2], -du[1]});
            normals.push_back({-du[2], 0.0L, du[0]});
            normals.push_back({du[1], -du[0], 0.0L});
        }
        // a box over the plane the trial aims at, its nearest corner at a height around R
        const std::size_t aim = triangle ? 0 : std::size_t(trial / 2) % 3;
        const Vec3 n_aim = Vec3(double(normals[aim][0]), double(normals[aim][1]), double(normals[aim][2])).normalized();
        const Vec3 half(2.0 * R * unit(rng), 2.0 * R * unit(rng), 2.0 * R * unit(rng));
        const double pad = trial % 4 == 1 ? 0.1 * R : 0.0;
        const double extent = n_aim.cwiseAbs().dot(half + Vec3::Constant(pad));
        const double h = (R * (1.0 + rel[trial % 11]) + extent) * (trial % 3 == 0 ? -1.0 : 1.0);
        const Vec3 foot =
            triangle ? Vec3(p1 + unit(rng) * u + unit(rng) * (1.0 - unit(rng)) * v) : Vec3(p1 + unit(rng) * u);
        const Vec3 centre = foot + h * n_aim;
        Aabb box;
        box.min = centre - half;
        box.max = centre + half;
        const bool clears = planes.clears(box, pad);
        long double best = 0.0L;
        for (const auto& n : normals) best = std::max(best, box_clearance(n.data(), p1, box, pad));
        const long double aimed = box_clearance(normals[aim].data(), p1, box, pad);
        const bool reliable = !triangle || u.cross(v).squaredNorm() > 1e-6 * u.squaredNorm() * v.squaredNorm();
        cleared += clears;
        // a cleared box is beyond R by far more than any kernel's rounding, on one side of a plane
        if (clears) {
            EXPECT_GT(best, 1.0004L * R) << "trial " << trial;
        }
        if (best <= R) {
            ++near;
            near_cleared += clears;
        } else if (best < 1.0004L * R) {
            between_cleared += clears;
        } else if (aimed > 1.001L * R && reliable) {
            ++far;
            far_cleared += clears;
        } else if (best <= 1.001L * R || aimed <= 1.001L * R) {
            band_cleared += clears;  // at the allowance's edge on the planes, either answer
        }
    }
    EXPECT_EQ(near_cleared, 0);
    EXPECT_EQ(between_cleared, 0);
    EXPECT_GT(near, 10000) << near;
    EXPECT_GT(far, 8000) << far;
    EXPECT_GE(far_cleared, far * 99 / 100) << far_cleared << " of " << far;  // the hit rate
    EXPECT_EQ(cleared, far_cleared + band_cleared);
}

TEST(Separation, ElementPlanesOfDegenerateOrNonFiniteInputsClearNothing) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    Aabb far_box;
    far_box.min = Vec3(-1, -1, 10);
    far_box.max = Vec3(1, 1, 12);
    const ElementPlanes flat = ElementPlanes::triangle(Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), 1.0);
    EXPECT_EQ(flat.count, 1);
    EXPECT_TRUE(flat.clears(far_box));
    EXPECT_FALSE(flat.clears(far_box, 9.0));  // grown to z = 1: within R
    Aabb crossing = far_box;
    crossing.min.z() = -12;
    EXPECT_FALSE(flat.clears(crossing));
    // a segment along x: the plane with normal d × e_x is 0, the two others hold it
    const ElementPlanes along_x = ElementPlanes::segment(Vec3(0, 0, 0), Vec3(10, 0, 0), 1.0);
    EXPECT_EQ(along_x.count, 2);
    EXPECT_TRUE(along_x.clears(far_box));
    Aabb beside;  // 3 m beside the line in y, straddling its plane z = 0
    beside.min = Vec3(-1, 3, -1);
    beside.max = Vec3(1, 4, 1);
    EXPECT_TRUE(along_x.clears(beside));
    EXPECT_EQ(ElementPlanes::triangle(Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(20, 1e-4, 0), 1.0).count, 0);  // sliver
    EXPECT_EQ(ElementPlanes::segment(Vec3(1, 2, 3), Vec3(1, 2, 3), 1.0).count, 0);
    EXPECT_FALSE(ElementPlanes::triangle(Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), nan).clears(far_box));
    EXPECT_FALSE(ElementPlanes::triangle(Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), inf).clears(far_box));
    EXPECT_FALSE(ElementPlanes::triangle(Vec3(nan, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), 1.0).clears(far_box));
    EXPECT_FALSE(ElementPlanes::segment(Vec3(0, 0, 0), Vec3(inf, 0, 0), 1.0).clears(far_box));
    Aabb bad = far_box;
    bad.max.z() = nan;
    EXPECT_FALSE(flat.clears(bad));
    bad.max.z() = inf;
    EXPECT_FALSE(flat.clears(bad));
    EXPECT_FALSE(flat.clears(far_box, nan));
    EXPECT_FALSE(flat.clears(far_box, inf));
    // tiny coordinates: the bound underflows, no decision
    Aabb tiny = far_box;
    tiny.min *= 1e-150;
    tiny.max *= 1e-150;
    EXPECT_FALSE(ElementPlanes::triangle(Vec3(0, 0, 0), Vec3(1e-149, 0, 0), Vec3(0, 1e-149, 0), 1e-150).clears(tiny));
}

// ---------------------------------------------------------------------------------------------
// The kernels with their early outs: the BVH detection turns them on for pairs with elements
// longer than 16 R (200 m against R = 0.75 here); the exhaustive detection never does, so it is
// the reference without them.

SceneDetection detect(const IntersectionParams& params, std::vector<CollisionModel*> models, ContactDetection how,
                      bool candidate_cache = true) {
    CollisionPipelineOptions o;
    o.sofa_output_order = false;
    o.candidate_cache = candidate_cache;
    CollisionPipeline pipe(params, o, how);
    pipe.set_models(std::move(models));
    return pipe.detect();
}

// Whether two detections have the same outputs bit for bit (gtest failures name the first
// differences); returns their number of outputs.
std::size_t same_outputs(const SceneDetection& got, const SceneDetection& ref) {
    std::size_t n = 0;
    EXPECT_EQ(got.size(), ref.size());
    for (std::size_t k = 0; k < std::min(got.size(), ref.size()); ++k) {
        EXPECT_EQ(got[k].outputs.size(), ref[k].outputs.size()) << "pair " << k;
        for (std::size_t i = 0; i < std::min(got[k].outputs.size(), ref[k].outputs.size()); ++i) {
            const DetectionOutput& a = got[k].outputs[i];
            const DetectionOutput& b = ref[k].outputs[i];
            EXPECT_TRUE(a.elem1 == b.elem1 && a.elem2 == b.elem2 && a.id == b.id && same_bits(a.point[0], b.point[0]) &&
                        same_bits(a.point[1], b.point[1]) && same_bits(a.normal, b.normal) &&
                        same_bits(a.value, b.value))
                << "pair " << k << " output " << i;
        }
        n += got[k].outputs.size();
    }
    return n;
}

// The BVH detection's outputs, after checking them bit for bit against the exhaustive ones.
std::size_t outputs_checked(const IntersectionParams& params, const std::vector<CollisionModel*>& models,
                            bool candidate_cache = true) {
    // the exhaustive detection first, so that the BVH detection's state (the triangles' planes) is
    // the last one left in the models
    const auto exhaustive = detect(params, models, ContactDetection::exhaustive);
    const auto bvh = detect(params, models, ContactDetection::bvh, candidate_cache);
    return same_outputs(bvh, exhaustive);
}

MeshTopology edges_topology(std::size_t points, std::vector<Edge> edges) {
    MeshTopology t;
    t.set_num_points(points);
    t.set_edges(std::move(edges));
    return t;
}

IntersectionParams params_with_alarm(IntersectionParams p, double alarm) {
    p.alarm_distance = alarm;
    p.contact_distance = 0.25;
    return p;
}

constexpr double kR = 0.75;
constexpr double kInside = kR * (1.0 - 1e-9);  // just within R: the output stays
constexpr double kBeyond = kR * 1.01;          // beyond R and the allowance: no output

TEST(Separation, MinProximityTrianglePointAndLineLineKeepTheirOutputsNearR) {
    const IntersectionParams min = params_with_alarm(IntersectionParams::min_proximity(), kR);
    // a slanted 200 m triangle, and a point over its interior along its normal
    const Vec3 a(-100, -3, -100), b(100, 7, -90), c(-20, 1, 110);
    const Vec3 n = (b - a).cross(c - a).normalized();
    const Vec3 inside = a + 0.3 * (b - a) + 0.3 * (c - a);
    auto tri = triangle_mesh({a, b, c}, {{0, 1, 2}});
    TriangleModel t(tri->state, tri->topo);
    for (const double sign : {1.0, -1.0}) {
        Vec3State s = make_state({inside + sign * kInside * n});
        PointModel p(s);
        EXPECT_EQ(outputs_checked(min, {&t, &p}), 1u) << sign;
        s.position[0] = inside + sign * kBeyond * n;
        EXPECT_EQ(outputs_checked(min, {&t, &p}), 0u);
    }
    // a 200 m segment and a 1 m segment crossing over its middle, perpendicular to both
    Vec3State long_state = make_state({{-100, 0, 0}, {100, 0, 0}});
    const MeshTopology long_topo = edges_topology(2, {{0, 1}});
    LineModel long_line(long_state, long_topo);
    const MeshTopology short_topo = edges_topology(2, {{0, 1}});
    for (const double sign : {1.0, -1.0}) {
        const Vec3 over(3.0, 0.0, sign * kInside);
        Vec3State short_state = make_state({over - Vec3(0, 0.5, 0), over + Vec3(0, 0.5, 0)});
        LineModel short_line(short_state, short_topo);
        EXPECT_EQ(outputs_checked(min, {&long_line, &short_line}), 1u) << sign;
        for (Vec3& x : short_state.position) x.z() = sign * kBeyond;
        EXPECT_EQ(outputs_checked(min, {&long_line, &short_line}), 0u);
    }
}

TEST(Separation, NewProximityTriangleKernelsKeepTheirOutputsNearR) {
    const IntersectionParams np = params_with_alarm(IntersectionParams::new_proximity(), kR);
    const IntersectionParams min = params_with_alarm(IntersectionParams::min_proximity(), kR);
    // a flat 200 m triangle at z = 0, seen from both sides
    auto big = triangle_mesh({{-100, -100, 0}, {100, -100, 0}, {0, 100, 0}}, {{0, 1, 2}});
    TriangleModel t(big->state, big->topo);
    const MeshTopology segment = edges_topology(2, {{0, 1}});
    for (const double sign : {1.0, -1.0}) {
        const double z = sign * kInside;
        Vec3State ps = make_state({{1, 2, z}});  // a point
        PointModel p(ps);
        EXPECT_EQ(outputs_checked(np, {&t, &p}), 1u) << sign;
        // a small triangle parallel to it: its three vertices face the big one
        auto small = triangle_mesh({{1, 2, z}, {2, 2, z}, {1, 3, z}}, {{0, 1, 2}});
        TriangleModel s(small->state, small->topo);
        EXPECT_EQ(outputs_checked(np, {&t, &s}), 3u) << sign;
        Vec3State ls = make_state({{1, 2, z}, {3, 2, z}});  // a segment parallel to it
        LineModel l(ls, segment);
        EXPECT_EQ(outputs_checked(np, {&t, &l}), 2u) << sign;
        Vec3State ss = make_state({{1, 2, sign * (kInside + 0.5)}});  // a sphere, radius 0.5
        SphereModel sp(ss, 0.5);
        EXPECT_EQ(outputs_checked(np, {&t, &sp}), 1u) << sign;
        EXPECT_EQ(outputs_checked(min, {&t, &sp}), 1u) << sign;
        ps.position[0].z() = sign * kBeyond;
        for (Vec3& x : small->state.position) x.z() = sign * kBeyond;
        for (Vec3& x : ls.position) x.z() = sign * kBeyond;
        ss.position[0].z() = sign * (kBeyond + 0.5);
        EXPECT_EQ(outputs_checked(np, {&t, &p}), 0u);
        EXPECT_EQ(outputs_checked(np, {&t, &s}), 0u);
        EXPECT_EQ(outputs_checked(np, {&t, &l}), 0u);
        EXPECT_EQ(outputs_checked(np, {&t, &sp}), 0u);
        EXPECT_EQ(outputs_checked(min, {&t, &sp}), 0u);
    }
}

// A pyramid of four 140 m faces (the shape of SOFA's floor2b.obj), its 8 edges and a cloud of
// points, short segments, small triangles and spheres around its faces at heights near R: the
// BVH detection, with the early outs, gives the exhaustive detection's outputs bit for bit.
TEST(Separation, PyramidAndCloudEqualTheExhaustiveDetection) {
    const std::vector<Vec3> corners = {{-75, 2, -75}, {75, 2, -75}, {75, 2, 75}, {-75, 2, 75}, {0, 52, 0}};
    auto pyramid = triangle_mesh(corners, {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}});
    const MeshTopology pyramid_edges =
        edges_topology(5, {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 4}, {1, 4}, {2, 4}, {3, 4}});
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double rel[] = {-0.5, -1e-6, -1e-9, 1e-9, 1e-6, 1e-3, 0.5};
    std::vector<Vec3> cloud;
    std::vector<Edge> cloud_edges;
    std::vector<Triangle> cloud_triangles;
    for (int k = 0; k < 600; ++k) {
        // a point over a face or an edge at a height near R
        const int f = k % 4;
        const Vec3 &a = corners[std::size_t(f)], &b = corners[std::size_t((f + 1) % 4)], &apex = corners[4];
        const Vec3 n = (b - a).cross(apex - a).normalized();
        const double u = unit(rng), v = unit(rng) * (1.0 - u);
        const Vec3 foot = k % 3 == 0 ? Vec3(a + u * (apex - a)) : Vec3(a + u * (b - a) + v * (apex - a));
        const Vec3 side = k % 3 == 0 ? Vec3(n.cross(apex - a).normalized()) : n;
        const Vec3 base = foot + kR * (1.0 + rel[k % 7]) * (k % 2 == 0 ? 1.0 : -1.0) * side;
        const int i = int(cloud.size());
        const Vec3 along = rand_unit(rng).cross(side).normalized() * 0.3;  // parallel to the face
        cloud.push_back(base);
        cloud.push_back(base + along);
        cloud.push_back(base + along.cross(side).normalized() * 0.3);
        cloud_edges.push_back({i, i + 1});
        cloud_triangles.push_back({i, i + 1, i + 2});
    }
    auto small = triangle_mesh(cloud, cloud_triangles);
    small->topo.set_edges(cloud_edges);
    PointModel points(small->state, nullptr, named("points"));
    LineModel segments(small->state, small->topo, named("segments"));
    TriangleModel triangles(small->state, small->topo, named("triangles"));
    SphereModel spheres(small->state, 0.05, {}, named("spheres"));
    // the traversal's row mode runs for the pyramid's models with or without the candidate
    // cache, and in the cache's collection (boxes grown by the slack) when the pyramid is static
    for (const bool pyramid_moves : {true, false}) {
        CollisionModelParams fp = named("faces"), ep = named("edges");
        fp.moving = ep.moving = pyramid_moves;
        TriangleModel faces(pyramid->state, pyramid->topo, fp);
        LineModel edges(pyramid->state, pyramid_edges, ep);
        for (const IntersectionParams& params : {params_with_alarm(IntersectionParams::new_proximity(), kR),
                                                 params_with_alarm(IntersectionParams::min_proximity(), kR)}) {
            for (const bool cache : {true, false}) {
                SCOPED_TRACE(::testing::Message() << intersection_method_name(params.method) << " pyramid moves "
                                                  << pyramid_moves << " cache " << cache);
                const std::size_t n =
                    outputs_checked(params, {&faces, &edges, &points, &segments, &triangles, &spheres}, cache);
                EXPECT_GT(n, 500u);  // the cloud within R of the pyramid has outputs
            }
        }
    }
}
// A static pyramid and a cloud of points and short segments drifting through its faces, over 60
// detections of one pipeline with the candidate cache: the row mode (in the traversal, and in the
// cache's collection with the boxes grown by the slack) gives the exhaustive detection's outputs
// at every step, and hands the kernels a small part of the element pairs whose boxes overlap.
// The cloud sinks 0.02 m a step, slowly enough for the cache to keep its candidates.
TEST(Separation, RowModeFollowsACloudDriftingThroughAStaticPyramid) {
    const std::vector<Vec3> corners = {{-75, 2, -75}, {75, 2, -75}, {75, 2, 75}, {-75, 2, 75}, {0, 52, 0}};
    auto pyramid = triangle_mesh(corners, {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}});
    const MeshTopology pyramid_edges =
        edges_topology(5, {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 4}, {1, 4}, {2, 4}, {3, 4}});
    CollisionModelParams fp = named("faces"), ep = named("edges");
    fp.moving = ep.moving = false;
    fp.simulated = ep.simulated = false;
    TriangleModel faces(pyramid->state, pyramid->topo, fp);
    LineModel edges(pyramid->state, pyramid_edges, ep);
    // points and 0.4 m segments 0.5–8 m over the faces (a quarter of them over the edges' line)
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Vec3> cloud;
    std::vector<Edge> segments;
    std::vector<Vec3> drift;  // per point: its face's inward normal (the cloud sinks into the faces)
    for (int k = 0; k < 400; ++k) {
        const int f = k % 4;
        const Vec3 &a = corners[std::size_t(f)], &b = corners[std::size_t((f + 1) % 4)], &apex = corners[4];
        const Vec3 n = (b - a).cross(apex - a).normalized();
        const double u = unit(rng), v = unit(rng) * (1.0 - u);
        const Vec3 foot = k % 4 == 0 ? Vec3(a + u * (apex - a)) : Vec3(a + u * (b - a) + v * (apex - a));
        const Vec3 p = foot + (0.5 + 7.5 * unit(rng)) * n;
        const Vec3 along = rand_unit(rng).cross(n).normalized() * 0.4;
        segments.push_back({int(cloud.size()), int(cloud.size()) + 1});
        cloud.push_back(p);
        cloud.push_back(p + along);
        drift.push_back(-n);
        drift.push_back(-n);
    }
    Vec3State state = make_state(cloud);
    const MeshTopology cloud_topo = edges_topology(cloud.size(), segments);
    PointModel points(state, nullptr, named("points"));
    LineModel lines(state, cloud_topo, named("segments"));
    const IntersectionParams params = params_with_alarm(IntersectionParams::min_proximity(), kR);
    for (const auto& [long_model, other] : {std::pair<CollisionModel*, CollisionModel*>{&faces, &points},
                                            std::pair<CollisionModel*, CollisionModel*>{&edges, &lines},
                                            std::pair<CollisionModel*, CollisionModel*>{&edges, &points}}) {
        SCOPED_TRACE(long_model->name() + " vs " + other->name());
        state.position = cloud;
        CollisionPipelineOptions o;
        o.sofa_output_order = false;
        CollisionPipeline bvh(params, o, ContactDetection::bvh);
        CollisionPipeline exhaustive(params, o, ContactDetection::exhaustive);
        bvh.set_models({long_model, other});
        exhaustive.set_models({long_model, other});
        std::size_t outputs = 0, overlapping = 0;
        for (int step = 0; step < 200; ++step) {
            for (std::size_t i = 0; i < cloud.size(); ++i) state.position[i] += 0.02 * drift[i];  // 4 m in all
            const SceneDetection& reference = exhaustive.detect();  // (first, as g++ ordered the call)
            outputs += same_outputs(bvh.detect(), reference);
            for (std::size_t e1 = 0; e1 < long_model->size(); ++e1)
                for (std::size_t e2 = 0; e2 < other->size(); ++e2)
                    overlapping += long_model->element_box(Index(e1)).overlaps(other->element_box(Index(e2)), kR + 0.5);
        }
        EXPECT_GT(outputs, 100u);                            // 163 for the edges and segments, thousands for the others
        EXPECT_GT(bvh.candidate_cache_stats().reused, 50u);  // the cache's path ran too (133 of 200)
        // the element pairs the kernels saw (each gives at most one output here): those near
        // the pyramid, 6–14 % of those whose boxes overlap
        EXPECT_GE(bvh.candidates_evaluated(), outputs);
        EXPECT_LT(bvh.candidates_evaluated(), overlapping / 5) << bvh.candidates_evaluated() << " of " << overlapping;
    }
}

// NewProximity Triangle–Triangle's per-vertex test against the other triangle's plane
// (TriangleModel::update_planes, run by the BVH detection only): two soups of small triangles
// (each owning its vertices and edges, so every vertex–triangle and edge–edge test runs) at
// heights around R from each other. The BVH detection's outputs are the exhaustive detection's
// bit for bit, and the test has work to do: a share of the vertex–triangle tests of
// box-overlapping pairs lie beyond R from the plane (they are skipped), and outputs exist.
TEST(Separation, TriangleTriangleVertexTestsAgainstThePlanesKeepTheOutputs) {
    std::mt19937 rng(20261124);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const double R = 0.2;
    IntersectionParams np = IntersectionParams::new_proximity();
    np.alarm_distance = R;
    np.contact_distance = 0.05;
    auto soup = [&](double z0, int count) {
        std::vector<Vec3> pts;
        std::vector<Triangle> tris;
        for (int t = 0; t < count; ++t) {
            // (draws in g++'s order of evaluation: z, y, x; penalty_test/random_draws.hpp)
            const double cz = unit(rng), cy = unit(rng), cx = unit(rng);
            const Vec3 centre(cx, cy, z0 + 0.15 * cz);
            for (int k = 0; k < 3; ++k) {
                const Vec3 d = draw_vec3(unit, rng);
                pts.push_back(centre + 0.25 * Vec3(d.x(), d.y(), 0.4 * d.z()));
            }
            tris.push_back({3 * t, 3 * t + 1, 3 * t + 2});
        }
        return triangle_mesh(pts, std::move(tris));
    };
    std::size_t outputs = 0, tests = 0, beyond = 0;
    for (int round = 0; round < 4; ++round) {
        auto lower = soup(0.0, 250);
        auto upper = soup(0.25 + 0.05 * round, 250);
        TriangleModel a(lower->state, lower->topo, named("lower"));
        TriangleModel b(upper->state, upper->topo, named("upper"));
        EXPECT_FALSE(a.planes_current());
        outputs += outputs_checked(np, {&a, &b});
        // the BVH detection left the planes current; count the vertex tests they decide
        ASSERT_TRUE(a.planes_current() && b.planes_current());
        const double M = std::max(a.coordinate_bound(), b.coordinate_bound());
        const double limit = detail::separation_limit(R, 12.0 * M * M);
        for (std::size_t i = 0; i < a.size(); ++i)
            for (std::size_t j = 0; j < b.size(); ++j) {
                if (!a.element_box(Index(i)).overlaps(b.element_box(Index(j)), R)) continue;
                for (int k = 0; k < 3; ++k) {
                    const double sa = a.plane_normal(Index(i)).dot(b.p(Index(j), k) - a.p(Index(i), 0));
                    const double sb = b.plane_normal(Index(j)).dot(a.p(Index(i), k) - b.p(Index(j), 0));
                    tests += 2;
                    beyond += (sa * sa > limit) + (sb * sb > limit);
                }
            }
        // a new update() makes them stale until the next detection
        a.update();
        EXPECT_FALSE(a.planes_current());
    }
    EXPECT_GT(outputs, 200u);
    EXPECT_GT(tests, 20000u);
    const double share = double(beyond) / double(tests);
    EXPECT_GT(share, 0.2);
    EXPECT_LT(share, 0.9);
}

TEST(Separation, TrianglePlanesAreUnitNormalsOrZeroWhenUnreliable) {
    // a right triangle, a sliver (angle at A about 1e-4 rad: below reliable_plane's 1e-3) and a
    // zero-area one
    auto mesh =
        triangle_mesh({{0, 0, 0}, {2, 0, 0}, {0, 3, 0}, {1, 1e-4, 0}, {1, 1, 1}}, {{0, 1, 2}, {0, 1, 3}, {0, 4, 4}});
    TriangleModel t(mesh->state, mesh->topo);
    t.update();
    t.update_planes();
    EXPECT_TRUE(t.planes_current());
    EXPECT_EQ(t.plane_normal(0), Vec3(0, 0, 1));
    EXPECT_EQ(t.plane_normal(1), Vec3::Zero());
    EXPECT_EQ(t.plane_normal(2), Vec3::Zero());
    EXPECT_EQ(t.coordinate_bound(), 3.0);
}

}  // namespace
#pragma GCC diagnostic pop

}  // namespace penalty::test
