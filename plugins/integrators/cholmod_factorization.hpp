// SuiteSparse CHOLMOD's supernodal Cholesky for projective dynamics' constant matrix
// (projective_dynamics.cpp), given as its upper triangle already in elimination order (the
// plugin's AMD order, kept: CHOLMOD's natural ordering, then its elimination-tree postorder).
// The three coordinates are one n x 3 right-hand side, solved by dense kernels per
// supernode. The right-hand side, solution and solve workspace are allocated once and reused
// by cholmod_solve2; a numeric factorisation allocates (CHOLMOD's update workspace).
#pragma once

#include <cholmod.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <cstddef>
#include <new>
#include <string>

namespace clothlab::builtin {

class CholmodFactorization {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  CholmodFactorization() {
    cholmod_start(&common_);
    common_.supernodal = CHOLMOD_SUPERNODAL;
    common_.nmethods = 1;
    common_.method[0].ordering = CHOLMOD_NATURAL;
    common_.print = 0;  // failures are reported by the caller, in one line
  }
  CholmodFactorization(const CholmodFactorization&) = delete;
  CholmodFactorization& operator=(const CholmodFactorization&) = delete;
  ~CholmodFactorization() {
    release();
    cholmod_finish(&common_);
  }

  // The symbolic analysis of `upper`'s pattern, and the solve's buffers.
  void analyze(const Matrix& upper) {
    release();
    const auto n = static_cast<std::size_t>(upper.rows());
    matrix_ = cholmod_allocate_sparse(n, n, static_cast<std::size_t>(upper.nonZeros()), 1, 1, 1,
                                      CHOLMOD_REAL, &common_);
    if (matrix_ == nullptr) throw std::bad_alloc();
    std::copy_n(upper.outerIndexPtr(), n + 1, static_cast<int*>(matrix_->p));
    std::copy_n(upper.innerIndexPtr(), upper.nonZeros(), static_cast<int*>(matrix_->i));
    factor_ = cholmod_analyze(matrix_, &common_);
    rhs_ = cholmod_allocate_dense(n, 3, n, CHOLMOD_REAL, &common_);
    if (factor_ == nullptr || rhs_ == nullptr) throw std::bad_alloc();
  }

  // An empty string on success, else why it failed.
  std::string factorize(const Matrix& upper) {
    std::copy_n(upper.valuePtr(), upper.nonZeros(), static_cast<double*>(matrix_->x));
    const int done = cholmod_factorize(matrix_, factor_, &common_);
    if (common_.status == CHOLMOD_NOT_POSDEF)
      return "not positive definite: pivot " + std::to_string(factor_->minor) + " of " +
             std::to_string(factor_->n) + " (CHOLMOD)";
    if (!done || common_.status != CHOLMOD_OK)
      return "CHOLMOD status " + std::to_string(common_.status);
    // A first solve sizes the solution and workspace, so that later solves do not allocate.
    cholmod_solve2(CHOLMOD_A, factor_, rhs_, nullptr, &solution_, nullptr, &workspace_y_,
                   &workspace_e_, &common_);
    return {};
  }

  // x = A^-1 x for x row-major n x 3 (a row per unknown).
  void solve_in_place(double* x) {
    const std::size_t n = factor_->n;
    auto* rhs = static_cast<double*>(rhs_->x);
    for (std::size_t u = 0; u < n; ++u)
      for (std::size_t k = 0; k < 3; ++k) rhs[k * n + u] = x[3 * u + k];
    cholmod_solve2(CHOLMOD_A, factor_, rhs_, nullptr, &solution_, nullptr, &workspace_y_,
                   &workspace_e_, &common_);
    const auto* solution = static_cast<const double*>(solution_->x);
    for (std::size_t u = 0; u < n; ++u)
      for (std::size_t k = 0; k < 3; ++k) x[3 * u + k] = solution[k * n + u];
  }

  // Bytes of the supernodal factor: its values, row indices, per-supernode index arrays and
  // per-column arrays (permutation, counts).
  std::size_t factor_bytes() const {
    return factor_->xsize * sizeof(double) + factor_->ssize * sizeof(int) +
           3 * (factor_->nsuper + 1) * sizeof(int) + 2 * factor_->n * sizeof(int);
  }
  // CHOLMOD's own peak of everything it allocated (the factor, the matrix, workspaces).
  std::size_t peak_bytes() const { return common_.memory_usage; }

 private:
  void release() {
    cholmod_free_factor(&factor_, &common_);
    cholmod_free_sparse(&matrix_, &common_);
    for (cholmod_dense** dense : {&rhs_, &solution_, &workspace_y_, &workspace_e_})
      cholmod_free_dense(dense, &common_);
  }

  cholmod_common common_{};
  cholmod_sparse* matrix_ = nullptr;
  cholmod_factor* factor_ = nullptr;
  cholmod_dense* rhs_ = nullptr;
  cholmod_dense* solution_ = nullptr;
  cholmod_dense* workspace_y_ = nullptr;
  cholmod_dense* workspace_e_ = nullptr;
};

}  // namespace clothlab::builtin
