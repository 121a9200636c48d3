// The springs' vector kernels (kernels/mechanics/springs.cpp, KernelPath::avx) against their scalar
// loops (KernelPath::scalar): the product, force, energy and stiffness, the same bits, the sign of zeros
// included, on random springs with degenerate ones and counts that are not multiples of the lane width.
#include "kernel_cases.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace penalty {
namespace {

using namespace test_kernel_cases;

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

}  // namespace
}  // namespace penalty
