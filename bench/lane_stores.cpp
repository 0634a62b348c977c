// What an AVX2 masked store (vmaskmovps to memory) costs against a plain 8-lane store, the
// reason the kernels store under a mask only where a lane must be left alone
// (docs/reference/simd-dispatch.md "Masked stores on AVX2"): 8 KiB of floats, in L1, stored a
// block of 8 lanes at a time, plainly, under a mask of every lane and under a mask of every
// other lane. Run by hand: build-portable/bin/clothlab_lane_stores --benchmark_min_time=0.2
// (the same code in either build)
#include <benchmark/benchmark.h>
#include <immintrin.h>

#include <cstddef>

namespace {

enum class Store { plain, every_lane_masked, every_other_lane_masked };

constexpr std::size_t kFloats = 2048;
alignas(64) float buffer[kFloats];

__attribute__((target("avx2"))) void store_blocks(Store kind, float value) {
  const __m256 lanes = _mm256_set1_ps(value);
  const __m256i every = _mm256_set1_epi32(-1);
  const __m256i every_other = _mm256_setr_epi32(-1, 0, -1, 0, -1, 0, -1, 0);
  for (std::size_t i = 0; i < kFloats; i += 8) {
    if (kind == Store::plain) {
      _mm256_storeu_ps(buffer + i, lanes);
    } else {
      _mm256_maskstore_ps(buffer + i, kind == Store::every_lane_masked ? every : every_other,
                          lanes);
    }
  }
}

void lane_stores(benchmark::State& state, Store kind) {
  if (!__builtin_cpu_supports("avx2")) {
    state.SkipWithError("this CPU has no AVX2");
    return;
  }
  float value = 0;
  for (auto _ : state) {
    store_blocks(kind, value);
    value += 1;
    benchmark::ClobberMemory();
  }
  state.counters["per_store"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * (kFloats / 8),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK_CAPTURE(lane_stores, plain, Store::plain);
BENCHMARK_CAPTURE(lane_stores, every_lane_masked, Store::every_lane_masked);
BENCHMARK_CAPTURE(lane_stores, every_other_lane_masked, Store::every_other_lane_masked);
BENCHMARK_MAIN();
