#pragma once
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

}  // namespace penalty::test
