// Characterization table: one row per (method, pair) with its outcome, checked twice:
//  1. pair_support() agrees with the table for every unordered pair of model types;
//  2. every supported row is run on seeded random single-element configurations against an
//     independent brute-force reference (dense sampling of both elements, analytic inside
//     tests for solids), with asserted hit rates, and is checked for invariance under rigid
//     motion.
// The table is the support matrix of docs/collision.md.
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace penalty {
namespace {

using M = IntersectionMethod;
using T = ModelType;

/// What a row promises when it reports a contact.
enum class Accuracy {
    Exact,       ///< reported gap = true distance between the elements (within sampling tol)
    LowerBound,  ///< reported gap ≥ true distance (sub-feature tests, SOFA's mirror quirk)
    Crossing,    ///< Discrete Triangle–Line: value 0 at a true crossing
    Unbounded,   ///< SOFA's NewProximity Triangle–Sphere: the point may leave the triangle along
                 ///< an edge extension (see SofaQuirkFixes::fix_newproximity_triangle_sphere_edge_range)
    None,        ///< unsupported / ignored
};

struct Row {
    M method;
    T a, b;  ///< registered order
    PairSupport support;
    Accuracy acc;
    bool complete;  ///< every pair closer than the alarm distance is reported
};

constexpr auto S = PairSupport::Supported;
constexpr auto I = PairSupport::Ignored;
constexpr auto B = PairSupport::BeyondSofa;

// rows not listed are Unsupported
const std::vector<Row> kTable = {
    // DiscreteIntersection
    {M::Discrete, T::Sphere, T::Sphere, S, Accuracy::Exact, true},
    {M::Discrete, T::RigidSphere, T::RigidSphere, S, Accuracy::Exact, true},
    {M::Discrete, T::Sphere, T::RigidSphere, S, Accuracy::Exact, true},
    {M::Discrete, T::Triangle, T::Line, S, Accuracy::Crossing, false},
    {M::Discrete, T::Tetrahedron, T::Point, B, Accuracy::Exact, true},
    // NewProximityIntersection
    {M::NewProximity, T::Sphere, T::Sphere, S, Accuracy::Exact, true},
    {M::NewProximity, T::RigidSphere, T::RigidSphere, S, Accuracy::Exact, true},
    {M::NewProximity, T::Sphere, T::RigidSphere, S, Accuracy::Exact, true},
    {M::NewProximity, T::Sphere, T::Point, S, Accuracy::Exact, true},
    {M::NewProximity, T::RigidSphere, T::Point, S, Accuracy::Exact, true},
    {M::NewProximity, T::Point, T::Point, S, Accuracy::Exact, true},
    {M::NewProximity, T::Line, T::Point, S, Accuracy::Exact, true},
    {M::NewProximity, T::Line, T::Line, S, Accuracy::Exact, false},
    {M::NewProximity, T::Line, T::Sphere, S, Accuracy::Exact, true},
    {M::NewProximity, T::Line, T::RigidSphere, S, Accuracy::Exact, true},
    {M::NewProximity, T::Triangle, T::Point, S, Accuracy::Exact, true},
    {M::NewProximity, T::Triangle, T::Sphere, S, Accuracy::Unbounded, false},
    {M::NewProximity, T::Triangle, T::RigidSphere, S, Accuracy::Unbounded, false},
    {M::NewProximity, T::Triangle, T::Line, S, Accuracy::LowerBound, false},
    {M::NewProximity, T::Triangle, T::Triangle, S, Accuracy::LowerBound, false},
    {M::NewProximity, T::Cylinder, T::Cylinder, B, Accuracy::Exact, true},
    {M::NewProximity, T::Cylinder, T::Triangle, B, Accuracy::Exact, true},
    {M::NewProximity, T::Cylinder, T::Sphere, B, Accuracy::Exact, true},
    {M::NewProximity, T::Cylinder, T::RigidSphere, B, Accuracy::Exact, true},
    {M::NewProximity, T::Tetrahedron, T::Point, B, Accuracy::Exact, true},
    // MinProximityIntersection
    {M::MinProximity, T::Sphere, T::Sphere, S, Accuracy::Exact, true},
    {M::MinProximity, T::RigidSphere, T::RigidSphere, S, Accuracy::Exact, true},
    {M::MinProximity, T::Sphere, T::RigidSphere, S, Accuracy::Exact, true},
    {M::MinProximity, T::Sphere, T::Point, S, Accuracy::Exact, true},
    {M::MinProximity, T::RigidSphere, T::Point, S, Accuracy::Exact, true},
    {M::MinProximity, T::Point, T::Point, S, Accuracy::Exact, true},
    {M::MinProximity, T::Line, T::Point, S, Accuracy::Exact, true},
    {M::MinProximity, T::Line, T::Line, S, Accuracy::Exact, false},
    {M::MinProximity, T::Line, T::Sphere, S, Accuracy::LowerBound, false},
    {M::MinProximity, T::Line, T::RigidSphere, S, Accuracy::LowerBound, false},
    {M::MinProximity, T::Triangle, T::Point, S, Accuracy::Exact, false},
    {M::MinProximity, T::Triangle, T::Sphere, S, Accuracy::Exact, false},
    {M::MinProximity, T::Triangle, T::RigidSphere, S, Accuracy::Exact, false},
    {M::MinProximity, T::Triangle, T::Line, I, Accuracy::None, false},
    {M::MinProximity, T::Triangle, T::Triangle, I, Accuracy::None, false},
    {M::MinProximity, T::Cylinder, T::Cylinder, B, Accuracy::Exact, true},
    {M::MinProximity, T::Cylinder, T::Triangle, B, Accuracy::Exact, true},
    {M::MinProximity, T::Cylinder, T::Sphere, B, Accuracy::Exact, true},
    {M::MinProximity, T::Cylinder, T::RigidSphere, B, Accuracy::Exact, true},
    {M::MinProximity, T::Tetrahedron, T::Point, B, Accuracy::Exact, true},
    // LocalMinDistance
    {M::LocalMinDistance, T::Sphere, T::Sphere, S, Accuracy::Exact, true},
    {M::LocalMinDistance, T::RigidSphere, T::RigidSphere, S, Accuracy::Exact, true},
    {M::LocalMinDistance, T::Sphere, T::RigidSphere, S, Accuracy::Exact, true},
    {M::LocalMinDistance, T::Sphere, T::Point, S, Accuracy::Exact, true},
    {M::LocalMinDistance, T::Point, T::Point, S, Accuracy::Exact, true},
    {M::LocalMinDistance, T::Line, T::Point, S, Accuracy::Exact, false},
    {M::LocalMinDistance, T::Line, T::Line, S, Accuracy::Exact, false},
    {M::LocalMinDistance, T::Line, T::Sphere, S, Accuracy::Exact, false},
    {M::LocalMinDistance, T::Triangle, T::Point, S, Accuracy::Exact, false},
    {M::LocalMinDistance, T::Triangle, T::Sphere, S, Accuracy::Exact, false},
    {M::LocalMinDistance, T::Triangle, T::Line, I, Accuracy::None, false},
    {M::LocalMinDistance, T::Triangle, T::Triangle, I, Accuracy::None, false},
    {M::LocalMinDistance, T::Tetrahedron, T::Point, B, Accuracy::Exact, true},
};

IntersectionParams params_for(M m) {
    IntersectionParams p;
    switch (m) {
        case M::Discrete:
            p = IntersectionParams::discrete();
            break;
        case M::NewProximity:
            p = IntersectionParams::new_proximity();
            break;
        case M::MinProximity:
            p = IntersectionParams::min_proximity();
            break;
        case M::LocalMinDistance:
            p = IntersectionParams::local_min_distance();
            break;
    }
    p.enable_beyond_sofa_pairs = true;
    return p;
}

const Row* find_row(M m, T a, T b) {
    for (const Row& r : kTable)
        if (r.method == m && ((r.a == a && r.b == b) || (r.a == b && r.b == a))) return &r;
    return nullptr;
}

std::string row_name(M m, T a, T b) {
    return std::string(intersection_method_name(m)) + " " + model_type_name(a) + "-" + model_type_name(b);
}

TEST(Characterization, SupportMatrixMatchesTable) {
    int supported = 0;
    for (int mi = 0; mi < kIntersectionMethodCount; ++mi) {
        const M m = M(mi);
        const IntersectionParams p = params_for(m);
        for (int i = 0; i < kModelTypeCount; ++i)
            for (int j = i; j < kModelTypeCount; ++j) {
                const T a = T(i), b = T(j);
                const Row* r = find_row(m, a, b);
                const PairSupport expected = r ? r->support : PairSupport::Unsupported;
                EXPECT_EQ(pair_support(p, a, b), expected) << row_name(m, a, b);
                if (r) {
                    EXPECT_TRUE(is_registered_order(r->a, r->b)) << row_name(m, a, b);
                    supported += r->support != I;
                }
            }
    }
    EXPECT_EQ(supported, 54);
    // MinProximity use* switches turn pairs into "ignored"
    auto p = IntersectionParams::min_proximity();
    p.use_sphere_triangle = false;
    EXPECT_EQ(pair_support(p, T::Triangle, T::Sphere), I);
    EXPECT_EQ(pair_support(p, T::Line, T::RigidSphere), I);
    EXPECT_EQ(pair_support(p, T::Point, T::Sphere), I);
    EXPECT_EQ(pair_support(p, T::Triangle, T::Point), S);
    p.use_line_line = false;
    EXPECT_EQ(pair_support(p, T::Line, T::Line), I);
    // NewProximity's useLineLine only adds sub-tests, the pair stays supported
    EXPECT_EQ(pair_support(IntersectionParams::new_proximity(), T::Line, T::Line), S);
}

TEST(Characterization, UnsupportedAndDisabledPairsAreExplicit) {
    Vec3State s = test::make_state({{0, 0, 0}});
    PointModel pt(s);
    SphereModel sph(s, 1.0);
    // Discrete Sphere–Point: unsupported, reported as such, no outputs
    auto det = detect_model_pair(IntersectionParams::discrete(), pt, sph);
    EXPECT_EQ(det.support, PairSupport::Unsupported);
    EXPECT_TRUE(det.outputs.empty());
    DetectionOutputList out;
    EXPECT_THROW(intersect_elements(IntersectionParams::discrete(), sph, 0, pt, 0, out), std::invalid_argument);
    // wrong order
    EXPECT_THROW(intersect_elements(IntersectionParams::new_proximity(), pt, 0, sph, 0, out), std::invalid_argument);
    // beyond-SOFA pairs are opt-in
    Rigid3State rs = test::make_rigid_state({RigidFrame{}});
    CylinderModel cyl(rs);
    auto p = IntersectionParams::new_proximity();
    det = detect_model_pair(p, sph, cyl);
    EXPECT_EQ(det.support, PairSupport::BeyondSofa);
    EXPECT_TRUE(det.outputs.empty());
    p.enable_beyond_sofa_pairs = true;
    det = detect_model_pair(p, sph, cyl);
    EXPECT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.model1, &cyl);
}

// ---------------------------------------------------------------------------------------------
// Random single-element models and their brute-force sampling.

// Sampling resolution divisor: Debug/sanitizer builds sample twice as coarsely (the tolerance
// follows the resolution, the number of configurations and the hit-rate gates do not change).
#ifdef NDEBUG
constexpr int kCoarse = 1;
#else
constexpr int kCoarse = 2;
#endif

struct Elem {
    T type;
    Vec3State vs;
    Rigid3State rs;
    MeshTopology topo;
    std::unique_ptr<CollisionModel> model;
    std::vector<Vec3> samples;                ///< boundary (and point) samples
    double inflate = 0.0;                     ///< sphere radius (the element is samples ⊕ ball(inflate))
    double spacing = 0.0;                     ///< max distance from any element point to the nearest sample
    std::function<bool(const Vec3&)> inside;  ///< analytic inside test for solids
};

std::unique_ptr<Elem> make_elem(T t, const Vec3& c, std::mt19937& g) {
    auto e = std::make_unique<Elem>();
    e->type = t;
    std::uniform_real_distribution<double> u(0, 1);
    switch (t) {
        case T::Point:
            e->vs = test::make_state({c});
            e->model = std::make_unique<PointModel>(e->vs);
            e->samples = {c};
            break;
        case T::Line: {
            const Vec3 a = c + test::rand_vec(g, 0.5), b = c + test::rand_vec(g, 0.5);
            e->vs = test::make_state({a, b});
            e->topo.set_num_points(2);
            e->topo.set_edges({{0, 1}});
            e->model = std::make_unique<LineModel>(e->vs, e->topo);
            const int n = 400 / kCoarse;
            for (int i = 0; i <= n; ++i) e->samples.push_back(a + (double(i) / n) * (b - a));
            e->spacing = (b - a).norm() / n;
            break;
        }
        case T::Triangle: {
            Vec3 p[3];
            do {
                for (auto& x : p) x = c + test::rand_vec(g, 0.6);
            } while ((p[1] - p[0]).cross(p[2] - p[0]).norm() < 0.05);
            e->vs = test::make_state({p[0], p[1], p[2]});
            e->topo.set_num_points(3);
            e->topo.set_triangles({{0, 1, 2}});
            e->model = std::make_unique<TriangleModel>(e->vs, e->topo);
            const int n = 40 / kCoarse;
            for (int i = 0; i <= n; ++i)
                for (int j = 0; i + j <= n; ++j)
                    e->samples.push_back(p[0] + (double(i) / n) * (p[1] - p[0]) + (double(j) / n) * (p[2] - p[0]));
            e->spacing = std::max({(p[1] - p[0]).norm(), (p[2] - p[0]).norm(), (p[2] - p[1]).norm()}) / n;
            break;
        }
        case T::Sphere:
        case T::RigidSphere: {
            const double r = 0.05 + 0.35 * u(g);
            if (t == T::Sphere) {
                e->vs = test::make_state({c});
                e->model = std::make_unique<SphereModel>(e->vs, r);
            } else {
                e->rs = test::make_rigid_state({RigidFrame{c, test::rand_quat(g)}});
                e->model = std::make_unique<RigidSphereModel>(e->rs, r);
            }
            e->samples = {c};
            e->inflate = r;
            break;
        }
        case T::Cylinder: {
            e->rs = test::make_rigid_state({RigidFrame{c, test::rand_quat(g)}});
            const double length = 0.2 + 0.8 * u(g), radius = 0.1 + 0.3 * u(g);  // (g++'s order of the call's draws)
            auto cyl = std::make_unique<CylinderModel>(e->rs, radius, length);
            const CylinderShape s = cyl->shape(0);
            e->model = std::move(cyl);
            const Vec3 e1 = any_orthogonal(s.axis), e2 = s.axis.cross(e1);
            const int na = 64 / kCoarse, nh = 24 / kCoarse, nr = 8 / kCoarse;
            for (int i = 0; i < na; ++i) {
                const double th = 2 * std::numbers::pi * i / na;
                const Vec3 rad = std::cos(th) * e1 + std::sin(th) * e2;
                for (int j = 0; j <= nh; ++j)
                    e->samples.push_back(s.center + (-s.half_height + 2 * s.half_height * j / nh) * s.axis +
                                         s.radius * rad);
                for (int k = 0; k < nr; ++k) {
                    const double rr = s.radius * k / nr;
                    e->samples.push_back(s.center + s.half_height * s.axis + rr * rad);
                    e->samples.push_back(s.center - s.half_height * s.axis + rr * rad);
                }
            }
            e->spacing = std::hypot(2 * std::numbers::pi * s.radius / na, 2 * s.half_height / nh, s.radius / nr);
            e->inside = [s](const Vec3& x) {
                const Vec3 d = x - s.center;
                const double y = d.dot(s.axis);
                return std::abs(y) <= s.half_height && (d - y * s.axis).norm() <= s.radius;
            };
            break;
        }
        case T::Tetrahedron: {
            Vec3 p[4];
            do {
                for (auto& x : p) x = c + test::rand_vec(g, 0.6);
            } while (std::abs((p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0]))) < 0.05);
            e->vs = test::make_state({p[0], p[1], p[2], p[3]});
            e->topo.set_num_points(4);
            e->topo.set_tetrahedra({{0, 1, 2, 3}});
            e->model = std::make_unique<TetrahedronModel>(e->vs, e->topo);
            const int f[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
            const int n = 30 / kCoarse;
            double lmax = 0;
            for (const auto& fk : f) {
                const Vec3 &a = p[fk[0]], &b = p[fk[1]], &cc = p[fk[2]];
                lmax = std::max({lmax, (b - a).norm(), (cc - a).norm(), (cc - b).norm()});
                for (int i = 0; i <= n; ++i)
                    for (int j = 0; i + j <= n; ++j)
                        e->samples.push_back(a + (double(i) / n) * (b - a) + (double(j) / n) * (cc - a));
            }
            e->spacing = lmax / n;
            Mat3 m;
            m << p[1] - p[0], p[2] - p[0], p[3] - p[0];
            const Mat3 inv = m.inverse();
            const Vec3 p0 = p[0];
            e->inside = [inv, p0](const Vec3& x) {
                const Vec3 b = inv * (x - p0);
                return b.minCoeff() >= 0.0 && b.sum() <= 1.0;
            };
            break;
        }
    }
    return e;
}

/// Brute-force gap between two elements: min over sample pairs minus the sphere radii; 0 if a
/// sample of one is inside the other (solids). `overlap` tells whether the solids intersect.
double brute_gap(const Elem& a, const Elem& b, bool& overlap) {
    overlap = false;
    for (const Vec3& x : b.samples) overlap = overlap || (a.inside && a.inside(x));
    for (const Vec3& x : a.samples) overlap = overlap || (b.inside && b.inside(x));
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& x : a.samples)
        for (const Vec3& y : b.samples) best = std::min(best, (x - y).squaredNorm());
    const double gap = std::sqrt(best) - a.inflate - b.inflate;
    if (overlap) return std::min(gap, 0.0) < 0.0 && (a.inflate + b.inflate) > 0.0 ? std::min(gap, 0.0) : 0.0;
    return gap;
}

struct RunStats {
    int samples = 0, hits = 0, checked = 0;
};

double reported_gap(const ModelPairDetection& d, const IntersectionParams& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& o : d.outputs) best = std::min(best, o.value + p.contact_distance);
    return best;
}

RunStats run_row(const Row& r, int n, unsigned seed, const SofaQuirkFixes& quirks = {}) {
    std::mt19937 g(seed);
    IntersectionParams p = params_for(r.method);
    p.quirks = quirks;
    Accuracy acc = r.acc;
    if (acc == Accuracy::Unbounded && quirks.fix_newproximity_triangle_sphere_edge_range) acc = Accuracy::Exact;
    // cylinders are large: place the second element further so that misses occur
    // placement radius of the second element: both hits and misses must occur
    double offset = r.a == T::Cylinder ? 3.0 : 2.0;
    if (r.method == M::Discrete) offset = 0.6;                                // Discrete needs an actual overlap
    if (r.method == M::LocalMinDistance && r.a == T::Triangle) offset = 0.9;  // interior + one side
    std::uniform_real_distribution<double> radial(0.0, offset);
    RunStats st;
    for (int s = 0; s < n; ++s) {
        auto ea = make_elem(r.a, test::rand_vec(g, 0.2), g);
        const Vec3 direction = test::rand_unit(g);  // (before the distance: g++'s order of the product's draws)
        auto eb = make_elem(r.b, radial(g) * direction, g);
        bool overlap = false;
        const double brute = brute_gap(*ea, *eb, overlap);
        const double tol = ea->spacing + eb->spacing + 1e-9;
        const auto det = detect_model_pair(p, *ea->model, *eb->model);
        EXPECT_EQ(det.model1, ea->model.get());
        ++st.samples;
        for (const auto& o : det.outputs) {
            EXPECT_TRUE(o.normal.allFinite() && o.point[0].allFinite() && o.point[1].allFinite() &&
                        std::isfinite(o.value));
            EXPECT_NEAR(o.normal.norm(), 1.0, 1e-9);
        }
        if (det.outputs.empty()) {
            // completeness: pairs clearly inside the alarm distance must be reported
            if (r.complete) {
                const double alarm = r.method == M::Discrete ? 0.0 : p.alarm_distance;
                EXPECT_FALSE(brute < alarm - tol)
                    << row_name(r.method, r.a, r.b) << " sample " << s << " missed, brute gap " << brute;
            }
            continue;
        }
        ++st.hits;
        const double gap = reported_gap(det, p);
        switch (acc) {
            case Accuracy::Exact:
                if (overlap) {
                    EXPECT_LE(gap, brute + tol) << row_name(r.method, r.a, r.b) << " sample " << s;
                } else {
                    EXPECT_NEAR(gap, brute, tol) << row_name(r.method, r.a, r.b) << " sample " << s;
                }
                ++st.checked;
                break;
            case Accuracy::LowerBound:
                EXPECT_GE(gap, brute - tol) << row_name(r.method, r.a, r.b) << " sample " << s;
                ++st.checked;
                break;
            case Accuracy::Crossing:
                EXPECT_EQ(gap, 0.0);
                EXPECT_LE(brute, tol);
                ++st.checked;
                break;
            case Accuracy::Unbounded:
                ++st.checked;
                break;
            case Accuracy::None:
                ADD_FAILURE() << "output from an ignored pair";
                break;
        }
    }
    return st;
}

class CharacterizationRow : public ::testing::TestWithParam<std::size_t> {};

TEST_P(CharacterizationRow, AgainstBruteForceWithHitRate) {
    const Row& r = kTable[GetParam()];
    SCOPED_TRACE(row_name(r.method, r.a, r.b));
    if (r.acc == Accuracy::None) {
        const RunStats st = run_row(r, 30, 1000 + unsigned(GetParam()));
        EXPECT_EQ(st.hits, 0);
        return;
    }
    const bool heavy = r.a == T::Cylinder || r.a == T::Tetrahedron || r.b == T::Triangle || r.b == T::Line;
    const int n = r.method == M::Discrete ? 400 : (heavy ? 100 : 300);
    const RunStats st = run_row(r, n, 1000 + unsigned(GetParam()));
    // hit rate: the row must actually produce contacts (Discrete needs overlap: rarer)
    const double rate = double(st.hits) / st.samples;
    const double min_rate = r.method == M::Discrete ? 0.03 : 0.08;
    EXPECT_GE(rate, min_rate) << st.hits << "/" << st.samples;
    EXPECT_GE(st.hits, 10);
    EXPECT_LT(rate, 1.0) << "every sample hit: the misses are not exercised";
    EXPECT_EQ(st.checked, st.hits);
}

std::string row_param_name(const ::testing::TestParamInfo<std::size_t>& info) {
    const Row& r = kTable[info.param];
    std::string m = intersection_method_name(r.method);
    return m + "_" + model_type_name(r.a) + "_" + model_type_name(r.b);
}

INSTANTIATE_TEST_SUITE_P(AllRows, CharacterizationRow, ::testing::Range<std::size_t>(0, kTable.size()), row_param_name);

TEST(Characterization, NewProximityTriangleSphereExactWithEdgeRangeFix) {
    SofaQuirkFixes q;
    q.fix_newproximity_triangle_sphere_edge_range = true;
    for (T b : {T::Sphere, T::RigidSphere}) {
        const Row* r = find_row(M::NewProximity, T::Triangle, b);
        const RunStats st = run_row(*r, 300, 77, q);
        EXPECT_GE(st.hits, 30);
        EXPECT_EQ(st.checked, st.hits);
    }
}

// ---------------------------------------------------------------------------------------------
// Invariance under rigid motion: moving both elements by the same rigid motion changes no
// value and rotates the normals.

void move_elem(Elem& e, const Mat3& R, const Vec3& t) {
    for (Vec3& x : e.vs.position) x = R * x + t;
    for (RigidFrame& f : e.rs.position) {
        f.center = R * f.center + t;
        f.orientation = Quat(R) * f.orientation;
    }
}

TEST(Characterization, InvariantUnderRigidMotion) {
    std::mt19937 g(4711);
    int compared = 0;
    for (const Row& r : kTable) {
        if (r.acc == Accuracy::None) continue;
        const IntersectionParams p = params_for(r.method);
        for (int s = 0; s < 20; ++s) {
            auto ea = make_elem(r.a, test::rand_vec(g, 0.2), g);
            auto eb = make_elem(r.b, test::rand_vec(g, 1.0), g);
            const auto d0 = detect_model_pair(p, *ea->model, *eb->model);
            const Mat3 R = test::rand_quat(g).toRotationMatrix();
            const Vec3 t = test::rand_vec(g, 3.0);
            move_elem(*ea, R, t);
            move_elem(*eb, R, t);
            const auto d1 = detect_model_pair(p, *ea->model, *eb->model);
            // thresholds (1e-6, strict tests) can flip on round-off; compare when both agree
            if (d0.outputs.size() != d1.outputs.size()) continue;
            for (std::size_t k = 0; k < d0.outputs.size(); ++k) {
                EXPECT_NEAR(d0.outputs[k].value, d1.outputs[k].value, 1e-9) << row_name(r.method, r.a, r.b);
                EXPECT_EQ(d0.outputs[k].id, d1.outputs[k].id);
                // GJK on curved supports (cylinder-cylinder/-triangle) converges the direction
                // to about sqrt(tolerance)
                const double ntol = r.a == T::Cylinder && r.b != T::Sphere && r.b != T::RigidSphere ? 1e-4 : 1e-7;
                if (r.acc != Accuracy::Crossing && std::abs(d0.outputs[k].value + p.contact_distance) > 1e-6) {
                    EXPECT_NEAR((R * d0.outputs[k].normal - d1.outputs[k].normal).norm(), 0.0, ntol)
                        << row_name(r.method, r.a, r.b);
                }
                ++compared;
            }
        }
    }
    EXPECT_GE(compared, 300);
}

// Invariance under vertex permutation where SOFA's semantics allow it: a single triangle with
// every flag owned (NewProximity, MinProximity) and a reversed line.
TEST(Characterization, TrianglePointInvariantUnderVertexPermutation) {
    std::mt19937 g(99);
    int compared = 0;
    for (M m : {M::NewProximity, M::MinProximity}) {
        const IntersectionParams p = params_for(m);
        for (int s = 0; s < 200; ++s) {
            const Vec3 v[3] = {test::rand_vec(g, 0.6), test::rand_vec(g, 0.6), test::rand_vec(g, 0.6)};
            Vec3State ps = test::make_state({test::rand_vec(g, 1.0)});
            PointModel pt(ps);
            std::vector<double> values;
            const int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
            for (const auto& pm : perm) {
                auto mesh = test::triangle_mesh({v[pm[0]], v[pm[1]], v[pm[2]]}, {{0, 1, 2}});
                TriangleModel tri(mesh->state, mesh->topo);
                const auto d = detect_model_pair(p, tri, pt);
                values.push_back(d.outputs.empty() ? 1e300 : d.outputs[0].value);
            }
            for (double x : values) EXPECT_NEAR(x, values[0], 1e-9) << intersection_method_name(m);
            compared += values[0] < 1e299;
        }
    }
    EXPECT_GE(compared, 100);
}

}  // namespace
}  // namespace penalty
