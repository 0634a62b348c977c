// XPBD's projection of the springs of one colour that start in one grid row
// (xpbd_constraint.hpp has the derivation of the update):
//   dlambda = (-ks h^2 C - lambda - kd h n.(dx_i - dx_j)) / ((ks h^2 + kd h)(w_i + w_j) + 1)
//   dx_i += w_i dlambda n,  dx_j -= w_j dlambda n,
// the springs at the positions x + dx (x stays at the substep's start).
// Spring c of the row joins particle first + c to first + c + offset, so both ends load
// as contiguous runs. In-row stencils alternate by column: a lane mask keeps the colour's
// columns (the others are computed and dropped; no two kept lanes share a particle, so
// the masked stores of one run never touch a particle another kept lane reads).
#pragma once

#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#if defined(__AVX512F__) && defined(__BMI2__)
#include <immintrin.h>
#endif

namespace clothlab::builtin {

template <class Real>
struct ColorRow {
  const Real* x;
  Real* displacement;
  const Real* inverse_mass;
  // The colour's multipliers, n of them; the springs of a row keep theirs at indices from
  // `first` on, below the next row's. Read unless `fresh`, written when `keep_lambda`.
  Real* lambda;
  std::size_t stride;
  std::size_t first;   // particle of the row's first spring start (column col_begin)
  std::size_t count;   // columns col_begin .. col_end
  std::size_t offset;  // partner = start + offset
  // Columns kept: all, or ((column >> alternation_shift) & 1) == parity for in-row
  // stencils (shift 0: step 1, shift 1: step 2); columns counted from 0 (col_begin is 0
  // for in-row stencils).
  bool alternates;
  uint32_t alternation_shift;
  uint32_t parity;
  Real rest;
  Real stiffness;  // ks h^2
  Real damping;    // kd h
  bool fresh;
  bool keep_lambda;
  // Every particle of the grid but those behind positions [varied_begin, varied_end) (from
  // `first`; a spring's start there, or its partner) has the inverse mass uniform_weight,
  // which is not 0: a run of springs outside needs neither the weights nor their
  // denominator (the AVX-512 kernels use this). uniform_weight 0: no such value.
  Real uniform_weight;
  std::size_t varied_begin, varied_end;
};

// Branch-free but for the stores, so it vectorises: a lane's ends are stored only where
// the lane is kept and pushes, since a dropped in-row lane's partner is a kept lane's start.
template <class Real, bool Fresh, bool KeepLambda>
inline void project_row_portable(const ColorRow<Real>& row) {
  const Real* __restrict x = row.x + row.first;
  Real* __restrict dx = row.displacement + row.first;
  const Real* __restrict w = row.inverse_mass + row.first;
  Real* __restrict lambda = row.lambda == nullptr ? nullptr : row.lambda + row.first;
  const std::size_t o = row.offset, y = row.stride, z = 2 * row.stride, count = row.count;
  const bool alternates = row.alternates;
  const uint32_t shift = row.alternation_shift, parity = row.parity;
  const Real rest = row.rest, stiffness = row.stiffness, damping = row.damping;
  const Real compliance_scale = stiffness + damping;
#pragma omp simd
  for (std::size_t c = 0; c < count; ++c) {
    const bool kept = !alternates | (((c >> shift) & 1u) == parity);  // | : no branch
    const Real m0 = dx[c] - dx[c + o], m1 = dx[c + y] - dx[c + y + o],
               m2 = dx[c + z] - dx[c + z + o];
    const Real d0 = (x[c] - x[c + o]) + m0, d1 = (x[c + y] - x[c + y + o]) + m1,
               d2 = (x[c + z] - x[c + z + o]) + m2;
    Real accumulated = 0;
    if constexpr (!Fresh) accumulated = lambda[c];
    const Real length = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    const bool pushed = kept & (length > 0);  // coincident ends: no direction to push along
    const Real inverse_length = pushed ? 1 / length : Real(0);
    const Real closing = (d0 * m0 + d1 * m1 + d2 * m2) * inverse_length;
    const Real wi = w[c], wj = w[c + o];
    const Real delta = pushed ? (-stiffness * (length - rest) - accumulated - damping * closing) /
                                    (compliance_scale * (wi + wj) + 1)
                              : Real(0);
    if constexpr (KeepLambda) {
      if (kept) lambda[c] = accumulated + delta;
    }
    const Real push_first = wi * delta * inverse_length, push_second = wj * delta * inverse_length;
    if (pushed & (wi != 0)) {
      dx[c] += push_first * d0, dx[c + y] += push_first * d1, dx[c + z] += push_first * d2;
    }
    if (pushed & (wj != 0)) {
      dx[c + o] -= push_second * d0, dx[c + y + o] -= push_second * d1;
      dx[c + z + o] -= push_second * d2;
    }
  }
}

template <class Real>
inline void project_row_portable(const ColorRow<Real>& row) {
  if (row.fresh)
    row.keep_lambda ? project_row_portable<Real, true, true>(row)
                    : project_row_portable<Real, true, false>(row);
  else
    row.keep_lambda ? project_row_portable<Real, false, true>(row)
                    : project_row_portable<Real, false, false>(row);
}

#if defined(__AVX512F__) && defined(__BMI2__)  // _pext_u32 for the in-row tail
// 16 lanes per iteration, without loading what the lanes just stored (a masked store
// blocks store forwarding). 1 / length from the 14-bit estimate and one Newton step, and
// the denominator (>= 1) from its reciprocal estimate and one Newton step: about 2 ulp
// each, where sqrt and divide would bound the kernel. Lengths below the smallest normal
// float count as coincident ends.
struct SpringLanes {
  __m512 d[3], moved[3];
  __m512 inverse_length, delta;
  __mmask16 pushed;
};

// 1 / ((ks h^2 + kd h)(w_i + w_j) + 1).
inline __m512 inverse_denominator(__m512 compliance_scale, __m512 wi, __m512 wj) {
  const __m512 denominator = compliance_scale * (wi + wj) + _mm512_set1_ps(1.0f);
  const __m512 reciprocal = _mm512_maskz_rcp14_ps(__mmask16(0xFFFF), denominator);
  return reciprocal * _mm512_fnmadd_ps(denominator, reciprocal, _mm512_set1_ps(2.0f));
}

// The colour's spring law in registers, read once per row: the kernels' stores go through
// float pointers, which could alias the row's float fields. The uniform weight's
// denominator comes from the same instructions as a lane's, so it has the same bits.
struct LawLanes {
  __m512 rest, stiffness, damping, compliance_scale;
  __m512 uniform_weight, uniform_inverse_denominator;
};

inline LawLanes law_lanes(const ColorRow<float>& row) {
  const __m512 compliance_scale = _mm512_set1_ps(row.stiffness + row.damping);
  const __m512 uniform_weight = _mm512_set1_ps(row.uniform_weight);
  return {_mm512_set1_ps(row.rest),
          _mm512_set1_ps(row.stiffness),
          _mm512_set1_ps(row.damping),
          compliance_scale,
          uniform_weight,
          inverse_denominator(compliance_scale, uniform_weight, uniform_weight)};
}

// Which springs of a row have both ends of the uniform weight: those at positions outside
// [varied_begin, varied_end), if there is one (read once per row: float stores may alias it).
struct UniformRuns {
  bool any;
  std::size_t varied_begin, varied_end;

  explicit UniformRuns(const ColorRow<float>& row)
      : any(row.uniform_weight != 0), varied_begin(row.varied_begin), varied_end(row.varied_end) {}
  bool covers(std::size_t begin, std::size_t end) const {
    return any && (end <= varied_begin || begin >= varied_end);
  }
};

// The update of the springs in `lanes` from both ends' positions and displacements. Always
// inlined: called out of line, its vectors and masks go through the stack.
__attribute__((always_inline)) inline SpringLanes spring_update(
    const LawLanes& law, __mmask16 lanes, const __m512 (&xi)[3], const __m512 (&xj)[3],
    const __m512 (&dxi)[3], const __m512 (&dxj)[3], __m512 inverse_denominator,
    __m512 accumulated) {
  SpringLanes out;
  for (int k = 0; k < 3; ++k) {
    out.moved[k] = dxi[k] - dxj[k];
    out.d[k] = (xi[k] - xj[k]) + out.moved[k];
  }
  const __m512 squared = out.d[0] * out.d[0] + out.d[1] * out.d[1] + out.d[2] * out.d[2];
  out.pushed = _mm512_mask_cmp_ps_mask(lanes, squared, _mm512_set1_ps(FLT_MIN), _CMP_NLT_UQ);
  const __m512 estimate = _mm512_maskz_rsqrt14_ps(out.pushed, squared);
  out.inverse_length = estimate * _mm512_fnmadd_ps(_mm512_set1_ps(0.5f) * squared * estimate,
                                                   estimate, _mm512_set1_ps(1.5f));
  const __m512 length = squared * out.inverse_length;
  const __m512 closing =
      (out.d[0] * out.moved[0] + out.d[1] * out.moved[1] + out.d[2] * out.moved[2]) *
      out.inverse_length;
  const __m512 numerator = _mm512_setzero_ps() - law.stiffness * (length - law.rest) - accumulated -
                           law.damping * closing;
  out.delta = numerator * inverse_denominator;
  return out;
}

inline void store_lambda(float* lambda, __mmask16 lanes, const SpringLanes& u, __m512 accumulated) {
  _mm512_mask_storeu_ps(lambda, lanes,
                        _mm512_mask_add_ps(accumulated, u.pushed, accumulated, u.delta));
}

// Pushes of the springs' two ends; on uniform-weight lanes one product serves both and a
// pushed spring moves both ends.
struct PushLanes {
  __m512 first, second;
  __mmask16 moves_first, moves_second;
};

template <bool Uniform>
inline PushLanes pushes(const SpringLanes& u, __m512 wi, __m512 wj) {
  const __m512 scale = u.delta * u.inverse_length;
  if constexpr (Uniform) {
    const __m512 push = wi * scale;
    return {push, push, u.pushed, u.pushed};
  } else {
    const __m512 zero = _mm512_setzero_ps();
    return {wi * scale, wj * scale, _mm512_mask_cmp_ps_mask(u.pushed, wi, zero, _CMP_NEQ_UQ),
            _mm512_mask_cmp_ps_mask(u.pushed, wj, zero, _CMP_NEQ_UQ)};
  }
}

// A row's arrays from its first spring start, and the spacings, copied out of the ColorRow
// once: the kernel's float stores could alias the row's fields, which the loop would then
// load again at every vector.
struct RowArrays {
  const float* x;
  float* dx;
  const float* w;
  float* lambda;
  std::size_t offset, stride;

  explicit RowArrays(const ColorRow<float>& row)
      : x(row.x + row.first),
        dx(row.displacement + row.first),
        w(row.inverse_mass + row.first),
        lambda(row.lambda == nullptr ? nullptr : row.lambda + row.first),
        offset(row.offset),
        stride(row.stride) {}
};

// Stencils reaching the next rows: every lane a spring, both ends contiguous runs.
template <bool Uniform, bool Fresh, bool KeepLambda>
inline void project_rows_run(const RowArrays& row, const LawLanes& law, std::size_t c,
                             __mmask16 lanes) {
  const float* x = row.x;
  float* dx = row.dx;
  const float* w = row.w;
  float* const lambda = row.lambda;
  const std::size_t o = row.offset, s = row.stride;
  __m512 xi[3], xj[3], dxi[3], dxj[3];
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t i = c + k * s;
    xi[k] = _mm512_maskz_loadu_ps(lanes, x + i);
    xj[k] = _mm512_maskz_loadu_ps(lanes, x + i + o);
    dxi[k] = _mm512_maskz_loadu_ps(lanes, dx + i);
    dxj[k] = _mm512_maskz_loadu_ps(lanes, dx + i + o);
  }
  __m512 wi = law.uniform_weight, wj = law.uniform_weight;
  __m512 inverse = law.uniform_inverse_denominator;
  if constexpr (!Uniform) {
    wi = _mm512_maskz_loadu_ps(lanes, w + c), wj = _mm512_maskz_loadu_ps(lanes, w + c + o);
    inverse = inverse_denominator(law.compliance_scale, wi, wj);
  }
  const __m512 accumulated = Fresh ? _mm512_setzero_ps() : _mm512_maskz_loadu_ps(lanes, lambda + c);
  const SpringLanes u = spring_update(law, lanes, xi, xj, dxi, dxj, inverse, accumulated);
  if constexpr (KeepLambda) store_lambda(lambda + c, lanes, u, accumulated);
  const PushLanes push = pushes<Uniform>(u, wi, wj);
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t i = c + k * s;
    _mm512_mask_storeu_ps(dx + i, lanes,
                          _mm512_mask3_fmadd_ps(push.first, u.d[k], dxi[k], push.moves_first));
    _mm512_mask_storeu_ps(dx + i + o, lanes,
                          _mm512_mask3_fnmadd_ps(push.second, u.d[k], dxj[k], push.moves_second));
  }
}

template <bool Fresh, bool KeepLambda>
inline void project_rows_avx512(const ColorRow<float>& row) {
  const LawLanes law = law_lanes(row);
  const UniformRuns uniform(row);
  const RowArrays arrays(row);
  const std::size_t count = row.count;
  for (std::size_t c = 0; c < count; c += 16) {
    const std::size_t left = count - c;
    const __mmask16 lanes = left >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << left) - 1u);
    if (uniform.covers(c, c + 16))
      project_rows_run<true, Fresh, KeepLambda>(arrays, law, c, lanes);
    else
      project_rows_run<false, Fresh, KeepLambda>(arrays, law, c, lanes);
  }
}

// In-row stencils (step 1 or 2 columns): a run of 32 particles from a start holds 16
// springs of the colour with both ends inside it (the starts are the first `step` of
// every 2 step particles), so two loads and two permutations give the 16 starts and the
// 16 partners, and two permutations merge the moved ends' displacements back for two
// stores.
struct InRowLanes {
  __m512i starts, partners;  // positions (0..31) of the springs' ends
  __m512i low, high;         // positions 0..15 and 16..31 from (starts, partners)
  uint32_t start_bits;
};

inline InRowLanes in_row_lanes(uint32_t step) {
  InRowLanes lanes;
  lanes.start_bits = step == 1 ? 0x55555555u : 0x33333333u;
  alignas(64) int32_t starts[16], partners[16], merged[32];
  int spring = 0;
  for (int p = 0; p < 32; ++p) {
    if ((lanes.start_bits >> p) & 1u) {
      starts[spring] = p;
      partners[spring] = p + static_cast<int>(step);
      merged[p] = spring;                                  // from the moved starts
      merged[p + static_cast<int>(step)] = 16 + spring++;  // from the moved partners
    }
  }
  lanes.starts = _mm512_load_si512(starts);
  lanes.partners = _mm512_load_si512(partners);
  lanes.low = _mm512_load_si512(merged);
  lanes.high = _mm512_load_si512(merged + 16);
  return lanes;
}

template <bool Fresh, bool KeepLambda>
inline void project_in_row_avx512(const ColorRow<float>& row) {
  const uint32_t step = 1u << row.alternation_shift;
  // The colour's first start is column parity * step.
  const std::size_t skip = std::size_t{row.parity} * step;
  if (row.count <= skip) return;
  const std::size_t count = row.count - skip;
  const float* x = row.x + row.first + skip;
  float* dx = row.displacement + row.first + skip;
  const float* w = row.inverse_mass + row.first + skip;
  float* const lambda_row = row.lambda == nullptr ? nullptr : row.lambda + row.first;
  const std::size_t s = row.stride;
  const LawLanes law = law_lanes(row);
  const UniformRuns uniform(row);
  static const InRowLanes lanes_of_step[2] = {in_row_lanes(1), in_row_lanes(2)};
  // Copies in registers: __m512i may alias the floats stored below.
  const InRowLanes& lanes_of_row = lanes_of_step[row.alternation_shift];
  const __m512i to_starts = lanes_of_row.starts, to_partners = lanes_of_row.partners,
                to_low = lanes_of_row.low, to_high = lanes_of_row.high;
  const uint32_t start_bits = lanes_of_row.start_bits;
  const __m512 zero = _mm512_setzero_ps();
  const auto run = [&](std::size_t c, auto uniform) {
    const std::size_t left = count - c;
    const uint32_t springs = left >= 32 ? start_bits : start_bits & ((uint32_t{1} << left) - 1u);
    const uint32_t touched = springs | springs << step;
    const auto low = static_cast<__mmask16>(touched), high = static_cast<__mmask16>(touched >> 16);
    const auto lanes = static_cast<__mmask16>(_pext_u32(springs, start_bits));
    __m512 xi[3], xj[3], dxi[3], dxj[3];
    const auto split = [&](const float* p, __m512& first, __m512& partner) {
      const __m512 a = _mm512_maskz_loadu_ps(low, p), b = _mm512_maskz_loadu_ps(high, p + 16);
      first = _mm512_permutex2var_ps(a, to_starts, b);
      partner = _mm512_permutex2var_ps(a, to_partners, b);
    };
    for (std::size_t k = 0; k < 3; ++k) {
      split(x + c + k * s, xi[k], xj[k]);
      split(dx + c + k * s, dxi[k], dxj[k]);
    }
    __m512 wi = law.uniform_weight, wj = law.uniform_weight;
    __m512 inverse = law.uniform_inverse_denominator;
    if constexpr (!decltype(uniform)::value) {
      split(w + c, wi, wj);
      inverse = inverse_denominator(law.compliance_scale, wi, wj);
    }
    // Multipliers by spring, 16 per run: unique within the colour's row.
    float* const lambda = lambda_row == nullptr ? nullptr : lambda_row + c / 2;
    const __m512 accumulated = Fresh ? zero : _mm512_maskz_loadu_ps(lanes, lambda);
    const SpringLanes u = spring_update(law, lanes, xi, xj, dxi, dxj, inverse, accumulated);
    if constexpr (KeepLambda) store_lambda(lambda, lanes, u, accumulated);
    const PushLanes push = pushes<decltype(uniform)::value>(u, wi, wj);
    const auto merge = [&](float* p, __m512 first, __m512 partner, __m512 d) {
      const __m512 moved_first = _mm512_mask3_fmadd_ps(push.first, d, first, push.moves_first);
      const __m512 moved_partner =
          _mm512_mask3_fnmadd_ps(push.second, d, partner, push.moves_second);
      const __m512 a = _mm512_permutex2var_ps(moved_first, to_low, moved_partner);
      const __m512 b = _mm512_permutex2var_ps(moved_first, to_high, moved_partner);
      if (left >= 32) {
        _mm512_storeu_ps(p, a);
        _mm512_storeu_ps(p + 16, b);
      } else {
        _mm512_mask_storeu_ps(p, low, a);
        _mm512_mask_storeu_ps(p + 16, high, b);
      }
    };
    for (std::size_t k = 0; k < 3; ++k) {
      merge(dx + c + k * s, dxi[k], dxj[k], u.d[k]);
    }
  };
  for (std::size_t c = 0; c < count; c += 32) {
    if (uniform.covers(skip + c, skip + c + 32))
      run(c, std::true_type{});
    else
      run(c, std::false_type{});
  }
}

template <bool Fresh, bool KeepLambda>
inline void project_row_avx512(const ColorRow<float>& row) {
  if (row.alternates)
    project_in_row_avx512<Fresh, KeepLambda>(row);
  else
    project_rows_avx512<Fresh, KeepLambda>(row);
}

// Fresh (lambda 0) and KeepLambda at compile time: a substep of one iteration neither reads
// nor stores a multiplier, and "- lambda" folds away (x - 0 is x, signed zeros included).
inline void project_row_avx512(const ColorRow<float>& row) {
  if (row.fresh)
    row.keep_lambda ? project_row_avx512<true, true>(row) : project_row_avx512<true, false>(row);
  else
    row.keep_lambda ? project_row_avx512<false, true>(row) : project_row_avx512<false, false>(row);
}
#endif

template <class Real>
inline void project_row(const ColorRow<Real>& row) {
#if defined(__AVX512F__) && defined(__BMI2__)
  if constexpr (std::is_same_v<Real, float>) {
    project_row_avx512(row);
    return;
  }
#endif
  project_row_portable(row);
}

}  // namespace clothlab::builtin
