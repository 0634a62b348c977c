#include <algorithm>
#include <clothlab/core/coloring.hpp>
#include <cstddef>
#include <numeric>

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

// An offset class (the springs of one second - first) this large takes two colours of its own.
constexpr std::size_t kOwnColorsFrom = 64;

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
  const auto count = static_cast<uint32_t>(first.size());
  const auto particles = static_cast<uint32_t>(adjacency_offsets.size() - 1);
  const auto offset = [&](uint32_t k) { return second[k] - first[k]; };
  std::vector<uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return offset(a) != offset(b) ? offset(a) < offset(b) : first[a] < first[b];
  });

  // A large class's springs share a particle only along its chains i, i + o, i + 2 o, ...:
  // two colours, alternating along each chain. A chain's start takes the parity of its index
  // neighbour in the class (the spring from i - 1, else the one from i + 1 if that one's chain
  // started earlier), so that runs of consecutive firsts keep one colour.
  std::vector<uint32_t> color_of(count, kUncolored);
  std::vector<uint32_t> class_at(particles, kUncolored);  // class stamp of the spring from i
  std::vector<uint8_t> parity_at(particles, 0);
  std::vector<uint32_t> rest;  // the small classes' springs
  uint32_t colors = 0;
  for (std::size_t p = 0; p < order.size();) {
    std::size_t q = p;
    while (q < order.size() && offset(order[q]) == offset(order[p])) ++q;
    if (q - p < kOwnColorsFrom) {
      rest.insert(rest.end(), order.begin() + static_cast<std::ptrdiff_t>(p),
                  order.begin() + static_cast<std::ptrdiff_t>(q));
      p = q;
      continue;
    }
    const uint32_t o = offset(order[p]), stamp = colors;  // unique per class
    enum : uint32_t { kMarked = 1u << 31 };               // in the class, parity not yet set
    for (std::size_t r = p; r < q; ++r) class_at[first[order[r]]] = stamp | kMarked;
    const auto colored = [&](uint32_t i) { return class_at[i] == stamp; };
    for (std::size_t r = p; r < q; ++r) {
      const uint32_t i = first[order[r]];
      uint8_t parity = 0;
      if (i >= o && colored(i - o)) {
        parity = static_cast<uint8_t>(parity_at[i - o] ^ 1);
      } else if (i > 0 && colored(i - 1)) {
        parity = parity_at[i - 1];
      } else if (i + 1 < particles && class_at[i + 1] == (stamp | kMarked) && i + 1 >= o &&
                 colored(i + 1 - o)) {
        parity = static_cast<uint8_t>(parity_at[i + 1 - o] ^ 1);  // the next spring's
      }
      parity_at[i] = parity;
      class_at[i] = stamp;
      color_of[order[r]] = colors + parity;
    }
    colors += 2;
    p = q;
  }

  // The rest in index order, each the smallest colour free at both its ends.
  std::sort(rest.begin(), rest.end());
  // Stamps start at 1: colour c is taken for spring k where seen_at[c] == k + 1.
  std::vector<uint32_t> seen_at(colors, 0);
  for (uint32_t k : rest) {
    const uint32_t stamp = k + 1;
    for (uint32_t end : {first[k], second[k]}) {
      for (uint32_t e = adjacency_offsets[end]; e < adjacency_offsets[end + 1]; ++e) {
        const uint32_t other = color_of[adjacent_springs[e]];
        if (other != kUncolored) seen_at[other] = stamp;
      }
    }
    color_of[k] = smallest_free(seen_at, stamp);
  }

  // Colours left empty (a class with no two springs on one chain) dropped.
  std::vector<uint32_t> renamed(seen_at.size(), kUncolored);
  for (uint32_t c : color_of) renamed[c] = 0;
  uint32_t used = 0;
  for (uint32_t& c : renamed)
    if (c == 0) c = used++;
  for (uint32_t& c : color_of) c = renamed[c];
  return group_by_color(color_of, used);
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
