// The machine's own rates, the yardsticks of docs/performance.md's "How far from the machine's
// limits" (issue 17: where a phase cannot reach its target, how close it is to its limit):
// - BM_Machine_VectorMulAdd: 4-lane double multiplies and adds, separate (no fused multiply-add:
//   the project builds with -ffp-contract=off, as SOFA's sums need), 6 independent multiply
//   chains beside 6 independent add chains, so that neither latency nor one pipe bounds it:
//   the peak rate of the instructions the FEM and spring kernels use (flops/s).
// - BM_Machine_VectorMulAdd8: the same in eight lanes (AVX-512F; skipped on CPUs without it),
//   the instructions of the FEM product's avx512 path.
// - BM_Machine_Triad/bytes: a[i] = b[i] + s·c[i] over three arrays of `bytes` in all, from the
//   first level cache to memory: the bandwidth (bytes/s read and written, write-allocate not
//   counted).

#include <benchmark/benchmark.h>

#include <cstddef>
#include <string>
#include <vector>

namespace {

#if defined(__x86_64__)
constexpr int kRepeat = 1024;  // multiply-add rounds per benchmark iteration

typedef double Lanes4 __attribute__((vector_size(32)));
typedef double Lanes8 __attribute__((vector_size(64)));

// 6 multiply chains (x ← x·m) and 6 add chains (y ← y + a) of W-lane vectors (GCC's vector
// extensions: each operator one vector instruction), each 3–4 cycles of latency: two multiplies
// and two adds can start every cycle. Returns the sum so the chains are live. The factors come
// through memory the compiler cannot see (`seeds`), so nothing is folded. Inlined into a caller
// compiled for its width's instructions.
template <class V, int W>
[[gnu::always_inline]] inline double mul_add_chains(const double* seeds, int repeat) {
    V m, a, one;
    for (int l = 0; l < W; ++l) {
        m[l] = seeds[0];
        a[l] = seeds[1];
        one[l] = seeds[2];
    }
    V x[6], y[6];
    x[0] = one;
    y[0] = m;
    for (int c = 1; c < 6; ++c) {
        x[c] = x[c - 1] + a;
        y[c] = y[c - 1] + a;
    }
    for (int r = 0; r < repeat; ++r) {
#pragma GCC unroll 6
        for (int c = 0; c < 6; ++c) {
            x[c] = x[c] * m;
            y[c] = y[c] + a;
        }
    }
    V s = x[0];
    for (int c = 1; c < 6; ++c) s = s + x[c];
    for (int c = 0; c < 6; ++c) s = s + y[c];
    double sum = 0.0;
    for (int l = 0; l < W; ++l) sum += s[l];
    return sum;
}

[[gnu::target("avx"), gnu::noinline]] double vector_mul_add4(const double* seeds, int repeat) {
    return mul_add_chains<Lanes4, 4>(seeds, repeat);
}
[[gnu::target("avx512f"), gnu::noinline]] double vector_mul_add8(const double* seeds, int repeat) {
    return mul_add_chains<Lanes8, 8>(seeds, repeat);
}

template <int W>
void mul_add_benchmark(benchmark::State& state, bool supported, const char* feature,
                       double (*chains)(const double*, int)) {
    if (!supported) {
        state.SkipWithError((std::string("no ") + feature + " on this CPU").c_str());
        return;
    }
    double seeds[3] = {0.9999999, 1e-9, 1.0};
    benchmark::DoNotOptimize(seeds);
    benchmark::ClobberMemory();
    for (auto _ : state) benchmark::DoNotOptimize(chains(seeds, kRepeat));
    // 12 instructions of W lanes per round
    state.counters["flops"] =
        benchmark::Counter(double(state.iterations()) * kRepeat * 12 * W, benchmark::Counter::kIsRate);
}

void BM_Machine_VectorMulAdd(benchmark::State& state) {
    mul_add_benchmark<4>(state, __builtin_cpu_supports("avx"), "AVX", vector_mul_add4);
}
void BM_Machine_VectorMulAdd8(benchmark::State& state) {
    mul_add_benchmark<8>(state, __builtin_cpu_supports("avx512f"), "AVX-512F", vector_mul_add8);
}
BENCHMARK(BM_Machine_VectorMulAdd);
BENCHMARK(BM_Machine_VectorMulAdd8);
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
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                            static_cast<std::int64_t>(3 * n * sizeof(double)));
}
// 24 KiB (first level), 192 KiB and 384 KiB (second), 6 MiB (third), 192 MiB (memory)
BENCHMARK(BM_Machine_Triad)->Arg(24 << 10)->Arg(192 << 10)->Arg(384 << 10)->Arg(6 << 20)->Arg(192 << 20);

}  // namespace
