#pragma once
/// @file
/// Three tiers of error reporting (see docs/architecture.md):
///  - PENALTY_ASSERT(cond): internal invariant, checked in debug builds only;
///  - PENALTY_DEMAND(cond): invariant that must always hold, checked in every build;
///  - throw_invalid_argument(...): bad user input at an API boundary, with the function name,
///    the parameter and the offending value in the message.

#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace penalty {

/// Thrown by PENALTY_DEMAND / PENALTY_ASSERT: a bug in penalty, not in the caller's input.
class InternalError : public std::logic_error {
public:
    using std::logic_error::logic_error;
};

namespace detail {
[[noreturn]] void fail_invariant(const char* condition, const char* file, int line);

template <class... Args>
std::string concat(const Args&... args) {
    std::ostringstream out;
    out.precision(17);
    (out << ... << args);
    return out.str();
}
}  // namespace detail

/// Throws std::invalid_argument with all arguments streamed into the message.
template <class... Args>
[[noreturn]] void throw_invalid_argument(const Args&... args) {
    throw std::invalid_argument(detail::concat(args...));
}

/// True when every component is finite (no NaN, no infinity).
template <class Vector>
bool all_finite(const Vector& v) {
    return v.allFinite();
}
inline bool is_finite(double x) { return std::isfinite(x); }
/// True when x[0 … n) are all finite, in one pass the compiler vectorises: Σ 0·x[i] is 0 when
/// every x[i] is finite and NaN otherwise (0·±inf and 0·NaN are NaN, and NaN survives any order
/// of the sum), for the per-step checks of whole states and box lists.
inline bool all_finite(const double* x, std::size_t n) {
    double lanes[4] = {0.0, 0.0, 0.0, 0.0};
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4)
        for (std::size_t k = 0; k < 4; ++k) lanes[k] += 0.0 * x[i + k];
    for (; i < n; ++i) lanes[0] += 0.0 * x[i];
    return (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) == 0.0;
}

}  // namespace penalty

#define PENALTY_DEMAND(condition)                                                            \
    do {                                                                                     \
        if (!(condition)) ::penalty::detail::fail_invariant(#condition, __FILE__, __LINE__); \
    } while (false)

#ifdef NDEBUG
#define PENALTY_ASSERT(condition) ((void)0)
#else
#define PENALTY_ASSERT(condition) PENALTY_DEMAND(condition)
#endif
