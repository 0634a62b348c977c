// The multigrid hierarchy on a rows x cols grid: the fine level (its matrix filled by the
// caller), coarser levels each with every other or every third node along both axes
// (multigrid_transfer.hpp),
// their Galerkin operators R A P, the smoothers (coloured Gauss-Seidel, multigrid_smoother.hpp,
// or Chebyshev on block-Jacobi, multigrid_chebyshev.hpp) and the coarsest level's Cholesky
// factor. All storage is sized when the hierarchy is built; `rebuild` after a
// change of the fine matrix only computes.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "multigrid_chebyshev.hpp"
#include "multigrid_coarse_solve.hpp"
#include "multigrid_galerkin_path.hpp"
#include "multigrid_level.hpp"
#include "multigrid_smoother.hpp"
#include "multigrid_transfer.hpp"

namespace clothlab::builtin {

struct GridSize {
  uint32_t rows, cols;
};

// The level sizes, fine first, each every `coarsening`-th node of the one above
// (multigrid_transfer.hpp): coarsen while the coarsest grid has more than
// `coarsest_particles` nodes and both its sides have at least 3 (one more level could not
// shrink). Throws std::invalid_argument, one line, where that leaves more than
// kMaxCoarsestNodes nodes for the dense direct solve (a long thin strip of cloth).
constexpr long kDefaultCoarsestNodes = 256;
constexpr uint32_t kMaxCoarsestNodes = 1024;

inline std::vector<GridSize> plan_levels(uint32_t rows, uint32_t cols, long coarsest_particles,
                                         int coarsening = kMinCoarsening) {
  const auto nodes = [](GridSize s) { return uint64_t{s.rows} * s.cols; };
  std::vector<GridSize> sizes{{rows, cols}};
  while (sizes.back().rows >= 3 && sizes.back().cols >= 3 &&
         nodes(sizes.back()) > static_cast<uint64_t>(coarsest_particles))
    sizes.push_back({coarse_axis_size(sizes.back().rows, coarsening),
                     coarse_axis_size(sizes.back().cols, coarsening)});
  const GridSize coarsest = sizes.back();
  if (nodes(coarsest) > kMaxCoarsestNodes)
    throw std::invalid_argument("the " + std::to_string(rows) + " x " + std::to_string(cols) +
                                " grid coarsens to no fewer than " + std::to_string(coarsest.rows) +
                                " x " + std::to_string(coarsest.cols) +
                                " particles (a side needs 3 to coarsen); the direct " +
                                "solve there takes at most " + std::to_string(kMaxCoarsestNodes));
  return sizes;
}

// How the levels above the coarsest smooth: gauss_seidel, a convergent stationary iteration
// (projective_dynamics' repeated V-cycles); chebyshev, cheaper per sweep where the V-cycle
// only preconditions CG, its fine level left to the caller (implicit_euler's host product).
enum class Smoothing { gauss_seidel, chebyshev };

class MultigridHierarchy {
 public:
  // fixed: the fine level's Dirichlet nodes (pins), node r * cols + c. fine_blocks: single
  // where the V-cycle only preconditions (implicit_euler's CG), exact where the fine level's
  // residual is the system solved (projective_dynamics), none where the caller holds the fine
  // matrix and forms level 1 (`rebuild_below(1)`). The coarse levels that smooth only
  // serve the V-cycle and are single; the coarsest, solved directly, stays exact. lanes: the
  // precision the single levels smooth in (multigrid_lanes.hpp). coarsening: the one `sizes`
  // were planned with (plan_levels).
  MultigridHierarchy(const std::vector<GridSize>& sizes, std::vector<uint8_t> fixed,
                     GridLevel::Blocks fine_blocks, LanePrecision lanes = LanePrecision::float64,
                     Smoothing smoothing = Smoothing::gauss_seidel,
                     int coarsening = kMinCoarsening) {
    levels_.reserve(sizes.size());
    // A fine level that is the coarsest is solved from its blocks: it keeps them.
    if (fine_blocks == GridLevel::Blocks::none && sizes.size() == 1)
      fine_blocks = GridLevel::Blocks::single;
    levels_.emplace_back(sizes[0].rows, sizes[0].cols, std::move(fixed), fine_blocks);
    for (std::size_t l = 1; l < sizes.size(); ++l) {
      transfers_.emplace_back(levels_.back(), coarsening);
      if (sizes[l].rows != coarse_axis_size(sizes[l - 1].rows, coarsening) ||
          sizes[l].cols != coarse_axis_size(sizes[l - 1].cols, coarsening))
        throw std::logic_error("multigrid: level sizes not planned with this coarsening");
      std::vector<uint8_t> coarse_fixed = transfers_.back().coarse_fixed(levels_.back());
      levels_.emplace_back(
          sizes[l].rows, sizes[l].cols, std::move(coarse_fixed),
          l + 1 < sizes.size() ? GridLevel::Blocks::single : GridLevel::Blocks::exact);
    }
    // Chebyshev's products run in its lanes or the caller's: no level reads packed rows.
    if (smoothing == Smoothing::chebyshev)
      for (GridLevel& level : levels_) level.drop_packing();
    for (std::size_t l = 0; l + 1 < levels_.size(); ++l)
      if (smoothing == Smoothing::gauss_seidel)
        smoothers_.emplace_back(levels_[l], lanes);
      else
        chebyshev_.emplace_back(levels_[l], l == 0 ? std::nullopt : std::optional(lanes));
    coarsest_solve_.emplace(levels_.back());
  }

  std::size_t level_count() const { return levels_.size(); }
  GridLevel& level(std::size_t l) { return levels_[l]; }
  const GridLevel& level(std::size_t l) const { return levels_[l]; }
  const GridTransfer& transfer(std::size_t l) const { return transfers_[l]; }  // l to l + 1
  GridTransfer& transfer(std::size_t l) { return transfers_[l]; }
  // The Galerkin products of the SIMD target that runs here, chosen at construction.
  const GalerkinProducts& galerkin_products() const { return galerkin_products_; }
  // Level l's smoother, l below the coarsest level, of a gauss_seidel or a chebyshev hierarchy.
  const BlockGaussSeidel& smoother(std::size_t l) const { return smoothers_[l]; }
  const BlockChebyshev& chebyshev(std::size_t l) const { return chebyshev_[l]; }

  // Level l's smoothing before its coarse correction: `sweeps` from x = 0, then out = b - A x.
  void pre_smooth(std::size_t l, const double* b, double* x, long sweeps, double* out,
                  int threads) const {
    if (!chebyshev_.empty())
      return chebyshev_[l].smooth_from_zero(levels_[l], b, x, sweeps, out, threads);
    std::fill_n(x, 3 * levels_[l].node_count(), 0.0);
    smoothers_[l].forward(levels_[l], b, x, sweeps, out, threads);
  }
  // Level l's smoothing after its coarse correction: the adjoint of pre_smooth's.
  void post_smooth(std::size_t l, const double* b, double* x, long sweeps, int threads) const {
    if (!chebyshev_.empty()) return chebyshev_[l].smooth(levels_[l], b, x, sweeps, threads);
    smoothers_[l].backward(levels_[l], b, x, sweeps, threads);
  }
  CoarseCholesky& coarsest_solve() { return *coarsest_solve_; }

  // Bytes of every level's matrix, the smoothers' and the coarsest level's factors (the
  // transfers' per-axis parent tables are a few bytes per row and column, left out).
  std::size_t storage_bytes() const {
    std::size_t bytes = coarsest_solve_->storage_bytes();
    for (const GridLevel& level : levels_) bytes += level.storage_bytes();
    for (const BlockGaussSeidel& smoother : smoothers_) bytes += smoother.storage_bytes();
    for (const BlockChebyshev& smoother : chebyshev_) bytes += smoother.storage_bytes();
    return bytes;
  }

  // The coarse operators and factors for the fine level's current matrix; false where a level
  // is not positive definite (then the V-cycle is no preconditioner for CG). The Galerkin
  // products run on `threads`.
  bool rebuild(int threads = 1) { return rebuild_below(0, threads); }
  // As rebuild, from level `first` down, its matrix formed by the caller (level 1 where the fine
  // level keeps no blocks: the caller smooths it and forms its Galerkin product).
  bool rebuild_below(std::size_t first, int threads = 1) {
    for (std::size_t l = first; l + 1 < levels_.size(); ++l) {
      levels_[l].pack();
      galerkin_products_.levels(transfers_[l], levels_[l], levels_[l + 1], threads);
      if (!(chebyshev_.empty() ? smoothers_[l].factor(levels_[l])
                               : chebyshev_[l].factor(levels_[l], threads)))
        return false;
    }
    return coarsest_solve().factor(levels_.back());
  }

 private:
  std::vector<GridLevel> levels_;
  std::vector<GridTransfer> transfers_;
  std::vector<BlockGaussSeidel> smoothers_;  // gauss_seidel's, else empty
  std::vector<BlockChebyshev> chebyshev_;    // chebyshev's, else empty
  std::optional<CoarseCholesky> coarsest_solve_;
  GalerkinProducts galerkin_products_ = choose_galerkin_products();
};

}  // namespace clothlab::builtin
