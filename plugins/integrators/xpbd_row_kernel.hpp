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

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "float_lanes.hpp"
#include "inverse_sqrt.hpp"
#include "simd_namespace.hpp"
#include "xpbd_color_row.hpp"

namespace clothlab::builtin::inline CLOTHLAB_SIMD_NAMESPACE {

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

#if defined(CLOTHLAB_FLOAT_LANES)
// A block of kLanes springs per step (float_lanes.hpp: 16 on AVX-512, 8 on AVX2), without
// loading what the lanes just stored (a masked store blocks store forwarding). 1 / length
// from the hardware estimate and one Newton step (inverse_sqrt.hpp), and the denominator
// (>= 1) from its reciprocal estimate and one Newton step: a few ulp each, where sqrt and
// divide would bound the kernel. Lengths below the smallest normal float count as
// coincident ends.
namespace row_lanes {

using namespace detail;

struct SpringLanes {
  Floats d[3], moved[3];
  Floats squared, closing;             // |d|^2, d.moved
  Floats twice_inverse_length, delta;  // 2 / |d| (inverse_sqrt.hpp's scale)
  LaneMask pushed;
};

// The lanes a block holds: every lane (no mask to apply), or those of a mask.
struct AllLanes {};
inline LaneMask within(AllLanes, LaneMask mask) { return mask; }
inline LaneMask within(LaneMask lanes, LaneMask mask) { return both(lanes, mask); }
inline AllLanes lanes_of(FullLanes) { return {}; }
inline LaneMask lanes_of(const TailLanes& block) { return block.mask(); }

// A row's last kLanes springs as a whole block, of which those before `lanes` were projected
// by the block before: whole loads and stores (a masked store is slow), the lanes done
// before pushed by nothing, so that their ends get back the displacements just stored
// (but for a zero's sign). Their multipliers keep what the block before stored (a fresh
// block's are 0), by a select.
struct LastLanes {
  LaneMask lanes;
  static Floats load(const float* p) { return load_floats(p); }
  static void store(float* p, Floats value) { store_floats(p, value); }
};
inline LaneMask lanes_of(const LastLanes& block) { return block.lanes; }

template <class Block>
inline void store_multipliers(const Block& block, float* p, Floats value) {
  block.store(p, value);
}
inline void store_multipliers(const LastLanes& block, float* p, Floats value) {
  store_floats(p, select(block.lanes, value, load_floats(p)));
}

// 1 / ((ks h^2 + kd h)(w_i + w_j) + 1).
inline Floats inverse_denominator(Floats compliance_scale, Floats wi, Floats wj) {
  const Floats denominator = compliance_scale * (wi + wj) + broadcast(1.0f);
  const Floats reciprocal = reciprocal_estimate(denominator);
  return reciprocal * fused_negated_multiply_add(denominator, reciprocal, broadcast(2.0f));
}

// The colour's spring law in registers, read once per row: the kernels' stores go through
// float pointers, which could alias the row's float fields. The uniform weight's
// denominator comes from the same instructions as a lane's, so it has the same bits. The
// stiffness and damping are halved for the inverse length's scale 2 (inverse_sqrt.hpp).
// The uniform weight's push (PushLanes<true>) takes the law times its factor
// K = w / (2 denominator) (uniform_scale): stiffness_rest, half_stiffness and half_damping
// times K as uniform_rest, uniform_stiffness and uniform_damping.
struct LawLanes {
  Floats stiffness_rest, half_stiffness, half_damping, compliance_scale;
  Floats uniform_inverse_denominator, uniform_scale;
  Floats uniform_rest, uniform_stiffness, uniform_damping;
};

// From ks h^2 and kd h (halving is exact): floats broadcast, or a law per lane.
inline Floats law_lanes_of(float value) { return broadcast(value); }
inline Floats law_lanes_of(Floats value) { return value; }

template <class Value>
inline LawLanes law_lanes(Value rest, Value stiffness, Value damping) {
  const Floats zero = zero_floats();  // the uniform weight's, set by the row's law_lanes
  return {law_lanes_of(stiffness * rest),
          law_lanes_of(0.5f * stiffness),
          law_lanes_of(0.5f * damping),
          law_lanes_of(stiffness + damping),
          zero,
          zero,
          zero,
          zero,
          zero};
}

inline LawLanes law_lanes(const ColorRow<float>& row) {
  LawLanes law = law_lanes(row.rest, row.stiffness, row.damping);
  const Floats weight = broadcast(row.uniform_weight);
  law.uniform_inverse_denominator = inverse_denominator(law.compliance_scale, weight, weight);
  law.uniform_scale = broadcast(0.5f * row.uniform_weight) * law.uniform_inverse_denominator;
  law.uniform_rest = law.uniform_scale * law.stiffness_rest;
  law.uniform_stiffness = law.uniform_scale * law.half_stiffness;
  law.uniform_damping = law.uniform_scale * law.half_damping;
  return law;
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
  // The blocks [skip + c, skip + c + width) for c a multiple of width below `whole` that
  // `covers` leaves out, as the c of [from, to): the row's runs before and after them are
  // uniform, so the loops over them test nothing per block.
  std::pair<std::size_t, std::size_t> varied_blocks(std::size_t skip, std::size_t width,
                                                    std::size_t whole) const {
    if (!any) return {0, whole};
    const auto up = [&](std::size_t v) { return std::min(whole, (v + width - 1) / width * width); };
    // Left out: skip + c + width > varied_begin and skip + c < varied_end.
    const std::size_t from =
        up(varied_begin + 1 > skip + width ? varied_begin + 1 - skip - width : 0);
    return {from, std::max(from, up(varied_end > skip ? varied_end - skip : 0))};
  }
};

// The update of the springs in `lanes` from the ends' position differences and both ends'
// displacements. Always inlined: called out of line, its vectors and masks go through the
// stack.
template <class Lanes>
__attribute__((always_inline)) inline SpringLanes spring_update(
    const LawLanes& law, Lanes lanes, const Floats (&x_difference)[3], const Floats (&dxi)[3],
    const Floats (&dxj)[3], Floats inverse_denominator, Floats accumulated) {
  SpringLanes out;
  for (int k = 0; k < 3; ++k) {
    out.moved[k] = dxi[k] - dxj[k];
    out.d[k] = x_difference[k] + out.moved[k];
  }
  const Floats squared = out.d[0] * out.d[0] + out.d[1] * out.d[1] + out.d[2] * out.d[2];
  out.pushed = within(lanes, not_less(squared, broadcast(FLT_MIN)));
  // ks h^2 C + kd h n.(dx_i - dx_j) = (ks h^2 |d|^2 + kd h d.moved) / |d| - ks h^2 rest, by
  // the scaled inverse length (2 / |d|). Where the spring is not pushed it may be infinite
  // and what follows from it NaN: every use below keeps only the pushed lanes.
  const Floats twice_inverse_length = unclamped_scaled_inverse_sqrt(squared);
  out.squared = squared;
  out.closing = out.d[0] * out.moved[0] + out.d[1] * out.moved[1] + out.d[2] * out.moved[2];
  out.twice_inverse_length = twice_inverse_length;
  const Floats pull = law.half_stiffness * squared + law.half_damping * out.closing;
  const Floats numerator =
      fused_negated_multiply_add(pull, twice_inverse_length, law.stiffness_rest - accumulated);
  out.delta = numerator * inverse_denominator;
  return out;
}

// Pushes of the springs' two ends, and the ends' displacements they give: dx_i + push_i d and
// dx_j - push_j d where the end moves, dx unchanged elsewhere.
template <bool Uniform>
struct PushLanes;

// Uniform-weight lanes: one product serves both ends, zero where the spring is not pushed, so
// the ends need no blend (six per block of lanes: a cost on 8 lanes, where a blend is an
// instruction of its own, and a masked FMA on 16 is one). A lane not pushed adds 0 d, d finite (its
// squared length is below FLT_MIN, and lanes outside the block load zeros): its displacement stays,
// but for a zero's sign. With u = 2 / |d| and K = w / (2 denominator) (LawLanes):
//   w delta / |d| = K (ks h^2 rest - lambda - (ks h^2/2 |d|^2 + kd h/2 d.moved) u) u,
// the law's constants times K, so that the push takes two operations after u where
// delta, then its product with u and w, took four.
template <>
struct PushLanes<true> {
  Floats push;

  // rest: K (ks h^2 rest - lambda).
  PushLanes(const SpringLanes& u, const LawLanes& law, Floats rest) {
    const Floats pull = law.uniform_stiffness * u.squared + law.uniform_damping * u.closing;
    const Floats scaled = fused_negated_multiply_add(pull, u.twice_inverse_length, rest);
    push = keep(u.pushed, u.twice_inverse_length * scaled);
  }
  Floats first_end(Floats d, Floats dx) const { return fused_multiply_add(push, d, dx); }
  Floats second_end(Floats d, Floats dx) const { return fused_negated_multiply_add(push, d, dx); }
};

// Lanes of another weight: an end of weight 0 (a pin) keeps its displacement bit for bit.
template <>
struct PushLanes<false> {
  Floats first, second;
  LaneMask moves_first, moves_second;

  PushLanes(const SpringLanes& u, Floats wi, Floats wj) {
    const Floats scale = u.delta * (broadcast(0.5f) * u.twice_inverse_length);
    const Floats zero = zero_floats();
    first = wi * scale, second = wj * scale;
    moves_first = both(u.pushed, not_equal(wi, zero));
    moves_second = both(u.pushed, not_equal(wj, zero));
  }
  Floats first_end(Floats d, Floats dx) const {
    return masked_fused_multiply_add(moves_first, first, d, dx);
  }
  Floats second_end(Floats d, Floats dx) const {
    return masked_fused_negated_multiply_add(moves_second, second, d, dx);
  }
};

// The push of lanes of the uniform weight or not, lambda the multipliers before the update.
template <bool Uniform, bool Fresh>
inline PushLanes<Uniform> push_lanes(const SpringLanes& u, const LawLanes& law, Floats wi,
                                     Floats wj, Floats lambda) {
  if constexpr (!Uniform)
    return PushLanes<false>(u, wi, wj);
  else if constexpr (Fresh)
    return PushLanes<true>(u, law, law.uniform_rest);
  else
    return PushLanes<true>(u, law,
                           fused_negated_multiply_add(law.uniform_scale, lambda, law.uniform_rest));
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

  RowArrays(const ColorRow<float>& row, std::size_t skip)
      : x(row.x + row.first + skip),
        dx(row.displacement + row.first + skip),
        w(row.inverse_mass + row.first + skip),
        lambda(row.lambda == nullptr ? nullptr : row.lambda + row.first),
        offset(row.offset),
        stride(row.stride) {}
};

// Stencils reaching the next rows: every lane a spring, both ends contiguous runs. `block`
// is FullLanes or TailLanes (float_lanes.hpp), or LastLanes (above).
template <bool Uniform, bool Fresh, bool KeepLambda, class Block>
inline void project_rows_block(const RowArrays& row, const LawLanes& law, std::size_t c,
                               Block block) {
  const std::size_t o = row.offset, s = row.stride;
  Floats x_difference[3], dxi[3], dxj[3];
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t i = c + k * s;
    x_difference[k] = block.load(row.x + i) - block.load(row.x + i + o);
    dxi[k] = block.load(row.dx + i);
    dxj[k] = block.load(row.dx + i + o);
  }
  Floats wi = zero_floats(), wj = wi;  // PushLanes<true> takes the uniform weight from the law
  Floats inverse = law.uniform_inverse_denominator;
  if constexpr (!Uniform) {
    wi = block.load(row.w + c), wj = block.load(row.w + c + o);
    inverse = inverse_denominator(law.compliance_scale, wi, wj);
  }
  Floats accumulated = zero_floats();
  if constexpr (!Fresh) accumulated = block.load(row.lambda + c);
  const SpringLanes u =
      spring_update(law, lanes_of(block), x_difference, dxi, dxj, inverse, accumulated);
  if constexpr (KeepLambda)
    store_multipliers(block, row.lambda + c, masked_add(u.pushed, accumulated, u.delta));
  const PushLanes<Uniform> push = push_lanes<Uniform, Fresh>(u, law, wi, wj, accumulated);
  // The partners' displacements read again (an operand of the update's FMA) rather than kept
  // in registers, which the loop lacks: the starts and the partners of a block are distinct
  // particles (no two springs of a colour share one), so the store before it leaves them as
  // they were loaded.
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t i = c + k * s;
    block.store(row.dx + i, push.first_end(u.d[k], dxi[k]));
    block.store(row.dx + i + o, push.second_end(u.d[k], block.load(row.dx + i + o)));
  }
}

template <bool Fresh, bool KeepLambda>
inline void project_rows(const ColorRow<float>& row) {
  const LawLanes law = law_lanes(row);
  const UniformRuns uniform(row);
  const RowArrays arrays(row, 0);
  const std::size_t count = row.count, whole = count / kLanes * kLanes;
  const auto [varied_from, varied_to] = uniform.varied_blocks(0, kLanes, whole);
  const auto blocks = [&](std::size_t from, std::size_t to, auto uniform_run) {
    for (std::size_t c = from; c < to; c += kLanes)
      project_rows_block<decltype(uniform_run)::value, Fresh, KeepLambda>(arrays, law, c,
                                                                          FullLanes{});
  };
  blocks(0, varied_from, std::true_type{});
  blocks(varied_from, varied_to, std::false_type{});
  blocks(varied_to, whole, std::true_type{});
  if (whole == count) return;
  const auto last = [&](std::size_t c, auto block) {
    if (uniform.covers(c, c + kLanes))
      project_rows_block<true, Fresh, KeepLambda>(arrays, law, c, block);
    else
      project_rows_block<false, Fresh, KeepLambda>(arrays, law, c, block);
  };
  if (whole > 0)
    last(count - kLanes, LastLanes{lanes_from_to(whole - (count - kLanes), kLanes)});
  else
    last(whole, TailLanes{lanes_from_to(0, count - whole)});
}

// In-row stencils (step 1 or 2 columns): a run of 2 kLanes particles from a start holds
// kLanes springs of the colour with both ends inside it (the starts are the first Step of
// every 2 Step particles), so two loads and a deinterleave give the starts and the partners,
// and an interleave merges the moved ends' displacements back for two stores. The lanes
// hold the run's springs in deinterleave's order; positions says where each lane's start,
// and each particle's spring start, lies in the run, for the masks of a run cut short.
struct InRowPositions {
  Floats starts;                 // by lane
  Floats owner_low, owner_high;  // by particle: the start of the spring it is an end of

  template <int Step>
  static InRowPositions of() {
    static constexpr float run[32] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10,
                                      11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21,
                                      22, 23, 24, 25, 26, 27, 28, 29, 30, 31};
    static_assert(2 * kLanes <= 32);
    InRowPositions positions;
    Floats partners;
    deinterleave<Step>(load_floats(run), load_floats(run + kLanes), positions.starts, partners);
    interleave<Step>(positions.starts, positions.starts, positions.owner_low, positions.owner_high);
    return positions;
  }
};

template <int Step, bool Fresh, bool KeepLambda>
inline void project_in_row(const ColorRow<float>& row) {
  // The colour's first start is column parity * Step.
  const std::size_t skip = std::size_t{row.parity} * Step;
  if (row.count <= skip) return;
  const std::size_t count = row.count - skip;
  const RowArrays arrays(row, skip);
  const float* x = arrays.x;
  float* dx = arrays.dx;
  const float* w = arrays.w;
  float* const lambda_row = arrays.lambda;
  const std::size_t s = arrays.stride;
  // The components' rows, so that the runs' loops step one index over all of them.
  const float* const xk[3] = {x, x + s, x + 2 * s};
  float* const dxk[3] = {dx, dx + s, dx + 2 * s};
  const LawLanes law = law_lanes(row);
  const UniformRuns uniform(row);
  // A run: whole; the row's last run of 2 kLanes particles, of which the springs that start
  // before `done` were projected by the run before (whole loads and stores, as LastLanes); or
  // a run cut short (masked), in a row of fewer particles.
  enum class Run { whole, last, cut };
  const auto run = [&](std::size_t c, auto uniform_run, auto kind, std::size_t done = 0) {
    constexpr bool kUniform = decltype(uniform_run)::value;
    constexpr Run kKind = decltype(kind)::value;
    constexpr bool kWhole = kKind == Run::whole, kMasked = kKind == Run::cut;
    LaneMask lanes = all_lanes(), low = all_lanes(), high = all_lanes();
    if constexpr (!kWhole) {
      const InRowPositions positions = InRowPositions::of<Step>();
      const Floats left = broadcast(static_cast<float>(count - c));
      lanes = greater(left, positions.starts);
      if constexpr (kMasked) {
        // The springs whose start lies in the run, and the particles they reach.
        low = greater(left, positions.owner_low), high = greater(left, positions.owner_high);
      } else {
        lanes = both(lanes, not_less(positions.starts, broadcast(static_cast<float>(done - c))));
      }
    }
    const auto load = [&](const float* p, LaneMask mask) {
      if constexpr (kMasked)
        return load_floats(mask, p);
      else
        return load_floats(p);
    };
    const auto store = [&](float* p, LaneMask mask, Floats value) {
      if constexpr (kMasked)
        store_floats(mask, p, value);
      else
        store_floats(p, value);
    };
    const auto split = [&](const float* p, Floats& first, Floats& partner) {
      deinterleave<Step>(load(p, low), load(p + kLanes, high), first, partner);
    };
    Floats x_difference[3], dxi[3], dxj[3];
    for (std::size_t k = 0; k < 3; ++k) {
      Floats xi, xj;
      split(xk[k] + c, xi, xj);
      x_difference[k] = xi - xj;
      split(dxk[k] + c, dxi[k], dxj[k]);
    }
    Floats wi = zero_floats(), wj = wi;  // PushLanes<true> takes the uniform weight from the law
    Floats inverse = law.uniform_inverse_denominator;
    if constexpr (!kUniform) {
      split(w + c, wi, wj);
      inverse = inverse_denominator(law.compliance_scale, wi, wj);
    }
    // Multipliers by spring, kLanes per run: unique within the colour's row.
    float* const lambda = lambda_row == nullptr ? nullptr : lambda_row + c / 2;
    Floats accumulated = zero_floats();
    if constexpr (!Fresh) accumulated = load(lambda, lanes);
    const SpringLanes u = [&] {
      if constexpr (kWhole)
        return spring_update(law, AllLanes{}, x_difference, dxi, dxj, inverse, accumulated);
      else
        return spring_update(law, lanes, x_difference, dxi, dxj, inverse, accumulated);
    }();
    if constexpr (KeepLambda) {
      // The last run's lanes done before keep another run's multipliers (by a select: a
      // masked store is slow); a cut run stores only its own.
      const Floats kept = masked_add(u.pushed, accumulated, u.delta);
      if constexpr (kWhole)
        store_floats(lambda, kept);
      else if constexpr (kMasked)
        store_floats(lanes, lambda, kept);
      else
        store_floats(lambda, select(lanes, kept, load_floats(lambda)));
    }
    const PushLanes<kUniform> push = push_lanes<kUniform, Fresh>(u, law, wi, wj, accumulated);
    for (std::size_t k = 0; k < 3; ++k) {
      Floats a, b;
      interleave<Step>(push.first_end(u.d[k], dxi[k]), push.second_end(u.d[k], dxj[k]), a, b);
      store(dxk[k] + c, low, a);
      store(dxk[k] + c + kLanes, high, b);
    }
  };
  using Whole = std::integral_constant<Run, Run::whole>;
  using Last = std::integral_constant<Run, Run::last>;
  using Cut = std::integral_constant<Run, Run::cut>;
  const auto run_of = [&](std::size_t c, auto kind, std::size_t done) {
    if (uniform.covers(skip + c, skip + c + 2 * kLanes))
      run(c, std::true_type{}, kind, done);
    else
      run(c, std::false_type{}, kind, done);
  };
  constexpr std::size_t kRun = 2 * kLanes;
  const std::size_t whole = count / kRun * kRun;
  const auto [varied_from, varied_to] = uniform.varied_blocks(skip, kRun, whole);
  for (std::size_t c = 0; c < varied_from; c += kRun) run(c, std::true_type{}, Whole{});
  for (std::size_t c = varied_from; c < varied_to; c += kRun) run(c, std::false_type{}, Whole{});
  for (std::size_t c = varied_to; c < whole; c += kRun) run(c, std::true_type{}, Whole{});
  if (whole == count) return;
  // The row's particles from the first start: count + Step. The last run starts at a multiple
  // of 2 Step, as every run does, so that its lanes hold the colour's springs, and must reach
  // the partner of the colour's last start (the first Step of every 2 Step positions).
  const std::size_t final_position = count - 1, phase = final_position % (2 * Step);
  const std::size_t last_start = phase < Step ? final_position : final_position - phase + Step - 1;
  const std::size_t last_run =
      count + Step >= kRun ? (count + Step - kRun) / (2 * Step) * (2 * Step) : 0;
  if (whole > 0 && last_run + kRun > last_start + Step)
    run_of(last_run, Last{}, whole);
  else
    run_of(whole, Cut{}, 0);
}

template <bool Fresh, bool KeepLambda>
inline void project_row(const ColorRow<float>& row) {
  if (!row.alternates)
    project_rows<Fresh, KeepLambda>(row);
  else if (row.alternation_shift == 0)
    project_in_row<1, Fresh, KeepLambda>(row);
  else
    project_in_row<2, Fresh, KeepLambda>(row);
}

}  // namespace row_lanes

// Fresh (lambda 0) and KeepLambda at compile time: a substep of one iteration neither reads
// nor stores a multiplier, and "- lambda" folds away (x - 0 is x, signed zeros included).
inline void project_row_lanes(const ColorRow<float>& row) {
  if (row.fresh)
    row.keep_lambda ? row_lanes::project_row<true, true>(row)
                    : row_lanes::project_row<true, false>(row);
  else
    row.keep_lambda ? row_lanes::project_row<false, true>(row)
                    : row_lanes::project_row<false, false>(row);
}
#endif

template <class Real>
inline void project_row(const ColorRow<Real>& row) {
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    project_row_lanes(row);
    return;
  }
#endif
  project_row_portable(row);
}

}  // namespace clothlab::builtin::inline CLOTHLAB_SIMD_NAMESPACE
