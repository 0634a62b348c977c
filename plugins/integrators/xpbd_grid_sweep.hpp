// XPBD's fast path on the grid: a substep as a wavefront over the rows (xpbd_wavefront.hpp),
// each colour projected a grid row at a time (xpbd_row_kernel.hpp).
//
// With several threads the rows split into two bands at a boundary B: one team runs the
// wavefront down from row 0, the other up from the last row, each touching only its own
// band's rows, so the two never wait for each other nor share a row in flight. B is where
// the two meet: the bands claim rows as they go (xpbd_bands.hpp). The rows next to B that
// neither wavefront reached (lag(phase) below B, lag(phase) - reach above it) are then
// projected phase by phase, each band's first thread on its side of B, the two meeting
// after each phase. Within a team each thread takes a contiguous run of phases and waits
// only for its predecessor to finish the same wavefront time. Every spring sees the same
// values in any split: the bits do not depend on the thread count.
//
// Where the host offers clothlab.external-forces/2, the thread that runs a band's predict pass
// computes the wind's accelerations a few rows ahead of it (external_ahead), so no pass of
// their own precedes the sweep.
//
// The substep's displacement dx lives in v's memory (the pins' velocities wait in the
// scratch array), and runs of springs whose ends all have the grid's common inverse mass
// skip the weights (xpbd_uniform_mass.hpp).
//
// The whole sweep is compiled per SIMD target in a portable build (xpbd_grid_path.hpp), so
// its predict, tether and velocity passes run the target's instructions as its row kernel
// does; what it works with is the plan built at prepare (xpbd_grid_plan.hpp).
#pragma once

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "float_lanes.hpp"
#include "simd_namespace.hpp"
#include "xpbd_bands.hpp"
#include "xpbd_color_row.hpp"
#include "xpbd_grid_plan.hpp"
#include "xpbd_row_kernel.hpp"
#include "xpbd_substep.hpp"
#include "xpbd_tether_projection.hpp"
#include "xpbd_wavefront.hpp"

namespace clothlab::builtin::inline CLOTHLAB_SIMD_NAMESPACE {

#if defined(CLOTHLAB_FLOAT_LANES)
// What a pass over a run of particles computes per block of lanes before storing it: two values
// of each of the three components.
struct RunValues {
  detail::Floats first[3], second[3];
};

// The lanes of a block whose inverse mass is not 0: all of them in a run AllFree.
template <bool AllFree, class Lanes>
inline detail::LaneMask free_lanes(Lanes lanes, const float* inverse_mass) {
  using namespace detail;
  if constexpr (AllFree)
    return all_lanes();
  else
    return not_equal(lanes.load(inverse_mass), zero_floats());
}

// compute(c, lanes), then store(c, lanes, its RunValues), over [0, count) in blocks of lanes. A
// run of kLanes or more ends with a whole block overlapping the one before instead of a masked
// one (masked stores are slow on AVX2): computed first, from the inputs as they were, and
// stored last, so that its lanes done twice are stored with the same bits.
template <class Compute, class Store>
inline void for_each_run_block(std::size_t count, Compute&& compute, Store&& store) {
  using namespace detail;
  if (count < kLanes || count % kLanes == 0) {
    for_each_lane_block(0, count,
                        [&](std::size_t c, auto lanes) { store(c, lanes, compute(c, lanes)); });
    return;
  }
  const std::size_t last = count - kLanes;
  const RunValues tail = compute(last, FullLanes{});
  for (std::size_t c = 0; c + kLanes <= count; c += kLanes)
    store(c, FullLanes{}, compute(c, FullLanes{}));
  store(last, FullLanes{}, tail);
}
#endif

template <class Real>
class GridSweep {
 public:
  GridSweep(GridPlan<Real>& plan, const Substep<Real>& s) : plan_(plan), s_(s) {}

  // One substep on `threads` threads; false when a velocity came out non-finite.
  bool run(int threads) {
    fill_color_rows();
    if (threads == 1) return sweep(0, 1);
    for (int thread = 0; thread < threads; ++thread) plan_.progress[thread].reset();
    for (std::size_t q = 0; q < plan_.phases.size(); ++q) plan_.seam_units[q].reset();
    plan_.claims->reset(plan_.layout.rows, band_reserve(plan_.phases));
    bool finite = true;
#pragma omp parallel num_threads(threads) reduction(&& : finite)
    finite = sweep(omp_get_thread_num(), omp_get_num_threads());
    return finite;
  }

 private:
  // This thread's phases over its band's wavefront, as long as the band claims rows, then
  // (each band's first thread, after all bands are done) the seam between the bands;
  // returns its share of "every velocity is finite".
  bool sweep(int thread, int threads) {
    const std::vector<Phase>& phases = plan_.phases;
    const uint32_t reserve = band_reserve(phases);
    const Bands bands = bands_of(threads, plan_.layout.rows, reserve);
    const uint32_t rows = plan_.layout.rows;
    const bool upper = thread >= bands.lower_threads;
    const int member = upper ? thread - bands.lower_threads : thread;
    const int team = upper ? threads - bands.lower_threads : bands.lower_threads;
    const auto [begin, end] = phases_of(phases, member, team);
    Progress* progress = plan_.progress.get();
    bool finite = true;
    uint32_t held = bands.two ? reserve : rows;  // the band's rows, for its first thread
    // The thread that runs the predict pass computes the external accelerations ahead of it.
    const bool external = plan_.external.forces != nullptr && begin == 0 && begin < end;
    uint32_t external_done = upper ? rows : 0;  // the rows done: below it, or (upper) from it
    uint32_t time = 0;
    for (;; ++time) {
      if (member > 0) {
        if (!wait_for(progress[thread - 1], time)) break;
      } else if (time == held) {
        if (bands.two) held += plan_.claims->claim();
        if (time == held) break;
      }
      if (external) external_ahead(upper, time, held, external_done, thread);
      for (std::size_t q = begin; q < end; ++q) {
        const Phase& phase = phases[q];
        if (time < phase.lag) break;  // lags ascend: the later phases start later still
        run_phase(phase, upper ? rows - 1 - time + phase.upward_offset : time - phase.lag, finite);
      }
      if (member + 1 < team && (time + 1) % plan_.publish_every == 0)
        progress[thread].completed.store(time + 1, std::memory_order_release);
    }
    if (member + 1 < team) progress[thread].end(time);
    if (threads > 1) {
#pragma omp barrier
    }
    // The lower band holds rows [0, boundary), the upper band the rest.
    if (thread == 0 || (bands.two && thread == bands.lower_threads))
      run_seam(bands.two, upper, upper ? rows - time : time, finite);
    return finite;
  }

  // The external accelerations of the rows the predict pass reaches at wavefront time `time`,
  // computed kExternalRows at a time within the band's rows held so far (`done`: see sweep).
  // A row's reads x on the rows beside it, which only the velocity pass changes, at its lag
  // (GridPlan::computes_external_ahead): the bits are those of one call before the sweep.
  void external_ahead(bool upper, uint32_t time, uint32_t held, uint32_t& done, int slot) {
    const uint32_t rows = plan_.layout.rows, chunk = GridPlan<Real>::kExternalRows;
    uint32_t first = done, last = done;
    if (!upper && time >= done) {
      last = std::min(done + chunk, held);
      done = last;
    } else if (upper && rows - 1 - time < done) {
      first = std::max(done - std::min(done, chunk), rows - held);
      done = first;
    } else {
      return;
    }
    const ExternalAhead<Real>& external = plan_.external;
    const clothlab_status status = external.forces->acceleration_rows(
        external.t, s_.x, external.a, first, last, static_cast<uint32_t>(slot));
    int32_t ok = CLOTHLAB_OK;
    if (status != CLOTHLAB_OK)
      plan_.external_status.compare_exchange_strong(ok, status, std::memory_order_relaxed);
  }

  // The rows next to the boundary that neither wavefront reached, phase by phase. One band:
  // thread 0 takes the last rows. Two bands: per phase, the rows below the boundary and those
  // above are two units (SeamUnits) that either band's first thread may claim, its own side
  // first; both must be done before the next phase (a phase's rows are independent, the next
  // phase reads rows either may have written).
  void run_seam(bool two_bands, bool upper, uint32_t boundary, bool& finite) {
    const std::vector<Phase>& phases = plan_.phases;
    if (!two_bands) {
      for (const Phase& phase : phases)
        for (uint32_t row = boundary - std::min(boundary, phase.lag); row < plan_.layout.rows;
             ++row)
          run_phase(phase, row, finite);
      return;
    }
    const int own = upper ? 1 : 0;
    for (std::size_t q = 0; q < phases.size(); ++q) {
      const Phase& phase = phases[q];
      if (phase.lag == 0) continue;  // no rows left on either side
      SeamUnits& units = plan_.seam_units[q];
      for (const int side : {own, 1 - own}) {
        // The partner's unit after a short spin: its rows are in the partner's cache, and a
        // partner that is running takes it in that time.
        if (side != own) units.settle(side);
        if (!units.claim(side)) continue;
        const uint32_t first = side == 1 ? boundary : boundary - std::min(boundary, phase.lag);
        const uint32_t last = side == 1 ? boundary + phase.upward_offset : boundary;  // one past
        for (uint32_t row = first; row < last; ++row) run_phase(phase, row, finite);
        units.done(side);
      }
      if (q + 1 < phases.size()) {
        units.wait(0);
        units.wait(1);
      }
    }
  }

  // What the row jobs of each projection phase share: all but the row's first start (here
  // the first column) and the span of other weights.
  void fill_color_rows() {
    const Substep<Real>& s = s_;
    for (std::size_t q = 0; q < plan_.phases.size(); ++q) {
      const Phase& phase = plan_.phases[q];
      if (phase.kind != Phase::Kind::project) continue;
      const GridColor& color = plan_.layout.colors[phase.color];
      Real* lambda = plan_.lambda.empty()
                         ? nullptr
                         : plan_.lambda.data() + std::size_t{phase.color} * s.particle_count;
      plan_.color_rows[q] = ColorRow<Real>{
          s.x,
          s.v,
          s.inverse_mass,
          lambda,
          s.stride,
          color.col_begin,
          color.col_end - color.col_begin,
          static_cast<std::size_t>(int64_t{color.row_step} * plan_.layout.cols + color.col_step),
          color.in_row(),
          color.col_step == 2 ? 1u : 0u,
          color.parity,
          static_cast<Real>(color.rest),
          static_cast<Real>(color.ks) * s.h_squared,
          static_cast<Real>(color.kd) * s.h,
          phase.iteration == 0,
          phase.iteration + 1 < static_cast<uint32_t>(plan_.iterations),
          static_cast<Real>(plan_.uniform.value()),
          0,
          0};
    }
  }

  // One component of one row, in place: v becomes the substep's displacement
  // dx = h (v + h a); a pin's dx is 0 and its velocity waits in `pinned_velocity` (the
  // general path's displacement array, touched only at pins). Nothing reads v between this
  // phase and the velocity phase, and one array streams where v and dx were two. AllFree:
  // a run without pins, whose inverse masses need no reading.
  template <bool AllFree>
  static void predict_row(Real* __restrict v, Real* __restrict pinned_velocity,
                          const Real* __restrict a, const Real* __restrict inverse_mass,
                          std::size_t count, Real h) {
#pragma omp simd
    for (std::size_t i = 0; i < count; ++i) {
      const bool free = AllFree || inverse_mass[i] != 0;
      if (!free) pinned_velocity[i] = v[i];
      v[i] = free ? h * (v[i] + h * a[i]) : Real(0);
    }
  }

  // One component of one row: x += dx, v = dx / h on the free particles, where v holds dx
  // (a pin gets its velocity back, bit for bit); false if a velocity is not finite (all
  // exponent bits set): an integer OR vectorises where a flag or a sum would not.
  template <bool AllFree>
  static bool velocity_row(Real* __restrict x, Real* __restrict v,
                           const Real* __restrict pinned_velocity,
                           const Real* __restrict inverse_mass, std::size_t count, Real inverse_h) {
    using Bits = std::conditional_t<sizeof(Real) == 4, uint32_t, uint64_t>;
    constexpr Bits exponent = std::bit_cast<Bits>(std::numeric_limits<Real>::infinity());
    Bits non_finite = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const bool free = AllFree || inverse_mass[i] != 0;
      const Real dx = v[i];
      const Real speed = free ? dx * inverse_h : pinned_velocity[i];
      x[i] = free ? x[i] + dx : x[i];
      v[i] = speed;
      non_finite |= free && (std::bit_cast<Bits>(speed) & exponent) == exponent;
    }
    return non_finite == 0;
  }

  // predict_row and velocity_row on the three components of a run of particles from e, in
  // blocks of SIMD lanes for float (one loop, for_each_run_block, where the compiler's
  // vectorised loops would take three, each with a scalar tail); the same bits. In a run with
  // pins (not AllFree) the pins' entries of the scratch array are rewritten as they were.
  template <bool AllFree>
  static void predict_run(const Substep<Real>& s, std::size_t e, std::size_t count,
                          const Real* inverse_mass) {
#if defined(CLOTHLAB_FLOAT_LANES)
    if constexpr (std::is_same_v<Real, float>) {
      using namespace detail;
      // Local copies: the stores could otherwise alias the Substep's fields.
      float* const v = s.v + e;
      float* const pinned = s.displacement + e;
      const float* const a = s.external_acceleration + e;
      const std::size_t stride = s.stride;
      const Floats h = broadcast(s.h);
      // first: the displacement, second: the scratch array (a pin's velocity).
      for_each_run_block(
          count,
          [&](std::size_t i, auto lanes) {
            RunValues out;
            const LaneMask free = free_lanes<AllFree>(lanes, inverse_mass + i);
            for (std::size_t k = 0; k < 3; ++k) {
              const std::size_t at = k * stride + i;
              const Floats velocity = lanes.load(v + at);
              const Floats dx = h * fused_multiply_add(h, lanes.load(a + at), velocity);
              if constexpr (AllFree) {
                out.first[k] = dx;
              } else {
                out.first[k] = keep(free, dx);
                out.second[k] = select(free, lanes.load(pinned + at), velocity);
              }
            }
            return out;
          },
          [&](std::size_t i, auto lanes, const RunValues& out) {
            for (std::size_t k = 0; k < 3; ++k) {
              if constexpr (!AllFree) lanes.store(pinned + k * stride + i, out.second[k]);
              lanes.store(v + k * stride + i, out.first[k]);
            }
          });
      return;
    }
#endif
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t component = k * s.stride + e;
      predict_row<AllFree>(s.v + component, s.displacement + component,
                           s.external_acceleration + component, inverse_mass, count, s.h);
    }
  }

  template <bool AllFree>
  static bool velocity_run(const Substep<Real>& s, std::size_t e, std::size_t count,
                           const Real* inverse_mass) {
#if defined(CLOTHLAB_FLOAT_LANES)
    if constexpr (std::is_same_v<Real, float>) {
      using namespace detail;
      float* const x = s.x + e;
      float* const v = s.v + e;
      const float* const pinned = s.displacement + e;
      const std::size_t stride = s.stride;
      const Floats inverse_h = broadcast(s.inverse_h), zero = zero_floats();
      Floats probe = zero;  // NaN in a lane exactly where some free speed was not finite
      // first: the position, second: the velocity.
      for_each_run_block(
          count,
          [&](std::size_t i, auto lanes) {
            RunValues out;
            const LaneMask free = free_lanes<AllFree>(lanes, inverse_mass + i);
            for (std::size_t k = 0; k < 3; ++k) {
              const std::size_t at = k * stride + i;
              const Floats dx = lanes.load(v + at);
              const Floats speed = dx * inverse_h;
              const Floats position = lanes.load(x + at);
              if constexpr (AllFree) {
                out.first[k] = position + dx;
                out.second[k] = speed;
                probe = fused_multiply_add(speed, zero, probe);
              } else {
                out.first[k] = select(free, position + dx, position);
                out.second[k] = select(free, speed, lanes.load(pinned + at));
                probe = fused_multiply_add(keep(free, speed), zero, probe);
              }
            }
            return out;
          },
          [&](std::size_t i, auto lanes, const RunValues& out) {
            for (std::size_t k = 0; k < 3; ++k) {
              lanes.store(x + k * stride + i, out.first[k]);
              lanes.store(v + k * stride + i, out.second[k]);
            }
          });
      return no_lane(unordered(probe, probe));
    }
#endif
    bool finite = true;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t component = k * s.stride + e;
      finite &= velocity_row<AllFree>(s.x + component, s.v + component, s.displacement + component,
                                      inverse_mass, count, s.inverse_h);
    }
    return finite;
  }

  // Most of a substep's calls project a colour's row, or find that none of its springs starts
  // there: those go straight to the row kernel, the passes over a whole row through a call of
  // their own (whose frame they alone pay for).
  void run_phase(const Phase& phase, uint32_t row, bool& finite) {
    if (phase.kind != Phase::Kind::project) {
      run_pass(phase, row, finite);
      return;
    }
    const RowSprings springs =
        plan_.row_springs[std::size_t{phase.color} * plan_.layout.rows + row];
    if (!springs.starts) return;
    ColorRow<Real> job = plan_.color_rows[static_cast<std::size_t>(&phase - plan_.phases.data())];
    job.first += std::size_t{row} * plan_.layout.cols;
    job.varied_begin = springs.varied_begin;
    job.varied_end = springs.varied_end;
    project_row(job);
  }

  // The predict and velocity passes' shortest run: a block of lanes where the lane passes run.
#if defined(CLOTHLAB_FLOAT_LANES)
  static constexpr uint32_t kMinRun = std::is_same_v<Real, float> ? detail::kLanes : 1;
#else
  static constexpr uint32_t kMinRun = 1;
#endif

  // The predict, tether and velocity passes over a row.
  __attribute__((noinline)) void run_pass(const Phase& phase, uint32_t row, bool& finite) {
    const Substep<Real>& s = s_;
    const std::size_t row_begin = std::size_t{row} * plan_.layout.cols;
    switch (phase.kind) {
      case Phase::Kind::predict:
        plan_.uniform.for_free_runs(
            row, kMinRun, [&](std::size_t begin, std::size_t count, auto all_free) {
              predict_run<decltype(all_free)::value>(s, row_begin + begin, count,
                                                     s.inverse_mass + row_begin + begin);
            });
        return;
      case Phase::Kind::tether:
        // On the grid v holds the substep's displacement between predict and velocity.
        project_tethers(*s.tethers, row_begin, row_begin + plan_.layout.cols, s.x, s.v,
                        s.inverse_mass, s.stride);
        return;
      case Phase::Kind::velocity: {
        bool bad = false;
        plan_.uniform.for_free_runs(
            row, kMinRun, [&](std::size_t begin, std::size_t count, auto all_free) {
              bad |= !velocity_run<decltype(all_free)::value>(s, row_begin + begin, count,
                                                              s.inverse_mass + row_begin + begin);
            });
        finite = finite && !bad;
        return;
      }
      case Phase::Kind::project:
        return;  // run_phase's
    }
  }

  GridPlan<Real>& plan_;
  const Substep<Real>& s_;
};

// One substep on the grid on `threads` threads (what a SIMD target's entry point runs,
// xpbd_grid_sweep_target.cpp); false when a velocity came out non-finite.
template <class Real>
bool sweep_grid(GridPlan<Real>& plan, const Substep<Real>& s, int threads) {
  return GridSweep<Real>(plan, s).run(threads);
}

}  // namespace clothlab::builtin::inline CLOTHLAB_SIMD_NAMESPACE
