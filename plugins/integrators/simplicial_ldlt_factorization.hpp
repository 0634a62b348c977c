// Eigen's SimplicialLDLT for projective dynamics' constant matrix (projective_dynamics.cpp),
// given as its upper triangle already in elimination order, with a solve of all three
// coordinates in one sweep over the factor each way.
#pragma once

#include <Eigen/SparseCholesky>
#include <cstddef>
#include <string>

namespace clothlab::builtin {

class SimplicialLdltFactorization {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  // The symbolic analysis, and the diagonal's storage, which the first factorisation would
  // otherwise allocate.
  void analyze(const Matrix& upper) {
    factor_.analyze(upper);
    factor_.reserve_diagonal(upper.rows());
  }

  // An empty string on success, else why it failed (a zero or negative pivot: the matrix is
  // not positive definite, where LDL^T would otherwise carry on).
  std::string factorize(const Matrix& upper) {
    factor_.refactorize(upper);
    if (factor_.info() != Eigen::Success) return "zero pivot (Eigen SimplicialLDLT)";
    const Eigen::VectorXd& diagonal = factor_.diagonal();
    for (Eigen::Index j = 0; j < diagonal.size(); ++j)
      if (!(diagonal[j] > 0.0))
        return "not positive definite: pivot " + std::to_string(j) + " of " +
               std::to_string(diagonal.size()) + " is " + std::to_string(diagonal[j]) +
               " (Eigen SimplicialLDLT)";
    return {};
  }

  // x = (L D L^T)^-1 x for x row-major n x 3 (a row per unknown), all three columns in one
  // sweep over L each way (Eigen's solve sweeps L once per column, three times the traffic).
  void solve_in_place(double* x) const {
    const Matrix& lower = factor_.lower();
    const Eigen::VectorXd& diagonal = factor_.diagonal();
    const int* column_start = lower.outerIndexPtr();
    const int* row = lower.innerIndexPtr();
    const double* value = lower.valuePtr();
    const auto count = static_cast<int>(lower.cols());
    for (int j = 0; j < count; ++j) {  // L y = b, L unit lower triangular
      const double x0 = x[3 * j], x1 = x[3 * j + 1], x2 = x[3 * j + 2];
      for (int p = column_start[j]; p < column_start[j + 1]; ++p) {
        if (row[p] <= j) continue;  // the unit diagonal
        double* target = &x[3 * row[p]];
        target[0] -= value[p] * x0, target[1] -= value[p] * x1, target[2] -= value[p] * x2;
      }
    }
    for (int j = 0; j < count; ++j)
      for (int k = 0; k < 3; ++k) x[3 * j + k] /= diagonal[j];
    for (int j = count - 1; j >= 0; --j) {  // L^T x = y
      double x0 = x[3 * j], x1 = x[3 * j + 1], x2 = x[3 * j + 2];
      for (int p = column_start[j]; p < column_start[j + 1]; ++p) {
        if (row[p] <= j) continue;
        const double* source = &x[3 * row[p]];
        x0 -= value[p] * source[0], x1 -= value[p] * source[1], x2 -= value[p] * source[2];
      }
      x[3 * j] = x0, x[3 * j + 1] = x1, x[3 * j + 2] = x2;
    }
  }

  // Bytes of the factor: L's values and row indices, its column starts, and D.
  std::size_t factor_bytes() const {
    const Matrix& lower = factor_.lower();
    return static_cast<std::size_t>(lower.nonZeros()) * (sizeof(double) + sizeof(int)) +
           static_cast<std::size_t>(lower.cols() + 1) * sizeof(int) +
           static_cast<std::size_t>(factor_.diagonal().size()) * sizeof(double);
  }

 private:
  // SimplicialLDLT's numeric factorisation of a matrix already in elimination order. Its
  // public factorize() first builds a (here identical) reordered copy, which allocates;
  // factorize_preordered, the step it then runs, is protected, hence the subclass. That
  // step's workspace (3 arrays of n) is on the stack up to Eigen's
  // EIGEN_STACK_ALLOCATION_LIMIT (16384 unknowns), on the heap above it.
  class Preordered
      : public Eigen::SimplicialLDLT<Matrix, Eigen::Upper, Eigen::NaturalOrdering<int>> {
   public:
    void analyze(const Matrix& upper) { this->analyzePattern(upper); }
    void reserve_diagonal(Eigen::Index n) { this->m_diag.resize(n); }
    void refactorize(const Matrix& upper) { this->template factorize_preordered<true>(upper); }
    // The factors by reference (matrixL() is a view, but vectorD() returns a copy).
    const Matrix& lower() const { return this->m_matrix; }
    const Eigen::VectorXd& diagonal() const { return this->m_diag; }
  };
  Preordered factor_;
};

}  // namespace clothlab::builtin
