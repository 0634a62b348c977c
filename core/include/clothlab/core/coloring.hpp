// Colourings: items (springs or particles) grouped into independent sets, so that the members of
// one colour can be updated in parallel (xpbd's constraint sweeps, vbd's vertex steps, the
// smoothers). Deterministic: springs by offset class (below), particles greedy in index order.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace clothlab {

// Colour c holds members[offsets[c] .. offsets[c + 1]), ascending (CSR).
struct Coloring {
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> members;

  uint32_t count() const { return static_cast<uint32_t>(offsets.size() - 1); }
  std::span<const uint32_t> color(uint32_t c) const {
    return {members.data() + offsets[c], members.data() + offsets[c + 1]};
  }
};

// Items grouped by color_of[item] (each < colors), ascending within a colour.
Coloring group_by_color(std::span<const uint32_t> color_of, uint32_t colors);

// Springs (first[k], second[k]) such that no two of a colour share a particle. The springs of
// a large offset class (one second - first, as a grid's stencil on a mesh numbered along rows)
// take two colours of the class's own, alternating along each chain i, i + o, i + 2 o, ... (the
// only springs of a class that share particles), a chain's start taking the colour of its
// index neighbour in the class; the rest, in index order, take the smallest colour none of
// their particles' earlier springs has. So each of a large class's colours holds runs of
// consecutive or alternate first particles, which xpbd's lane blocks load in order instead of
// gathering; the grid read as a mesh gets the grid's 12 stencil colours.
// adjacency_offsets / adjacent_springs: the particle -> spring lists (ClothModel's).
Coloring color_springs(std::span<const uint32_t> first, std::span<const uint32_t> second,
                       std::span<const uint32_t> adjacency_offsets,
                       std::span<const uint32_t> adjacent_springs);

// Particles such that no spring joins two of a colour: each particle, in index order, takes the
// smallest colour none of its earlier spring partners has.
Coloring color_particles(std::span<const uint32_t> first, std::span<const uint32_t> second,
                         std::span<const uint32_t> adjacency_offsets,
                         std::span<const uint32_t> adjacent_springs);

}  // namespace clothlab
