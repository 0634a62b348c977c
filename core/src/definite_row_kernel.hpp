// The definite Jacobian's product (jacobian_row_kernel.hpp, JacobianForm::kDefinite) for all six
// Provot stencils starting in one grid row r, in one sweep over its columns, a block of SIMD lanes
// (float_lanes.hpp) at a time, from each spring's inverse length, which the state fixes and
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
#include "simd_namespace.hpp"

#if defined(CLOTHLAB_FLOAT_LANES)

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

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

// The update at the block of columns from c within `lanes`; fresh: the new p where active, else 0
// (as the sweep reads p). The one arithmetic of the update, whether the sweep does it (the row two
// below) or a row pass before it (definite_direction_row): the same bits either way. A pinned
// lane keeps its values by a select, not a masked store (slow on some AVX2 CPUs), so only an
// edge block, whose lanes reach past the row, stores under a mask.
template <bool Edge>
inline void definite_direction_block(const DefiniteDirection& row, std::size_t c, LaneMask lanes,
                                     Floats (&fresh)[3]) {
  const auto load = [&](const float* p) {
    if constexpr (Edge) return load_floats(lanes, p);
    return load_floats(p);
  };
  const auto store = [&](float* p, Floats value) {
    if constexpr (Edge) {
      store_floats(lanes, p, value);
    } else {
      store_floats(p, value);
    }
  };
  const LaneMask active = both(lanes, greater(load(row.inverse_mass + c), zero_floats()));
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t e = c + k * row.stride;
    const Floats p = load(row.p + e);
    const Floats solution = load(row.solution + e);
    store(row.solution + e,
          select(active, fused_multiply_add(broadcast(row.alpha), p, solution), solution));
    const Floats next = fused_multiply_add(broadcast(row.beta), p, load(row.z + e));
    store(row.p + e, select(active, next, p));
    fresh[k] = keep(active, next);
  }
}

inline void definite_direction_row(const DefiniteDirection& row, std::size_t cols) {
  Floats fresh[3];
  std::size_t c = 0;
  for (; c + kLanes <= cols; c += kLanes)
    definite_direction_block<false>(row, c, all_lanes(), fresh);
  if (c < cols) definite_direction_block<true>(row, c, columns_in(c, 0, cols), fresh);
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
  for (std::size_t c = 0; c < row.cols; c += kLanes) {
    const LaneMask valid = columns_in(c, row.col_begin, row.col_end);
    Floats squared = zero_floats();
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t e = c + k * row.stride;
      const Floats d = load_floats(valid, row.x_partner + e) - load_floats(valid, row.x + e);
      squared = squared + d * d;
    }
    const LaneMask in_row = columns_in(c, 0, row.cols);
    store_floats(in_row, row.inverse_length + c, keep(valid, inverse_sqrt_or_zero(squared)));
  }
}

// right1, right2: the (0,1) and (0,2) products of the block before (zero before the first);
// dot: the row's <u, q> so far, in two sets of double lanes (add_widened).
template <bool Edge>
__attribute__((always_inline)) inline void definite_row_block(const DefiniteRow& row, std::size_t c,
                                                              Floats (&right1)[3],
                                                              Floats (&right2)[3],
                                                              Doubles (&dot)[2]) {
  using Vec3 = Floats[3];
  const std::size_t stride = row.stride, span = row.span, cols = row.cols;
  const Floats zero = zero_floats();
  const auto lanes = [&](std::size_t begin, std::size_t end) -> LaneMask {
    if constexpr (Edge) return columns_in(c, begin, end);
    return all_lanes();
  };
  // Loads under a mask at the edges only (the compiler keeps a masked load of every lane): the
  // mask must be one of columns, all lanes away from the edges; a pin mask is applied by keep.
  const auto load_lanes = [&](LaneMask valid, const float* p) {
    if constexpr (Edge) return load_floats(valid, p);
    return load_floats(p);
  };
  const auto load = [&](const float* p, std::ptrdiff_t shift, LaneMask valid, Vec3& out) {
    for (std::size_t k = 0; k < 3; ++k) out[k] = load_lanes(valid, p + c + k * stride + shift);
  };
  // u at (row, shift) where that particle is active and the lane a spring.
  const auto direction = [&](int dr, std::ptrdiff_t shift, LaneMask valid, Vec3& out) {
    const LaneMask active = greater(load_lanes(valid, row.inverse_mass[dr] + c + shift), zero);
    load(row.u[dr], shift, valid, out);
    for (std::size_t k = 0; k < 3; ++k) out[k] = keep(active, out[k]);
  };
  const LaneMask all = lanes(0, cols);
  // Into a row of the product; an edge block stores only the row's own columns.
  const auto put = [&](float* p, bool first, const Vec3& value) {
    for (std::size_t k = 0; k < 3; ++k) {
      float* q = p + c + k * stride;
      const Floats sum = first ? value[k] : load_lanes(all, q) + value[k];
      if constexpr (Edge) {
        store_floats(all, q, sum);
      } else {
        store_floats(q, sum);
      }
    }
  };
  Vec3 x, u, own = {zero, zero, zero};
  load(row.x[0], 0, all, x);
  direction(0, 0, all, u);
  // Stencil s to the partner at (r + dr, c + dc): its product joins `own`; returns it.
  // Inlined by force: as a call, its vectors go through memory (GCC 12 does not inline it).
  // fresh: the partners' u, already loaded.
  const auto spring = [&](int s, int dr, std::ptrdiff_t dc, LaneMask valid, Vec3& product,
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
    Floats across, along;
    definite_coefficients(load_lanes(valid, row.inverse_length[s] + c), broadcast(row.ks[s]),
                          broadcast(row.ks_rest[s]), broadcast(row.along_scale[s]),
                          broadcast(row.c_x), zero, across, along);
    along = along * (d[0] * du[0] + d[1] * du[1] + d[2] * du[2]);
    for (std::size_t k = 0; k < 3; ++k) {
      product[k] = across * du[k] + along * d[k];
      own[k] = own[k] + product[k];
    }
  };
  const auto store_scratch = [&](float* p, const Vec3& value) {
    for (std::size_t k = 0; k < 3; ++k) store_floats(p + c + k * span, value[k]);
  };
  Vec3 product;
  // The in-row partner ends, one and two columns over, join `own` one and two lanes up, the
  // block's last lanes carried into the next block.
  spring(0, 0, 1, lanes(0, cols - 1), product);
  for (std::size_t k = 0; k < 3; ++k) {
    own[k] = own[k] - shift_up<1>(product[k], right1[k]);
    right1[k] = product[k];
  }
  spring(4, 0, 2, lanes(0, cols >= 2 ? cols - 2 : 0), product);
  for (std::size_t k = 0; k < 3; ++k) {
    own[k] = own[k] - shift_up<2>(product[k], right2[k]);
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
      definite_direction_block<Edge>(*row.direction_below, c, all, fresh);
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
  const Floats inverse_mass = load_lanes(all, row.inverse_mass[0] + c);
  Floats u_dot_q = zero;
  for (std::size_t k = 0; k < 3; ++k) {
    float* q = row.out[0] + c + k * stride;
    const Floats sum = row.first[0] ? own[k] : own[k] + load_lanes(all, q);
    const Floats value = u[k] + inverse_mass * sum;
    u_dot_q = u_dot_q + u[k] * value;
    if constexpr (Edge) {
      store_floats(all, q, value);
    } else {
      store_floats(q, value);
    }
  }
  add_widened(load_lanes(all, row.mass + c) * u_dot_q, dot);
}

// One row's sweep (the edge blocks mask lanes outside the grid or a stencil's columns); with
// write[0], row r's shifted product q = u + D u is final and the return value is its <u, q>.
inline double definite_row(const DefiniteRow& row) {
  const std::size_t cols = row.cols;
  Floats right1[3], right2[3];
  for (std::size_t k = 0; k < 3; ++k) right1[k] = right2[k] = zero_floats();
  Doubles dot[2] = {zero_doubles(), zero_doubles()};
  std::size_t c = 0;
  definite_row_block<true>(row, c, right1, right2, dot);
  for (c = kLanes; c + kLanes + 2 <= cols; c += kLanes)
    definite_row_block<false>(row, c, right1, right2, dot);
  for (; c < cols; c += kLanes) definite_row_block<true>(row, c, right1, right2, dot);
  return lane_sum(dot);
}

// The scratch rows' partner ends after the sweep: row r + 1 gets those of (1,1) and (1,-1)
// (from columns c - 1 and c + 1).
inline void definite_row_shifted_ends(const DefiniteRow& row) {
  if (!row.rows_below[0] || !row.write[1]) return;
  const std::size_t stride = row.stride, span = row.span, cols = row.cols;
  // As wide as the sweep's loads of the row: narrower stores here would not forward to them.
  for (std::size_t k = 0; k < 3; ++k) {
    float* out = row.out[1] + k * stride;
    const float* below_right = row.ends_below[0] + k * span - 1;
    const float* below_left = row.ends_below[1] + k * span + 1;
    for_each_lane_block(0, cols, [&](std::size_t c, auto lanes) {
      const Floats ends = lanes.load(below_right + c) + lanes.load(below_left + c);
      lanes.store(out + c, lanes.load(out + c) - ends);
    });
  }
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE

#endif
