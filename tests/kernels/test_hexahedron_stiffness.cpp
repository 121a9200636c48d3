// A hexahedron's K·d kernel (kernels/mechanics/hexahedron_stiffness.cpp): the scalar path is
// SOFA's Mat<24,24>·Vec<24> (each row summed left to right, type::Mat::operator*), and the AVX
// path is the scalar one to the bit (the sign of zeros and infinities included; a NaN is a NaN on
// both, whose payload and sign follow which operand the compiler put first, as in SOFA's own
// builds) on random matrices and vectors with entries of every sign and size.
#include "kernel_cases.hpp"
#include "kernels/mechanics/hexahedron_stiffness.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

namespace penalty {
namespace {

using namespace test_kernel_cases;
using detail::HexahedronStiffness;
using detail::HexahedronVector;

/// An entry of K or d: product_entry's (zeros of both signs, tiny and ordinary values), and with
/// `special`, subnormals, infinities and NaNs now and then.
double entry(std::mt19937& rng, bool special) {
    double value = 0.0;
    return draw_special(rng, special, 16, value) ? value : product_entry(rng);
}

/// SOFA's Mat<L,C>·Vec<C>: r_i = m_i0·v_0, then r_i += m_ij·v_j for j = 1 … C − 1.
HexahedronVector sofa_product(const HexahedronStiffness& k, const HexahedronVector& d) {
    HexahedronVector r;
    for (int i = 0; i < 24; ++i) {
        r[i] = k(i, 0) * d[0];
        for (int j = 1; j < 24; ++j) r[i] += k(i, j) * d[j];
    }
    return r;
}

/// Each entry the same bits, or NaN in both.
bool same_bits(const HexahedronVector& a, const HexahedronVector& b) {
    for (int i = 0; i < 24; ++i)
        if (std::memcmp(&a[i], &b[i], sizeof(double)) != 0 && !(std::isnan(a[i]) && std::isnan(b[i]))) return false;
    return true;
}

TEST(HexahedronStiffness, ScalarPathIsSofasRowByRowProduct) {
    std::mt19937 rng(41);
    int order_matters = 0;
    for (int c = 0; c < 200; ++c) {
        HexahedronStiffness k;
        HexahedronVector d;
        for (int i = 0; i < 24 * 24; ++i) k.data()[i] = std::uniform_real_distribution<double>(-1e4, 1e4)(rng);
        for (int i = 0; i < 24; ++i) d[i] = product_entry(rng);
        const HexahedronVector f = detail::hexahedron_stiffness_times(KernelPath::scalar, k, d);
        EXPECT_TRUE(same_bits(f, sofa_product(k, d))) << "case " << c;
        // the comparison can fail: summed right to left, some rows differ in their last bits
        HexahedronVector backwards;
        for (int i = 0; i < 24; ++i) {
            backwards[i] = k(i, 23) * d[23];
            for (int j = 22; j >= 0; --j) backwards[i] += k(i, j) * d[j];
        }
        order_matters += same_bits(f, backwards) ? 0 : 1;
    }
    EXPECT_GT(order_matters, 100);
}

TEST(HexahedronStiffness, AvxPathIsTheScalarPathToTheBit) {
    if (!avx_available()) GTEST_SKIP() << "this CPU has no AVX";
    std::mt19937 rng(43);
    int non_finite = 0;
    for (int c = 0; c < 2000; ++c) {
        const bool special = c % 4 == 3;
        HexahedronStiffness k;
        HexahedronVector d;
        for (int i = 0; i < 24 * 24; ++i) k.data()[i] = entry(rng, special);
        for (int i = 0; i < 24; ++i) d[i] = entry(rng, special);
        const HexahedronVector scalar = detail::hexahedron_stiffness_times(KernelPath::scalar, k, d);
        const HexahedronVector avx = detail::hexahedron_stiffness_times(KernelPath::avx, k, d);
        EXPECT_TRUE(same_bits(scalar, avx)) << "case " << c;
        // avx512 runs avx
        EXPECT_TRUE(same_bits(scalar, detail::hexahedron_stiffness_times(KernelPath::avx512, k, d))) << "case " << c;
        non_finite += scalar.allFinite() ? 0 : 1;
    }
    EXPECT_GT(non_finite, 100);  // the special values reached the results
}

}  // namespace
}  // namespace penalty
