// The SIMD lanes of the engine's hand-written float kernels: 16 floats on AVX-512, 8 on AVX2
// with FMA (most laptops, AMD Zen 2 and 3). A kernel is written once against `Floats` and the
// few operations below (arithmetic through GCC's vector operators). A translation unit compiled
// for one of a module's SIMD targets (simd_target_begin.hpp) gets that target's lanes; any
// other gets those of the build's flags. Without either instruction set, CLOTHLAB_FLOAT_LANES
// stays undefined and the kernels' portable loops run.
#pragma once

#include <cfloat>
#include <cstddef>
#include <cstdint>

#include "simd_namespace.hpp"

#if defined(CLOTHLAB_SIMD_AVX512) || (!defined(CLOTHLAB_SIMD_AVX2) && defined(__AVX512F__))
#define CLOTHLAB_LANES_AVX512 1
#elif defined(CLOTHLAB_SIMD_AVX2) || (defined(__AVX2__) && defined(__FMA__))
#define CLOTHLAB_LANES_AVX2 1
#endif

#if defined(CLOTHLAB_LANES_AVX512) || defined(CLOTHLAB_LANES_AVX2)
#include <immintrin.h>
#define CLOTHLAB_FLOAT_LANES 1
#endif

#if defined(CLOTHLAB_FLOAT_LANES)

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

#if defined(CLOTHLAB_LANES_AVX512)

using Floats = __m512;
using LaneMask = __mmask16;  // a bit per lane
using Doubles = __m512d;     // half as many doubles as Floats lanes
inline constexpr std::size_t kLanes = 16;

inline Floats broadcast(float value) { return _mm512_set1_ps(value); }
// A constant of a kernel's whole loop kept in memory, where the loop has no register for it:
// AVX-512's instructions broadcast a float as they read it, so it stays a float.
using LoopConstant = float;
inline LoopConstant loop_constant(float value) { return value; }
inline Floats lanes_of(LoopConstant value) { return broadcast(value); }
inline Floats zero_floats() { return _mm512_setzero_ps(); }
inline Floats load_floats(const float* p) { return _mm512_loadu_ps(p); }
inline void store_floats(float* p, Floats value) { _mm512_storeu_ps(p, value); }
// Masked: lanes outside the mask read 0 and are not written (nor touched in memory).
inline Floats load_floats(LaneMask lanes, const float* p) {
  return _mm512_maskz_loadu_ps(lanes, p);
}
inline void store_floats(LaneMask lanes, float* p, Floats value) {
  _mm512_mask_storeu_ps(p, lanes, value);
}
inline Floats keep(LaneMask lanes, Floats value) { return _mm512_maskz_mov_ps(lanes, value); }
// The lanes of the mask from consecutive floats at p, in order (one float read per lane); 0
// elsewhere.
#define CLOTHLAB_EXPAND_LOADS 1
inline Floats expand_floats(LaneMask lanes, const float* p) {
  return _mm512_maskz_expandloadu_ps(lanes, p);
}
inline LaneMask all_lanes() { return LaneMask(0xffff); }
inline LaneMask both(LaneMask a, LaneMask b) { return LaneMask(a & b); }
inline bool no_lane(LaneMask lanes) { return lanes == 0; }
// Lanes [low, high) of a block, 0 <= low <= high <= kLanes.
inline LaneMask lanes_from_to(std::size_t low, std::size_t high) {
  return LaneMask(((1u << high) - 1) & ~((1u << low) - 1));
}
// The lanes l whose bit l of `bits` is set.
inline LaneMask lanes_of_bits(uint32_t bits) { return LaneMask(bits); }
// The same from a compact record's mask in memory (read straight into a mask register).
inline LaneMask lanes_of_bits(const uint16_t* bits) { return LaneMask(*bits); }
inline LaneMask greater(Floats a, Floats b) { return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ); }
inline LaneMask not_less(Floats a, Floats b) { return _mm512_cmp_ps_mask(a, b, _CMP_NLT_UQ); }
inline LaneMask unordered(Floats a, Floats b) { return _mm512_cmp_ps_mask(a, b, _CMP_UNORD_Q); }
// a where the mask is set, else b. A blend rather than _mm512_max_ps in lane_max: that
// one's header trips GCC 12's -Wmaybe-uninitialized.
inline Floats select(LaneMask lanes, Floats a, Floats b) {
  return _mm512_mask_blend_ps(lanes, b, a);
}
inline Floats fused_multiply_add(Floats a, Floats b, Floats c) { return _mm512_fmadd_ps(a, b, c); }
inline Floats fused_negated_multiply_add(Floats a, Floats b, Floats c) {  // c - a b
  return _mm512_fnmadd_ps(a, b, c);
}
// 1/sqrt(s) to within about 12 (AVX2) or 14 (AVX-512) bits, 0 outside the mask.
inline Floats inverse_sqrt_estimate(LaneMask lanes, Floats s) {
  return _mm512_maskz_rsqrt14_ps(lanes, s);
}
inline Floats inverse_sqrt_estimate(Floats s) { return inverse_sqrt_estimate(all_lanes(), s); }
// The smaller of a and b by lane, b where either is NaN (maskz form: see add_widened).
inline Floats lane_min(Floats a, Floats b) { return _mm512_maskz_min_ps(0xffff, a, b); }
// Lanes moved Shift places up, the lowest Shift from the top of `before` (valignd; the maskz
// form, as the plain one's header trips GCC 12's -Wuninitialized).
template <int Shift>
inline Floats shift_up(Floats value, Floats before) {
  return _mm512_castsi512_ps(_mm512_maskz_alignr_epi32(0xffff, _mm512_castps_si512(value),
                                                       _mm512_castps_si512(before), 16 - Shift));
}
// The lanes' values widened to double, the low half into sums[0] and the high into sums[1].
// maskz forms: the plain ones' headers (and _mm512_castps512_ps256's) trip GCC 12's
// -Wmaybe-uninitialized.
inline void add_widened(Floats value, Doubles (&sums)[2]) {
  const __m512d halves = _mm512_castps_pd(value);
  sums[0] = sums[0] + _mm512_maskz_cvtps_pd(
                          0xff, _mm256_castpd_ps(_mm512_maskz_extractf64x4_pd(0xf, halves, 0)));
  sums[1] = sums[1] + _mm512_maskz_cvtps_pd(
                          0xff, _mm256_castpd_ps(_mm512_maskz_extractf64x4_pd(0xf, halves, 1)));
}
inline Doubles zero_doubles() { return _mm512_setzero_pd(); }
// The sum of both sets' lanes in a fixed order (_mm512_reduce_add_pd trips GCC 12).
inline double lane_sum(const Doubles (&sums)[2]) {
  alignas(64) double lanes[8];
  _mm512_store_pd(lanes, sums[0] + sums[1]);
  return ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) +
         ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]));
}

// 1/s to within about 14 (AVX-512) or 12 (AVX2) bits.
inline Floats reciprocal_estimate(Floats s) {
  return _mm512_maskz_rcp14_ps(__mmask16(0xffff), s);  // maskz: see add_widened
}
inline LaneMask not_equal(Floats a, Floats b) { return _mm512_cmp_ps_mask(a, b, _CMP_NEQ_UQ); }
// c + a b in the lanes of the mask, c in the others.
inline Floats masked_fused_multiply_add(LaneMask lanes, Floats a, Floats b, Floats c) {
  return _mm512_mask3_fmadd_ps(a, b, c, lanes);
}
// c - a b in the lanes of the mask, c in the others.
inline Floats masked_fused_negated_multiply_add(LaneMask lanes, Floats a, Floats b, Floats c) {
  return _mm512_mask3_fnmadd_ps(a, b, c, lanes);
}
// a + b in the lanes of the mask, a in the others.
inline Floats masked_add(LaneMask lanes, Floats a, Floats b) {
  return _mm512_mask_add_ps(a, lanes, a, b);
}
// The two ends of the pairs in a run of 2 kLanes floats, a then b, whose first ends are the
// first Step of every 2 Step floats and whose second ends lie Step further. Shuffles within
// each 128-bit quarter only: the pairs come out in a fixed order of the run's quarters
// (xpbd_row_kernel.hpp keeps track), not in the run's order; interleave puts them back.
template <int Step>
inline void deinterleave(Floats a, Floats b, Floats& first, Floats& second) {
  static_assert(Step == 1 || Step == 2);
  // maskz forms: see add_widened.
  first = _mm512_maskz_shuffle_ps(0xffff, a, b,
                                  Step == 1 ? _MM_SHUFFLE(2, 0, 2, 0) : _MM_SHUFFLE(1, 0, 1, 0));
  second = _mm512_maskz_shuffle_ps(0xffff, a, b,
                                   Step == 1 ? _MM_SHUFFLE(3, 1, 3, 1) : _MM_SHUFFLE(3, 2, 3, 2));
}
template <int Step>
inline void interleave(Floats first, Floats second, Floats& a, Floats& b) {
  static_assert(Step == 1 || Step == 2);
  if constexpr (Step == 1) {
    a = _mm512_maskz_unpacklo_ps(0xffff, first, second);
    b = _mm512_maskz_unpackhi_ps(0xffff, first, second);
  } else {
    a = _mm512_maskz_shuffle_ps(0xffff, first, second, _MM_SHUFFLE(1, 0, 1, 0));
    b = _mm512_maskz_shuffle_ps(0xffff, first, second, _MM_SHUFFLE(3, 2, 3, 2));
  }
}

// kLanes 32-bit indices, for gathers from arrays a kernel cannot read in order.
using Indices = __m512i;
inline Indices load_indices(const uint32_t* p) { return _mm512_loadu_si512(p); }
// base[indices[l]] in lane l (maskz form: see add_widened).
inline Floats gather_floats(const float* base, Indices indices) {
  return _mm512_mask_i32gather_ps(_mm512_setzero_ps(), __mmask16(0xffff), indices, base, 4);
}
// The indices with their top bit cleared, and value negated in the lanes whose index has it
// set: one array of indices that also says which entries count with a minus sign.
inline Indices without_top_bit(Indices indices) {
  return _mm512_and_si512(indices, _mm512_set1_epi32(0x7fffffff));
}
inline Floats negated_where_top_bit(Floats value, Indices indices) {
  const __m512i sign = _mm512_and_si512(indices, _mm512_set1_epi32(int32_t(0x80000000u)));
  return _mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(value), sign));
}
// value negated (its sign bit flipped) in the lanes set.
inline Floats negated_where(LaneMask lanes, Floats value) {
  const __m512i bits = _mm512_castps_si512(value);
  return _mm512_castsi512_ps(
      _mm512_mask_xor_epi32(bits, lanes, bits, _mm512_set1_epi32(int32_t(0x80000000u))));
}

#else  // AVX2 and FMA

using Floats = __m256;
// All bits set in a lane that is in. A type of its own, so that a mask and a value passed in
// each other's place do not compile (on AVX-512 the mask is an integer already).
struct LaneMask {
  __m256 bits;
};
using Doubles = __m256d;
inline constexpr std::size_t kLanes = 8;

inline Floats broadcast(float value) { return _mm256_set1_ps(value); }
// A constant of a kernel's whole loop kept in memory, where the loop has no register for it:
// AVX2's instructions cannot broadcast an operand, so it is kept broadcast (a float would cost a
// broadcast per use).
using LoopConstant = Floats;
inline LoopConstant loop_constant(float value) { return broadcast(value); }
inline Floats lanes_of(LoopConstant value) { return value; }
inline Floats zero_floats() { return _mm256_setzero_ps(); }
inline Floats load_floats(const float* p) { return _mm256_loadu_ps(p); }
inline void store_floats(float* p, Floats value) { _mm256_storeu_ps(p, value); }
inline Floats load_floats(LaneMask lanes, const float* p) {
  return _mm256_maskload_ps(p, _mm256_castps_si256(lanes.bits));
}
// A masked store costs several plain ones on some AVX2 CPUs (it is microcoded there): a mask
// of every lane stores plainly, which writes the same memory.
inline void store_floats(LaneMask lanes, float* p, Floats value) {
  if (_mm256_movemask_ps(lanes.bits) == 0xff) {
    _mm256_storeu_ps(p, value);
  } else {
    _mm256_maskstore_ps(p, _mm256_castps_si256(lanes.bits), value);
  }
}
inline Floats keep(LaneMask lanes, Floats value) { return _mm256_and_ps(lanes.bits, value); }
inline LaneMask all_lanes() { return {_mm256_castsi256_ps(_mm256_set1_epi32(-1))}; }
inline LaneMask both(LaneMask a, LaneMask b) { return {_mm256_and_ps(a.bits, b.bits)}; }
inline bool no_lane(LaneMask lanes) { return _mm256_movemask_ps(lanes.bits) == 0; }
inline LaneMask lanes_from_to(std::size_t low, std::size_t high) {
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i below_high = _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>(high)), lane);
  const __m256i below_low = _mm256_cmpgt_epi32(_mm256_set1_epi32(static_cast<int>(low)), lane);
  return {_mm256_castsi256_ps(_mm256_andnot_si256(below_low, below_high))};
}
// The lanes l whose bit l is set in `broadcast`'s every lane (its low byte is enough).
inline LaneMask lanes_of_broadcast_bits(__m256i broadcast) {
  const __m256i lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  const __m256i set = _mm256_and_si256(broadcast, lane_bit);
  return {_mm256_castsi256_ps(_mm256_cmpeq_epi32(set, lane_bit))};
}
inline LaneMask lanes_of_bits(uint32_t bits) {
  return lanes_of_broadcast_bits(_mm256_set1_epi32(static_cast<int>(bits)));
}
// The same from a compact record's byte in memory: broadcast as it is read, not widened first.
inline LaneMask lanes_of_bits(const uint8_t* bits) {
  return lanes_of_broadcast_bits(_mm256_set1_epi8(static_cast<char>(*bits)));
}
inline LaneMask greater(Floats a, Floats b) { return {_mm256_cmp_ps(a, b, _CMP_GT_OQ)}; }
inline LaneMask not_less(Floats a, Floats b) { return {_mm256_cmp_ps(a, b, _CMP_NLT_UQ)}; }
inline LaneMask unordered(Floats a, Floats b) { return {_mm256_cmp_ps(a, b, _CMP_UNORD_Q)}; }
inline Floats select(LaneMask lanes, Floats a, Floats b) {
  return _mm256_blendv_ps(b, a, lanes.bits);
}
inline Floats fused_multiply_add(Floats a, Floats b, Floats c) { return _mm256_fmadd_ps(a, b, c); }
inline Floats fused_negated_multiply_add(Floats a, Floats b, Floats c) {
  return _mm256_fnmadd_ps(a, b, c);
}
inline Floats inverse_sqrt_estimate(LaneMask lanes, Floats s) {
  return _mm256_and_ps(lanes.bits, _mm256_rsqrt_ps(s));
}
inline Floats inverse_sqrt_estimate(Floats s) { return _mm256_rsqrt_ps(s); }
inline Floats lane_min(Floats a, Floats b) { return _mm256_min_ps(a, b); }
template <int Shift>
inline Floats shift_up(Floats value, Floats before) {
  // Both rotated Shift lanes up; the lowest Shift lanes then come from `before`'s top.
  const __m256i rotate =
      _mm256_setr_epi32((8 - Shift) % 8, (9 - Shift) % 8, (10 - Shift) % 8, (11 - Shift) % 8,
                        (12 - Shift) % 8, (13 - Shift) % 8, (14 - Shift) % 8, (15 - Shift) % 8);
  return _mm256_blend_ps(_mm256_permutevar8x32_ps(value, rotate),
                         _mm256_permutevar8x32_ps(before, rotate), (1 << Shift) - 1);
}
inline void add_widened(Floats value, Doubles (&sums)[2]) {
  sums[0] = sums[0] + _mm256_cvtps_pd(_mm256_castps256_ps128(value));
  sums[1] = sums[1] + _mm256_cvtps_pd(_mm256_extractf128_ps(value, 1));
}
inline Doubles zero_doubles() { return _mm256_setzero_pd(); }
inline double lane_sum(const Doubles (&sums)[2]) {
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, sums[0] + sums[1]);
  return (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
}

inline Floats reciprocal_estimate(Floats s) { return _mm256_rcp_ps(s); }
inline LaneMask not_equal(Floats a, Floats b) { return {_mm256_cmp_ps(a, b, _CMP_NEQ_UQ)}; }
inline Floats masked_fused_multiply_add(LaneMask lanes, Floats a, Floats b, Floats c) {
  return _mm256_blendv_ps(c, _mm256_fmadd_ps(a, b, c), lanes.bits);
}
inline Floats masked_fused_negated_multiply_add(LaneMask lanes, Floats a, Floats b, Floats c) {
  return _mm256_blendv_ps(c, _mm256_fnmadd_ps(a, b, c), lanes.bits);
}
inline Floats masked_add(LaneMask lanes, Floats a, Floats b) {
  return _mm256_blendv_ps(a, a + b, lanes.bits);
}
template <int Step>
inline void deinterleave(Floats a, Floats b, Floats& first, Floats& second) {
  static_assert(Step == 1 || Step == 2);
  first = _mm256_shuffle_ps(a, b, Step == 1 ? _MM_SHUFFLE(2, 0, 2, 0) : _MM_SHUFFLE(1, 0, 1, 0));
  second = _mm256_shuffle_ps(a, b, Step == 1 ? _MM_SHUFFLE(3, 1, 3, 1) : _MM_SHUFFLE(3, 2, 3, 2));
}
template <int Step>
inline void interleave(Floats first, Floats second, Floats& a, Floats& b) {
  static_assert(Step == 1 || Step == 2);
  if constexpr (Step == 1) {
    a = _mm256_unpacklo_ps(first, second), b = _mm256_unpackhi_ps(first, second);
  } else {
    a = _mm256_shuffle_ps(first, second, _MM_SHUFFLE(1, 0, 1, 0));
    b = _mm256_shuffle_ps(first, second, _MM_SHUFFLE(3, 2, 3, 2));
  }
}

using Indices = __m256i;
inline Indices load_indices(const uint32_t* p) {
  return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
}
inline Floats gather_floats(const float* base, Indices indices) {
  return _mm256_i32gather_ps(base, indices, 4);
}
inline Indices without_top_bit(Indices indices) {
  return _mm256_and_si256(indices, _mm256_set1_epi32(0x7fffffff));
}
inline Floats negated_where_top_bit(Floats value, Indices indices) {
  const __m256i sign = _mm256_and_si256(indices, _mm256_set1_epi32(int32_t(0x80000000u)));
  return _mm256_castsi256_ps(_mm256_xor_si256(_mm256_castps_si256(value), sign));
}
inline Floats negated_where(LaneMask lanes, Floats value) {
  return _mm256_xor_ps(value, _mm256_and_ps(lanes.bits, _mm256_set1_ps(-0.0f)));
}

#endif

// Loads and stores of a block of lanes: full width, or masked for the last columns of a row
// (masked stores are slower, so only the tail pays for them).
struct FullLanes {
  static LaneMask mask() { return all_lanes(); }
  static Floats load(const float* p) { return load_floats(p); }
  static void store(float* p, Floats value) { store_floats(p, value); }
};
struct TailLanes {
  LaneMask lanes;
  LaneMask mask() const { return lanes; }
  Floats load(const float* p) const { return load_floats(lanes, p); }
  void store(float* p, Floats value) const { store_floats(lanes, p, value); }
};

// Runs body(c, lanes) over [begin, end) in blocks of kLanes, the last one with TailLanes.
template <class Body>
inline void for_each_lane_block(std::size_t begin, std::size_t end, Body&& body) {
  std::size_t c = begin;
  for (; c + kLanes <= end; c += kLanes) body(c, FullLanes{});
  if (c < end) body(c, TailLanes{lanes_from_to(0, end - c)});
}

// Runs body(c, FullLanes{}) over [begin, end) in whole blocks, the last one overlapping the one
// before rather than masked (a masked store is microcoded on some AVX2 CPUs); a range shorter
// than a block runs masked. Only for a body whose outputs alias none of its inputs and whose
// lanes are independent (no shift across lanes, nothing carried from block to block): the
// columns done twice then get the same bits. A row updated in place needs its last block
// computed first (xpbd_grid_sweep.hpp's for_each_run_block).
template <class Body>
inline void for_each_whole_lane_block(std::size_t begin, std::size_t end, Body&& body) {
  if (end - begin < kLanes) {
    for_each_lane_block(begin, end, body);
    return;
  }
  std::size_t c = begin;
  for (; c + kLanes <= end; c += kLanes) body(c, FullLanes{});
  if (c < end) body(end - kLanes, FullLanes{});
}

// Lanes of the block at column c whose column lies in [begin, end).
inline LaneMask columns_in(std::size_t c, std::size_t begin, std::size_t end) {
  const std::size_t low = begin > c ? (begin - c < kLanes ? begin - c : kLanes) : 0;
  const std::size_t high = end > c ? (end - c < kLanes ? end - c : kLanes) : 0;
  return lanes_from_to(low, high);  // empty where high <= low
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE

#endif
