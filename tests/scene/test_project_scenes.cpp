// End-to-end tests of the project's own example scenes (scenes/*.scn, see scenes/README.md):
//
//  * regression: each scene runs as `penalty run --steps N --export-every M --export-states`
//    (the runs of tests/scene/expected/manifest.txt) and its state files must match the stored
//    ones in tests/scene/expected/<scene>/ (scripts/regenerate-expected.sh writes them);
//  * coverage: every collision-model pair a scene is meant to exercise must get contacts
//    (penalty springs) at some step, and no other pair may appear;
//  * physics (beyond-SOFA features): Coulomb friction on an incline (sliding acceleration
//    g (sin θ − μ cos θ), sticking when tan θ < μ) and the bounce height ratio of a damped
//    penalty contact.
//
// Regression tolerance: SOFA's criterion (output::compare_with_reference: Σ over samples and
// scalars of |x − x_ref| / number of DOFs, averaged over states) must stay ≤ 1e-9 m. The runs are
// deterministic (fixed model and pair order, -ffp-contract=off, no random input): on one build
// the error is exactly 0; 1e-9 leaves room only for last-bit differences between compilers,
// optimisation levels or libm versions (positions are O(1) m, written with 17 digits), while any
// change of the physics (a formula, a stiffness, a contact rule) moves positions by far more
// (the contact penetrations alone are ~1e-3 m).

#include "penalty/collision/collision_model.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/response/collision_response.hpp"
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"

#include <gtest/gtest.h>
#include "penalty_test/paths.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kSource = penalty::test::source_dir();
const fs::path kScenes = kSource / "scenes";
const fs::path kExpected = kSource / "tests" / "scene" / "expected";

struct ManifestRun {
    std::string scene;
    std::int64_t steps = 0;
    std::int64_t every = 1;
};

void PrintTo(const ManifestRun& r, std::ostream* os) {
    *os << r.scene << " (" << r.steps << " steps, every " << r.every << ")";
}

std::vector<ManifestRun> read_manifest() {
    std::ifstream in(kExpected / "manifest.txt");
    std::vector<ManifestRun> runs;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        ManifestRun r;
        if (s >> r.scene >> r.steps >> r.every) runs.push_back(r);
    }
    return runs;
}

/// The model pairs (registered order, "Type1-Type2") each scene must exercise.
const std::map<std::string, std::set<std::string>>& expected_pairs() {
    static const std::map<std::string, std::set<std::string>> m = {
        {"sphere_pairs",
         {"Sphere-Sphere", "Sphere-RigidSphere", "RigidSphere-RigidSphere", "Sphere-Point", "RigidSphere-Point",
          "Point-Point"}},
        {"line_pairs", {"Line-Point", "Line-Line", "Line-Sphere", "Line-RigidSphere"}},
        {"triangle_pairs",
         {"Triangle-Sphere", "Triangle-RigidSphere", "Triangle-Point", "Triangle-Line", "Triangle-Triangle"}},
        {"cylinders", {"Cylinder-Cylinder", "Cylinder-Triangle", "Cylinder-Sphere", "Cylinder-RigidSphere"}},
        {"tetra_point", {"Tetrahedron-Point"}},
        {"friction_incline", {"Triangle-Point"}},
        {"damped_bounce", {"Triangle-Point"}},
    };
    return m;
}

/// Per pair type ("Triangle-Point"): the largest number of contact springs, and of active ones
/// (penetration > 0 at the last force evaluation), summed over the live model pairs of that
/// type, over the steps observed.
struct PairCount {
    std::size_t springs = 0;
    std::size_t active = 0;
};
using PairCounts = std::map<std::string, PairCount>;

void record_pairs(const penalty::scene::Scene& scene, PairCounts& counts) {
    std::map<std::string, PairCount> step;
    for (const auto& p : scene.pipelines()) {
        for (const penalty::ContactPairEntry& e : p.pipeline->response().pairs()) {
            if (!e.contact) continue;
            const std::string key = std::string(penalty::model_type_name(e.model1->type())) + "-" +
                                    penalty::model_type_name(e.model2->type());
            step[key].springs += e.contact->force_field().size();
            step[key].active += e.contact->force_field().active_count();
        }
    }
    for (const auto& [key, c] : step) {
        PairCount& m = counts[key];
        m.springs = std::max(m.springs, c.springs);
        m.active = std::max(m.active, c.active);
    }
}

fs::path fresh_temp_dir(const std::string& name) {
    const fs::path d =
        fs::temp_directory_path() / ("penalty_project_scenes_" + name + "_" +
                                     std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::vector<fs::path> sorted_files(const fs::path& dir) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_regular_file()) files.push_back(e.path());
    // "<k>_<name>_mstate.txt": order by k
    std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
        return std::stol(a.filename().string()) < std::stol(b.filename().string());
    });
    return files;
}

const penalty::Vec3Object& vec3_state(const penalty::scene::Scene& scene, const std::string& name) {
    for (const auto& r : scene.states())
        if (r.name == name)
            if (const auto* v = dynamic_cast<const penalty::Vec3Object*>(r.state)) return *v;
    throw std::runtime_error("no Vec3 state '" + name + "'");
}

// ---- regression + pair coverage --------------------------------------------------------------

class ProjectScene : public ::testing::TestWithParam<ManifestRun> {};

TEST_P(ProjectScene, MatchesExpectedStatesAndExercisesItsPairs) {
    const ManifestRun& run = GetParam();
    const fs::path scene_file = kScenes / (run.scene + ".scn");
    ASSERT_TRUE(fs::exists(scene_file)) << scene_file;
    auto scene = penalty::scene::load_scene(scene_file);
    for (const std::string& w : scene->warnings()) ADD_FAILURE() << run.scene << ": warning: " << w;

    const fs::path out = fresh_temp_dir(run.scene);
    penalty::scene::RunOptions options;
    options.steps = run.steps;
    options.export_every = run.every;
    options.states_directory = out;
    PairCounts counts;
    const auto summary = penalty::scene::run_scene(
        *scene, options,
        [&](std::int64_t, std::int64_t, const penalty::scene::RunSummary&) { record_pairs(*scene, counts); });
    EXPECT_EQ(summary.steps, run.steps);
    EXPECT_GT(summary.max_contacts, 0U);

    // every pair of the scene got active contacts (penetration > 0), and no other pair got any
    // contact spring
    std::set<std::string> seen, active;
    std::ostringstream measured;
    for (const auto& [pair, n] : counts) {
        measured << " " << pair << " " << n.springs << "/" << n.active;
        if (n.springs > 0) seen.insert(pair);
        if (n.active > 0) active.insert(pair);
    }
    const auto it = expected_pairs().find(run.scene);
    ASSERT_NE(it, expected_pairs().end()) << "no pair list for scene " << run.scene;
    EXPECT_EQ(seen, it->second) << run.scene << ": max springs/active per pair:" << measured.str();
    EXPECT_EQ(active, it->second) << run.scene << ": max springs/active per pair:" << measured.str();
    RecordProperty("max_springs_active_per_pair", measured.str());
    std::cout << "[ pairs    ] " << run.scene << " (max springs/active):" << measured.str() << "\n";

    // the exported states match the stored ones
    const fs::path ref_dir = kExpected / run.scene;
    ASSERT_TRUE(fs::is_directory(ref_dir)) << ref_dir << " (run scripts/regenerate-expected.sh)";
    const std::vector<fs::path> ours = sorted_files(out);
    const std::vector<fs::path> refs = sorted_files(ref_dir);
    ASSERT_EQ(ours.size(), refs.size());
    for (std::size_t i = 0; i < refs.size(); ++i) EXPECT_EQ(ours[i].filename(), refs[i].filename());
    ASSERT_EQ(summary.values_per_dof.size(), refs.size());
    const auto result = penalty::output::compare_with_reference(refs, ours, summary.values_per_dof);
    for (const std::string& m : result.messages) ADD_FAILURE() << run.scene << ": " << m;
    EXPECT_LE(result.mean_error, 1e-9) << run.scene;
    // the comparison covers every exported sample of every state
    for (const fs::path& r : refs)
        EXPECT_EQ(penalty::output::read_state_file(r).size(), std::size_t(run.steps / run.every + 1)) << r;
    fs::remove_all(out);
}

std::vector<ManifestRun> manifest_or_placeholder() {
    std::vector<ManifestRun> runs = read_manifest();
    if (runs.empty()) runs.push_back({"missing_manifest", 0, 1});  // fails loudly below
    return runs;
}

INSTANTIATE_TEST_SUITE_P(Scenes, ProjectScene, ::testing::ValuesIn(manifest_or_placeholder()),
                         [](const ::testing::TestParamInfo<ManifestRun>& param_info) {
                             return param_info.param.scene;
                         });

TEST(ProjectScenes, ManifestListsEveryScene) {
    std::set<std::string> listed;
    for (const ManifestRun& r : read_manifest()) listed.insert(r.scene);
    std::set<std::string> files;
    for (const auto& e : fs::directory_iterator(kScenes))
        if (e.path().extension() == ".scn") files.insert(e.path().stem().string());
    EXPECT_EQ(listed, files);
    std::set<std::string> with_pairs;
    for (const auto& [scene, pairs] : expected_pairs()) with_pairs.insert(scene);
    EXPECT_EQ(with_pairs, files);
    // together the scenes exercise every pair that has an intersector (docs/collision.md)
    std::set<std::string> all;
    for (const auto& [scene, pairs] : expected_pairs()) all.insert(pairs.begin(), pairs.end());
    EXPECT_EQ(all.size(), 20U);
}

// ---- friction on an incline ------------------------------------------------------------------
// scenes/friction_incline.scn: μ = 0.3 (plates 0.3 + particles 0), particles of 0.1 kg released
// at rest on a 30° and a 15° incline (rotation about z; downhill = −(cos θ, sin θ, 0)).

constexpr double kG = 9.81;
constexpr double kMu = 0.3;

double downhill_distance(const penalty::Vec3& p, const penalty::Vec3& p0, double theta_deg) {
    const double t = theta_deg * std::numbers::pi / 180.0;
    return -(p - p0).dot(penalty::Vec3(std::cos(t), std::sin(t), 0.0));
}

double normal_offset(const penalty::Vec3& p, const penalty::Vec3& plane_point, double theta_deg) {
    const double t = theta_deg * std::numbers::pi / 180.0;
    return (p - plane_point).dot(penalty::Vec3(-std::sin(t), std::cos(t), 0.0));
}

TEST(FrictionIncline, SlidingAccelerationIsGTimesSinMinusMuCos) {
    auto scene = penalty::scene::load_scene(kScenes / "friction_incline.scn");
    const auto& block = vec3_state(*scene, "sliding_block");
    const penalty::Vec3 p0 = block.position[0];
    const double dt = scene->dt();
    // least-squares fit s(t) = s0 + v0 t + a t²/2 over t in [0.1, 0.7] s: the normal transient
    // (a few steps) is over and the particle is still on the plate (it leaves it at t ≈ 0.8 s)
    double sums[5] = {0, 0, 0, 0, 0}, rhs[3] = {0, 0, 0};
    double min_offset = 1e9, max_offset = -1e9;
    for (int k = 1; k <= 140; ++k) {
        scene->step();
        const double t = k * dt;
        const double s = downhill_distance(block.position[0], p0, 30.0);
        if (t < 0.1 - 1e-12) continue;
        const double off = normal_offset(block.position[0], {-1.0, 0.0, 0.0}, 30.0);
        min_offset = std::min(min_offset, off);
        max_offset = std::max(max_offset, off);
        double tp = 1.0;
        for (double& x : sums) {
            x += tp;
            tp *= t;
        }
        rhs[0] += s;
        rhs[1] += s * t;
        rhs[2] += s * t * t;
    }
    Eigen::Matrix3d A;
    A << sums[0], sums[1], sums[2], sums[1], sums[2], sums[3], sums[2], sums[3], sums[4];
    const Eigen::Vector3d c = A.ldlt().solve(Eigen::Vector3d(rhs[0], rhs[1], rhs[2]));
    const double a = 2.0 * c[2];
    const double th = 30.0 * std::numbers::pi / 180.0;
    const double expected = kG * (std::sin(th) - kMu * std::cos(th));  // 2.356 m/s²
    // Implicit Euler is exact on a uniformly accelerated motion (v += h a, x += h v: the second
    // difference of x is exactly h² a) and the fit absorbs the velocity left by the first steps'
    // transient, so only a friction force different from μ m g cos θ moves a: measured relative
    // error 8.5e-9; tolerance 1e-4 (a 1 % change of μ moves a by 1.1 %).
    EXPECT_NEAR(a, expected, 1e-4 * expected);
    EXPECT_LT(a, 0.6 * kG * std::sin(th));  // friction acts: frictionless would be 4.905 m/s²
    // it slides on the plane: the normal offset stays at C − m g cos θ / ks = 0.02 − 1.7e-4 m
    EXPECT_NEAR(min_offset, 0.02 - 0.1 * kG * std::cos(th) / 5000.0, 2e-5);
    EXPECT_NEAR(max_offset, 0.02 - 0.1 * kG * std::cos(th) / 5000.0, 2e-5);
}

TEST(FrictionIncline, StaysStuckWhenTanThetaBelowMu) {
    auto scene = penalty::scene::load_scene(kScenes / "friction_incline.scn");
    const auto& block = vec3_state(*scene, "sticking_block");
    const penalty::Vec3 p0 = block.position[0];
    ASSERT_LT(std::tan(15.0 * std::numbers::pi / 180.0), kMu);
    double max_slide = 0.0;
    for (int k = 1; k <= 140; ++k) {
        scene->step();
        max_slide = std::max(max_slide, std::abs(downhill_distance(block.position[0], p0, 15.0)));
    }
    // sticking: only the tangential spring's elastic stretch m g sin θ / kt = 5e-5 m at most
    // (kt = ks = 5000 N/m); frictionless it would slide g sin 15° t²/2 = 0.62 m in 0.7 s
    EXPECT_LT(max_slide, 1e-4);
    // and it rests on the plane
    EXPECT_NEAR(normal_offset(block.position[0], {1.0, 0.0, 0.0}, 15.0),
                0.02 - 0.1 * kG * std::cos(15.0 * std::numbers::pi / 180.0) / 5000.0, 2e-6);
}

// ---- damped bounce ---------------------------------------------------------------------------
// scenes/damped_bounce.scn: m = 0.1 kg, ks = 20·10/0.02 = 10000 N/m, drop height h0 = 0.1 m above
// the contact height y = C = 0.02 m; A undamped, B with c = 6 N·s/m.
//
// Expected restitution: in contact, with p the penetration, m p'' + c p' + ks p = m g, p(0) = 0,
// p'(0) = v0 = sqrt(2 g h0); the contact ends at the first T > 0 with p(T) = 0, e = −p'(T)/v0
// and the apex height ratio is e². Closed form p(t) = δ + e^(−ζωt)(A cos ω_d t + B sin ω_d t),
// δ = m g / ks; T from bisection. ζ = 0.0949 gives e² = 0.5385 (0.5495 without gravity).
double restitution_with_gravity(double m, double ks, double c, double g, double v0) {
    const double w = std::sqrt(ks / m), z = c / (2.0 * std::sqrt(ks * m)), wd = w * std::sqrt(1.0 - z * z);
    const double d = m * g / ks;
    const double A = -d, B = (v0 + z * w * A) / wd;  // p(0) = 0, p'(0) = −zωA + ω_d B = v0
    auto p = [&](double t) { return d + std::exp(-z * w * t) * (A * std::cos(wd * t) + B * std::sin(wd * t)); };
    auto pd = [&](double t) {
        return std::exp(-z * w * t) *
               ((-z * w * A + wd * B) * std::cos(wd * t) + (-z * w * B - wd * A) * std::sin(wd * t));
    };
    double lo = 0.5 * std::numbers::pi / wd, hi = 1.5 * std::numbers::pi / wd;  // p > 0 at lo, < 0 at hi
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (p(mid) > 0 ? lo : hi) = mid;
    }
    return -pd(lo) / v0;
}

TEST(DampedBounce, HeightRatioMatchesSpringDashpotRestitution) {
    auto scene = penalty::scene::load_scene(kScenes / "damped_bounce.scn");
    const auto& a = vec3_state(*scene, "ball_a");
    const auto& b = vec3_state(*scene, "ball_b");
    const double y_contact = 0.02, h0 = a.position[0].y() - y_contact;
    ASSERT_NEAR(h0, 0.1, 1e-12);
    double apex_a = -1.0, apex_b = -1.0;
    bool bounced_a = false, bounced_b = false;
    std::size_t contacts = 0;
    for (int k = 1; k <= 12000; ++k) {
        scene->step();
        for (const auto& r : scene->contacts()) contacts = std::max(contacts, r.field->size());
        // after the contact (the particle moves up above the contact height), track the apex
        bounced_a = bounced_a || (a.velocity[0].y() > 0 && a.position[0].y() > y_contact);
        bounced_b = bounced_b || (b.velocity[0].y() > 0 && b.position[0].y() > y_contact);
        if (bounced_a) apex_a = std::max(apex_a, a.position[0].y());
        if (bounced_b) apex_b = std::max(apex_b, b.position[0].y());
    }
    ASSERT_TRUE(bounced_a && bounced_b);
    EXPECT_GT(contacts, 0U);
    // both reached their apex before the end (0.3 s): now falling again
    EXPECT_LT(a.velocity[0].y(), 0.0);
    EXPECT_LT(b.velocity[0].y(), 0.0);
    const double ratio_a = (apex_a - y_contact) / h0, ratio_b = (apex_b - y_contact) / h0;
    const double e = restitution_with_gravity(0.1, 1e4, 6.0, kG, std::sqrt(2.0 * kG * h0));
    const double expected = e * e;  // 0.5385
    EXPECT_NEAR(expected, 0.5385, 1e-4);
    // A: only implicit Euler's numerical dissipation, ≈ exp(−π ω dt) = 0.975 at ω dt = 0.0079
    EXPECT_GT(ratio_a, 0.96);
    EXPECT_LT(ratio_a, 1.0);
    // B / A removes the integrator's loss (to first order): within 1 % of e² (measured −0.3 %)
    EXPECT_NEAR(ratio_b / ratio_a, expected, 0.01 * expected);
    // B alone: e² less the integrator's loss (2.5 %): within 4 %
    EXPECT_NEAR(ratio_b, expected, 0.04 * expected);
}

}  // namespace
