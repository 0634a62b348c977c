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

// An offset class (the springs of one second - first) this large takes colours of its own.
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
  const auto offset = [&](uint32_t k) { return second[k] - first[k]; };
  // The large offset classes first, class by class, each by first particle; then the rest in
  // index order. owner[c]: the class whose colour c is, kUncolored for a shared one.
  std::vector<uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return offset(a) != offset(b) ? offset(a) < offset(b) : first[a] < first[b];
  });
  std::vector<uint32_t> class_of(count, kUncolored);  // by spring: its large class's offset
  std::vector<uint32_t> rest;
  for (std::size_t p = 0; p < order.size();) {
    std::size_t q = p;
    while (q < order.size() && offset(order[q]) == offset(order[p])) ++q;
    if (q - p >= kOwnColorsFrom) {
      for (std::size_t r = p; r < q; ++r) class_of[order[r]] = offset(order[p]);
    } else {
      rest.insert(rest.end(), order.begin() + static_cast<std::ptrdiff_t>(p),
                  order.begin() + static_cast<std::ptrdiff_t>(q));
    }
    p = q;
  }
  std::sort(rest.begin(), rest.end());
  std::size_t large = 0;
  for (uint32_t k : order) large += class_of[k] != kUncolored;
  std::stable_partition(order.begin(), order.end(),
                        [&](uint32_t k) { return class_of[k] != kUncolored; });
  std::copy(rest.begin(), rest.end(), order.begin() + static_cast<std::ptrdiff_t>(large));

  std::vector<uint32_t> color_of(count, kUncolored);
  std::vector<uint32_t> seen_at;  // stamps start at 1: colour c taken for spring stamp - 1
  std::vector<uint32_t> owner;
  for (uint32_t k : order) {
    const uint32_t stamp = k + 1;
    for (uint32_t end : {first[k], second[k]}) {
      for (uint32_t e = adjacency_offsets[end]; e < adjacency_offsets[end + 1]; ++e) {
        const uint32_t other = color_of[adjacent_springs[e]];
        if (other != kUncolored) seen_at[other] = stamp;
      }
    }
    uint32_t color = 0;
    if (class_of[k] == kUncolored) {
      color = smallest_free(seen_at, stamp);
    } else {  // the smallest of its class's own colours free here, or a new one
      while (color < seen_at.size() && (owner[color] != class_of[k] || seen_at[color] == stamp))
        ++color;
      if (color == seen_at.size()) seen_at.push_back(0);
    }
    if (color == owner.size()) owner.push_back(class_of[k]);
    color_of[k] = color;
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
