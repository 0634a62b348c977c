// XPBD's general path: a substep over any topology, through the springs' indices.
//
// Predict dx = h (v + h a) on the free particles, then `iterations` Gauss-Seidel sweeps over
// the springs colour by colour (the topology extension's independent sets), each colour's
// springs in parallel: no two share a particle, so every thread count gives the same bits.
// In float32 with lanes a colour's springs run in blocks of lanes (xpbd_color_blocks.hpp), the
// SIMD target's that runs here, a portable build's wider ones included (xpbd_lane_blocks.hpp).
// Then the tethers, and v = dx / h, x += dx on the free particles. With Chebyshev
// acceleration on (xpbd_chebyshev.hpp), each sweep's iterate is extrapolated.
#pragma once

#include <omp.h>

#include <algorithm>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "simd_entry.hpp"
#include "xpbd_chebyshev.hpp"
#include "xpbd_color_blocks.hpp"
#include "xpbd_constraint.hpp"
#include "xpbd_lane_blocks.hpp"
#include "xpbd_substep.hpp"
#include "xpbd_tether_projection.hpp"

namespace clothlab::builtin {

#if defined(CLOTHLAB_SIMD_WITH_AVX2)
std::unique_ptr<LaneBlocks> make_color_blocks_avx2();
#endif
#if defined(CLOTHLAB_SIMD_WITH_AVX512)
std::unique_ptr<LaneBlocks> make_color_blocks_avx512();
#endif

// The plugin's own lane blocks; none without float lanes.
inline std::unique_ptr<LaneBlocks> make_own_color_blocks() {
#if defined(CLOTHLAB_FLOAT_LANES)
  return std::make_unique<ColorBlocks>();
#else
  return nullptr;
#endif
}

// The lane blocks of the SIMD target that runs here (xpbd_lane_blocks.hpp, simd_entry.hpp).
inline std::unique_ptr<LaneBlocks> make_lane_blocks() {
  using Make = std::unique_ptr<LaneBlocks> (*)();
  return simd_entry<Make>(make_own_color_blocks, CLOTHLAB_AVX2_ENTRY(make_color_blocks_avx2),
                          CLOTHLAB_AVX512_ENTRY(make_color_blocks_avx512))();
}

template <class Real>
class GeneralSweep {
 public:
  // Copies the springs colour by colour; springs with both ends pinned never move and are
  // left out (their colour ranges shrink accordingly). rho = 0: no acceleration.
  // Each substep runs on `threads` threads. lane_runs false: every lane block gathered (the
  // runs' test).
  void build(const sdk::System<Real>& system, const sdk::Topology& topology, int iterations,
             double chebyshev_rho, long chebyshev_delay, int threads, bool lane_runs = true) {
    iterations_ = iterations;
    threads_ = threads;
    const Real* inverse_mass = system.inverse_mass();
    springs_.clear();
    springs_.reserve(topology.spring_count());
    color_offsets_.assign(1, 0);
    for (uint32_t color = 0; color < topology.spring_color_count(); ++color) {
      for (uint32_t k : topology.spring_color(color)) {
        const uint32_t i = topology.first()[k], j = topology.second()[k];
        if (inverse_mass[i] == 0 && inverse_mass[j] == 0) continue;
        springs_.push_back({i, j, static_cast<Real>(topology.rest_length()[k]),
                            static_cast<Real>(topology.ks()[k]),
                            static_cast<Real>(topology.kd()[k]), inverse_mass[i], inverse_mass[j]});
      }
      color_offsets_.push_back(static_cast<uint32_t>(springs_.size()));
    }
    std::size_t multipliers = springs_.size();
    if constexpr (std::is_same_v<Real, float>) {
      blocks_ = make_lane_blocks();
      if (blocks_ != nullptr) {
        blocks_->build(springs_, color_offsets_, system.particle_count(), threads, lane_runs);
        multipliers = blocks_->slots();
      }
    }
    lambda_.assign(multipliers, 0);
    chebyshev_.build(chebyshev_rho, chebyshev_delay, iterations, system.particle_count(),
                     system.stride(), multipliers);
  }

  // One substep; false when a velocity came out non-finite. The worksharing loops run on the
  // team of a parallel region, or, on one thread, orphaned (no team, no barrier cost, no
  // allocation).
  bool run(const Substep<Real>& s) {
    if (threads_ == 1) {
      const Share share = sweep(s);
      first_change_ = share.first_change, last_change_ = share.last_change;
      return share.finite;
    }
    bool finite = true;
    Real first = 0, last = 0;
#pragma omp parallel num_threads(threads_) reduction(&& : finite) reduction(max : first, last)
    {
      const Share share = sweep(s);
      finite = share.finite, first = share.first_change, last = share.last_change;
    }
    first_change_ = first, last_change_ = last;
    return finite;
  }

  // Whether the last substep's accelerated sweeps diverged (xpbd_chebyshev.hpp), and by how much:
  // the largest displacement change of its first and of its last sweep.
  bool diverged() const { return last_change_ > first_change_; }
  Real first_change() const { return first_change_; }
  Real last_change() const { return last_change_; }

 private:
  // The tethers are projected in blocks of particles, a vector loop each; the prediction and
  // the velocities likewise, a vector loop per coordinate.
  static constexpr long tether_block = 256, particle_block = 256;

  // This thread's part of a colour's blocks [begin, end). One call per thread and colour, not
  // per block, into the target's lane blocks.
  static std::pair<long, long> share(long begin, long end) {
    return thread_share(begin, end, omp_get_thread_num(), omp_get_num_threads());
  }

  // This thread's share of "every velocity is finite" and of the first and last sweeps' changes
  // (0 without acceleration).
  struct Share {
    bool finite;
    Real first_change, last_change;
  };

  // Predict, project colour by colour, update velocities.
  Share sweep(const Substep<Real>& s) {
    const auto n = static_cast<long>(s.particle_count);
    const Constraint<Real>* springs = springs_.data();
    Real* lambda = lambda_.data();
    Real first_change = 0, last_change = 0;
    const long particle_blocks = (n + particle_block - 1) / particle_block;
#pragma omp for schedule(static)
    for (long block = 0; block < particle_blocks; ++block)
      for (std::size_t c = 0; c < 3; ++c)
        for (long i = block * particle_block; i < std::min(n, (block + 1) * particle_block); ++i) {
          const std::size_t e = c * s.stride + static_cast<std::size_t>(i);
          const Real predicted = s.h * (s.v[e] + s.h * s.external_acceleration[e]);
          s.displacement[e] = s.inverse_mass[i] == 0 ? 0 : predicted;  // a pin's dx is 0
        }
    for (int iteration = 0; iteration < iterations_; ++iteration) {
      if (chebyshev_.active()) chebyshev_.save(iteration, s.displacement, lambda);
      for (std::size_t color = 0; color + 1 < color_offsets_.size(); ++color) {
        if constexpr (std::is_same_v<Real, float>) {
          if (blocks_ != nullptr) {
            // Chebyshev extrapolates the multipliers too; else the last sweep's are not read.
            const LaneArrays arrays{s.x,
                                    s.displacement,
                                    s.inverse_mass,
                                    lambda,
                                    s.stride,
                                    s.h,
                                    s.h_squared,
                                    iteration == 0,
                                    chebyshev_.active() || iteration + 1 < iterations_,
                                    omp_get_num_threads()};
            const auto [begin, end] =
                share(blocks_->blocks_begin(color), blocks_->blocks_begin(color + 1));
            blocks_->project(begin, end, arrays);
#pragma omp barrier
            continue;
          }
        }
        const long begin = color_offsets_[color], end = color_offsets_[color + 1];
#pragma omp for schedule(static)
        for (long k = begin; k < end; ++k)
          project_constraint(springs[k], lambda[k], iteration == 0, s.x, s.displacement, s.stride,
                             s.h, s.h_squared);
      }
      if (!chebyshev_.active()) continue;
      chebyshev_.extrapolate(iteration, s.displacement, lambda);
      if (iteration == 0) first_change = chebyshev_.change(iteration, s.displacement);
      if (iteration + 1 == iterations_) last_change = chebyshev_.change(iteration, s.displacement);
    }
    if (s.tethers != nullptr) {
      const long blocks = (n + tether_block - 1) / tether_block;
#pragma omp for schedule(static)
      for (long block = 0; block < blocks; ++block)
        project_tethers(*s.tethers, static_cast<std::size_t>(block * tether_block),
                        static_cast<std::size_t>(std::min(n, (block + 1) * tether_block)), s.x,
                        s.displacement, s.inverse_mass, s.stride);
    }
    int nonfinite = 0;
#pragma omp for schedule(static)
    for (long block = 0; block < particle_blocks; ++block)
      for (std::size_t c = 0; c < 3; ++c)
        for (long i = block * particle_block; i < std::min(n, (block + 1) * particle_block); ++i) {
          const std::size_t e = c * s.stride + static_cast<std::size_t>(i);
          const bool moves = s.inverse_mass[i] != 0;
          const Real dx = s.displacement[e], v = dx * s.inverse_h;
          s.x[e] = moves ? s.x[e] + dx : s.x[e];
          s.v[e] = moves ? v : s.v[e];
          nonfinite |= moves & !(std::abs(v) <= std::numeric_limits<Real>::max());
        }
    return {nonfinite == 0, first_change, last_change};
  }

  int iterations_ = 1;
  int threads_ = 1;  // each substep's
  std::vector<Constraint<Real>> springs_;
  std::vector<Real> lambda_;             // one per spring (float lanes: per slot)
  std::unique_ptr<LaneBlocks> blocks_;   // float32's springs in lane blocks, where lanes run
  std::vector<uint32_t> color_offsets_;  // springs of colour c: [offsets[c], offsets[c + 1])
  XpbdChebyshev<Real> chebyshev_;
  Real first_change_ = 0, last_change_ = 0;  // of the last substep
};

}  // namespace clothlab::builtin
