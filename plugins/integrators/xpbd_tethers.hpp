// Long-range attachments ("tethers", Kim, Chentanez, Mueller 2012, "Long Range Attachments -
// A Method to Simulate Inextensible Clothing in Computer Games") for XPBD: each free particle
// gets unilateral distance constraints to a few pinned particles (inverse mass 0),
//   |p_i - p_a| <= (1 + slack) rest_ia,
// projected once per substep after the spring sweeps. A particle's tethers are projected in
// turn: the last holds exactly, the earlier ones to within what the later ones move the
// particle (1.3 % of the length at most in xpbd_tethers_test's soft hanging sheet; cyclic
// projections onto several spheres converge only geometrically, so no fixed number of rounds
// makes them exact). One Gauss-Seidel sweep passes a
// correction on by a row or two, so the weight of a cloth hanging over hundreds of rows
// stretches it unless thousands of substeps converge the sweeps; a tether carries the whole
// distance to the pin in one projection. The anchors do not move and have no mass, so a
// projection changes only its free particle: particles are independent, any partition of them
// between threads gives the same bits.
//
// Rest distance: the straight line between the particle and the anchor in the state at
// prepare. That is the geodesic (the shortest path within the cloth) when the cloth starts
// flat, unstretched and with no hole or notch between the two (the built-in scenarios start
// flat in the x-y plane). Violated: a curved or folded start, or a notch in the way, makes the
// straight line shorter than the geodesic, and the tether holds the particle nearer its
// anchor than the cloth would hang (the start's shape partly frozen in; slack relaxes it); a
// stretched start makes tethers longer, i.e. looser. The shortest path over the springs is no
// substitute: on the Provot grid it overestimates the geodesic by up to 8 % (1 / cos 22.5 deg
// with diagonals), which would let the cloth stretch by as much.
//
// Anchors: the pinned particles form islands (joined by springs between two pins: a pole, a
// corner). A free particle's slots take first the nearest pin of each island, nearest island
// first, then each island's spread points (farthest-point sampling: the two ends of a pole,
// then its middle, ...), skipping pins already taken. The spread points matter on a pinned
// edge: a flag particle tethered only to the nearest pin on its pole, at its own height, may
// swing down about that pin (the flag shears, and cotton shears easily); a tether to the
// pole's top forbids it. Fewer distinct pins than slots: the last slot repeats (projecting
// onto the same sphere twice changes nothing); there are as many slots as the most distinct
// pins any particle got. Cost at prepare: free particles x pins.
#pragma once

#include <algorithm>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

namespace clothlab::builtin {

template <class Real>
class Tethers {
 public:
  // Replaces the tethers: up to `per_particle` per free particle (0: none), max length
  // (1 + slack) x the straight-line distance at `x` (the state at prepare).
  void build(const sdk::Topology& topology, const Real* x, std::size_t stride,
             const Real* inverse_mass, uint32_t per_particle, double slack) {
    const uint32_t n = topology.particle_count();
    particle_count_ = n;
    anchor_particles_.clear();
    slot_anchor_.clear();
    slot_limit_.clear();
    slots_ = 0;
    std::vector<uint32_t> pins;
    for (uint32_t i = 0; i < n; ++i)
      if (inverse_mass[i] == 0) pins.push_back(i);
    if (per_particle == 0 || pins.empty()) return;
    const auto distance = [&](uint32_t i, uint32_t j) {
      double sum = 0;
      for (std::size_t c = 0; c < 3; ++c) {
        const double d = double{x[c * stride + i]} - double{x[c * stride + j]};
        sum += d * d;
      }
      return std::sqrt(sum);
    };
    const std::vector<std::vector<uint32_t>> islands = pin_islands(topology, pins);
    std::vector<std::vector<uint32_t>> spread;
    for (const std::vector<uint32_t>& island : islands)
      spread.push_back(spread_points(island, per_particle, distance));

    std::vector<std::pair<double, uint32_t>> nearest(islands.size());  // (distance, pin)
    std::vector<std::vector<uint32_t>> chosen_of(n);
    for (uint32_t i = 0; i < n; ++i) {
      if (inverse_mass[i] == 0) continue;
      for (std::size_t s = 0; s < islands.size(); ++s) {
        nearest[s] = {INFINITY, 0};
        for (uint32_t pin : islands[s])
          nearest[s] = std::min(nearest[s], std::make_pair(distance(i, pin), pin));
      }
      std::vector<std::size_t> order(islands.size());
      std::iota(order.begin(), order.end(), std::size_t{0});
      std::stable_sort(order.begin(), order.end(),
                       [&](std::size_t a, std::size_t b) { return nearest[a] < nearest[b]; });
      std::vector<uint32_t>& chosen = chosen_of[i];
      const auto take = [&](uint32_t pin) {
        if (chosen.size() < per_particle &&
            std::find(chosen.begin(), chosen.end(), pin) == chosen.end())
          chosen.push_back(pin);
      };
      for (std::size_t s : order) take(nearest[s].second);
      for (std::size_t s : order)
        for (uint32_t pin : spread[s]) take(pin);
      slots_ = std::max(slots_, static_cast<uint32_t>(chosen.size()));
    }
    // As many slots as the most distinct pins a particle got (the sheet's two corners: 2).
    slot_anchor_.assign(std::size_t{slots_} * n, 0);
    slot_limit_.assign(std::size_t{slots_} * n, std::numeric_limits<Real>::infinity());
    std::vector<uint32_t> anchor_of_pin(n, UINT32_MAX);  // pin -> index in anchor_particles_
    for (uint32_t i = 0; i < n; ++i) {
      const std::vector<uint32_t>& chosen = chosen_of[i];
      if (chosen.empty()) continue;  // a pin
      for (uint32_t slot = 0; slot < slots_; ++slot) {
        const uint32_t pin = chosen[std::min<std::size_t>(slot, chosen.size() - 1)];
        if (anchor_of_pin[pin] == UINT32_MAX) {
          anchor_of_pin[pin] = static_cast<uint32_t>(anchor_particles_.size());
          anchor_particles_.push_back(pin);
        }
        slot_anchor_[std::size_t{slot} * n + i] = anchor_of_pin[pin];
        // Rounded once to Real: a fixed radius, no noise.
        slot_limit_[std::size_t{slot} * n + i] = static_cast<Real>((1 + slack) * distance(i, pin));
      }
    }
    anchor_position_.assign(3 * anchor_particles_.size(), 0);
  }

  bool active() const { return slots_ > 0; }
  uint32_t slots() const { return slots_; }
  // Slot `slot` of particle i: the pinned particle and the max length (infinite for a pin).
  uint32_t anchor(uint32_t slot, uint32_t i) const {
    return anchor_particles_[slot_anchor_[std::size_t{slot} * particle_count_ + i]];
  }
  Real limit(uint32_t slot, uint32_t i) const {
    return slot_limit_[std::size_t{slot} * particle_count_ + i];
  }

  // Copies the anchors' positions (the pins, fixed within a step) out of x: the projections
  // then read no position another thread's velocity pass writes.
  void refresh_anchors(const Real* x, std::size_t stride) {
    const std::size_t count = anchor_particles_.size();
    for (std::size_t a = 0; a < count; ++a)
      for (std::size_t c = 0; c < 3; ++c)
        anchor_position_[c * count + a] = x[c * stride + anchor_particles_[a]];
  }

  // What a projection reads (xpbd_tether_projection.hpp): slot `slot`'s anchors (indices into
  // the anchors' positions) and max lengths, one per particle, and the anchors' positions
  // (3 x anchor_count(), SoA).
  const uint32_t* slot_anchors(uint32_t slot) const {
    return slot_anchor_.data() + std::size_t{slot} * particle_count_;
  }
  const Real* slot_limits(uint32_t slot) const {
    return slot_limit_.data() + std::size_t{slot} * particle_count_;
  }
  const double* anchor_positions() const { return anchor_position_.data(); }
  std::size_t anchor_count() const { return anchor_particles_.size(); }

 private:
  // The pins' connected components over springs joining two pins, each ascending.
  static std::vector<std::vector<uint32_t>> pin_islands(const sdk::Topology& topology,
                                                        const std::vector<uint32_t>& pins) {
    std::vector<uint32_t> parent(topology.particle_count());
    std::iota(parent.begin(), parent.end(), 0u);
    const auto root = [&](uint32_t i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    std::vector<bool> pinned(topology.particle_count(), false);
    for (uint32_t pin : pins) pinned[pin] = true;
    for (uint32_t k = 0; k < topology.spring_count(); ++k) {
      const uint32_t i = topology.first()[k], j = topology.second()[k];
      if (pinned[i] && pinned[j]) parent[std::max(root(i), root(j))] = std::min(root(i), root(j));
    }
    std::vector<std::vector<uint32_t>> islands;
    std::vector<uint32_t> island_of(topology.particle_count(), UINT32_MAX);
    for (uint32_t pin : pins) {
      uint32_t& island = island_of[root(pin)];
      if (island == UINT32_MAX) {
        island = static_cast<uint32_t>(islands.size());
        islands.emplace_back();
      }
      islands[island].push_back(pin);
    }
    return islands;
  }

  // Up to `count` pins of an island spread over it: the pin farthest from its first, then
  // each time the pin farthest from those taken.
  template <class Distance>
  static std::vector<uint32_t> spread_points(const std::vector<uint32_t>& island, uint32_t count,
                                             const Distance& distance) {
    std::vector<double> gap(island.size());
    for (std::size_t p = 0; p < island.size(); ++p) gap[p] = distance(island[p], island[0]);
    std::vector<uint32_t> taken;
    for (std::size_t next = std::max_element(gap.begin(), gap.end()) - gap.begin();;) {
      taken.push_back(island[next]);
      for (std::size_t p = 0; p < island.size(); ++p)
        gap[p] = taken.size() == 1 ? distance(island[p], island[next])
                                   : std::min(gap[p], distance(island[p], island[next]));
      next = std::max_element(gap.begin(), gap.end()) - gap.begin();
      // Done when enough, or every pin is taken (or coincides with one taken).
      if (taken.size() == count || gap[next] == 0) return taken;
    }
  }

  uint32_t particle_count_ = 0;
  uint32_t slots_ = 0;
  std::vector<uint32_t> anchor_particles_;  // the pins some tether uses
  std::vector<uint32_t> slot_anchor_;       // slots x particles: index into anchor_particles_
  std::vector<Real> slot_limit_;            // slots x particles: max length
  std::vector<double> anchor_position_;     // 3 x anchors (SoA), refreshed per step
};

}  // namespace clothlab::builtin
