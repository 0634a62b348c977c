// The multigrid V-cycle as a preconditioner: z = B b from z = 0 on the fine level, with
// `sweeps` smoothing sweeps before the coarse correction and as many after it (forward and
// backward coloured Gauss-Seidel, or the same Chebyshev polynomial: the hierarchy's Smoothing),
// and the direct solve on the coarsest level; the smoothing and the residual of each level
// large enough run on `threads`. Pre- and post-smoothing are each other's adjoints and the coarse
// correction is exact at the bottom and Galerkin above, so B is symmetric and positive definite for
// a positive definite fine matrix: a valid preconditioner for conjugate gradients. Vectors hold 3
// doubles per node; all are sized here.
#pragma once

#include <clothlab/sdk/threads.hpp>
#include <cstddef>
#include <vector>

#include "multigrid_hierarchy.hpp"

namespace clothlab::builtin {

// implicit_euler's default `multigrid_sweeps`: on the cotton flag, with every other node kept
// per level, 2 sweeps took 33 CG iterations where 1 took 52, for about the same time per solve
// (lab/real-cloth.md).
constexpr long kDefaultMultigridSweeps = 2;

class VCycle {
 public:
  // Builds the OpenMP team of `threads` here, so that the first cycle does not allocate.
  VCycle(MultigridHierarchy& hierarchy, long sweeps, int threads = 1)
      : hierarchy_(hierarchy), sweeps_(sweeps), threads_(threads) {
    for (std::size_t l = 0; l < hierarchy.level_count(); ++l) {
      const std::size_t size = 3 * hierarchy.level(l).node_count();
      solution_.emplace_back(size, 0.0);
      rhs_.emplace_back(size, 0.0);
      residual_.emplace_back(size, 0.0);
    }
    sdk::start_thread_team(threads_);
  }

  // The threads the smoothing and residuals of large levels run on.
  int threads() const { return threads_; }

  // Bytes of the per-level vectors.
  std::size_t storage_bytes() const {
    std::size_t doubles = 0;
    for (std::size_t l = 0; l < solution_.size(); ++l)
      doubles += solution_[l].size() + rhs_[l].size() + residual_[l].size();
    return doubles * sizeof(double);
  }

  // The fine level's right-hand side, to fill before `apply`.
  double* fine_rhs() { return rhs_[0].data(); }
  // z = B b for b in fine_rhs(); the result stays valid until the next apply.
  const double* apply() {
    cycle(0);
    return solution_[0].data();
  }

  // The fine level's coarse correction alone, for a fine smoother run by the caller: x += P B_1
  // R r, B_1 the cycle from level 1 down, for the fine residual r; both 3 doubles per node.
  // Needs a hierarchy of at least two levels.
  void correct(const double* residual, double* x) {
    const GridLevel& fine = hierarchy_.level(0);
    correct(
        [&](int r, int c0, int c1, double weight, GridTransfer::ChunkRow& sum) {
          for (int c = c0; c < c1; ++c)
            if (!fine.fixed(fine.node(r, c)))
              for (int k = 0; k < 3; ++k)
                sum[k][c - c0] += weight * residual[3 * fine.node(r, c) + k];
        },
        [&](int r, int c0, int c1, const GridTransfer::ChunkRow& value) {
          for (int c = c0; c < c1; ++c)
            if (!fine.fixed(fine.node(r, c)))
              for (int k = 0; k < 3; ++k) x[3 * fine.node(r, c) + k] += value[k][c - c0];
        });
  }
  // As correct, on the caller's layout: r read by add_residual_row (GridTransfer::restrict_from's
  // add_row), P B_1 R r handed to add_correction_row (prolong_to's add_row).
  template <class AddResidualRow, class AddCorrectionRow>
  void correct(AddResidualRow&& add_residual_row, AddCorrectionRow&& add_correction_row) {
    const GridTransfer& transfer = hierarchy_.transfer(0);
    transfer.restrict_from(hierarchy_.level(0), hierarchy_.level(1), rhs_[1].data(), threads_,
                           add_residual_row);
    cycle(1);
    transfer.prolong_to(hierarchy_.level(0), hierarchy_.level(1), solution_[1].data(), threads_,
                        add_correction_row);
  }

 private:
  void cycle(std::size_t l) {
    const GridLevel& level = hierarchy_.level(l);
    double* x = solution_[l].data();
    const double* b = rhs_[l].data();
    if (l + 1 == hierarchy_.level_count()) {
      hierarchy_.coarsest_solve().solve(level, b, x);
      return;
    }
    hierarchy_.pre_smooth(l, b, x, sweeps_, residual_[l].data(), threads_);
    const GridTransfer& transfer = hierarchy_.transfer(l);
    const GridLevel& coarse = hierarchy_.level(l + 1);
    transfer.restrict_to(level, residual_[l].data(), coarse, rhs_[l + 1].data(), threads_);
    cycle(l + 1);
    transfer.prolong_add(level, coarse, solution_[l + 1].data(), x, threads_);
    hierarchy_.post_smooth(l, b, x, sweeps_, threads_);
  }

  MultigridHierarchy& hierarchy_;
  long sweeps_;
  int threads_;
  std::vector<std::vector<double>> solution_, rhs_, residual_;  // per level
};

}  // namespace clothlab::builtin
