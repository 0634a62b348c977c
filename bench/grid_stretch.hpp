// The warp/weft stretch of a rows x cols grid cloth from its positions alone, so that two
// engines' cloths are judged by one measure: length over rest length of every structural
// neighbour pair (along a row and along a column), and the nearest-rank percentile of those
// ratios, as Cloth::stretch_percentile(Springs::Structural, fraction) computes it from the
// engine's own state.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace clothlab::bench {

// xyz: 3 values per particle, particle r * cols + c. Rest lengths: column_spacing along a
// row, row_spacing along a column. fraction in (0, 1]; 1 without pairs.
inline double warp_weft_stretch_percentile(const std::vector<double>& xyz, uint32_t rows,
                                           uint32_t cols, double row_spacing, double column_spacing,
                                           double fraction) {
  std::vector<double> ratios;
  ratios.reserve(2 * std::size_t{rows} * cols);
  const auto length = [&](std::size_t a, std::size_t b) {
    return std::hypot(xyz[3 * a] - xyz[3 * b], xyz[3 * a + 1] - xyz[3 * b + 1],
                      xyz[3 * a + 2] - xyz[3 * b + 2]);
  };
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c) {
      const std::size_t i = std::size_t{r} * cols + c;
      if (c + 1 < cols) ratios.push_back(length(i, i + 1) / column_spacing);
      if (r + 1 < rows) ratios.push_back(length(i, i + cols) / row_spacing);
    }
  if (ratios.empty()) return 1.0;
  const auto count = static_cast<double>(ratios.size());
  const auto rank = static_cast<std::size_t>(std::max(1.0, std::ceil(fraction * count)));
  const auto nth = ratios.begin() + static_cast<std::ptrdiff_t>(rank - 1);
  std::nth_element(ratios.begin(), nth, ratios.end());
  return *nth;
}

}  // namespace clothlab::bench
