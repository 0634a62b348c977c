// The Galerkin product R A P of a transfer (multigrid_transfer.hpp), from a level's own blocks or
// from the host's block table (multigrid_block_table.hpp), and the block-Jacobi bound of a
// row: the set-up's double lanes, compiled per SIMD target in a portable build
// (multigrid_galerkin_target.cpp, chosen by multigrid_galerkin_path.hpp) as xpbd's grid
// sweep is. The sums' order does not depend on the target: every copy gives the same bits.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "multigrid_block_table.hpp"
#include "multigrid_level.hpp"
#include "multigrid_transfer.hpp"
#include "simd_namespace.hpp"

namespace clothlab::builtin {
inline namespace CLOTHLAB_SIMD_NAMESPACE {

// sum += weight a over a 3x3 block: one fused multiply-add per entry on any path, in lanes
// (sum and a do not overlap).
inline void add_scaled_block(double* __restrict sum, double weight, const double* __restrict a) {
#pragma omp simd
  for (int k = 0; k < 9; ++k) sum[k] += weight * a[k];
}

// Row i's part of the bound below: the largest row sum of |D_i^-1 A_ij| over the blocks that
// row_blocks(visit) visits (visit(a) for each block a of the row); d = D_i^-1, row-major.
template <class RowBlocks>
double jacobi_row_bound(const double* d, RowBlocks&& row_blocks) {
  std::array<double, 3> row_sums{};
  row_blocks([&](const double* a) {
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        row_sums[static_cast<std::size_t>(k)] +=
            std::abs(d[3 * k] * a[j] + d[3 * k + 1] * a[3 + j] + d[3 * k + 2] * a[6 + j]);
  });
  return std::max({row_sums[0], row_sums[1], row_sums[2]});
}

// galerkin_row for a row that follows its class's plan, (pr, pc) its first parent: each block
// of A P summed whole, its terms (the fine blocks read, by window place) in the order the
// general path adds them, so the same bits, then added to each owned parent's row, whose
// window is whole (the block's slot fixed by the parent).
template <class Owned, class RowBlocks>
void galerkin_planned_row(const GridTransfer::ClassPlan& plan, GridLevel& coarse, int r, int c,
                          int pr, int pc, bool once, const Owned& owned, RowBlocks& row_blocks) {
  alignas(64) double blocks[GridTransfer::kSpan * GridTransfer::kSpan][9];
  uint32_t read = 0;  // a bit per window place read
  row_blocks(r, c, once, [&](int r2, int c2, const double* a) {
    const int place = (r2 - r + 2) * GridTransfer::kSpan + (c2 - c + 2);
    std::copy_n(a, 9, blocks[place]);
    read |= uint32_t{1} << place;
  });
  std::array<double*, 4> targets{};
  std::array<double, 4> weights{};
  std::array<int, 4> shifts{};
  std::size_t parents = 0;
  for (const GridTransfer::ClassParent& parent : plan.parents)
    if (owned(pr + parent.row)) {
      targets[parents] = coarse.row_blocks(pr + parent.row, pc + parent.col);
      weights[parents] = parent.weight;
      shifts[parents++] = GridTransfer::kSpan * parent.row + parent.col;
    }
  if (parents == 0) return;
  for (const GridTransfer::ClassBlock& block : plan.blocks) {
    alignas(64) double sum[9] = {};
    bool any = false;
    for (uint16_t t = block.begin; t < block.end; ++t) {
      const GridTransfer::ClassTerm term = plan.terms[t];
      if (!(read >> term.place & 1)) continue;
      add_scaled_block(sum, term.weight, blocks[term.place]);
      any = true;
    }
    if (!any) continue;
    for (std::size_t p = 0; p < parents; ++p)
      add_scaled_block(targets[p] + 9 * (block.local - shifts[p]), weights[p], sum);
  }
}

// Fine row (r, c)'s terms of R A P in the coarse rows `owned` accepts.
template <class Owned, class RowBlocks>
void galerkin_row(const GridTransfer& transfer, const GridLevel& fine, GridLevel& coarse, int r,
                  int c, bool once, const Owned& owned, RowBlocks& row_blocks) {
  const AxisParents& row_parents = transfer.row_parents();
  const AxisParents& col_parents = transfer.col_parents();
  // f's A P row lies within 2 coarse rows/cols of f's first parent: each g of the row is at
  // most one coarse interval from f.
  const int row0 = row_parents.parent(r, 0) - 2, col0 = col_parents.parent(c, 0) - 2;
  if (transfer.planned(fine, r, c))
    return galerkin_planned_row(transfer.plan(r, c), coarse, r, c, row0 + 2, col0 + 2, once, owned,
                                row_blocks);
  std::array<double, 9 * GridTransfer::kSpan * GridTransfer::kSpan> product{};
  std::array<uint8_t, GridTransfer::kSpan * GridTransfer::kSpan> touched{};
  row_blocks(r, c, once, [&](int r2, int c2, const double* a) {
    if (fine.fixed(fine.node(r2, c2))) return;
    for (int i = 0; i < row_parents.count(r2); ++i)
      for (int j = 0; j < col_parents.count(c2); ++j) {
        const int pr = row_parents.parent(r2, i), pc = col_parents.parent(c2, j);
        if (coarse.fixed(coarse.node(pr, pc))) continue;
        const int local = (pr - row0) * GridTransfer::kSpan + (pc - col0);
        add_scaled_block(&product[9 * static_cast<std::size_t>(local)],
                         row_parents.weight(r2, i) * col_parents.weight(c2, j), a);
        touched[local] = 1;
      }
  });
  for (int i = 0; i < row_parents.count(r); ++i)
    for (int j = 0; j < col_parents.count(c); ++j) {
      const int pr = row_parents.parent(r, i), pc = col_parents.parent(c, j);
      if (!owned(pr) || coarse.fixed(coarse.node(pr, pc))) continue;
      const double weight = row_parents.weight(r, i) * col_parents.weight(c, j);
      // The touched blocks lie in (pr, pc)'s window.
      const GridLevel::Window w = coarse.window(pr, pc);
      double* const row = coarse.row_blocks(pr, pc);
      for (int local = 0; local < GridTransfer::kSpan * GridTransfer::kSpan; ++local) {
        if (!touched[local]) continue;
        add_scaled_block(row + 9 * GridLevel::window_slot(w, row0 + local / GridTransfer::kSpan,
                                                          col0 + local % GridTransfer::kSpan),
                         weight, &product[9 * static_cast<std::size_t>(local)]);
      }
    }
}

// coarse = R fine P, a row of A P at a time: (A P)_fJ = sum_g A_fg P_gJ, then
// (R A P)_IJ += P_fI (A P)_fJ for f's parents I. The fine blocks come from the level's own
// (the offsets `pack` found coupled), or from row_blocks(r, c, once, visit), which calls
// visit(r2, c2, a) for each block a of the free fine row (r, c); `once` is true on exactly
// one of a row's reads (a fine row under two bands is read by both), on the thread that
// reads the fine row of nodes r in order, so per-row work done there has one writer. The
// coarse rows split among `threads` in bands, each band from the fine rows under it: a
// coarse block sums its terms in the fine rows' order. The bands are fixed by the level
// (set_band_rows), not by `threads`: a band plan changes no bits (tested from the host's table
// with one, two and nine bands), but a plan of one band per thread once gave other float64
// bits on one and two threads, cause not found.
template <class RowBlocks>
void galerkin(const GridTransfer& transfer, const GridLevel& fine, GridLevel& coarse, int threads,
              RowBlocks&& row_blocks) {
  const AxisParents& row_parents = transfer.row_parents();
  const int coarsening = transfer.coarsening(), band_rows = transfer.band_rows();
  coarse.clear();
  const int bands = (coarse.rows() + band_rows - 1) / band_rows;
  fine.for_each_index(bands, threads, [&](int band) {
    const int first = band * band_rows, last = std::min(first + band_rows, coarse.rows());
    const auto owned = [&](int pr) { return pr >= first && pr < last; };
    for (int r = std::max(coarsening * (first - 1), 0);
         r < std::min(coarsening * last + 1, fine.rows()); ++r) {
      if (!owned(row_parents.parent(r, 0)) &&
          !(row_parents.count(r) == 2 && owned(row_parents.parent(r, 1))))
        continue;
      const bool once = owned(row_parents.parent(r, 0));
      for (int c = 0; c < fine.cols(); ++c)
        if (!fine.fixed(fine.node(r, c)))
          galerkin_row(transfer, fine, coarse, r, c, once, owned, row_blocks);
    }
  });
}

// The level's own fine blocks (the offsets `pack` found coupled).
inline void galerkin(const GridTransfer& transfer, const GridLevel& fine, GridLevel& coarse,
                     int threads = 1) {
  galerkin(transfer, fine, coarse, threads, [&](int r, int c, bool, auto&& visit) {
    const GridLevel::Window w = fine.window(r, c);
    const double* row = fine.row_blocks(r, c);
    for (const GridLevel::Offset& offset : fine.couplings()) {
      const int r2 = r + offset.rows, c2 = c + offset.cols;
      if (r2 >= w.row_begin && r2 < w.row_end && c2 >= w.col_begin && c2 < w.col_end)
        visit(r2, c2, row + 9 * GridLevel::window_slot(w, r2, c2));
    }
  });
}

// S's blocks of the free fine row i from the table, formed as they are read: S_ij = m_i D_ij
// made exactly symmetric (M D is symmetric up to rounding) by taking the upper triangle's
// blocks, S_ji = S_ij^T for j > i and the diagonal block's upper half, so that the V-cycle
// stays exactly symmetric, and M added on the diagonal. A lower block's transpose lies in a row
// at most two grid rows back, read just before (the caches hold it), where the mean of both
// would read the rows ahead too. visit(r2, c2, block) for each free j = r2 * cols + c2 the row
// couples to.
inline void table_block(const BlockTable& table, uint32_t i, uint32_t k, double* s);
template <class Visit>
[[gnu::always_inline]] inline void table_row(const BlockTable& table, const GridLevel& fine,
                                             uint32_t i, Visit&& visit) {
  constexpr int kWindowWidth = 2 * GridLevel::reach + 1;
  const auto cols = static_cast<uint32_t>(fine.cols());
  const auto r = static_cast<int>(i / cols) - GridLevel::reach;
  const auto c = static_cast<int>(i % cols) - GridLevel::reach;
  for (uint32_t k = table.pattern->row_offsets[i]; k < table.pattern->row_offsets[i + 1]; ++k) {
    if (fine.fixed(table.pattern->columns[k])) continue;
    double s[9];
    table_block(table, i, k, s);
    const int place = table.window_places[k];
    visit(r + place / kWindowWidth, c + place % kWindowWidth, static_cast<const double*>(s));
  }
}
// table_row's block of slot k, in row i, into s. An off-diagonal block's first 8 entries are
// formed and stored in lanes, so that a caller's wide read of s forwards from the store.
inline void table_block(const BlockTable& table, uint32_t i, uint32_t k, double* s) {
  using Lanes = double __attribute__((vector_size(64)));
  using Order = int64_t __attribute__((vector_size(64)));
  const uint32_t j = table.pattern->columns[k];
  if (j != i) {
    const bool upper = j > i;
    const double* a = table.values + 9 * std::size_t{upper ? k : table.transposed[k]};
    const double m = table.mass[upper ? i : j];
    Lanes block;
    std::memcpy(&block, a, sizeof block);
    // s_(row, col) = m a_(row, col), or m t_(col, row) of the transpose t (entry 8 in place)
    block = m * (upper ? block : __builtin_shuffle(block, Order{0, 3, 6, 1, 4, 7, 2, 5}));
    std::memcpy(s, &block, sizeof block);
    s[8] = m * a[8];
  } else {
    const double* a = table.values + 9 * std::size_t{k};
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col)
        s[3 * row + col] = table.mass[i] * a[3 * std::min(row, col) + std::max(row, col)];
    for (int d = 0; d < 3; ++d) s[4 * d] += table.mass[i];
  }
}

// Level 1 = R S P from the table's rows, and with it, once per fine row, D^-1 (store_jacobi)
// and the bound on D^-1 A's eigenvalues (those of D_S^-1 S, D_S = M D): row_bounds[r] the
// largest over the free nodes of fine row r (zeroed by the caller), NaN once a diagonal block
// is not positive definite.
inline void galerkin_from_table(const BlockTable& table, const GridTransfer& transfer,
                                const GridLevel& fine, GridLevel& coarse, int threads) {
  galerkin(transfer, fine, coarse, threads, [&](int r, int c, bool once, auto&& visit) {
    const auto i = static_cast<uint32_t>(fine.node(r, c));
    if (!once) return table_row(table, fine, i, visit);
    double diagonal[9], inverse[9];  // NaN unless the diagonal block is positive definite
    std::fill_n(inverse, 9, std::numeric_limits<double>::quiet_NaN());
    table_block(table, i, table.diagonal_slots[i], diagonal);
    invert_positive_definite(diagonal, inverse);
    store_jacobi(i, table.mass[i], inverse, table.particles, table.jacobi, table.jacobi_single);
    const double row = jacobi_row_bound(inverse, [&](auto&& bound_visit) {
      table_row(table, fine, i, [&](int r2, int c2, const double* block) {
        visit(r2, c2, block);
        bound_visit(block);
      });
    });
    double& bound = table.row_bounds[static_cast<std::size_t>(r)];
    if (!std::isnan(bound)) bound = std::isnan(row) ? row : std::max(bound, row);
  });
}

}  // namespace CLOTHLAB_SIMD_NAMESPACE
}  // namespace clothlab::builtin
