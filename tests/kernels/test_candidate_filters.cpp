// NewProximity Triangle–Point and Triangle–Sphere's candidate filter
// (penalty/collision/candidate_filters.hpp): it keeps exactly the candidates to which the
// kernel, at an alarm distance that every pair is within, gives an output, on both paths, and
// the AVX path keeps the scalar path's candidates.
#include "fixtures.hpp"
#include "kernels/collision/candidate_filters.hpp"
#include "penalty/core/pair_key.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace penalty::test {
namespace {

// A jittered n × n grid surface (2 (n − 1)² triangles sharing edges and vertices, so that each
// vertex and edge is owned by one of its triangles), then three degenerate triangles: a
// repeated vertex, three collinear vertices, and two vertices at one position.
std::unique_ptr<Mesh> feature_filter_surface(std::mt19937& g, int n) {
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    std::vector<Vec3> pts;
    std::vector<Triangle> tris;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) pts.emplace_back(i + jitter(g), j + jitter(g), jitter(g));
    for (int i = 0; i + 1 < n; ++i)
        for (int j = 0; j + 1 < n; ++j) {
            const int a = i * n + j, b = a + n, c = a + 1, d = a + n + 1;
            tris.push_back({a, b, d});
            tris.push_back({a, d, c});
        }
    const int m = int(pts.size());
    pts.emplace_back(0.5, 0.5, 2.0);
    pts.emplace_back(1.5, 1.5, 2.0);
    pts.emplace_back(2.5, 2.5, 2.0);  // on the line of the previous two
    pts.emplace_back(1.0, 3.0, 2.0);
    pts.emplace_back(1.0, 3.0, 2.0);  // the previous point again
    tris.push_back({0, 0, 1});
    tris.push_back({m, m + 1, m + 2});
    tris.push_back({m + 3, m + 4, 1});
    return triangle_mesh(pts, tris);
}

// Points around the surface: random ones, and for each triangle points over its vertices,
// edges and the thresholds of both kernels' regions (α, β near 0, 10⁻⁷, 10⁻⁶, 1 − 10⁻⁶, 1 and
// beyond), lifted off the plane so that no point is at distance 0 from its closest feature.
std::vector<Vec3> feature_filter_points(std::mt19937& g, const Mesh& mesh, int n) {
    std::uniform_real_distribution<double> u(-0.5, n - 0.5);
    std::uniform_real_distribution<double> height(0.05, 1.0);
    std::vector<Vec3> q;
    for (int k = 0; k < 300; ++k) q.emplace_back(u(g), u(g), (k % 2 ? 1.0 : -1.0) * height(g));
    const double marks[] = {-0.2, -1e-6, -1e-7, 0.0, 1e-7, 1e-6, 2e-6, 0.3, 0.5, 0.999998, 0.999999, 1.0, 1.2};
    std::uniform_int_distribution<std::size_t> pick(0, std::size(marks) - 1);
    for (std::size_t t = 0; t < mesh.topo.triangles().size(); t += 7) {
        const Triangle& tri = mesh.topo.triangles()[t];
        const Vec3& p1 = mesh.state.position[std::size_t(tri[0])];
        const Vec3 ab = mesh.state.position[std::size_t(tri[1])] - p1;
        const Vec3 ac = mesh.state.position[std::size_t(tri[2])] - p1;
        Vec3 normal = ab.cross(ac);
        normal = normal.norm() > 1e-12 ? Vec3(normal.normalized()) : Vec3::UnitZ();
        for (int k = 0; k < 12; ++k) {
            const double alpha = marks[pick(g)];
            const double beta = k < 4 ? 0.0 : marks[pick(g)];
            q.push_back(p1 + ab * alpha + ac * beta + normal * height(g));
        }
    }
    return q;
}

// The candidates PairKey(e1, e2).bits() to which the kernel gives an output (all pairs, in order).
std::vector<std::uint64_t> feature_filter_kernel_keeps(const IntersectionParams& params, CollisionModel& t,
                                                       CollisionModel& m2, std::size_t& total) {
    std::vector<std::uint64_t> keys;
    DetectionOutputList out;
    total = 0;
    for (std::size_t e1 = 0; e1 < t.size(); ++e1)
        for (std::size_t e2 = 0; e2 < m2.size(); ++e2) {
            ++total;
            out.clear();
            if (intersect_elements(params, t, Index(e1), m2, Index(e2), out) > 0)
                keys.push_back(pair_key::make(e1, e2));
        }
    return keys;
}

std::vector<std::uint64_t> feature_filter_all_keys(std::size_t n1, std::size_t n2) {
    std::vector<std::uint64_t> keys;
    for (std::size_t e1 = 0; e1 < n1; ++e1)
        for (std::size_t e2 = 0; e2 < n2; ++e2) keys.push_back(pair_key::make(e1, e2));
    return keys;
}

// The filter of the pair (m1, m2) under params: keep_triangle_candidates or
// keep_line_line_candidates.
void feature_filter_run(const IntersectionParams& params, CollisionModel& m1, CollisionModel& m2,
                        std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept, KernelPath path) {
    if (m1.type() == ModelType::Line) {
        detail::keep_line_line_candidates(params, static_cast<LineModel&>(m1), static_cast<LineModel&>(m2), keys, kept,
                                          path);
    } else {
        detail::keep_triangle_candidates(params, static_cast<TriangleModel&>(m1), m2, keys, kept, path);
    }
}

void expect_filter_keeps_the_kernels_candidates(const IntersectionParams& params, CollisionModel& t,
                                                CollisionModel& m2) {
    std::size_t total = 0;
    const std::vector<std::uint64_t> expected = feature_filter_kernel_keeps(params, t, m2, total);
    const std::vector<std::uint64_t> keys = feature_filter_all_keys(t.size(), m2.size());
    std::vector<KernelPath> paths = {KernelPath::scalar};
    if (kernel_path_supported(KernelPath::avx)) paths.push_back(KernelPath::avx);
    for (const KernelPath path : paths) {
        SCOPED_TRACE(to_string(path));
        std::vector<std::uint64_t> kept = {7};  // appended to, not replaced
        feature_filter_run(params, t, m2, keys, kept, path);
        ASSERT_EQ(kept.front(), 7u);
        kept.erase(kept.begin());
        EXPECT_EQ(kept, expected);
        // odd counts: the AVX path's last candidates go through the scalar path
        std::vector<std::uint64_t> tail;
        feature_filter_run(params, t, m2, std::span(keys).first(keys.size() - 3), tail, path);
        std::vector<std::uint64_t> expected_tail;
        for (const std::uint64_t k : expected)
            if (k < keys[keys.size() - 3]) expected_tail.push_back(k);
        EXPECT_EQ(tail, expected_tail);
    }
    // hit rate: the filter both keeps and drops a real share of the candidates (MinProximity's
    // triangles keep only the points that project into their interior: about one triangle a
    // point here)
    EXPECT_GT(expected.size(), params.method == IntersectionMethod::MinProximity ? total / 200 : total / 20);
    EXPECT_LT(expected.size(), total - total / 5);
}

IntersectionParams feature_filter_params(IntersectionMethod method = IntersectionMethod::NewProximity) {
    IntersectionParams p = method == IntersectionMethod::NewProximity ? IntersectionParams::new_proximity()
                                                                      : IntersectionParams::min_proximity();
    p.alarm_distance = 1e6;  // every pair within range: an output iff the feature tests pass
    p.contact_distance = 0.1;
    return p;
}

TEST(CandidateFilters, KeepsExactlyTheTriangleToPointCandidatesTheKernelGivesAnOutput) {
    std::mt19937 g(20261127);
    const int n = 7;
    auto mesh = feature_filter_surface(g, n);
    Vec3State cloud = make_state(feature_filter_points(g, *mesh, n));
    TriangleModel t(mesh->state, mesh->topo, named("surface"));
    PointModel points(cloud, nullptr, named("points"));
    t.update();
    points.update();
    expect_filter_keeps_the_kernels_candidates(feature_filter_params(), t, points);
    SCOPED_TRACE("MinProximity: the strict interior only");
    expect_filter_keeps_the_kernels_candidates(feature_filter_params(IntersectionMethod::MinProximity), t, points);
}

TEST(CandidateFilters, KeepsExactlyTheTriangleToSphereCandidatesUnderEachQuirkSetting) {
    std::mt19937 g(1127);
    const int n = 6;
    auto mesh = feature_filter_surface(g, n);
    const std::vector<Vec3> centres = feature_filter_points(g, *mesh, n);
    Vec3State cloud = make_state(centres);
    std::vector<RigidFrame> frames;
    for (const Vec3& c : centres) frames.push_back(RigidFrame{c, rand_quat(g)});
    Rigid3State rigid = make_rigid_state(frames);
    TriangleModel t(mesh->state, mesh->topo, named("surface"));
    SphereModel balls(cloud, 0.05, {}, named("balls"));
    RigidSphereModel rigid_balls(rigid, 0.05, {}, named("rigid-balls"));
    t.update();
    balls.update();
    rigid_balls.update();
    for (const bool fix_range : {false, true})
        for (const bool fix_flags : {false, true}) {
            SCOPED_TRACE(::testing::Message()
                         << "edge range fixed " << fix_range << ", edge flags fixed " << fix_flags);
            IntersectionParams params = feature_filter_params();
            params.quirks.fix_newproximity_triangle_sphere_edge_range = fix_range;
            params.quirks.fix_newproximity_triangle_sphere_edge_flags = fix_flags;
            expect_filter_keeps_the_kernels_candidates(params, t, balls);
            expect_filter_keeps_the_kernels_candidates(params, t, rigid_balls);
        }
    SCOPED_TRACE("MinProximity");
    expect_filter_keeps_the_kernels_candidates(feature_filter_params(IntersectionMethod::MinProximity), t, balls);
    expect_filter_keeps_the_kernels_candidates(feature_filter_params(IntersectionMethod::MinProximity), t, rigid_balls);
}

// Right triangles with unit legs along the axes at the origin, where α and β are q's own
// coordinates, exactly: points on both kernels' thresholds (ε, 10⁻⁶, 1 − 10⁻⁶, 1 − ε, …) and
// their neighbouring doubles test each comparison's strictness. T0 owns its vertices, T1
// (the same vertices again) none of them, T2 shares O, Y and the edge OY with T0.
TEST(CandidateFilters, ExactThresholdsOnRightTrianglesDecideAsTheKernel) {
    const double eps = std::numeric_limits<double>::epsilon();
    std::vector<double> marks = {-1e-6,     -1e-7, -eps,     0.0,       eps, 2 * eps,   1e-7, 1e-6,
                                 0.5 - eps, 0.5,   0.999999, 1.0 - eps, 1.0, 1.0 + eps, 2.0};
    for (const double m : {eps, 1e-7, 1e-6, 0.999999, 1.0 - eps}) {
        marks.push_back(std::nextafter(m, 0.0));
        marks.push_back(std::nextafter(m, 2.0));
    }
    auto mesh =
        triangle_mesh({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0)}, {{0, 1, 2}, {0, 1, 2}, {0, 2, 3}});
    std::vector<Vec3> centres;
    for (const double a : marks)
        for (const double b : marks) {
            centres.emplace_back(a, b, 0.25);
            centres.emplace_back(-b, a, -0.25);  // T2's α = y, β = −x
        }
    Vec3State cloud = make_state(centres);
    TriangleModel t(mesh->state, mesh->topo, named("right-triangles"));
    PointModel points(cloud, nullptr, named("points"));
    SphereModel balls(cloud, 0.05, {}, named("balls"));
    t.update();
    ASSERT_EQ(t.flags(0) & TriangleModel::kPoints, TriangleModel::kPoints);
    ASSERT_EQ(t.flags(1) & TriangleModel::kPoints, 0u);
    expect_filter_keeps_the_kernels_candidates(feature_filter_params(), t, points);
    for (const bool fix_range : {false, true}) {
        IntersectionParams params = feature_filter_params();
        params.quirks.fix_newproximity_triangle_sphere_edge_range = fix_range;
        expect_filter_keeps_the_kernels_candidates(params, t, balls);
    }
    const IntersectionParams min = feature_filter_params(IntersectionMethod::MinProximity);
    expect_filter_keeps_the_kernels_candidates(min, t, points);
    expect_filter_keeps_the_kernels_candidates(min, t, balls);
}

// Line–Line: a unit segment along x against segments along y at height h, whose closest points
// are α = a and β = b exactly (q1 = (a, −2b, h), q2 = (a, 2 − 2b, h): every product and quotient
// of the 2 × 2 system is exact), for a, b on both methods' thresholds (10⁻⁶, 0.999999, 10⁻¹⁵,
// 1 − 10⁻¹⁵) and the doubles beside them; parallel segments (always kept, α = β = ½), one at
// NewProximity's parallel bound exactly; and random segments against random segments.
TEST(CandidateFilters, LineLineKeepsExactlyTheKernelsCandidatesAtItsThresholds) {
    std::vector<double> marks = {-0.5, -1e-6, 0.0, 0.25, 0.5, 1.0, 1.5};
    for (const double m : {1e-15, 1e-6, 0.999999, 1.0 - 1e-15}) {
        marks.push_back(m);
        marks.push_back(std::nextafter(m, 0.0));
        marks.push_back(std::nextafter(m, 2.0));
    }
    std::vector<Vec3> ends = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 0)};  // and reversed
    std::vector<Vec3> others;
    for (const double a : marks)
        for (const double b : marks) {
            others.emplace_back(a, -2.0 * b, 0.25);
            others.emplace_back(a, 2.0 - 2.0 * b, 0.25);
        }
    others.emplace_back(-1.0, 0.5, 0.5);  // parallel to x
    others.emplace_back(3.0, 0.5, 0.5);
    others.emplace_back(0.2, 0.0, 1.0);  // zero length
    others.emplace_back(0.2, 0.0, 1.0);
    others.emplace_back(0.5, 0.0, 0.25);  // det = 1 · (10⁻⁶)² = 10⁻¹², NewProximity's `parallel`, exactly
    others.emplace_back(0.5, 1e-6, 0.25);
    std::mt19937 g(17);
    for (int k = 0; k < 80; ++k) {
        const Vec3 c = rand_vec(g, 1.0);
        ends.push_back(c);
        ends.push_back(c + rand_vec(g, 0.6));
        others.push_back(c + rand_vec(g, 0.3));
        others.push_back(others.back() + rand_vec(g, 0.6));
    }
    const auto segments = [](std::size_t n) {
        MeshTopology topo;
        topo.set_num_points(n);
        std::vector<Edge> edges;
        for (std::size_t i = 0; i + 1 < n; i += 2) edges.push_back({int(i), int(i + 1)});
        topo.set_edges(std::move(edges));
        return topo;
    };
    Vec3State state1 = make_state(ends), state2 = make_state(others);
    const MeshTopology topo1 = segments(ends.size()), topo2 = segments(others.size());
    LineModel l1(state1, topo1, named("along-x"));
    LineModel l2(state2, topo2, named("others"));
    l1.update();
    l2.update();
    for (const auto method : {IntersectionMethod::NewProximity, IntersectionMethod::MinProximity}) {
        SCOPED_TRACE(intersection_method_name(method));
        expect_filter_keeps_the_kernels_candidates(feature_filter_params(method), l1, l2);
    }
}

// NewProximity's triangle filter drops unowned features (and degenerate triangles): the
// kernels skip it for a soup of separate triangles, each owning every vertex and edge.
TEST(CandidateFilters, ASoupOfSeparateTrianglesOwnsEveryFeatureAndASurfaceDoesNot) {
    std::mt19937 g(5);
    auto surface = feature_filter_surface(g, 4);
    TriangleModel shared(surface->state, surface->topo, named("surface"));
    EXPECT_FALSE(shared.owns_every_feature());
    std::vector<Vec3> pts;
    std::vector<Triangle> tris;
    for (int k = 0; k < 5; ++k) {
        for (int c = 0; c < 3; ++c) pts.push_back(rand_vec(g, 1.0));
        tris.push_back({3 * k, 3 * k + 1, 3 * k + 2});
    }
    auto soup = triangle_mesh(pts, tris);
    TriangleModel separate(soup->state, soup->topo, named("soup"));
    EXPECT_TRUE(separate.owns_every_feature());
    // and then the filter keeps every candidate of a non-degenerate soup
    Vec3State cloud = make_state({Vec3(0, 0, 2), Vec3(3, 0, 0), Vec3(-1, 2, 0.5)});
    PointModel points(cloud, nullptr, named("points"));
    std::vector<std::uint64_t> kept;
    detail::keep_triangle_candidates(feature_filter_params(), separate, points, feature_filter_all_keys(5, 3), kept,
                                     KernelPath::scalar);
    EXPECT_EQ(kept.size(), 15u);
}

TEST(CandidateFilters, DegenerateTrianglesKeepNothingAndOtherModelKindsAndMethodsAreRefused) {
    std::mt19937 g(3);
    auto mesh = feature_filter_surface(g, 3);
    Vec3State cloud = make_state(feature_filter_points(g, *mesh, 3));
    TriangleModel t(mesh->state, mesh->topo, named("surface"));
    PointModel points(cloud, nullptr, named("points"));
    t.update();
    const std::size_t first_degenerate = t.size() - 3;
    std::vector<std::uint64_t> keys;
    for (std::size_t e1 = first_degenerate; e1 < t.size(); ++e1)
        for (std::size_t e2 = 0; e2 < points.size(); ++e2) keys.push_back(pair_key::make(e1, e2));
    for (const KernelPath path : {KernelPath::scalar, KernelPath::avx}) {
        if (!kernel_path_supported(path)) continue;
        std::vector<std::uint64_t> kept;
        detail::keep_triangle_candidates(feature_filter_params(), t, points, keys, kept, path);
        EXPECT_TRUE(kept.empty()) << to_string(path) << ": " << kept.size() << " of " << keys.size();
    }
    LineModel lines(mesh->state, mesh->topo, named("edges"));
    std::vector<std::uint64_t> kept;
    try {
        detail::keep_triangle_candidates(feature_filter_params(), t, lines, keys, kept, KernelPath::scalar);
        ADD_FAILURE() << "a Line model was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("'edges' is a Line model"), std::string::npos) << e.what();
    }
    try {
        detail::keep_triangle_candidates(IntersectionParams::local_min_distance(), t, points, keys, kept,
                                         KernelPath::scalar);
        ADD_FAILURE() << "LocalMinDistance was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("no filter for LocalMinDistance"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace penalty::test
