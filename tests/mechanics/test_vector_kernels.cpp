// The vector kernels of the per-CG-product force fields (KernelPath::avx) against their scalar
// loops (KernelPath::scalar): the same bits, the sign of zeros included, on random springs and
// tetrahedra with degenerate cases and counts that are not multiples of the lane width.
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace penalty {
namespace {

/// Bitwise equality of two Vec3 lists (−0 differs from +0, NaNs compare by payload).
void expect_same_bits(const std::vector<Vec3>& expected, const std::vector<Vec3>& actual, const std::string& what) {
    ASSERT_EQ(expected.size(), actual.size()) << what;
    for (std::size_t i = 0; i < expected.size(); ++i)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(0, std::memcmp(&expected[i][c], &actual[i][c], sizeof(double)))
                << what << ": DOF " << i << " component " << c << ": " << expected[i][c] << " against " << actual[i][c];
}

/// dx and df entries of every sign and size, zeros of both signs included.
double product_entry(std::mt19937& rng) {
    switch (rng() % 8) {
        case 0:
            return 0.0;
        case 1:
            return -0.0;
        case 2:
            return std::ldexp(std::uniform_real_distribution<double>(-1, 1)(rng), -40);
        default:
            return std::uniform_real_distribution<double>(-3, 3)(rng);
    }
}

void fill_products(Vec3Object& s, std::mt19937& rng) {
    for (auto& d : s.dx) d = Vec3(product_entry(rng), product_entry(rng), product_entry(rng));
    for (auto& d : s.df) d = Vec3(product_entry(rng), product_entry(rng), product_entry(rng));
}

/// DOFs whose df the product changed (the comparison is not vacuous).
int changed_dofs(const std::vector<Vec3>& before, const std::vector<Vec3>& after) {
    int n = 0;
    for (std::size_t i = 0; i < before.size(); ++i) n += before[i] != after[i] ? 1 : 0;
    return n;
}

bool avx_available() { return kernel_path_supported(KernelPath::avx); }

/// One spring list on two states (or one), with zero-length springs (coincident ends, a spring
/// from a DOF to itself), springs at the null length, long and short springs.
struct SpringCase {
    Vec3Object s1, s2;
    std::vector<Spring> springs;
};

void build_springs(SpringCase& c, std::mt19937& rng, std::size_t count, bool two_states) {
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 9; ++i) c.s1.position.emplace_back(u(rng), u(rng), u(rng));
    for (int i = 0; i < 9; ++i) c.s1.velocity.emplace_back(u(rng), u(rng), u(rng));
    c.s1.position[3] = c.s1.position[2];                      // coincident DOFs
    c.s1.position[5] = c.s1.position[4] + Vec3(1e-10, 0, 0);  // below the null length
    c.s1.position[7] = c.s1.position[6] + Vec3(0, 0, 1e-6);   // short, but a spring
    c.s1.init();
    c.s2.position = c.s1.position;
    c.s2.velocity = c.s1.velocity;
    for (auto& p : c.s2.position) p += Vec3(1e-3, 0, 0) * u(rng);
    c.s2.position[0] = c.s1.position[0];
    c.s2.init();
    for (std::size_t k = 0; k < count; ++k) {
        Index a = static_cast<Index>(rng() % 9);
        Index b = static_cast<Index>(rng() % 9);
        if (k % 5 == 0) b = a;  // zero length on one state
        if (k % 7 == 1) std::tie(a, b) = std::pair<Index, Index>{2, 3};
        if (k % 7 == 2) std::tie(a, b) = std::pair<Index, Index>{4, 5};
        if (k % 7 == 3) std::tie(a, b) = std::pair<Index, Index>{6, 7};
        c.springs.push_back(
            {a, b, 1000 * std::abs(u(rng)), 0.5 * std::abs(u(rng)), two_states ? 0.0 : std::abs(u(rng))});
    }
}

TEST(VectorKernels, SpringProductIsBitwiseTheScalarLoopOnEveryPath) {
    if (!avx_available()) GTEST_SKIP() << "this CPU has no AVX: only the scalar path runs";
    std::mt19937 rng(17);
    int compared = 0, changed = 0;
    for (const SpringArithmetic arithmetic :
         {SpringArithmetic::spring_force_field, SpringArithmetic::quadular_bending_springs})
        for (const bool two_states : {false, true})
            for (const std::size_t count : {std::size_t{1}, std::size_t{2}, std::size_t{3}, std::size_t{5},
                                            std::size_t{7}, std::size_t{13}, std::size_t{64}, std::size_t{203}}) {
                SpringCase c;
                build_springs(c, rng, count, two_states);
                const auto make = [&](KernelPath path) {
                    auto ff = two_states ? std::make_unique<SpringForceField>(c.s1, c.s2)
                                         : std::make_unique<SpringForceField>(c.s1);
                    ff->set_arithmetic(arithmetic);
                    ff->set_kernel_path(path);
                    for (const auto& s : c.springs) ff->add_spring(s);
                    ff->init();
                    return ff;
                };
                auto scalar = make(KernelPath::scalar);
                auto vector = make(KernelPath::avx);
                scalar->accumulate_force();
                vector->accumulate_force();
                for (const double k : {-0.0123, 1.0, -0.0}) {
                    fill_products(c.s1, rng);
                    fill_products(c.s2, rng);
                    const std::vector<Vec3> df1(c.s1.df.begin(), c.s1.df.end()), df2(c.s2.df.begin(), c.s2.df.end());
                    scalar->accumulate_dforce(k, 0.0);
                    const std::vector<Vec3> expected1(c.s1.df.begin(), c.s1.df.end()),
                        expected2(c.s2.df.begin(), c.s2.df.end());
                    changed += changed_dofs(df1, expected1) + changed_dofs(df2, expected2);
                    std::copy(df1.begin(), df1.end(), c.s1.df.begin());
                    std::copy(df2.begin(), df2.end(), c.s2.df.begin());
                    vector->accumulate_dforce(k, 0.0);
                    const std::string what = "springs " + std::to_string(count) + (two_states ? " (two states)" : "");
                    expect_same_bits(expected1, {c.s1.df.begin(), c.s1.df.end()}, what);
                    expect_same_bits(expected2, {c.s2.df.begin(), c.s2.df.end()}, what);
                    ++compared;
                }
            }
    EXPECT_EQ(compared, 2 * 2 * 8 * 3);
    EXPECT_GT(changed, 300);
}

TEST(VectorKernels, SpringForceEnergyAndStiffnessAreBitwiseTheScalarLoopOnEveryPath) {
    if (!avx_available()) GTEST_SKIP() << "this CPU has no AVX: only the scalar path runs";
    std::mt19937 rng(29);
    int compared = 0, changed = 0, short_springs = 0;
    for (const SpringArithmetic arithmetic :
         {SpringArithmetic::spring_force_field, SpringArithmetic::quadular_bending_springs})
        for (const bool two_states : {false, true})
            for (const std::size_t count : {std::size_t{1}, std::size_t{3}, std::size_t{4}, std::size_t{5},
                                            std::size_t{8}, std::size_t{13}, std::size_t{64}, std::size_t{203}}) {
                SpringCase c;
                build_springs(c, rng, count, two_states);
                c.s1.velocity[8] = Vec3(-0.0, 1e-300, -7.0);
                const auto run = [&](KernelPath path, std::vector<Vec3>& f1, std::vector<Vec3>& f2, TripletList& k) {
                    auto ff = two_states ? std::make_unique<SpringForceField>(c.s1, c.s2)
                                         : std::make_unique<SpringForceField>(c.s1);
                    ff->set_arithmetic(arithmetic);
                    ff->set_kernel_path(path);
                    for (const auto& s : c.springs) ff->add_spring(s);
                    ff->init();
                    std::mt19937 same(count);  // the same starting forces on both paths
                    fill_products(c.s1, same);
                    fill_products(c.s2, same);
                    for (std::size_t i = 0; i < c.s1.force.size(); ++i) c.s1.force[i] = c.s1.df[i];
                    for (std::size_t i = 0; i < c.s2.force.size(); ++i) c.s2.force[i] = c.s2.df[i];
                    const std::vector<Vec3> before(c.s1.force.begin(), c.s1.force.end());
                    ff->accumulate_force();
                    changed += changed_dofs(before, {c.s1.force.begin(), c.s1.force.end()});
                    f1.assign(c.s1.force.begin(), c.s1.force.end());
                    f2.assign(c.s2.force.begin(), c.s2.force.end());
                    ff->add_stiffness_triplets(k, 0, two_states ? 27 : 0, 1.0);
                    return ff->potential_energy();
                };
                std::vector<Vec3> sf1, sf2, vf1, vf2;
                TripletList sk, vk;
                const double scalar_energy = run(KernelPath::scalar, sf1, sf2, sk);
                const double vector_energy = run(KernelPath::avx, vf1, vf2, vk);
                const std::string what = "springs " + std::to_string(count) + (two_states ? " (two states)" : "");
                expect_same_bits(sf1, vf1, what + ", f1");
                expect_same_bits(sf2, vf2, what + ", f2");
                EXPECT_EQ(0, std::memcmp(&scalar_energy, &vector_energy, sizeof(double)))
                    << what << ": energy " << scalar_energy << " against " << vector_energy;
                ASSERT_EQ(sk.size(), vk.size());
                for (std::size_t i = 0; i < sk.size(); ++i) {
                    const double a = sk[i].value(), b = vk[i].value();
                    ASSERT_EQ(0, std::memcmp(&a, &b, sizeof(double)))
                        << what << ": stiffness entry " << i << ": " << a << " against " << b;
                    short_springs += (i % 36 == 0 && a == 0.0) ? 1 : 0;
                }
                if (count >= 4) {
                    EXPECT_GT(scalar_energy, 0.0) << what;  // the first three springs are short
                }
                ++compared;
            }
    EXPECT_EQ(compared, 2 * 2 * 8);
    EXPECT_GT(changed, 150);       // the forces moved
    EXPECT_GT(short_springs, 40);  // springs at or below the null length: zero stiffness
}

TEST(VectorKernels, CorotationalTetrahedronForceAndProductAreBitwiseTheScalarLoops) {
    if (!avx_available()) GTEST_SKIP() << "this CPU has no AVX: only the scalar path runs";
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(-1, 1);
    int compared = 0, changed = 0, changed_forces = 0;
    // avx512 (eight lanes, add_dforce only) where this CPU has AVX-512F; its blocks are filled at
    // init, or by set_kernel_path after init (count % 2 == 1), from the rotations of that moment
    const bool wide_available = kernel_path_supported(KernelPath::avx512);
    int compared_wide = 0;
    for (const std::size_t count : {std::size_t{1}, std::size_t{2}, std::size_t{3}, std::size_t{4}, std::size_t{5},
                                    std::size_t{6}, std::size_t{8}, std::size_t{9}, std::size_t{17}, std::size_t{57}}) {
        // a cloud of points, each element on four distinct points with a clear rest volume
        Vec3Object s;
        const std::size_t points = 12;
        for (std::size_t i = 0; i < points; ++i) s.position.emplace_back(u(rng), u(rng), u(rng));
        s.init();
        std::vector<Tetrahedron> tetrahedra;
        while (tetrahedra.size() < count) {
            Tetrahedron t{};
            for (auto& v : t) v = static_cast<PointId>(rng() % points);
            const auto& x = s.rest_position;
            const auto p = [&](int k) { return x[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])]; };
            if (std::abs((p(1) - p(0)).cross(p(2) - p(0)).dot(p(3) - p(0))) < 0.05) continue;
            tetrahedra.push_back(t);
        }
        MeshTopology topo;
        topo.set_tetrahedra(tetrahedra);
        TetrahedronFEMForceField scalar(s, topo, 1e4, 0.3, FemMethod::Large);
        TetrahedronFEMForceField vector(s, topo, 1e4, 0.3, FemMethod::Large);
        TetrahedronFEMForceField wide(s, topo, 1e4, 0.3, FemMethod::Large);
        scalar.set_kernel_path(KernelPath::scalar);
        vector.set_kernel_path(KernelPath::avx);
        wide.set_kernel_path(count % 2 == 1 ? KernelPath::avx
                                            : (wide_available ? KernelPath::avx512 : KernelPath::avx));
        scalar.init();
        vector.init();
        wide.init();
        for (int configuration = 0; configuration < 3; ++configuration) {
            // deformed and turned; the third time collapsed (coincident vertices: degenerate frames)
            for (std::size_t i = 0; i < points; ++i)
                s.position[i] = s.rest_position[i] + 0.3 * Vec3(u(rng), u(rng), u(rng));
            if (configuration == 2) {
                s.position[1] = s.position[0];
                s.position[3] = s.position[2];
                s.position[5] = Vec3::Zero();
            }
            // add_force: f and the energy bit for bit (the vector path forms R, δ and F in lanes)
            for (auto& f : s.force) f = Vec3(product_entry(rng), product_entry(rng), product_entry(rng));
            const std::vector<Vec3> force_before(s.force.begin(), s.force.end());
            scalar.accumulate_force();
            const std::vector<Vec3> expected_force(s.force.begin(), s.force.end());
            std::copy(force_before.begin(), force_before.end(), s.force.begin());
            vector.accumulate_force();
            expect_same_bits(expected_force, {s.force.begin(), s.force.end()},
                             "add_force, tetrahedra " + std::to_string(count));
            EXPECT_EQ(scalar.potential_energy(), vector.potential_energy());
            std::copy(force_before.begin(), force_before.end(), s.force.begin());
            wide.accumulate_force();
            expect_same_bits(expected_force, {s.force.begin(), s.force.end()},
                             "add_force (wide), tetrahedra " + std::to_string(count));
            if (configuration == 0 && count % 2 == 1 && wide_available) wide.set_kernel_path(KernelPath::avx512);
            changed_forces += changed_dofs(force_before, expected_force);
            for (const double k : {-0.0123, 1.0}) {
                fill_products(s, rng);
                const std::vector<Vec3> df(s.df.begin(), s.df.end());
                scalar.accumulate_dforce(k, 0.0);
                const std::vector<Vec3> expected(s.df.begin(), s.df.end());
                changed += changed_dofs(df, expected);
                std::copy(df.begin(), df.end(), s.df.begin());
                vector.accumulate_dforce(k, 0.0);
                expect_same_bits(expected, {s.df.begin(), s.df.end()}, "tetrahedra " + std::to_string(count));
                std::copy(df.begin(), df.end(), s.df.begin());
                wide.accumulate_dforce(k, 0.0);
                expect_same_bits(expected, {s.df.begin(), s.df.end()},
                                 std::string(to_string(wide.kernel_path())) + ", tetrahedra " + std::to_string(count));
                compared_wide += wide.kernel_path() == KernelPath::avx512 ? 1 : 0;
                ++compared;
            }
        }
    }
    EXPECT_EQ(compared, 10 * 3 * 2);
    EXPECT_EQ(compared_wide, wide_available ? 10 * 3 * 2 : 0);
    EXPECT_GT(changed, 200);
    EXPECT_GT(changed_forces, 100);
}

TEST(VectorKernels, PathsAreReportedAndUnsupportedOnesRefused) {
    EXPECT_TRUE(kernel_path_supported(KernelPath::scalar));
    EXPECT_EQ(best_kernel_path(), avx_available() ? KernelPath::avx : KernelPath::scalar);
    EXPECT_STREQ(to_string(KernelPath::avx), "avx");
    EXPECT_STREQ(to_string(KernelPath::avx512), "avx512");
    // the FEM's default: eight lanes on Intel CPUs with AVX-512F only
#if defined(__x86_64__) && defined(__GNUC__)
    const bool intel_wide = kernel_path_supported(KernelPath::avx512) && __builtin_cpu_is("intel");
#else
    const bool intel_wide = false;
#endif
    EXPECT_EQ(best_fem_kernel_path(), intel_wide ? KernelPath::avx512 : best_kernel_path());
    Vec3Object s;
    s.position = {Vec3::Zero(), Vec3::UnitX()};
    s.init();
    SpringForceField springs(s);
    EXPECT_EQ(springs.kernel_path(), best_kernel_path());
    springs.set_kernel_path(KernelPath::scalar);
    EXPECT_EQ(springs.kernel_path(), KernelPath::scalar);
    if (!avx_available()) {
        EXPECT_THROW(springs.set_kernel_path(KernelPath::avx), std::invalid_argument);
    }
    EXPECT_THROW(springs.set_kernel_path(KernelPath::avx512), std::invalid_argument);  // the FEM's only
    EXPECT_EQ(springs.kernel_path(), KernelPath::scalar);
    Vec3Object body;
    body.position = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
    body.init();
    MeshTopology topo;
    topo.set_tetrahedra({Tetrahedron{0, 1, 2, 3}});
    TetrahedronFEMForceField fem(body, topo, 1e4, 0.3, FemMethod::Large);
    EXPECT_EQ(fem.kernel_path(), best_fem_kernel_path());
    if (!kernel_path_supported(KernelPath::avx512)) {
        EXPECT_THROW(fem.set_kernel_path(KernelPath::avx512), std::invalid_argument);
    }
}

}  // namespace
}  // namespace penalty
