// The two triangles of a grid cell, shared by the kernels that act on the cloth's surface.
//
// Cell c of a row has corners a = c, b = c + 1 in this row and c' = c, d = c + 1 in the next;
// its triangles are (a, b, c') and (b, d, c'), each given by the edges from its first corner.
#pragma once

#include <cstddef>

#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

// The corners of cell c from a row and the next, whose components lie `span` apart.
template <class Real>
inline void load_cell_corners(const Real* row, const Real* below, std::size_t c, std::size_t span,
                              Real (&a)[3], Real (&b)[3], Real (&c_below)[3], Real (&d)[3]) {
  for (std::size_t k = 0; k < 3; ++k) {
    a[k] = row[c + k * span];
    b[k] = row[c + 1 + k * span];
    c_below[k] = below[c + k * span];
    d[k] = below[c + 1 + k * span];
  }
}

// Edges ab, ac' of the first triangle and bd, bc' of the second.
template <class Lane>
inline void cell_triangle_edges(const Lane (&a)[3], const Lane (&b)[3], const Lane (&c_below)[3],
                                const Lane (&d)[3], Lane (&ab)[3], Lane (&ac)[3], Lane (&bd)[3],
                                Lane (&bc)[3]) {
  for (int k = 0; k < 3; ++k) {
    ab[k] = b[k] - a[k];
    ac[k] = c_below[k] - a[k];
    bd[k] = d[k] - b[k];
    bc[k] = c_below[k] - b[k];
  }
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
