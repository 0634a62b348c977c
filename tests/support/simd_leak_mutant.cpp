// A function compiled for AVX2 outside any SIMD target's namespace: what
// tools/check_simd_isolation.py must find (tests/plugins/CMakeLists.txt).
#include <cstddef>

void leaked_avx2_loop(float* values, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) values[i] = values[i] * 3.0f + 1.0f;
}
