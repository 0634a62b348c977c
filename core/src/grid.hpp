// Geometry of the regular grid cloth: initial layout and the Provot spring stencils.
#pragma once

#include <array>
#include <clothlab/core/cloth.hpp>
#include <cmath>
#include <cstdint>

namespace clothlab::detail {

// A spring family as a stencil: particle (r, c) connects to (r + row_step, c + col_step).
struct Stencil {
  uint32_t row_step;
  int32_t col_step;
  SpringFamily Scene::*family;
};

inline constexpr std::array<Stencil, 6> kProvotStencils{{
    {0, 1, &Scene::structural},
    {1, 0, &Scene::structural},
    {1, 1, &Scene::shear},
    {1, -1, &Scene::shear},
    {0, 2, &Scene::flexion},
    {2, 0, &Scene::flexion},
}};

// Springs of one stencil start at rows [0, row_end) and columns [col_begin, col_end).
struct StencilExtent {
  uint32_t row_end = 0;
  uint32_t col_begin = 0;
  uint32_t col_end = 0;
  uint64_t count() const {
    return col_end > col_begin ? uint64_t{row_end} * (col_end - col_begin) : 0;
  }
};

inline StencilExtent stencil_extent(const Stencil& stencil, uint32_t rows, uint32_t cols) {
  StencilExtent extent;
  extent.row_end = rows > stencil.row_step ? rows - stencil.row_step : 0;
  if (stencil.col_step >= 0) {
    const auto step = static_cast<uint32_t>(stencil.col_step);
    extent.col_end = cols > step ? cols - step : 0;
  } else {
    extent.col_begin = static_cast<uint32_t>(-stencil.col_step);
    extent.col_end = cols;
  }
  return extent;
}

// Index distance from a spring's first particle to its second.
inline int64_t stencil_offset(const Stencil& stencil, uint32_t cols) {
  return int64_t{stencil.row_step} * cols + stencil.col_step;
}

inline Vec3 initial_position(const Scene& scene, uint32_t row, uint32_t col) {
  const double along_cols = col * scene.column_spacing();
  const double along_rows = row * scene.row_spacing();
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    p[k] = scene.origin[k] + along_cols * scene.col_axis[k] + along_rows * scene.row_axis[k];
  }
  return p;
}

// Every spring of a stencil has the same rest length on the regular initial layout.
inline double stencil_rest_length(const Scene& scene, const Stencil& stencil) {
  const double along_cols = stencil.col_step * scene.column_spacing();
  const double along_rows = stencil.row_step * scene.row_spacing();
  double squared = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = along_cols * scene.col_axis[k] + along_rows * scene.row_axis[k];
    squared += d * d;
  }
  return std::sqrt(squared);
}

}  // namespace clothlab::detail
