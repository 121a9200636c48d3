#pragma once
#include <algorithm>
#include <vector>
// Whether this test binary runs under AddressSanitizer (the `asan` preset: ASan + UBSan, about
// 20-90× slower than release). The few long statistical or scene tests use it to run a smaller
// instance of the same code under the sanitizers; the release suite runs the full size.
namespace penalty::test {

#if defined(__SANITIZE_ADDRESS__)  // g++
inline constexpr bool kUnderSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)  // clang++
inline constexpr bool kUnderSanitizer = true;
#else
inline constexpr bool kUnderSanitizer = false;
#endif
#else
inline constexpr bool kUnderSanitizer = false;
#endif

// The thread counts a same-bits-on-threads test runs: `full` in the release suite; under the
// sanitizers only one thread (where `full` has it) and the largest count, the widest split of the
// same code, which is what ASan and UBSan look at.
inline std::vector<int> thread_counts_to_compare(std::vector<int> full) {
    if (!kUnderSanitizer) return full;
    std::vector<int> kept;
    if (std::ranges::find(full, 1) != full.end()) kept.push_back(1);
    kept.push_back(std::ranges::max(full));
    return kept;
}

}  // namespace penalty::test
