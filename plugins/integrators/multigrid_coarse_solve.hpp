// The direct solve on the coarsest grid level: the free nodes' 3x3 blocks gathered into one
// dense matrix and factored by Cholesky (Eigen's LLT), storage sized once.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cstddef>
#include <vector>

#include "multigrid_level.hpp"

namespace clothlab::builtin {

class CoarseCholesky {
 public:
  explicit CoarseCholesky(const GridLevel& level) : dense_index_(level.node_count(), -1) {
    for (std::size_t i = 0; i < level.node_count(); ++i)
      if (!level.fixed(i)) {
        dense_index_[i] = static_cast<long>(free_nodes_.size());
        free_nodes_.push_back(i);
      }
    const auto size = static_cast<Eigen::Index>(3 * free_nodes_.size());
    matrix_.resize(size, size);
    rhs_.resize(size);
    cholesky_ = Eigen::LLT<Eigen::MatrixXd>(size);
  }

  // Factors the level's matrix; false where it is not positive definite.
  bool factor(const GridLevel& level) {
    matrix_.setZero();
    for (int r = 0; r < level.rows(); ++r)
      for (int c = 0; c < level.cols(); ++c) {
        const long row = dense_index_[level.node(r, c)];
        if (row < 0) continue;
        const GridLevel::Window w = level.window(r, c);
        const double* a = level.row_blocks(r, c);
        for (int r2 = w.row_begin; r2 < w.row_end; ++r2)
          for (int c2 = w.col_begin; c2 < w.col_end; ++c2, a += 9) {
            const long column = dense_index_[level.node(r2, c2)];
            if (column < 0) continue;
            for (int k = 0; k < 9; ++k) matrix_(3 * row + k / 3, 3 * column + k % 3) = a[k];
          }
      }
    cholesky_.compute(matrix_);
    return cholesky_.info() == Eigen::Success;
  }

  // Bytes of the dense matrix, its factor and the index arrays.
  std::size_t storage_bytes() const {
    return 2 * static_cast<std::size_t>(matrix_.size()) * sizeof(double) +
           static_cast<std::size_t>(rhs_.size()) * sizeof(double) +
           dense_index_.size() * sizeof(long) + free_nodes_.size() * sizeof(std::size_t);
  }

  // x = A^-1 b on the free nodes, 0 on fixed ones.
  void solve(const GridLevel& level, const double* b, double* x) {
    for (std::size_t k = 0; k < free_nodes_.size(); ++k)
      for (int d = 0; d < 3; ++d)
        rhs_(static_cast<Eigen::Index>(3 * k + d)) = b[3 * free_nodes_[k] + d];
    cholesky_.matrixL().solveInPlace(rhs_);
    cholesky_.matrixU().solveInPlace(rhs_);
    std::fill(x, x + 3 * level.node_count(), 0.0);
    for (std::size_t k = 0; k < free_nodes_.size(); ++k)
      for (int d = 0; d < 3; ++d)
        x[3 * free_nodes_[k] + d] = rhs_(static_cast<Eigen::Index>(3 * k + d));
  }

 private:
  std::vector<long> dense_index_;  // per node: its place among the free ones, -1 if fixed
  std::vector<std::size_t> free_nodes_;
  Eigen::MatrixXd matrix_;
  Eigen::VectorXd rhs_;
  Eigen::LLT<Eigen::MatrixXd> cholesky_;
};

}  // namespace clothlab::builtin
