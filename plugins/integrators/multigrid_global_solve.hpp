// projective_dynamics' global solve by multigrid instead of a factorisation (`factorization`
// = 2): the constant matrix A = M + h D + h^2 K, a scalar matrix acting alike on x, y and z,
// goes into the fine level of the grid hierarchy (multigrid_hierarchy.hpp) as A_ij times the
// 3x3 identity, the hierarchy's Galerkin levels and factors are built once per step size, and
// a solve repeats V-cycles (multigrid_cycle.hpp) in correction form,
//   x <- x + B (b - A x),
// from the caller's guess (the previous local/global iterate) until
// |b - A x| <= tolerance |b - A x0| (Euclidean norms over the three coordinates) or
// `max_cycles` have run. x0 is the caller's origin (the step's start positions): the tolerance
// then scales with the step's forces, b - A x0, and not with how far the cloth sits from the
// coordinates' origin (relative to |b| a translated cloth would solve more loosely). The V-cycle is
// a convergent stationary iteration for a positive definite A (symmetric Gauss-Seidel smoothing,
// Galerkin coarse correction), so no Krylov method is needed around it. Storage and setup grow
// linearly with the grid; every buffer is sized in the constructor, so neither `factorize` nor
// `solve` allocates. The unknowns are rows of a row-major n x 3 array, unknown u on grid node
// node_of[u]; the hierarchy works in node order, so a solve gathers and scatters once.
#pragma once

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "multigrid_cycle.hpp"
#include "multigrid_hierarchy.hpp"

namespace clothlab::builtin {

// projective_dynamics' defaults for the multigrid solve.
constexpr double kDefaultGlobalSolveTolerance = 1e-6;
constexpr long kDefaultGlobalSolveMaxCycles = 100;

class MultigridGlobalSolve {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  struct Outcome {
    long cycles;      // V-cycles run
    double residual;  // |b - A x| / |b - A x0| at the end (0 where b = A x0)
    bool converged;   // residual <= tolerance
  };

  // sizes: the levels (plan_levels); fixed: per grid node, 1 where no unknown lives (a pin);
  // node_of: per unknown, its grid node r * cols + c.
  MultigridGlobalSolve(const std::vector<GridSize>& sizes, std::vector<uint8_t> fixed,
                       std::vector<uint32_t> node_of, long sweeps, double tolerance,
                       long max_cycles, int threads)
      : hierarchy_(sizes, std::move(fixed), GridLevel::Blocks::exact),
        cycle_(hierarchy_, sweeps, threads),
        node_of_(std::move(node_of)),
        tolerance_(tolerance),
        max_cycles_(max_cycles),
        rhs_(3 * hierarchy_.level(0).node_count(), 0.0),
        solution_(rhs_.size(), 0.0),
        shifted_rhs_(rhs_.size(), 0.0),
        residual_(rhs_.size(), 0.0) {}
  MultigridGlobalSolve(const MultigridGlobalSolve&) = delete;
  MultigridGlobalSolve& operator=(const MultigridGlobalSolve&) = delete;

  // A's upper triangle (in the unknowns' numbering) into the fine level, then the coarse
  // levels and factors. An empty string on success, else why it failed in one line.
  std::string factorize(const Matrix& upper) {
    GridLevel& fine = hierarchy_.level(0);
    fine.clear();
    for (int column = 0; column < upper.outerSize(); ++column)
      for (Matrix::InnerIterator entry(upper, column); entry; ++entry) {
        if (entry.row() > column) continue;  // the upper triangle only
        const uint32_t a = node_of_[static_cast<std::size_t>(entry.row())];
        const uint32_t b = node_of_[static_cast<std::size_t>(column)];
        const int ra = static_cast<int>(a) / fine.cols(), ca = static_cast<int>(a) % fine.cols();
        const int rb = static_cast<int>(b) / fine.cols(), cb = static_cast<int>(b) % fine.cols();
        if (std::abs(ra - rb) > GridLevel::reach || std::abs(ca - cb) > GridLevel::reach)
          return "multigrid: the matrix couples grid nodes " + std::to_string(a) + " and " +
                 std::to_string(b) + ", more than 2 grid spacings apart";
        add_identity(fine.block(ra, ca, rb, cb), entry.value());
        if (a != b) add_identity(fine.block(rb, cb, ra, ca), entry.value());
      }
    if (!hierarchy_.rebuild())
      return "not positive definite: a diagonal block or the coarsest level's Cholesky failed "
             "(multigrid)";
    return {};
  }

  // x = A^-1 b to the tolerance, from the guess in x, the tolerance relative to b - A origin;
  // b, origin and x row-major n x 3. Solves A (x - origin) = b - A origin.
  Outcome solve(const double* b, const double* origin, double* x) {
    const GridLevel& fine = hierarchy_.level(0);
    for (std::size_t u = 0; u < node_of_.size(); ++u)
      for (std::size_t k = 0; k < 3; ++k) {
        rhs_[3 * node_of_[u] + k] = b[3 * u + k];
        solution_[3 * node_of_[u] + k] = origin[3 * u + k];
      }
    fine.residual(rhs_.data(), solution_.data(), shifted_rhs_.data(), cycle_.threads());
    for (std::size_t u = 0; u < node_of_.size(); ++u)
      for (std::size_t k = 0; k < 3; ++k)
        solution_[3 * node_of_[u] + k] = x[3 * u + k] - origin[3 * u + k];
    const double rhs_norm = norm(shifted_rhs_);
    Outcome outcome{0, 0.0, true};
    if (rhs_norm == 0.0) {
      std::fill(solution_.begin(), solution_.end(), 0.0);
    } else {
      for (;; ++outcome.cycles) {
        fine.residual(shifted_rhs_.data(), solution_.data(), residual_.data(), cycle_.threads());
        outcome.residual = norm(residual_) / rhs_norm;
        outcome.converged = outcome.residual <= tolerance_;
        if (outcome.converged || outcome.cycles == max_cycles_ || !std::isfinite(outcome.residual))
          break;
        std::copy(residual_.begin(), residual_.end(), cycle_.fine_rhs());
        const double* correction = cycle_.apply();
        for (std::size_t k = 0; k < solution_.size(); ++k) solution_[k] += correction[k];
      }
    }
    for (std::size_t u = 0; u < node_of_.size(); ++u)
      for (std::size_t k = 0; k < 3; ++k)
        x[3 * u + k] = origin[3 * u + k] + solution_[3 * node_of_[u] + k];
    return outcome;
  }

  std::size_t level_count() const { return hierarchy_.level_count(); }
  // Bytes of the hierarchy (every level's matrix and factors) and of the solve's vectors.
  std::size_t storage_bytes() const {
    return hierarchy_.storage_bytes() + cycle_.storage_bytes() + 4 * rhs_.size() * sizeof(double) +
           node_of_.size() * sizeof(uint32_t);
  }

 private:
  static void add_identity(double* block, double value) {
    block[0] += value, block[4] += value, block[8] += value;
  }
  static double norm(const std::vector<double>& v) {
    double sum = 0.0;
    for (double value : v) sum += value * value;
    return std::sqrt(sum);
  }

  MultigridHierarchy hierarchy_;
  VCycle cycle_;  // its threads run the residuals too
  std::vector<uint32_t> node_of_;
  double tolerance_;
  long max_cycles_;
  // 3 per grid node, node order: b, x - origin, b - A origin, the cycle's residual.
  std::vector<double> rhs_, solution_, shifted_rhs_, residual_;
};

}  // namespace clothlab::builtin
