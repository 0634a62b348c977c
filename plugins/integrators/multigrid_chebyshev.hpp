// Chebyshev smoothing on block-Jacobi for a grid level: x <- x + p(D^-1 A) D^-1 (b - A x), D the
// diagonal blocks, p the Chebyshev polynomial of degree `sweeps` - 1 that damps D^-1 A's
// eigenvalues in [lambda_max / kChebyshevRatio, lambda_max] (the smooth rest is the coarser
// levels'). lambda_max is a block Gershgorin bound: an estimate from below (power iteration)
// would let the polynomial amplify the stiffest modes. Pre- and post-smoothing apply the same
// polynomial, whose error propagation I - p(D^-1 A) D^-1 A is self-adjoint in the A inner
// product, so a V-cycle that smooths with it on both sides is symmetric.
//
// Where Gauss-Seidel updates a node from its neighbours' newest values, a Chebyshev step reads
// only the last iterate: a step is one product pass over the level's lanes (multigrid_lanes.hpp)
// that also forms the direction and the next iterate, its rows independent, so the rows split
// among any number of threads with the same bits. `sweeps` steps cost `sweeps` products (the
// first from x = 0 needs none, the residual for the coarse level one more), where Gauss-Seidel's
// cost as much per sweep and its residual too.
//
// A level's smoother also serves a caller that smooths the level itself (implicit_euler's fine
// level, over the host's product): then it keeps no lanes, only D^-1 and the bound.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <vector>

#include "multigrid_galerkin.hpp"
#include "multigrid_lanes.hpp"
#include "multigrid_level.hpp"

namespace clothlab::builtin {

// The polynomial's target: D^-1 A's eigenvalues down to lambda_max / this ratio.
constexpr double kChebyshevRatio = 30.0;

// The coefficients of Chebyshev's steps for eigenvalues in [lambda_max / kChebyshevRatio,
// lambda_max]: direction_0 = D^-1 r_0 / theta, then direction_k = keep_k direction_{k-1} +
// scale_k D^-1 r_k and x_{k+1} = x_k + direction_k, r_k = b - A x_k (Saad, "Iterative Methods
// for Sparse Linear Systems", algorithm 12.1, on D^-1 A).
class ChebyshevSteps {
 public:
  explicit ChebyshevSteps(double lambda_max)
      : theta_(0.5 * lambda_max * (1.0 + 1.0 / kChebyshevRatio)),
        delta_(0.5 * lambda_max * (1.0 - 1.0 / kChebyshevRatio)),
        sigma_(theta_ / delta_),
        rho_(1.0 / sigma_) {}

  // D^-1 r_0's factor in the first direction.
  double first_scale() const { return 1.0 / theta_; }
  // The next step's keep and scale (advances to it).
  struct Step {
    double keep, scale;
  };
  Step next() {
    const double rho_next = 1.0 / (2.0 * sigma_ - rho_);
    const Step step{rho_next * rho_, 2.0 * rho_next / delta_};
    rho_ = rho_next;
    return step;
  }

 private:
  double theta_, delta_, sigma_, rho_;
};

// An upper bound on D^-1 A's eigenvalues for a level's free rows: the largest row sum of
// |D_i^-1 A_ij| over a row's blocks; `inverse_diagonal` 9 per node, row-major. Rows of nodes
// split among `threads`, each its own bound, their largest taken in order.
inline double jacobi_spectral_bound(const GridLevel& level,
                                    const std::vector<double>& inverse_diagonal, int threads = 1) {
  std::vector<double> row_bounds(static_cast<std::size_t>(level.rows()), 0.0);
  level.for_each_index(level.rows(), threads, [&](int r) {
    double bound = 0.0;
    for (int c = 0; c < level.cols(); ++c) {
      const std::size_t i = level.node(r, c);
      if (level.fixed(i)) continue;
      const GridLevel::Window w = level.window(r, c);
      bound = std::max(
          bound, jacobi_row_bound(&inverse_diagonal[9 * i], [&](auto&& visit) {
            for (const GridLevel::Offset& offset : level.couplings()) {
              const int r2 = r + offset.rows, c2 = c + offset.cols;
              if (r2 >= w.row_begin && r2 < w.row_end && c2 >= w.col_begin && c2 < w.col_end)
                visit(level.block(r, c, r2, c2));
            }
          }));
    }
    row_bounds[static_cast<std::size_t>(r)] = bound;
  });
  double bound = 0.0;
  for (const double row : row_bounds) bound = std::max(bound, row);
  return bound;
}

class BlockChebyshev {
 public:
  // lanes: the precision the smoothing runs in; none where the caller smooths the level.
  BlockChebyshev(const GridLevel& level, std::optional<LanePrecision> lanes)
      : inverse_diagonal_(9 * level.node_count()) {
    if (lanes == LanePrecision::float32) float_lanes_.emplace(level);
    if (lanes == LanePrecision::float64) double_lanes_.emplace(level);
  }

  // Inverts the level's diagonal blocks and bounds D^-1 A's spectrum; false where a free
  // node's diagonal block is not positive definite or no finite bound comes out. Rows split
  // among `threads`: the same bits on any count.
  bool factor(const GridLevel& level, int threads = 1) {
    if (!invert_diagonal_blocks(level, inverse_diagonal_, threads)) return false;
    lambda_max_ = jacobi_spectral_bound(level, inverse_diagonal_, threads);
    if (!(lambda_max_ > 0.0 && std::isfinite(lambda_max_))) return false;
    if (float_lanes_) float_lanes_->load(level, inverse_diagonal_, threads);
    if (double_lanes_) double_lanes_->load(level, inverse_diagonal_, threads);
    return true;
  }

  const std::vector<double>& inverse_diagonal() const { return inverse_diagonal_; }
  // The bound on D^-1 A's eigenvalues from the last `factor`.
  double lambda_max() const { return lambda_max_; }

  std::size_t storage_bytes() const {
    return inverse_diagonal_.size() * sizeof(double) +
           (float_lanes_ ? float_lanes_->storage_bytes() : 0) +
           (double_lanes_ ? double_lanes_->storage_bytes() : 0);
  }

  // `sweeps` steps from x = 0 (x is only written), then out = b - A x where out is not null.
  void smooth_from_zero(const GridLevel& level, const double* b, double* x, long sweeps,
                        double* out, int threads) const {
    if (float_lanes_) return run(*float_lanes_, level, b, x, true, sweeps, out, threads);
    if (double_lanes_) return run(*double_lanes_, level, b, x, true, sweeps, out, threads);
    throw std::logic_error("multigrid: a level smoothed by its caller has no lanes");
  }
  // `sweeps` steps from x.
  void smooth(const GridLevel& level, const double* b, double* x, long sweeps, int threads) const {
    if (float_lanes_) return run(*float_lanes_, level, b, x, false, sweeps, nullptr, threads);
    if (double_lanes_) return run(*double_lanes_, level, b, x, false, sweeps, nullptr, threads);
    throw std::logic_error("multigrid: a level smoothed by its caller has no lanes");
  }

 private:
  template <class Real>
  void run(LaneLevel<Real>& lanes, const GridLevel& level, const double* b, double* x,
           bool from_zero, long sweeps, double* out, int threads) const {
    lanes.gather(level, b, from_zero ? nullptr : x, threads);
    ChebyshevSteps steps(lambda_max_);
    const auto rows = [&](auto&& body) { level.for_each_index(level.rows(), threads, body); };
    long step = 0;
    if (from_zero) {
      const auto scale = static_cast<Real>(steps.first_scale());
      rows([&](int r) { lanes.start_chebyshev_row(r, scale); });
      step = 1;
    }
    for (; step < sweeps; ++step) {
      const ChebyshevSteps::Step next =
          step == 0 ? ChebyshevSteps::Step{0.0, steps.first_scale()} : steps.next();
      rows([&](int r) {
        lanes.chebyshev_row(r, static_cast<Real>(next.keep), static_cast<Real>(next.scale));
      });
      lanes.swap_iterates();
    }
    if (out != nullptr) rows([&](int r) { lanes.residual_row(r); });
    lanes.scatter(level, x, out, threads);
  }

  std::vector<double> inverse_diagonal_;  // 9 per node
  double lambda_max_ = 0.0;
  // The lanes in one precision, or none; their vectors are the smoothing's scratch.
  mutable std::optional<LaneLevel<float>> float_lanes_;
  mutable std::optional<LaneLevel<double>> double_lanes_;
};

}  // namespace clothlab::builtin
