// The multigrid hierarchy on a rows x cols grid: the fine level (its matrix filled by the
// caller), coarser levels each with every other node along both axes (multigrid_transfer.hpp),
// their Galerkin operators R A P, the smoothers' inverted diagonal blocks and the coarsest
// level's Cholesky factor. All storage is sized when the hierarchy is built; `rebuild` after a
// change of the fine matrix only computes.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "multigrid_coarse_solve.hpp"
#include "multigrid_level.hpp"
#include "multigrid_smoother.hpp"
#include "multigrid_transfer.hpp"

namespace clothlab::builtin {

struct GridSize {
  uint32_t rows, cols;
};

// The level sizes, fine first, for `levels` levels (0: coarsen until the coarsest grid has at
// most kAutomaticCoarsestNodes nodes). Throws std::invalid_argument, one line, where `levels`
// is more than the grid allows (an axis must have 3 nodes to coarsen) or leaves a coarsest grid
// over kMaxCoarsestNodes nodes for the dense direct solve.
constexpr uint32_t kAutomaticCoarsestNodes = 256;
constexpr uint32_t kMaxCoarsestNodes = 1024;

inline std::vector<GridSize> plan_levels(uint32_t rows, uint32_t cols, long levels) {
  const auto coarsens = [](GridSize s) { return s.rows >= 3 && s.cols >= 3; };
  const auto nodes = [](GridSize s) { return uint64_t{s.rows} * s.cols; };
  std::vector<GridSize> sizes{{rows, cols}};
  while (coarsens(sizes.back()) && (levels == 0 ? nodes(sizes.back()) > kAutomaticCoarsestNodes
                                                : static_cast<long>(sizes.size()) < levels))
    sizes.push_back({coarse_axis_size(sizes.back().rows), coarse_axis_size(sizes.back().cols)});
  const std::string grid = std::to_string(rows) + " x " + std::to_string(cols) + " grid";
  if (levels != 0 && static_cast<long>(sizes.size()) < levels)
    throw std::invalid_argument("multigrid_levels = " + std::to_string(levels) +
                                " is more than the " + grid + " allows (at most " +
                                std::to_string(sizes.size()) + ")");
  const GridSize coarsest = sizes.back();
  if (nodes(coarsest) > kMaxCoarsestNodes)
    throw std::invalid_argument(
        "multigrid_levels = " + std::to_string(levels) + " leaves the " + grid + " a " +
        std::to_string(coarsest.rows) + " x " + std::to_string(coarsest.cols) +
        " coarsest level; its direct solve takes at most " + std::to_string(kMaxCoarsestNodes) +
        " nodes (use more levels, or 0 = automatic)");
  return sizes;
}

class MultigridHierarchy {
 public:
  // fixed: the fine level's Dirichlet nodes (pins), node r * cols + c.
  MultigridHierarchy(const std::vector<GridSize>& sizes, std::vector<uint8_t> fixed) {
    levels_.reserve(sizes.size());
    levels_.emplace_back(sizes[0].rows, sizes[0].cols, std::move(fixed));
    for (std::size_t l = 1; l < sizes.size(); ++l) {
      transfers_.emplace_back(levels_.back());
      std::vector<uint8_t> coarse_fixed = transfers_.back().coarse_fixed(levels_.back());
      levels_.emplace_back(sizes[l].rows, sizes[l].cols, std::move(coarse_fixed));
    }
    for (std::size_t l = 0; l + 1 < levels_.size(); ++l) smoothers_.emplace_back(levels_[l]);
    coarsest_solve_.emplace(levels_.back());
  }

  std::size_t level_count() const { return levels_.size(); }
  GridLevel& level(std::size_t l) { return levels_[l]; }
  const GridLevel& level(std::size_t l) const { return levels_[l]; }
  const GridTransfer& transfer(std::size_t l) const { return transfers_[l]; }  // l to l + 1
  const BlockGaussSeidel& smoother(std::size_t l) const { return smoothers_[l]; }
  CoarseCholesky& coarsest_solve() { return *coarsest_solve_; }

  // The coarse operators and factors for the fine level's current matrix; false where a level
  // is not positive definite (then the V-cycle is no preconditioner for CG).
  bool rebuild() {
    for (std::size_t l = 0; l + 1 < levels_.size(); ++l) {
      levels_[l].find_couplings();
      transfers_[l].galerkin(levels_[l], levels_[l + 1]);
      if (!smoothers_[l].factor(levels_[l])) return false;
    }
    return coarsest_solve().factor(levels_.back());
  }

 private:
  std::vector<GridLevel> levels_;
  std::vector<GridTransfer> transfers_;
  std::vector<BlockGaussSeidel> smoothers_;
  std::optional<CoarseCholesky> coarsest_solve_;
};

}  // namespace clothlab::builtin
