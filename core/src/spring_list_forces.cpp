#include "spring_list_forces.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <type_traits>

#include "air_kernel.hpp"
#include "simd_namespace.hpp"
#include "spring_kernel.hpp"
#include "wind_kernel.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {
namespace {

constexpr std::size_t kChunk = 1024;                  // items per thread work item
constexpr std::size_t kTile = kChunk / kSpringBlock;  // particle blocks per sweep tile

std::size_t chunks_of(std::size_t items) { return (items + kChunk - 1) / kChunk; }

#if defined(CLOTHLAB_FLOAT_LANES)
// The wind's shares of the block of triangle slots from t, whose corners follow in order (plain
// loads, as the grid's cells), its dead lanes (live's clear bits) 0; laid out as the slots.
inline void wind_block_lanes(const float* x, std::size_t stride,
                             const std::array<uint32_t, 4>& corners, const Floats (&pressure)[3],
                             uint32_t live, float* share, std::size_t share_stride) {
  Floats e1[3], e2[3], out[3];
  for (std::size_t k = 0; k < 3; ++k) {
    const float* component = x + k * stride;
    const Floats corner = load_floats(component + corners[0]);
    e1[k] = load_floats(component + corners[1]) - corner;
    e2[k] = load_floats(component + corners[2]) - corner;
  }
  triangle_wind_share(e1, e2, pressure, out);
  const LaneMask lanes = lanes_of_bits(live);
  for (std::size_t k = 0; k < 3; ++k) store_floats(share + k * share_stride, keep(lanes, out[k]));
}

// wind_block_lanes for the block of a chosen band (LaneBands): its four corners (lane 0's at
// corners[c]) loaded in order, each lane's three corners picked from them by the block's masks.
inline void wind_block_chosen(const float* x, std::size_t stride,
                              const std::array<uint32_t, 4>& corners, const ChosenLanes<3>& ends,
                              const Floats (&pressure)[3], uint32_t live, float* share,
                              std::size_t share_stride) {
  LaneMask low[3], high[3];
  for (std::size_t e = 0; e < 3; ++e)
    low[e] = lanes_of_bits(&ends.low[e]), high[e] = lanes_of_bits(&ends.high[e]);
  Floats e1[3], e2[3], out[3];
  for (std::size_t k = 0; k < 3; ++k) {
    Floats corner[4];
    for (std::size_t c = 0; c < 4; ++c) corner[c] = load_floats(x + k * stride + corners[c]);
    const Floats first = chosen_end(corner, low[0], high[0]);
    e1[k] = chosen_end(corner, low[1], high[1]) - first;
    e2[k] = chosen_end(corner, low[2], high[2]) - first;
  }
  triangle_wind_share(e1, e2, pressure, out);
  const LaneMask lanes = lanes_of_bits(live);
  for (std::size_t k = 0; k < 3; ++k) store_floats(share + k * share_stride, keep(lanes, out[k]));
}
#endif

}  // namespace

template <class Real>
SpringListForces<Real>::SpringListForces(const ClothModel& model, const Scene& scene,
                                         std::size_t stride, const Real* inverse_mass,
                                         bool velocity_forces, int threads, bool parallel)
    : n_(model.particle_count),
      stride_(stride),
      inverse_mass_(inverse_mass),
      threads_(threads),
      parallel_(parallel),
      velocity_forces_(velocity_forces),
      springs_(model, velocity_forces, kTile),
      spring_count_(model.spring_count()),
      triangle_count_(model.triangle_count()) {
  spring_force_ = AlignedBuffer<Real>(3 * springs_.slots());
  spring_rings_ =
      AlignedBuffer<Real>(static_cast<std::size_t>(threads) * 3 * springs_.ring_slots());

  Real wind_direction[3];
  for (int k = 0; k < 3; ++k) {
    gravity_[k] = static_cast<Real>(scene.gravity[k]);
    wind_direction[k] = static_cast<Real>(scene.wind_direction[k]);
    air_wind_[k] = static_cast<Real>(scene.air.wind_velocity[k]);
  }
  wind_ = scene.has_wind() && triangle_count_ > 0;
  air_ = scene.has_air() && triangle_count_ > 0;
  const auto wind_strength = static_cast<Real>(scene.wind_strength);
  wind_pressure(wind_direction, wind_strength, kScalarInverseSqrtScale, wind_pressure_);
#if defined(CLOTHLAB_FLOAT_LANES)
  wind_pressure(wind_direction, wind_strength, kLanesInverseSqrtScale, lane_wind_pressure_);
#endif
  air_drag_twelfth_ = static_cast<Real>(scene.air.density * scene.air.drag_coefficient / 12.0);
  air_lift_twelfth_ = static_cast<Real>(scene.air.density * scene.air.lift_coefficient / 12.0);
  if (wind_ || air_) lay_out_triangles(model);
  formed_x_ = AlignedBuffer<Real>(3 * stride_);
  formed_v_ = AlignedBuffer<Real>(3 * stride_);
}

template <class Real>
void SpringListForces<Real>::lay_out_triangles(const ClothModel& model) {
  std::vector<uint32_t> rotated(model.triangles.size());
  for (std::size_t t = 0; t < triangle_count_; ++t) {
    const uint32_t* corners = &model.triangles[3 * t];
    const std::size_t low = std::min_element(corners, corners + 3) - corners;
    for (std::size_t c = 0; c < 3; ++c) rotated[3 * t + c] = corners[(low + c) % 3];
  }
  triangles_.emplace(n_, rotated, 3, 0u, kTile);
  const std::size_t slots = triangles_->slots();
  triangle_share_ = AlignedBuffer<Real>(3 * slots);
  triangle_rings_ =
      AlignedBuffer<Real>(static_cast<std::size_t>(threads_) * 3 * triangles_->ring_slots());
  triangle_blocks_.assign(triangles_->slot_blocks(), TriangleBlock{});
  for (std::size_t s = 0; s < slots; ++s)
    if (triangles_->item_in(s) != triangle_count_)
      triangle_blocks_[s / kSpringBlock].live |= static_cast<uint16_t>(1u << (s % kSpringBlock));
  for (std::size_t b = 0; b < triangles_->slot_blocks(); ++b) {
    TriangleBlock& block = triangle_blocks_[b];
    block.in_order = triangles_->ends_in_order(b);
    for (std::size_t c = 0; c < 3; ++c) block.corner[c] = triangles_->ends(c)[b * kSpringBlock];
    ChosenLanes<3> ends;
    if (!block.in_order && block.live != 0 && triangles_->chosen_lanes(b, ends)) {
      block.chosen = static_cast<uint32_t>(triangle_lanes_.size());
      triangle_lanes_.push_back(ends);
      for (std::size_t c = 0; c < 4; ++c)  // modulo 2^32, as chosen_lanes says
        block.corner[c] =
            static_cast<uint32_t>(b * kSpringBlock) + triangles_->chosen_corners()[ends.band][c];
    }
  }
}

template <class Real>
const Real* SpringListForces<Real>::form(const StateCombination<Real>& state, Real* out) {
  if (state.count == 0) return state.base;
  const auto chunks = static_cast<std::ptrdiff_t>(chunks_of(n_));
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
    form_range(state, out, begin, std::min(kChunk, n_ - begin));
  }
  return out;
}

template <class Real>
void SpringListForces<Real>::form_range(const StateCombination<Real>& state, Real* out,
                                        std::size_t begin, std::size_t count) const {
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t at = k * stride_ + begin;
    const Real* vectors[StateCombination<Real>::kMaxTerms];
    for (uint32_t t = 0; t < state.count; ++t) vectors[t] = state.vectors[t] + at;
    combine_row(out + at, state.base + at, state.count, state.coefficients, vectors,
                inverse_mass_ + begin, count);
  }
}

template <class Real>
Real SpringListForces<Real>::spring_sweep(const Real* x, const Real* v, Real* a, bool triangles,
                                          double& triangle_seconds, const TileEpilogue* after) {
  Real check = 0;
  const auto shares = [&](std::size_t begin, std::size_t end, Real* out, std::size_t out_stride) {
    if (omp_get_thread_num() != 0) return triangle_shares(x, v, begin, end, out, out_stride);
    const auto start = std::chrono::steady_clock::now();
    triangle_shares(x, v, begin, end, out, out_stride);
    triangle_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const SlotBuffers<Real> spring_slots{spring_force_.data(), spring_rings_.data()};
  const SlotBuffers<Real> triangle_slots{triangle_share_.data(), triangle_rings_.data()};
  springs_.sweep(
      threads_, parallel_, spring_slots,
      [&](std::size_t begin, std::size_t end, Real* out, std::size_t out_stride) {
        springs_.forces(x, v, stride_, begin, end, out, out_stride);
      },
      [&](std::size_t, std::size_t begin, std::size_t end, const Real* ring,
          const Real* triangle_ring) {
        Real tile_check = 0;
        for (std::size_t block = begin; block < end; ++block)
          tile_check +=
              gather_block(block, a, ring, triangles ? triangle_ring : nullptr, true, triangles);
        if (after != nullptr) {
          const std::size_t first = begin * kSpringBlock;
          const std::size_t count = std::min(n_, end * kSpringBlock) - first;
          if (after->step != nullptr) {
            advance_range(after->advanced_x, after->advanced_v, *after->step, first, count);
          } else {
            if (after->x.count != 0) form_range(after->x, after->formed_x, first, count);
            if (after->v.count != 0) form_range(after->v, after->formed_v, first, count);
          }
        }
#pragma omp atomic
        check += tile_check;
      },
      triangles ? &*triangles_ : nullptr, &triangle_slots, &shares);
  return check;
}

template <class Real>
void SpringListForces<Real>::triangle_pass(const Real* x, const Real* v) {
  const std::size_t blocks = triangles_->slot_blocks();
  const std::size_t chunk_blocks = kChunk / kSpringBlock;
  const auto chunks = static_cast<std::ptrdiff_t>((blocks + chunk_blocks - 1) / chunk_blocks);
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * chunk_blocks;
    const std::size_t end = std::min(blocks, begin + chunk_blocks);
    triangle_shares(x, v, begin, end, triangle_share_.data() + begin * kSpringBlock,
                    triangles_->slots());
  }
}

template <class Real>
void SpringListForces<Real>::triangle_shares(const Real* x, const Real* v, std::size_t begin,
                                             std::size_t end, Real* out,
                                             std::size_t out_stride) const {
  const std::size_t s1 = stride_, s2 = 2 * stride_;
  const Real third = Real(1) / Real(3);
  const uint32_t *corner_a = triangles_->ends(0), *corner_b = triangles_->ends(1),
                 *corner_c = triangles_->ends(2);
#if defined(CLOTHLAB_FLOAT_LANES)
  Floats pressure[3] = {zero_floats(), zero_floats(), zero_floats()};
  if constexpr (std::is_same_v<Real, float>)
    for (std::size_t k = 0; k < 3; ++k) pressure[k] = broadcast(lane_wind_pressure_[k]);
#endif
  for (std::size_t block = begin; block < end; ++block) {
    Real* share_out = out + (block - begin) * kSpringBlock;
    const TriangleBlock& lanes = triangle_blocks_[block];
    if (lanes.live == 0) {
      // Dead slots join particles that may not be finite: they give 0 whatever the state.
      for (std::size_t k = 0; k < 3; ++k)
        std::fill_n(share_out + k * out_stride, kSpringBlock, Real(0));
      continue;
    }
#if defined(CLOTHLAB_FLOAT_LANES)
    if constexpr (std::is_same_v<Real, float>) {
      if (!air_ && lanes.in_order) {
        wind_block_lanes(x, stride_, lanes.corner, pressure, lanes.live, share_out, out_stride);
        continue;
      }
      if (!air_ && lanes.chosen != kNotChosen) {
        wind_block_chosen(x, stride_, lanes.corner, triangle_lanes_[lanes.chosen], pressure,
                          lanes.live, share_out, out_stride);
        continue;
      }
    }
#endif
    for (std::size_t t = block * kSpringBlock, l = 0; l < kSpringBlock; ++t, ++l) {
      Real share[3] = {0, 0, 0};
      if ((lanes.live >> l & 1u) != 0) {
        const std::size_t a = corner_a[t], b = corner_b[t], c = corner_c[t];
        const Real e1[3] = {x[b] - x[a], x[b + s1] - x[a + s1], x[b + s2] - x[a + s2]};
        const Real e2[3] = {x[c] - x[a], x[c + s1] - x[a + s1], x[c + s2] - x[a + s2]};
        if (wind_) triangle_wind_share(e1, e2, wind_pressure_, share);
        if (air_) {
          Real velocity[3] = {0, 0, 0};
          if (v != nullptr)
            for (std::size_t k = 0; k < 3; ++k) {
              const std::size_t at = k * stride_;
              velocity[k] = (v[a + at] + v[b + at] + v[c + at]) * third;
            }
          Real air[3];
          triangle_air_share(e1, e2, velocity, air_wind_, air_drag_twelfth_, air_lift_twelfth_,
                             air);
          for (int k = 0; k < 3; ++k) share[k] += air[k];
        }
      }
      for (std::size_t k = 0; k < 3; ++k) share_out[k * out_stride + l] = share[k];
    }
  }
}

template <class Real>
Real SpringListForces<Real>::gather_block(std::size_t block, Real* a, const Real* spring_ring,
                                          const Real* triangle_ring, bool springs,
                                          bool triangles) const {
  alignas(kAlignment) Real force[3][kSpringBlock] = {};
  if (springs) springs_.sum_incident(spring_force_.data(), spring_ring, block, force);
  const std::size_t first = block * kSpringBlock;
  const std::size_t count = std::min(kSpringBlock, n_ - first);
  if (triangles) triangles_->sum_incident(triangle_share_.data(), triangle_ring, block, force);
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    if (count == kSpringBlock) {
      const Floats inverse_mass = load_floats(inverse_mass_ + first);
      const LaneMask active = greater(inverse_mass, zero_floats());
      Floats check = zero_floats();
      for (std::size_t k = 0; k < 3; ++k) {
        const Floats value = keep(active, fused_multiply_add(load_floats(force[k]), inverse_mass,
                                                             broadcast(gravity_[k])));
        store_floats(a + k * stride_ + first, value);
        check = check + zero_floats() * value;
      }
      return no_lane(unordered(check, check)) ? 0.0f : std::numeric_limits<float>::quiet_NaN();
    }
  }
#endif
  Real check = 0;
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t l = 0; l < count; ++l) {
      const Real inverse_mass = inverse_mass_[first + l];
      const Real value =
          inverse_mass > Real(0) ? force[k][l] * inverse_mass + gravity_[k] : Real(0);
      a[k * stride_ + first + l] = value;
      check += Real(0) * value;
    }
  return check;
}

template <class Real>
Real SpringListForces<Real>::gather_external(Real* a, bool triangles) {
  const std::size_t blocks = springs_.particle_blocks();
  const auto chunks = static_cast<std::ptrdiff_t>(chunks_of(blocks * kSpringBlock));
  Real check = 0;
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_) reduction(+ : check)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * (kChunk / kSpringBlock);
    const std::size_t end = std::min(blocks, begin + kChunk / kSpringBlock);
    for (std::size_t block = begin; block < end; ++block)
      check += gather_block(block, a, nullptr, nullptr, false, triangles);
  }
  return check;
}

template <class Real>
bool SpringListForces<Real>::evaluate(const StateCombination<Real>& x,
                                      const StateCombination<Real>* v, Real* a,
                                      StageCounters& counters) {
  const auto start = std::chrono::steady_clock::now();
  const Real* positions = form(x, formed_x_.data());
  const Real* velocities = v == nullptr ? nullptr : form(*v, formed_v_.data());
  counters.internal_forces_s +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return sweep_stage(positions, velocities, a, nullptr, counters);
}

template <class Real>
bool SpringListForces<Real>::sweep_stage(const Real* positions, const Real* velocities, Real* a,
                                         const TileEpilogue* after, StageCounters& counters) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const bool cells = wind_ || air_;
  // The sweep is fused, so its time is split by thread 0's share of triangle work (as the grid's).
  double triangle_seconds = 0.0;
  const Real check = spring_sweep(positions, velocities, a, cells, triangle_seconds, after);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  triangle_seconds = std::min(triangle_seconds, seconds);
  counters.external_forces_s += triangle_seconds;
  counters.internal_forces_s += seconds - triangle_seconds;
  ++counters.force_evals;
  counters.springs_evaluated += spring_count_;
  counters.springs_damped += velocities != nullptr ? springs_.damped_count() : 0;
  counters.normals_computed += cells ? triangle_count_ : 0;
  return check == Real(0);
}

template <class Real>
bool SpringListForces<Real>::evaluate_external(const Real* x, const Real* v, Real* a) {
  const bool cells = wind_ || air_;
  if (cells) triangle_pass(x, v);
  return gather_external(a, cells) == Real(0);
}

template <class Real>
void SpringListForces<Real>::reserve_stages(uint32_t stages) {
  while (stage_a_.size() < stages) stage_a_.emplace_back(3 * stride_);
  reserved_stages_ = std::max(reserved_stages_, stages);
}

template <class Real>
StateCombination<Real> SpringListForces<Real>::stage_state(const Real* x, const Real* v,
                                                           const RknStep<Real>& step, uint32_t s,
                                                           bool velocity) const {
  StateCombination<Real> state;
  state.base = velocity ? v : x;
  const auto add = [&](const Real* vector, Real coefficient) {
    if (coefficient == Real(0)) return;
    state.vectors[state.count] = vector;
    state.coefficients[state.count++] = coefficient;
  };
  if (!velocity) add(v, step.x_velocity[s]);
  for (uint32_t k = 0; k < s; ++k)
    add(stage_a_[k].data(), velocity ? step.v_stage[s][k] : step.x_stage[s][k]);
  return state;
}

template <class Real>
void SpringListForces<Real>::advance_range(Real* x, Real* v, const RknStep<Real>& step,
                                           std::size_t begin, std::size_t count) const {
  const Real* stages[RknStep<Real>::kMaxStages];
  for (uint32_t s = 0; s < step.stages; ++s) stages[s] = stage_a_[s].data() + begin;
  const Real h = step.h;
  const Real* __restrict inverse_mass = inverse_mass_ + begin;
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    // On lanes, the stages' sums kept in registers (GCC's own vectorisation of the loops below
    // gathers one stage's loads); each sum in the same order as there.
    for (std::size_t i = 0; i < count; i += kLanes) {
      const LaneMask lanes = lanes_from_to(0, std::min(kLanes, count - i));
      const LaneMask active =
          both(lanes, not_equal(load_floats(lanes, inverse_mass + i), zero_floats()));
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t at = k * stride_ + begin + i;
        const Floats velocity = load_floats(lanes, v + at);
        Floats dx = broadcast(h) * velocity, dv = zero_floats();
        for (uint32_t s = 0; s < step.stages; ++s) {
          const Floats stage = load_floats(lanes, stages[s] + k * stride_ + i);
          dx = fused_multiply_add(broadcast(step.x_weights[s]), stage, dx);
          dv = fused_multiply_add(broadcast(step.v_weights[s]), stage, dv);
        }
        const Floats position = load_floats(lanes, x + at);
        store_floats(lanes, x + at, select(active, position + dx, position));
        store_floats(lanes, v + at, select(active, velocity + dv, velocity));
      }
    }
    return;
  }
#endif
  // Stage by stage over the range, so the loops run on lanes; each sum in the same order.
  alignas(kAlignment) Real dx[kChunk], dv[kChunk];
  for (std::size_t k = 0; k < 3; ++k) {
    Real* __restrict xk = x + k * stride_ + begin;
    Real* __restrict vk = v + k * stride_ + begin;
#pragma omp simd
    for (std::size_t i = 0; i < count; ++i) {
      dx[i] = h * vk[i];
      dv[i] = 0;
    }
    for (uint32_t s = 0; s < step.stages; ++s) {
      const Real* __restrict stage = stages[s] + k * stride_;
      const Real x_weight = step.x_weights[s], v_weight = step.v_weights[s];
#pragma omp simd
      for (std::size_t i = 0; i < count; ++i) {
        dx[i] += x_weight * stage[i];
        dv[i] += v_weight * stage[i];
      }
    }
#pragma omp simd
    for (std::size_t i = 0; i < count; ++i) {
      const bool active = inverse_mass[i] != Real(0);
      xk[i] = active ? xk[i] + dx[i] : xk[i];
      vk[i] = active ? vk[i] + dv[i] : vk[i];
    }
  }
}

template <class Real>
bool SpringListForces<Real>::step_rkn(Real* x, Real* v, const RknStep<Real>& step,
                                      StageCounters& counters) {
  // Stage s: X_s = x + x_velocity[s] v + sum_k x_stage[s][k] A_k, V_s = v + sum_k v_stage[s][k]
  // A_k. Each sweep's tiles form the next stage's states as their accelerations come out (over
  // this stage's, in place), and the last sweep's advance x and v: after the sweep's barrier a
  // tile's forces read only its own and later particles of the thread's share (LaneBands::sweep),
  // so no pass over whole vectors is left.
  const auto start = std::chrono::steady_clock::now();
  const Real* positions = form(stage_state(x, v, step, 0, false), formed_x_.data());
  const Real* velocities = form(stage_state(x, v, step, 0, true), formed_v_.data());
  counters.internal_forces_s +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bool finite = true;
  for (uint32_t s = 0; s < step.stages; ++s) {
    TileEpilogue after;
    if (s + 1 < step.stages) {
      after.x = stage_state(x, v, step, s + 1, false);
      after.v = stage_state(x, v, step, s + 1, true);
      after.formed_x = formed_x_.data();
      after.formed_v = formed_v_.data();
    } else {
      after.step = &step;
      after.advanced_x = x;
      after.advanced_v = v;
    }
    finite = sweep_stage(positions, velocities, stage_a_[s].data(), &after, counters) && finite;
    positions = after.x.count != 0 ? after.formed_x : x;
    velocities = after.v.count != 0 ? after.formed_v : v;
  }
  return finite;
}

template class SpringListForces<float>;
template class SpringListForces<double>;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
