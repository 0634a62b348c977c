// Coloured block Gauss-Seidel on a grid level: x_i = A_ii^-1 (b_i - sum_{j != i} A_ij x_j), one
// colour of nodes at a time. A row couples nodes up to GridLevel::reach = 2 spacings away, so
// the colour (r mod 3, c mod 3) leaves no two coupled nodes in one colour: nine colours (red/
// black or four colours would need nearest-neighbour coupling only, which the flexion springs
// break). Nodes of one colour are independent, so the result is the same whatever order or
// thread updates them. The rows of one class r mod 3 do not couple either, so a sweep takes
// one class at a time, split among `threads` (the same bits on any count), each row through
// its three colours.
// `forward` sweeps the colours 0..8, `backward` 8..0: the backward sweep is the forward one's
// adjoint in the A inner product, which makes a V-cycle with forward pre- and backward
// post-smoothing a symmetric preconditioner.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "multigrid_level.hpp"

namespace clothlab::builtin {

class BlockGaussSeidel {
 public:
  static constexpr int kPeriod = GridLevel::reach + 1;

  explicit BlockGaussSeidel(const GridLevel& level) : inverse_diagonal_(9 * level.node_count()) {}

  // Inverts the level's diagonal blocks; false where one of a free node is not positive definite.
  bool factor(const GridLevel& level) {
    for (int r = 0; r < level.rows(); ++r)
      for (int c = 0; c < level.cols(); ++c) {
        const std::size_t i = level.node(r, c);
        if (level.fixed(i)) continue;
        if (!invert_positive_definite(level.block(r, c, r, c), &inverse_diagonal_[9 * i]))
          return false;
      }
    return true;
  }

  std::size_t storage_bytes() const { return inverse_diagonal_.size() * sizeof(double); }

  void forward(const GridLevel& level, const double* b, double* x, int threads = 1) const {
    for (int row_class = 0; row_class < kPeriod; ++row_class)
      sweep_rows(level, row_class, false, b, x, threads);
  }
  void backward(const GridLevel& level, const double* b, double* x, int threads = 1) const {
    for (int row_class = kPeriod - 1; row_class >= 0; --row_class)
      sweep_rows(level, row_class, true, b, x, threads);
  }

 private:
  // The colours (row_class, 0..2), or 2..0 where backward, one row at a time. Rows of one class
  // are 3 apart and do not couple, so this updates each node from the same values as sweeping
  // each colour over the whole level in turn, while a row's blocks stay in the cache for its
  // three colours.
  void sweep_rows(const GridLevel& level, int row_class, bool backward, const double* b, double* x,
                  int threads) const {
    const int row_count = (level.rows() - row_class + kPeriod - 1) / kPeriod;
    level.for_each_index(row_count, threads, [&](int k) {
      const int r = row_class + k * kPeriod;
      for (int step = 0; step < kPeriod; ++step)
        update_colour(level, r, backward ? kPeriod - 1 - step : step, b, x);
    });
  }

  // x_i for the nodes of row r in columns col_class, col_class + 3, ...
  void update_colour(const GridLevel& level, int r, int col_class, const double* b,
                     double* x) const {
    for (int c = col_class; c < level.cols(); c += kPeriod) {
      const std::size_t i = level.node(r, c);
      if (level.fixed(i)) continue;
      double sum[3] = {b[3 * i], b[3 * i + 1], b[3 * i + 2]};
      level.subtract_row_product(r, c, x, sum, true);
      const double* d = &inverse_diagonal_[9 * i];
      for (int j = 0; j < 3; ++j)
        x[3 * i + j] = d[3 * j] * sum[0] + d[3 * j + 1] * sum[1] + d[3 * j + 2] * sum[2];
    }
  }

  // out = a^-1 for a symmetric 3x3 block (row-major); false unless a is positive definite.
  static bool invert_positive_definite(const double* a, double* out) {
    const std::array<double, 9> cofactor{
        a[4] * a[8] - a[5] * a[7], a[2] * a[7] - a[1] * a[8], a[1] * a[5] - a[2] * a[4],
        a[5] * a[6] - a[3] * a[8], a[0] * a[8] - a[2] * a[6], a[2] * a[3] - a[0] * a[5],
        a[3] * a[7] - a[4] * a[6], a[1] * a[6] - a[0] * a[7], a[0] * a[4] - a[1] * a[3]};
    const double determinant = a[0] * cofactor[0] + a[1] * cofactor[3] + a[2] * cofactor[6];
    // Sylvester: the leading minors of a positive definite block are positive.
    if (!(a[0] > 0.0 && cofactor[8] > 0.0 && determinant > 0.0)) return false;
    for (int k = 0; k < 9; ++k) out[k] = cofactor[k] / determinant;
    return true;
  }

  std::vector<double> inverse_diagonal_;  // 9 per node
};

}  // namespace clothlab::builtin
