// 1/sqrt(s), or 0 where s is 0: the one transcendental of the spring and wind kernels,
// per lane type. A spring of zero length, or a degenerate triangle, has no direction
// and exerts no force.
#pragma once

#include <cfloat>
#include <cmath>
#include <cstddef>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace clothlab::detail {

template <class Real>
inline Real inverse_sqrt_or_zero(Real s) {
  return s > Real(0) ? Real(1) / std::sqrt(s) : Real(0);
}

#if defined(__AVX512F__)
// 16 floats: the 14-bit hardware estimate refined by one Newton step, y (3 - s y^2) / 2,
// to within about 2 ulp. A sqrt and a divide per lane bounded the kernels before (perf:
// a third of a step). Below the smallest normal float the estimate is not reliable, so
// such lanes count as zero length (a spring shorter than 1e-19); NaN stays NaN, so a
// broken state still shows as non-finite accelerations.
inline __m512 inverse_sqrt_or_zero(__m512 s) {
  const __mmask16 normal = _mm512_cmp_ps_mask(s, _mm512_set1_ps(FLT_MIN), _CMP_NLT_UQ);
  const __m512 y = _mm512_maskz_rsqrt14_ps(normal, s);  // 0 in the other lanes stays 0
  const __m512 half_s_y = _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(0.5f), s), y);
  return _mm512_mul_ps(y, _mm512_fnmadd_ps(half_s_y, y, _mm512_set1_ps(1.5f)));
}

// Loads and stores of 16 floats for the AVX-512 kernels: full width, or masked for the last
// columns of a row (masked stores are slower, so only the tail pays for them).
struct FullLanes {
  static __m512 load(const float* p) { return _mm512_loadu_ps(p); }
  static void store(float* p, __m512 value) { _mm512_storeu_ps(p, value); }
};
struct TailLanes {
  __mmask16 lanes;
  __m512 load(const float* p) const { return _mm512_maskz_loadu_ps(lanes, p); }
  void store(float* p, __m512 value) const { _mm512_mask_storeu_ps(p, lanes, value); }
};

// Runs body(c, lanes) over [begin, end) in steps of 16, the last step with TailLanes.
template <class Body>
inline void for_each_16(std::size_t begin, std::size_t end, Body&& body) {
  std::size_t c = begin;
  for (; c + 16 <= end; c += 16) body(c, FullLanes{});
  if (c < end) body(c, TailLanes{__mmask16((1u << (end - c)) - 1)});
}
#endif

}  // namespace clothlab::detail
