// A triangle mesh's edges as the sorted list of their uses by triangles (the validation's
// non-manifold check and the mesh builder's spring derivation), and a triangle's size.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace clothlab::detail {

// One triangle's use of an edge: the edge (a < b) as key a << 32 | b, the triangle, and the
// triangle's corner opposite the edge.
struct EdgeUse {
  uint64_t key;
  uint32_t triangle;
  uint32_t opposite;
  uint32_t a() const { return static_cast<uint32_t>(key >> 32); }
  uint32_t b() const { return static_cast<uint32_t>(key); }
};

inline uint64_t edge_key(uint32_t i, uint32_t j) {
  return i < j ? uint64_t{i} << 32 | j : uint64_t{j} << 32 | i;
}

// Sorted by edge, then by triangle: the uses of one edge are adjacent.
inline std::vector<EdgeUse> edge_uses(std::span<const uint32_t> triangles) {
  std::vector<EdgeUse> uses;
  uses.reserve(triangles.size());
  for (uint32_t t = 0; t < triangles.size() / 3; ++t) {
    const uint32_t* c = triangles.data() + 3 * std::size_t{t};
    uses.push_back({edge_key(c[0], c[1]), t, c[2]});
    uses.push_back({edge_key(c[1], c[2]), t, c[0]});
    uses.push_back({edge_key(c[2], c[0]), t, c[1]});
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& l, const EdgeUse& r) {
    return l.key != r.key ? l.key < r.key : l.triangle < r.triangle;
  });
  return uses;
}

struct TriangleShape {
  double double_area = 0;  // |e1 x e2|
  double longest_edge_squared = 0;
};

inline TriangleShape triangle_shape(std::span<const double> positions, const uint32_t* corner) {
  double edge[3][3];
  for (int e = 0; e < 3; ++e)
    for (int k = 0; k < 3; ++k)
      edge[e][k] = positions[3 * std::size_t{corner[(e + 1) % 3]} + k] -
                   positions[3 * std::size_t{corner[e]} + k];
  const double n[3] = {edge[0][1] * edge[2][2] - edge[0][2] * edge[2][1],
                       edge[0][2] * edge[2][0] - edge[0][0] * edge[2][2],
                       edge[0][0] * edge[2][1] - edge[0][1] * edge[2][0]};
  TriangleShape shape;
  shape.double_area = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (const auto& d : edge)
    shape.longest_edge_squared =
        std::max(shape.longest_edge_squared, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return shape;
}

}  // namespace clothlab::detail
