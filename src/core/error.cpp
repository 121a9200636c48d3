#include "penalty/core/error.hpp"

namespace penalty::detail {

void fail_invariant(const char* condition, const char* file, int line) {
    throw InternalError(concat("penalty internal error: '", condition, "' failed at ", file, ":", line));
}

}  // namespace penalty::detail
