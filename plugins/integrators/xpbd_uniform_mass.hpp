// The grid's common inverse mass and, per row, the columns of another: most cloths are all
// one mass but a few pins, and runs of springs and particles inside the common part need
// not read their inverse masses (xpbd_row_kernel.hpp, the grid sweep's predict and velocity
// passes).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include "xpbd_grid.hpp"

namespace clothlab::builtin {

// Columns [begin, end) of a grid row that hull its particles of another inverse mass than
// the grid's uniform one; begin >= end: none.
struct ColumnSpan {
  uint32_t begin, end;
};

class UniformInverseMass {
 public:
  // The inverse mass of the grid's middle particle, taken as the uniform one, and each
  // row's columns of another.
  template <class Real>
  void find(const Real* inverse_mass, uint32_t rows, uint32_t cols) {
    cols_ = cols;
    const Real uniform = inverse_mass[std::size_t{rows / 2} * cols + cols / 2];
    value_ = uniform;
    varied_columns_.assign(rows, ColumnSpan{cols, 0});
    for (uint32_t r = 0; r < rows; ++r)
      for (uint32_t c = 0; c < cols; ++c)
        if (inverse_mass[std::size_t{r} * cols + c] != uniform) {
          ColumnSpan& span = varied_columns_[r];
          span.begin = std::min(span.begin, c);
          span.end = std::max(span.end, c + 1);
        }
  }

  double value() const { return value_; }  // exact in the Real it was found in

  // Calls run(begin, count, all_free) on the columns of `row` in up to three runs: before
  // and after its span of another inverse mass with std::true_type when the uniform one
  // is not 0 (no particle there is pinned), the span itself (or all) with std::false_type.
  // Every run is at least min_run columns long where the row is: the span widens, and takes
  // in a shorter run beside it (a run of whole blocks of lanes needs no masked stores).
  template <class Run>
  void for_free_runs(uint32_t row, uint32_t min_run, Run&& run) const {
    const uint32_t cols = cols_;
    ColumnSpan span = varied_columns_[row];
    if (value_ == 0) {
      run(0, cols, std::false_type{});
      return;
    }
    if (span.begin >= span.end) {
      run(0, cols, std::true_type{});
      return;
    }
    const uint32_t width = std::min(min_run, cols);
    if (span.end - span.begin < width) {
      span.end = std::min(cols, span.begin + width);
      span.begin = span.end - width;
    }
    if (span.begin < min_run) span.begin = 0;
    if (cols - span.end < min_run) span.end = cols;
    if (span.begin > 0) run(0, span.begin, std::true_type{});
    run(span.begin, span.end - span.begin, std::false_type{});
    if (span.end < cols) run(span.end, cols - span.end, std::true_type{});
  }

  // The positions of colour `color`'s springs from `row` (from column col_begin) with an
  // end of another inverse mass: the hull of the start row's and the partner row's spans.
  std::pair<std::size_t, std::size_t> varied_positions(const GridColor& color, uint32_t row) const {
    int64_t begin = std::numeric_limits<int64_t>::max(), end = 0;
    const auto add = [&](const ColumnSpan& span, int64_t start_column_offset) {
      if (span.begin >= span.end) return;
      begin = std::min(begin, int64_t{span.begin} - start_column_offset);
      end = std::max(end, int64_t{span.end} - start_column_offset);
    };
    add(varied_columns_[row], color.col_begin);
    add(varied_columns_[row + color.row_step], int64_t{color.col_begin} + color.col_step);
    if (begin >= end) return {0, 0};
    return {static_cast<std::size_t>(std::max<int64_t>(begin, 0)), static_cast<std::size_t>(end)};
  }

 private:
  double value_ = 0;
  uint32_t cols_ = 0;
  std::vector<ColumnSpan> varied_columns_;  // per grid row
};

}  // namespace clothlab::builtin
