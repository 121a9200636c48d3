// The machine's own rates, the yardsticks of docs/performance.md's "How far from the machine's
// limits" (issue 17: where a phase cannot reach its target, how close it is to its limit):
// - BM_Machine_VectorMulAdd: 4-lane double multiplies and adds, separate (no fused multiply-add:
//   the project builds with -ffp-contract=off, as SOFA's sums need), 6 independent multiply
//   chains beside 6 independent add chains, so that neither latency nor one pipe bounds it:
//   the peak rate of the instructions the FEM and spring kernels use (flops/s).
// - BM_Machine_Triad/bytes: a[i] = b[i] + s·c[i] over three arrays of `bytes` in all, from the
//   first level cache to memory: the bandwidth (bytes/s read and written, write-allocate not
//   counted).

#include <benchmark/benchmark.h>

#include <cstddef>
#include <vector>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace {

#if defined(__x86_64__)
constexpr int kRepeat = 1024;  // multiply-add rounds per benchmark iteration

// 6 multiply chains (x ← x·m) and 6 add chains (y ← y + a), each 3–4 cycles of latency: two
// multiplies and two adds can start every cycle. Returns the sum so the chains are live.
// The factors come through memory the compiler cannot see (`seeds`), so nothing is folded.
[[gnu::target("avx"), gnu::noinline]] double vector_mul_add(const double* seeds, int repeat) {
    const __m256d m = _mm256_set1_pd(seeds[0]);
    const __m256d a = _mm256_set1_pd(seeds[1]);
    const __m256d one = _mm256_set1_pd(seeds[2]);
    __m256d x0 = one, x1 = _mm256_add_pd(one, a), x2 = _mm256_add_pd(x1, a), x3 = _mm256_add_pd(x2, a),
            x4 = _mm256_add_pd(x3, a), x5 = _mm256_add_pd(x4, a);
    __m256d y0 = m, y1 = _mm256_add_pd(m, a), y2 = _mm256_add_pd(y1, a), y3 = _mm256_add_pd(y2, a),
            y4 = _mm256_add_pd(y3, a), y5 = _mm256_add_pd(y4, a);
    for (int r = 0; r < repeat; ++r) {
        x0 = _mm256_mul_pd(x0, m);
        y0 = _mm256_add_pd(y0, a);
        x1 = _mm256_mul_pd(x1, m);
        y1 = _mm256_add_pd(y1, a);
        x2 = _mm256_mul_pd(x2, m);
        y2 = _mm256_add_pd(y2, a);
        x3 = _mm256_mul_pd(x3, m);
        y3 = _mm256_add_pd(y3, a);
        x4 = _mm256_mul_pd(x4, m);
        y4 = _mm256_add_pd(y4, a);
        x5 = _mm256_mul_pd(x5, m);
        y5 = _mm256_add_pd(y5, a);
    }
    const __m256d s = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(x0, x1), _mm256_add_pd(x2, x3)),
                                    _mm256_add_pd(_mm256_add_pd(x4, x5), _mm256_add_pd(_mm256_add_pd(y0, y1),
                                                                                      _mm256_add_pd(_mm256_add_pd(y2, y3),
                                                                                                    _mm256_add_pd(y4, y5)))));
    alignas(32) double lanes[4];
    _mm256_store_pd(lanes, s);
    return lanes[0] + lanes[1] + lanes[2] + lanes[3];
}

void BM_Machine_VectorMulAdd(benchmark::State& state) {
    if (!__builtin_cpu_supports("avx")) {
        state.SkipWithError("no AVX on this CPU");
        return;
    }
    double seeds[3] = {0.9999999, 1e-9, 1.0};
    benchmark::DoNotOptimize(seeds);
    benchmark::ClobberMemory();
    for (auto _ : state) benchmark::DoNotOptimize(vector_mul_add(seeds, kRepeat));
    // 12 instructions of 4 lanes per round
    state.counters["flops"] = benchmark::Counter(double(state.iterations()) * kRepeat * 12 * 4,
                                                 benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Machine_VectorMulAdd);
#endif

void BM_Machine_Triad(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0)) / (3 * sizeof(double));
    std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
    const double s = 0.5;
    for (auto _ : state) {
        double* pa = a.data();
        const double* pb = b.data();
        const double* pc = c.data();
        for (std::size_t i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
        benchmark::DoNotOptimize(a.data());
        benchmark::ClobberMemory();
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(3 * n * sizeof(double)));
}
// 24 KiB (first level), 192 KiB and 384 KiB (second), 6 MiB (third), 192 MiB (memory)
BENCHMARK(BM_Machine_Triad)->Arg(24 << 10)->Arg(192 << 10)->Arg(384 << 10)->Arg(6 << 20)->Arg(192 << 20);

}  // namespace
