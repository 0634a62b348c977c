// The floating-point peak of one thread: independent chains of 8-lane fused multiply-adds (AVX2
// with FMA), the peak that docs/results.md "The bound" divides the force kernel's arithmetic by.
// On two threads it also tells whether each thread has a core's FMA pipes to itself: each
// thread's rate is its flops over its own wall time, and `on_cpu` its CPU time over that wall
// time, so a thread that shares its core's time with another program reads on_cpu below 1.
// Run by hand: build/bin/clothlab_fma_peak --benchmark_min_time=0.2
#include <benchmark/benchmark.h>
#include <immintrin.h>

#include <ctime>

namespace {

// Enough independent chains to keep two FMA pipes busy through each FMA's latency.
constexpr int kChains = 12;
constexpr long kRounds = 1L << 20;
constexpr double kFlopsPerFma = 2 * 8;

double seconds(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

__attribute__((target("avx2,fma"))) float fma_chains(long rounds) {
  __m256 chain[kChains];
  for (int k = 0; k < kChains; ++k) chain[k] = _mm256_set1_ps(1.0f + 1e-3f * static_cast<float>(k));
  const __m256 scale = _mm256_set1_ps(0.9999999f), offset = _mm256_set1_ps(1e-7f);
  for (long i = 0; i < rounds; ++i)
    for (int k = 0; k < kChains; ++k) chain[k] = _mm256_fmadd_ps(chain[k], scale, offset);
  __m256 sum = chain[0];
  for (int k = 1; k < kChains; ++k) sum = _mm256_add_ps(sum, chain[k]);
  return _mm256_cvtss_f32(sum);
}

void fma_peak(benchmark::State& state) {
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) {
    state.SkipWithError("this CPU has no AVX2 with FMA");
    return;
  }
  double wall = 0, cpu = 0;
  for (auto _ : state) {
    const double wall_start = seconds(CLOCK_MONOTONIC),
                 cpu_start = seconds(CLOCK_THREAD_CPUTIME_ID);
    benchmark::DoNotOptimize(fma_chains(kRounds));
    wall += seconds(CLOCK_MONOTONIC) - wall_start;
    cpu += seconds(CLOCK_THREAD_CPUTIME_ID) - cpu_start;
  }
  const double flops = static_cast<double>(state.iterations()) * kRounds * kChains * kFlopsPerFma;
  state.counters["gflops_per_thread"] =
      benchmark::Counter(flops / wall * 1e-9, benchmark::Counter::kAvgThreads);
  state.counters["on_cpu"] = benchmark::Counter(cpu / wall, benchmark::Counter::kAvgThreads);
}

}  // namespace

BENCHMARK(fma_peak)->Threads(1)->Threads(2)->UseRealTime();
BENCHMARK_MAIN();
