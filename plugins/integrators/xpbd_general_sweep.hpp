// XPBD's general path: a substep over any topology, one spring at a time through its indices.
//
// Predict dx = h (v + h a) on the free particles, then `iterations` Gauss-Seidel sweeps over
// the springs colour by colour (the topology extension's independent sets), each colour's
// springs in parallel: no two share a particle, so every thread count gives the same bits.
// In float a colour's springs go kLanes at a time through the grid's lane update
// (xpbd_row_kernel.hpp), their ends gathered and scattered by index.
// Then the tethers, and v = dx / h, x += dx on the free particles. With Chebyshev
// acceleration on (xpbd_chebyshev.hpp), each sweep's iterate is extrapolated.
#pragma once

#include <algorithm>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "xpbd_chebyshev.hpp"
#include "xpbd_constraint.hpp"
#include "xpbd_row_kernel.hpp"
#include "xpbd_substep.hpp"

namespace clothlab::builtin {

template <class Real>
class GeneralSweep {
 public:
  // Copies the springs colour by colour, each colour padded to whole blocks; springs with both
  // ends pinned never move and are left out. rho = 0: no acceleration.
  void build(const sdk::System<Real>& system, const sdk::Topology& topology, int iterations,
             double chebyshev_rho, long chebyshev_delay) {
    iterations_ = iterations;
    const Real* inverse_mass = system.inverse_mass();
    springs_ = {};
    color_offsets_.assign(1, 0);
    color_ends_.clear();
    for (uint32_t color = 0; color < topology.spring_color_count(); ++color) {
      for (uint32_t k : topology.spring_color(color)) {
        const uint32_t i = topology.first()[k], j = topology.second()[k];
        if (inverse_mass[i] == 0 && inverse_mass[j] == 0) continue;
        springs_.push_back(i, j, static_cast<Real>(topology.rest_length()[k]),
                           static_cast<Real>(topology.ks()[k]), static_cast<Real>(topology.kd()[k]),
                           inverse_mass[i], inverse_mass[j]);
      }
      color_ends_.push_back(static_cast<uint32_t>(springs_.first.size()));
      while (springs_.first.size() % kBlock != 0) springs_.push_back(0, 0, 0, 0, 0, 0, 0);
      color_offsets_.push_back(static_cast<uint32_t>(springs_.first.size()));
    }
    lambda_.assign(springs_.first.size(), 0);
    chebyshev_.build(chebyshev_rho, chebyshev_delay, iterations, system.particle_count(),
                     system.stride(), springs_.first.size());
  }

  // One substep; false when a velocity came out non-finite. The worksharing loops run on the
  // team of a parallel region, or, on one thread, orphaned (no team, no barrier cost, no
  // allocation).
  bool run(const Substep<Real>& s, int threads) {
    if (threads == 1) {
      const Share share = sweep(s);
      first_change_ = share.first_change, last_change_ = share.last_change;
      return share.finite;
    }
    bool finite = true;
    Real first = 0, last = 0;
#pragma omp parallel num_threads(threads) reduction(&& : finite) reduction(max : first, last)
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
  // The tethers are projected in blocks of particles, a vector loop each.
  static constexpr long tether_block = 256;

  // This thread's share of "every velocity is finite" and of the first and last sweeps' changes
  // (0 without acceleration).
  struct Share {
    bool finite;
    Real first_change, last_change;
  };

  // Predict, project colour by colour, update velocities.
  Share sweep(const Substep<Real>& s) {
    const auto n = static_cast<long>(s.particle_count);
    Real* lambda = lambda_.data();
    Real first_change = 0, last_change = 0;
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t e = c * s.stride + static_cast<std::size_t>(i);
        s.displacement[e] = 0;  // pinned too: their dx must be 0
        if (s.inverse_mass[i] == 0) continue;
        s.displacement[e] = s.h * (s.v[e] + s.h * s.external_acceleration[e]);
      }
    for (int iteration = 0; iteration < iterations_; ++iteration) {
      if (chebyshev_.active()) chebyshev_.save(iteration, s.displacement, lambda);
      for (std::size_t color = 0; color + 1 < color_offsets_.size(); ++color)
        project_color(s, color, iteration == 0);
      if (!chebyshev_.active()) continue;
      chebyshev_.extrapolate(iteration, s.displacement, lambda);
      if (iteration == 0) first_change = chebyshev_.change(iteration, s.displacement);
      if (iteration + 1 == iterations_) last_change = chebyshev_.change(iteration, s.displacement);
    }
    if (s.tethers != nullptr) {
      const long blocks = (n + tether_block - 1) / tether_block;
#pragma omp for schedule(static)
      for (long block = 0; block < blocks; ++block)
        s.tethers->project(static_cast<std::size_t>(block * tether_block),
                           static_cast<std::size_t>(std::min(n, (block + 1) * tether_block)), s.x,
                           s.displacement, s.inverse_mass, s.stride);
    }
    bool finite = true;
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) {
      if (s.inverse_mass[i] == 0) continue;
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t e = c * s.stride + static_cast<std::size_t>(i);
        s.x[e] += s.displacement[e];
        s.v[e] = s.displacement[e] * s.inverse_h;
        finite = finite && std::isfinite(s.v[e]);
      }
    }
    return {finite, first_change, last_change};
  }

#if defined(CLOTHLAB_FLOAT_LANES)
  static constexpr std::size_t kBlock = std::is_same_v<Real, float> ? detail::kLanes : 1;
#else
  static constexpr std::size_t kBlock = 1;
#endif

  // The springs, one array per field (Constraint's), so that a block's fields load as lanes.
  struct Springs {
    std::vector<uint32_t> first, second;
    std::vector<Real> rest, ks, kd, first_weight, second_weight;

    void push_back(uint32_t i, uint32_t j, Real rest_length, Real stiffness, Real damping, Real wi,
                   Real wj) {
      first.push_back(i), second.push_back(j), rest.push_back(rest_length);
      ks.push_back(stiffness), kd.push_back(damping);
      first_weight.push_back(wi), second_weight.push_back(wj);
    }
    Constraint<Real> operator[](std::size_t k) const {
      return {first[k], second[k], rest[k], ks[k], kd[k], first_weight[k], second_weight[k]};
    }
  };

  // One colour's springs; a worksharing loop, as sweep's.
  void project_color(const Substep<Real>& s, std::size_t color, bool fresh) {
    const long begin = color_offsets_[color], end = color_ends_[color];
#if defined(CLOTHLAB_FLOAT_LANES)
    if constexpr (std::is_same_v<Real, float>) {
      const long blocks = (color_offsets_[color + 1] - begin) / static_cast<long>(kBlock);
#pragma omp for schedule(static)
      for (long block = 0; block < blocks; ++block) {
        const long start = begin + block * static_cast<long>(kBlock);
        project_block(s, static_cast<std::size_t>(start),
                      static_cast<std::size_t>(std::min<long>(end - start, kBlock)), fresh);
      }
      return;
    }
#endif
#pragma omp for schedule(static)
    for (long k = begin; k < end; ++k)
      project_constraint(springs_[static_cast<std::size_t>(k)],
                         lambda_[static_cast<std::size_t>(k)], fresh, s.x, s.displacement, s.stride,
                         s.h, s.h_squared);
  }

#if defined(CLOTHLAB_FLOAT_LANES)
  // The springs [start, start + count) of one colour, count <= kLanes: no two share a
  // particle, so the lanes' scatters never collide.
  void project_block(const Substep<float>& s, std::size_t start, std::size_t count, bool fresh) {
    using namespace detail;
    using namespace row_lanes;
    const LaneMask lanes = lanes_from_to(0, count);
    const Indices i = load_indices(&springs_.first[start]);
    const Indices j = load_indices(&springs_.second[start]);
    Floats x_difference[3], dxi[3], dxj[3];
    for (std::size_t k = 0; k < 3; ++k) {
      const float* x = s.x + k * s.stride;
      const float* dx = s.displacement + k * s.stride;
      x_difference[k] = gather_floats(x, i) - gather_floats(x, j);
      dxi[k] = gather_floats(dx, i);
      dxj[k] = gather_floats(dx, j);
    }
    LawLanes law{};
    law.rest = load_floats(&springs_.rest[start]);
    law.stiffness = load_floats(&springs_.ks[start]) * broadcast(s.h_squared);
    law.damping = load_floats(&springs_.kd[start]) * broadcast(s.h);
    law.compliance_scale = law.stiffness + law.damping;
    const Floats wi = load_floats(&springs_.first_weight[start]);
    const Floats wj = load_floats(&springs_.second_weight[start]);
    const Floats accumulated = fresh ? zero_floats() : load_floats(&lambda_[start]);
    const row_lanes::SpringLanes u =
        spring_update(law, lanes, x_difference, dxi, dxj,
                      inverse_denominator(law.compliance_scale, wi, wj), accumulated);
    store_floats(&lambda_[start], masked_add(u.pushed, accumulated, u.delta));
    const PushLanes push = pushes<false>(u, wi, wj);
    for (std::size_t k = 0; k < 3; ++k) {
      float* dx = s.displacement + k * s.stride;
      scatter_floats(dx, push.moves_first, i, fused_multiply_add(push.first, u.d[k], dxi[k]));
      scatter_floats(dx, push.moves_second, j,
                     fused_negated_multiply_add(push.second, u.d[k], dxj[k]));
    }
  }
#endif

  int iterations_ = 1;
  Springs springs_;
  std::vector<Real> lambda_;  // one per spring
  // Springs of colour c: [offsets[c], ends[c]), padded with no-op springs to offsets[c + 1].
  std::vector<uint32_t> color_offsets_, color_ends_;
  XpbdChebyshev<Real> chebyshev_;
  Real first_change_ = 0, last_change_ = 0;  // of the last substep
};

}  // namespace clothlab::builtin
