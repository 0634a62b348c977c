// Vertex block descent's sweep order: the free particles colour by colour, from the topology
// extension's particle colouring (no spring joins two particles of a colour, so a colour's
// blocks read only other colours' displacements: any order, any number of threads, the same
// bits), each with its mass and the springs that touch it, stored in sweep order.
#pragma once

#include <clothlab/sdk.hpp>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "vbd_vertex_step.hpp"

namespace clothlab::builtin {

template <class Real>
class VertexBlocks {
 public:
  void build(const sdk::Topology& topology, const Real* inverse_mass) {
    particles_.clear();
    masses_.clear();
    springs_.clear();
    spring_offsets_.assign(1, 0);
    color_offsets_.assign(1, 0);
    for (uint32_t color = 0; color < topology.particle_color_count(); ++color) {
      for (const uint32_t i : topology.particle_color(color)) {
        if (inverse_mass[i] == 0) continue;  // pinned: never moves
        particles_.push_back(i);
        masses_.push_back(1 / inverse_mass[i]);
        for (const uint32_t s : topology.springs_of(i)) {
          const uint32_t first = topology.first()[s], second = topology.second()[s];
          springs_.push_back(
              {first == i ? second : first, static_cast<Real>(topology.rest_length()[s]),
               static_cast<Real>(topology.ks()[s]), static_cast<Real>(topology.kd()[s])});
        }
        spring_offsets_.push_back(static_cast<uint32_t>(springs_.size()));
      }
      color_offsets_.push_back(static_cast<uint32_t>(particles_.size()));
    }
  }

  std::size_t color_count() const { return color_offsets_.size() - 1; }
  // The blocks of colour c are [color_begin(c), color_begin(c + 1)).
  long color_begin(std::size_t color) const { return color_offsets_[color]; }
  std::size_t block_count() const { return particles_.size(); }

  uint32_t particle(long block) const { return particles_[static_cast<std::size_t>(block)]; }
  Real mass(long block) const { return masses_[static_cast<std::size_t>(block)]; }
  std::span<const SpringEnd<Real>> springs(long block) const {
    const auto b = static_cast<std::size_t>(block);
    return {springs_.data() + spring_offsets_[b], springs_.data() + spring_offsets_[b + 1]};
  }

 private:
  std::vector<uint32_t> particles_;  // free particles, colour by colour
  std::vector<Real> masses_;         // by block
  std::vector<SpringEnd<Real>> springs_;
  std::vector<uint32_t> spring_offsets_;  // springs of block b: [offsets[b], offsets[b + 1])
  std::vector<uint32_t> color_offsets_;   // blocks of colour c: [offsets[c], offsets[c + 1])
};

}  // namespace clothlab::builtin
