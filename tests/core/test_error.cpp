#include "penalty/core/error.hpp"
#include "penalty/core/types.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace penalty {
namespace {

TEST(Error, InvalidArgumentMessageStreamsEveryPart) {
    try {
        throw_invalid_argument("f(): stiffness of contact ", 3, " is ", -1.5);
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "f(): stiffness of contact 3 is -1.5");
    }
}

TEST(Error, DemandThrowsInternalErrorWithCondition) {
    try {
        PENALTY_DEMAND(1 + 1 == 3);
        FAIL() << "no exception";
    } catch (const InternalError& e) {
        EXPECT_NE(std::string(e.what()).find("1 + 1 == 3"), std::string::npos);
    }
    EXPECT_NO_THROW(PENALTY_DEMAND(2 > 1));
}

TEST(Error, AllFiniteDetectsNaNAndInfinity) {
    EXPECT_TRUE(all_finite(Vec3(1, 2, 3)));
    EXPECT_FALSE(all_finite(Vec3(1, std::numeric_limits<double>::quiet_NaN(), 3)));
    EXPECT_FALSE(all_finite(Vec3(std::numeric_limits<double>::infinity(), 0, 0)));
}

// the array form used by the per-step checks: every position of a bad value, every tail length
TEST(Error, AllFiniteOfAnArrayFindsABadValueAnywhere) {
    const double bad[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                          -std::numeric_limits<double>::infinity()};
    int found = 0, cases = 0;
    for (std::size_t n = 0; n <= 11; ++n) {
        std::vector<double> x(n);
        for (std::size_t i = 0; i < n; ++i) x[i] = (i % 2 ? -1.0 : 1.0) * std::ldexp(1.0, int(i) * 97 - 500);
        x.push_back(std::numeric_limits<double>::max());  // finite extremes stay finite
        x.push_back(-0.0);
        EXPECT_TRUE(all_finite(x.data(), x.size())) << n;
        for (std::size_t i = 0; i < x.size(); ++i)
            for (const double b : bad) {
                std::vector<double> y = x;
                y[i] = b;
                ++cases;
                if (!all_finite(y.data(), y.size())) ++found;
            }
    }
    EXPECT_EQ(found, cases);
    EXPECT_EQ(cases, 3 * (2 * 12 + 66));
    EXPECT_TRUE(all_finite(nullptr, 0));
}

}  // namespace
}  // namespace penalty
