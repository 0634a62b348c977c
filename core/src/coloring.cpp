#include <clothlab/core/coloring.hpp>

namespace clothlab {
namespace {

// The smallest colour not marked for `stamp` in `seen_at` (marks: colour -> last stamp), grown
// as colours are added.
uint32_t smallest_free(std::vector<uint32_t>& seen_at, uint32_t stamp) {
  uint32_t color = 0;
  while (color < seen_at.size() && seen_at[color] == stamp) ++color;
  if (color == seen_at.size()) seen_at.push_back(0);
  return color;
}

constexpr uint32_t kUncolored = ~0u;

}  // namespace

Coloring group_by_color(std::span<const uint32_t> color_of, uint32_t colors) {
  Coloring out;
  out.offsets.assign(colors + 1, 0);
  for (uint32_t color : color_of) ++out.offsets[color + 1];
  for (uint32_t c = 0; c < colors; ++c) out.offsets[c + 1] += out.offsets[c];
  out.members.resize(color_of.size());
  std::vector<uint32_t> next(out.offsets.begin(), out.offsets.end() - 1);
  for (uint32_t item = 0; item < color_of.size(); ++item)
    out.members[next[color_of[item]]++] = item;
  return out;
}

Coloring color_springs(std::span<const uint32_t> first, std::span<const uint32_t> second,
                       std::span<const uint32_t> adjacency_offsets,
                       std::span<const uint32_t> adjacent_springs) {
  std::vector<uint32_t> color_of(first.size(), kUncolored);
  std::vector<uint32_t> seen_at;  // stamps start at 1: colour c taken for spring stamp - 1
  for (uint32_t k = 0; k < first.size(); ++k) {
    const uint32_t stamp = k + 1;
    for (uint32_t end : {first[k], second[k]}) {
      for (uint32_t e = adjacency_offsets[end]; e < adjacency_offsets[end + 1]; ++e) {
        const uint32_t other = color_of[adjacent_springs[e]];
        if (other != kUncolored) seen_at[other] = stamp;
      }
    }
    color_of[k] = smallest_free(seen_at, stamp);
  }
  return group_by_color(color_of, static_cast<uint32_t>(seen_at.size()));
}

Coloring color_particles(std::span<const uint32_t> first, std::span<const uint32_t> second,
                         std::span<const uint32_t> adjacency_offsets,
                         std::span<const uint32_t> adjacent_springs) {
  const auto n = static_cast<uint32_t>(adjacency_offsets.size() - 1);
  std::vector<uint32_t> color_of(n, kUncolored);
  std::vector<uint32_t> seen_at;
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t stamp = i + 1;
    for (uint32_t e = adjacency_offsets[i]; e < adjacency_offsets[i + 1]; ++e) {
      const uint32_t spring = adjacent_springs[e];
      const uint32_t partner = first[spring] == i ? second[spring] : first[spring];
      if (color_of[partner] != kUncolored) seen_at[color_of[partner]] = stamp;
    }
    color_of[i] = smallest_free(seen_at, stamp);
  }
  return group_by_color(color_of, static_cast<uint32_t>(seen_at.size()));
}

}  // namespace clothlab
