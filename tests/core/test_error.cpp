#include "penalty/core/error.hpp"
#include "penalty/core/types.hpp"

#include <gtest/gtest.h>

#include <limits>

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

}  // namespace
}  // namespace penalty
