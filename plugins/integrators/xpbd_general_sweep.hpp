// XPBD's general path: a substep over any topology, one spring at a time through its indices.
//
// Predict dx = h (v + h a) on the free particles, then `iterations` Gauss-Seidel sweeps over
// the springs colour by colour (the topology extension's independent sets), each colour's
// springs in parallel: no two share a particle, so every thread count gives the same bits.
// Then the tethers, and v = dx / h, x += dx on the free particles.
#pragma once

#include <algorithm>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "xpbd_constraint.hpp"
#include "xpbd_substep.hpp"

namespace clothlab::builtin {

template <class Real>
class GeneralSweep {
 public:
  // Copies the springs colour by colour; springs with both ends pinned never move and are
  // left out (their colour ranges shrink accordingly).
  void build(const sdk::System<Real>& system, const sdk::Topology& topology, int iterations) {
    iterations_ = iterations;
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
    lambda_.assign(springs_.size(), 0);
  }

  // One substep; false when a velocity came out non-finite. The worksharing loops run on the
  // team of a parallel region, or, on one thread, orphaned (no team, no barrier cost, no
  // allocation).
  bool run(const Substep<Real>& s, int threads) {
    if (threads == 1) return sweep(s);
    bool finite = true;
#pragma omp parallel num_threads(threads) reduction(&& : finite)
    finite = sweep(s);
    return finite;
  }

 private:
  // The tethers are projected in blocks of particles, a vector loop each.
  static constexpr long tether_block = 256;

  // Predict, project colour by colour, update velocities. Returns this thread's share of
  // "every velocity is finite".
  bool sweep(const Substep<Real>& s) {
    const auto n = static_cast<long>(s.particle_count);
    const Constraint<Real>* springs = springs_.data();
    Real* lambda = lambda_.data();
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t e = c * s.stride + static_cast<std::size_t>(i);
        s.displacement[e] = 0;  // pinned too: their dx must be 0
        if (s.inverse_mass[i] == 0) continue;
        s.displacement[e] = s.h * (s.v[e] + s.h * s.external_acceleration[e]);
      }
    for (int iteration = 0; iteration < iterations_; ++iteration)
      for (std::size_t color = 0; color + 1 < color_offsets_.size(); ++color) {
        const long begin = color_offsets_[color], end = color_offsets_[color + 1];
#pragma omp for schedule(static)
        for (long k = begin; k < end; ++k)
          project_constraint(springs[k], lambda[k], iteration == 0, s.x, s.displacement, s.stride,
                             s.h, s.h_squared);
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
    return finite;
  }

  int iterations_ = 1;
  std::vector<Constraint<Real>> springs_;
  std::vector<Real> lambda_;             // one per spring
  std::vector<uint32_t> color_offsets_;  // springs of colour c: [offsets[c], offsets[c + 1])
};

}  // namespace clothlab::builtin
