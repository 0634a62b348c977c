// The definite Jacobian's product (jacobian_row_kernel.hpp, JacobianForm::kDefinite) for all six
// Provot stencils starting in one grid row r, in one sweep over its columns, 16 floats at a time
// on AVX-512, from each spring's inverse length, which the state fixes and
// definite_inverse_length_row stores once per linearisation: a CG solve takes hundreds of
// products at one state. One stored float per spring rather than its two coefficients: the
// sweep is bound by the bytes it streams, and the coefficients follow from 1/l in a few
// multiplies (definite_row_block). The row's own positions and directions are loaded once and the
// products on its own particles summed in registers over the six springs, as the force
// pipeline's interior row kernel does. Partner ends in the same column of rows r + 1 and r + 2 go
// straight into the product; those one or two columns over go to scratch rows (their
// read-modify-writes would overlap each other's and stall store forwarding), added by
// definite_row_shifted_ends.
//
// Each out row's first contribution is a store, not an add (no clearing pass): row r + 2's is
// always the (2, 0) stencil of row r, rows 0 and 1 get theirs from row 0. Rows r, r + 1 and
// r + 2 are written only where `write` says so (the thread owns them); the sums run in the same
// order whatever the thread's block, so the bits do not depend on the thread count.
#pragma once

#include <cstddef>

#include "interior_row_kernel.hpp"
#include "jacobian_row_kernel.hpp"

#if defined(__AVX512F__)

namespace clothlab::detail {

// CG's direction update on one grid row (pointers at its column 0, components `stride` apart):
// solution += alpha p, then p = z + beta p, on the active particles.
struct DefiniteDirection {
  const float* z;
  float* p;
  float* solution;
  const float* inverse_mass;
  float alpha, beta;
  std::size_t stride;
};

// The update at columns [c, c + 16) within `lanes`; fresh: the new p where active, else 0 (as
// the sweep reads p). The one arithmetic of the update, whether the sweep does it (the row two
// below) or a row pass before it (definite_direction_row): the same bits either way.
inline void definite_direction_block(const DefiniteDirection& row, std::size_t c, __mmask16 lanes,
                                     __m512 (&fresh)[3]) {
  const __mmask16 active = _mm512_mask_cmp_ps_mask(
      lanes, _mm512_maskz_loadu_ps(lanes, row.inverse_mass + c), _mm512_setzero_ps(), _CMP_GT_OQ);
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t e = c + k * row.stride;
    const __m512 p = _mm512_maskz_loadu_ps(lanes, row.p + e);
    _mm512_mask_storeu_ps(row.solution + e, active,
                          _mm512_fmadd_ps(_mm512_set1_ps(row.alpha), p,
                                          _mm512_maskz_loadu_ps(lanes, row.solution + e)));
    const __m512 next =
        _mm512_fmadd_ps(_mm512_set1_ps(row.beta), p, _mm512_maskz_loadu_ps(lanes, row.z + e));
    _mm512_mask_storeu_ps(row.p + e, active, next);
    fresh[k] = _mm512_maskz_mov_ps(active, next);
  }
}

inline void definite_direction_row(const DefiniteDirection& row, std::size_t cols) {
  __m512 fresh[3];
  for (std::size_t c = 0; c < cols; c += 16)
    definite_direction_block(row, c, columns_in(c, 0, cols), fresh);
}

// Stencils in kProvotStencils order: (0,1), (1,0), (1,1), (1,-1), (0,2), (2,0).
struct DefiniteRow {
  const float* x[3];               // rows r, r + 1, r + 2 at column 0; components `stride` apart
  const float* u[3];               // likewise
  const float* inverse_mass[3];    // likewise, one component
  const float* mass;               // row r's masses (0 where pinned)
  const float* inverse_length[6];  // per stencil, its springs' 1/l at row r (0 where none)
  // Per stencil, fixed by the linearisation: what definite_coefficients takes beside 1/l.
  float ks[6], ks_rest[6];  // ks, ks l0
  float along_scale[6];     // c_x ks + c_v kd (kd 0 without damping)
  float c_x;
  float* out[3];         // the product's rows r, r + 1, r + 2 (r: u + D u once complete)
  bool write[3];         // rows of out this call may write
  bool first[3];         // rows whose first contribution this is
  bool rows_below[2];    // rows r + 1 and r + 2 exist
  float* ends_below[2];  // scratch: partner ends of (1,1) and (1,-1), components `span` apart
  // Not null: row r + 2's direction update, done block by block just before the sweep reads it.
  const DefiniteDirection* direction_below;
  std::size_t stride, span, cols;
};

// One stencil's inverse spring lengths along row r at columns [0, cols) (0 outside
// [col_begin, col_end)), from the positions of row r and of its partners' row.
struct DefiniteInverseLengthRow {
  const float* x;
  const float* x_partner;  // shifted so that column c lines up with the partner
  float* inverse_length;
  std::size_t stride, cols, col_begin, col_end;
};

inline void definite_inverse_length_row(const DefiniteInverseLengthRow& row) {
  for (std::size_t c = 0; c < row.cols; c += 16) {
    const __mmask16 valid = columns_in(c, row.col_begin, row.col_end);
    __m512 squared = _mm512_setzero_ps();
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t e = c + k * row.stride;
      const __m512 d =
          _mm512_maskz_loadu_ps(valid, row.x_partner + e) - _mm512_maskz_loadu_ps(valid, row.x + e);
      squared = squared + d * d;
    }
    const __mmask16 in_row = columns_in(c, 0, row.cols);
    _mm512_mask_storeu_ps(row.inverse_length + c, in_row,
                          _mm512_maskz_mov_ps(valid, inverse_sqrt_or_zero(squared)));
  }
}

// right1, right2: the (0,1) and (0,2) products of the block before (zero before the first);
// dot: the row's <u, q> so far, in two sets of 8 double lanes.
template <bool Edge>
__attribute__((always_inline)) inline void definite_row_block(const DefiniteRow& row, std::size_t c,
                                                              __m512 (&right1)[3],
                                                              __m512 (&right2)[3],
                                                              __m512d (&dot)[2]) {
  using Vec3 = __m512[3];
  const std::size_t stride = row.stride, span = row.span, cols = row.cols;
  const __m512 zero = _mm512_setzero_ps();
  const auto lanes = [&](std::size_t begin, std::size_t end) -> __mmask16 {
    if constexpr (Edge) return columns_in(c, begin, end);
    return __mmask16(0xffff);
  };
  const auto load = [&](const float* p, std::ptrdiff_t shift, __mmask16 valid, Vec3& out) {
    for (std::size_t k = 0; k < 3; ++k)
      out[k] = _mm512_maskz_loadu_ps(valid, p + c + k * stride + shift);
  };
  // u at (row, shift) where that particle is active and the lane a spring.
  const auto direction = [&](int dr, std::ptrdiff_t shift, __mmask16 valid, Vec3& out) {
    const __mmask16 active = _mm512_mask_cmp_ps_mask(
        valid, _mm512_maskz_loadu_ps(valid, row.inverse_mass[dr] + c + shift), zero, _CMP_GT_OQ);
    load(row.u[dr], shift, active, out);
  };
  const __mmask16 all = lanes(0, cols);
  // Into a row of the product; an edge block stores only the row's own columns.
  const auto put = [&](float* p, bool first, const Vec3& value) {
    for (std::size_t k = 0; k < 3; ++k) {
      float* q = p + c + k * stride;
      const __m512 sum = first ? value[k] : _mm512_add_ps(_mm512_maskz_loadu_ps(all, q), value[k]);
      if constexpr (Edge) {
        _mm512_mask_storeu_ps(q, all, sum);
      } else {
        _mm512_storeu_ps(q, sum);
      }
    }
  };
  Vec3 x, u, own = {zero, zero, zero};
  load(row.x[0], 0, all, x);
  direction(0, 0, all, u);
  // Stencil s to the partner at (r + dr, c + dc): its product joins `own`; returns it.
  // Inlined by force: as a call, its vectors go through memory (GCC 12 does not inline it).
  // fresh: the partners' u, already loaded.
  const auto spring = [&](int s, int dr, std::ptrdiff_t dc, __mmask16 valid, Vec3& product,
                          const Vec3* fresh = nullptr) __attribute__((always_inline)) {
    Vec3 partner, du, d;
    load(row.x[dr], dc, valid, partner);
    if (fresh != nullptr) {
      for (std::size_t k = 0; k < 3; ++k) du[k] = (*fresh)[k];
    } else {
      direction(dr, dc, valid, du);
    }
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = partner[k] - x[k];
      du[k] = du[k] - u[k];
    }
    // 1/l is 0 in the lanes without a spring (and for a zero-length one): no force there.
    __m512 across, along;
    definite_coefficients(_mm512_maskz_loadu_ps(valid, row.inverse_length[s] + c),
                          _mm512_set1_ps(row.ks[s]), _mm512_set1_ps(row.ks_rest[s]),
                          _mm512_set1_ps(row.along_scale[s]), _mm512_set1_ps(row.c_x), zero, across,
                          along);
    along = along * (d[0] * du[0] + d[1] * du[1] + d[2] * du[2]);
    for (std::size_t k = 0; k < 3; ++k) {
      product[k] = across * du[k] + along * d[k];
      own[k] = own[k] + product[k];
    }
  };
  const auto store_scratch = [&](float* p, const Vec3& value) {
    for (std::size_t k = 0; k < 3; ++k) _mm512_storeu_ps(p + c + k * span, value[k]);
  };
  Vec3 product;
  // The in-row partner ends, one and two columns over, join `own` a lane up (valignd; the
  // maskz form, as the plain one's header trips GCC 12's -Wuninitialized), the block's last
  // lanes carried into the next block.
  spring(0, 0, 1, lanes(0, cols - 1), product);
  for (std::size_t k = 0; k < 3; ++k) {
    own[k] =
        own[k] - _mm512_castsi512_ps(_mm512_maskz_alignr_epi32(
                     0xffff, _mm512_castps_si512(product[k]), _mm512_castps_si512(right1[k]), 15));
    right1[k] = product[k];
  }
  spring(4, 0, 2, lanes(0, cols >= 2 ? cols - 2 : 0), product);
  for (std::size_t k = 0; k < 3; ++k) {
    own[k] =
        own[k] - _mm512_castsi512_ps(_mm512_maskz_alignr_epi32(
                     0xffff, _mm512_castps_si512(product[k]), _mm512_castps_si512(right2[k]), 14));
    right2[k] = product[k];
  }
  if (row.rows_below[0]) {
    spring(1, 1, 0, all, product);
    if (row.write[1]) {
      for (std::size_t k = 0; k < 3; ++k) product[k] = zero - product[k];
      put(row.out[1], row.first[1], product);
    }
    spring(2, 1, 1, lanes(0, cols - 1), product);
    store_scratch(row.ends_below[0], product);
    spring(3, 1, -1, lanes(1, cols), product);
    store_scratch(row.ends_below[1], product);
  }
  if (row.rows_below[1]) {
    if (row.direction_below != nullptr) {
      Vec3 fresh;
      definite_direction_block(*row.direction_below, c, all, fresh);
      spring(5, 2, 0, all, product, &fresh);
    } else {
      spring(5, 2, 0, all, product);
    }
    if (row.write[2]) {
      for (std::size_t k = 0; k < 3; ++k) product[k] = zero - product[k];
      put(row.out[2], true, product);
    }
  }
  if (!row.write[0]) return;
  // Row r is complete now (the rows above added theirs before): out = q = u + M^-1 (sum), u
  // being 0 and M^-1 0 on pinned particles, and the block's m u.q into the row's dot.
  const __m512 inverse_mass = _mm512_maskz_loadu_ps(all, row.inverse_mass[0] + c);
  __m512 u_dot_q = zero;
  for (std::size_t k = 0; k < 3; ++k) {
    float* q = row.out[0] + c + k * stride;
    const __m512 sum = row.first[0] ? own[k] : own[k] + _mm512_maskz_loadu_ps(all, q);
    const __m512 value = u[k] + inverse_mass * sum;
    u_dot_q = u_dot_q + u[k] * value;
    if constexpr (Edge) {
      _mm512_mask_storeu_ps(q, all, value);
    } else {
      _mm512_storeu_ps(q, value);
    }
  }
  const __m512 term = _mm512_maskz_loadu_ps(all, row.mass + c) * u_dot_q;
  // maskz forms: the plain ones' headers (and _mm512_castps512_ps256's) trip GCC 12's
  // -Wmaybe-uninitialized.
  const __m512d terms = _mm512_castps_pd(term);
  dot[0] = dot[0] + _mm512_maskz_cvtps_pd(
                        0xff, _mm256_castpd_ps(_mm512_maskz_extractf64x4_pd(0xf, terms, 0)));
  dot[1] = dot[1] + _mm512_maskz_cvtps_pd(
                        0xff, _mm256_castpd_ps(_mm512_maskz_extractf64x4_pd(0xf, terms, 1)));
}

// One row's sweep (the edge blocks mask lanes outside the grid or a stencil's columns); with
// write[0], row r's shifted product q = u + D u is final and the return value is its <u, q>.
inline double definite_row(const DefiniteRow& row) {
  const std::size_t cols = row.cols;
  __m512 right1[3], right2[3];
  for (std::size_t k = 0; k < 3; ++k) right1[k] = right2[k] = _mm512_setzero_ps();
  __m512d dot[2] = {_mm512_setzero_pd(), _mm512_setzero_pd()};
  std::size_t c = 0;
  definite_row_block<true>(row, c, right1, right2, dot);
  for (c = 16; c + 16 + 2 <= cols; c += 16) definite_row_block<false>(row, c, right1, right2, dot);
  for (; c < cols; c += 16) definite_row_block<true>(row, c, right1, right2, dot);
  alignas(64) double lanes[8];  // summed in a fixed order (_mm512_reduce_add_pd trips GCC 12)
  _mm512_store_pd(lanes, dot[0] + dot[1]);
  return ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) +
         ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]));
}

// The scratch rows' partner ends after the sweep: row r + 1 gets those of (1,1) and (1,-1)
// (from columns c - 1 and c + 1).
inline void definite_row_shifted_ends(const DefiniteRow& row) {
  if (!row.rows_below[0] || !row.write[1]) return;
  const std::size_t stride = row.stride, span = row.span, cols = row.cols;
  // 16 lanes as the sweep's loads of the row: narrower stores here would not forward to them.
  for (std::size_t k = 0; k < 3; ++k) {
    float* out = row.out[1] + k * stride;
    const float* below_right = row.ends_below[0] + k * span - 1;
    const float* below_left = row.ends_below[1] + k * span + 1;
    for (std::size_t c = 0; c < cols; c += 16) {
      const __mmask16 lanes = columns_in(c, 0, cols);
      const __m512 ends = _mm512_maskz_loadu_ps(lanes, below_right + c) +
                          _mm512_maskz_loadu_ps(lanes, below_left + c);
      _mm512_mask_storeu_ps(out + c, lanes, _mm512_maskz_loadu_ps(lanes, out + c) - ends);
    }
  }
}

}  // namespace clothlab::detail

#endif
