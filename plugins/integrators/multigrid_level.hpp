// One level of the multigrid hierarchy: a symmetric block matrix on a rows x cols grid whose
// node (r, c) couples only to nodes within two grid spacings along each axis (the Provot
// grid's flexion springs skip one particle, and Galerkin coarsening keeps that reach: see
// multigrid_transfer.hpp). Row (r, c) stores a 3x3 block for every node of its 5 x 5 window
// clipped to the grid, ascending, zero where nothing couples. Fixed (Dirichlet) nodes, the pins,
// have zero rows and columns and stay 0 in every vector. For the V-cycle's products a level may
// also keep its interior rows packed: only the coupled blocks, in single precision (`pack`).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace clothlab::builtin {

class GridLevel {
 public:
  static constexpr int reach = 2;  // grid spacings a row's couplings span along each axis

  // How `pack` keeps the blocks: exact (double), or rounded to single precision with the
  // interior rows packed for the V-cycle's products; none: the level keeps no blocks (a fine
  // level whose matrix its caller holds and smooths, forming the next level's Galerkin product).
  enum class Blocks { exact, single, none };

  GridLevel(uint32_t rows, uint32_t cols, std::vector<uint8_t> fixed, Blocks blocks = Blocks::exact)
      : rows_(static_cast<int>(rows)),
        cols_(static_cast<int>(cols)),
        single_(blocks == Blocks::single),
        fixed_(std::move(fixed)) {
    if (blocks == Blocks::none) return;
    offsets_.resize(node_count() + 1, 0);
    for (int r = 0; r < rows_; ++r)
      for (int c = 0; c < cols_; ++c) {
        const Window w = window(r, c);
        offsets_[node(r, c) + 1] =
            offsets_[node(r, c)] + static_cast<std::size_t>((w.row_end - w.row_begin) * w.width());
      }
    blocks_.assign(9 * offsets_.back(), 0.0);
    couplings_.reserve(kWindow * kWindow);
    coupling_steps_.reserve(kWindow * kWindow);
    for (int k = 0; k < kWindow * kWindow; ++k)
      couplings_.push_back({k / kWindow - reach, k % kWindow - reach});
    if (single_) packed_.resize(9 * (kWindow * kWindow - 1) * interior_count());
  }

  // A window offset: (r + rows, c + cols) from node (r, c).
  struct Offset {
    int rows, cols;
  };

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  std::size_t node_count() const { return static_cast<std::size_t>(rows_) * cols_; }
  std::size_t node(int r, int c) const { return static_cast<std::size_t>(r) * cols_ + c; }
  bool fixed(std::size_t node) const { return fixed_[node] != 0; }

  // The window of node (r, c): rows [row_begin, row_end) x columns [col_begin, col_end).
  struct Window {
    int row_begin, row_end, col_begin, col_end;
    int width() const { return col_end - col_begin; }
  };
  Window window(int r, int c) const {
    return {std::max(r - reach, 0), std::min(r + reach + 1, rows_), std::max(c - reach, 0),
            std::min(c + reach + 1, cols_)};
  }

  // The 3x3 block (row-major) coupling (r, c) to (r2, c2), which must lie in (r, c)'s window.
  double* block(int r, int c, int r2, int c2) { return &blocks_[9 * slot(r, c, r2, c2)]; }
  const double* block(int r, int c, int r2, int c2) const {
    return &blocks_[9 * slot(r, c, r2, c2)];
  }
  // Row (r, c)'s block coupling it to (r2, c2), in window w = window(r, c), from row_blocks.
  static std::size_t window_slot(const Window& w, int r2, int c2) {
    return static_cast<std::size_t>((r2 - w.row_begin) * w.width() + (c2 - w.col_begin));
  }
  // Row (r, c)'s blocks in window order.
  double* row_blocks(int r, int c) { return &blocks_[9 * offsets_[node(r, c)]]; }
  const double* row_blocks(int r, int c) const { return &blocks_[9 * offsets_[node(r, c)]]; }
  // Whether the level keeps its off-diagonal blocks in single precision (Blocks::single).
  bool single() const { return single_; }
  // The window offsets with a nonzero block in some row, as `pack` found them (before: all).
  const std::vector<Offset>& couplings() const { return couplings_; }
  // Whether products read the interior rows from their packed blocks (a single level, packed
  // since its blocks last changed).
  bool packed() const { return packed_valid_; }
  // Frees the packed rows and packs none from now on: for a level whose products run elsewhere
  // (Chebyshev's lanes, or the caller's).
  void drop_packing() { packed_ = {}; }
  void clear() {
    std::fill(blocks_.begin(), blocks_.end(), 0.0);
    packed_valid_ = false;
  }

  // Whether a pass over this level's rows is worth splitting among `threads`: a team's start
  // costs more than the rows of a small (coarse) level.
  bool splits(int threads) const { return threads > 1 && node_count() >= kNodesWorthATeam; }

  // body(k) for k in [0, count), split among `threads` where the level splits, else on the
  // calling thread outside OpenMP: a region of another team size (an `if` clause makes one of
  // 1) would allocate its team anew each time the size changes.
  template <class Body>
  void for_each_index(int count, int threads, Body&& body) const {
    if (splits(threads)) {
#pragma omp parallel for schedule(static) num_threads(threads)
      for (int k = 0; k < count; ++k) body(k);
    } else {
      for (int k = 0; k < count; ++k) body(k);
    }
  }

  // out = b - A x on free nodes, 0 on fixed ones; vectors hold 3 doubles per node. Rows are
  // split among `threads`, each row's sum the same on any count.
  void residual(const double* b, const double* x, double* out, int threads = 1) const {
    for_each_index(rows_, threads, [&](int r) { residual_row(r, b, x, out); });
  }
  // The residual's row r of nodes.
  void residual_row(int r, const double* b, const double* x, double* out) const {
    for (int c = 0; c < cols_; ++c) {
      const std::size_t i = node(r, c);
      double sum[3] = {b[3 * i], b[3 * i + 1], b[3 * i + 2]};
      if (!fixed(i)) subtract_row_product(r, c, x, sum, false);
      for (int k = 0; k < 3; ++k) out[3 * i + k] = fixed(i) ? 0.0 : sum[k];
    }
  }

  // Bytes of the level's storage: its blocks, packed blocks, row starts and fixed flags.
  std::size_t storage_bytes() const {
    return blocks_.size() * sizeof(double) + packed_.size() * sizeof(PackedReal) +
           offsets_.size() * sizeof(std::size_t) + fixed_.size();
  }

  // sum -= (row (r, c) of A) x, without the diagonal block where skip_diagonal; only the
  // offsets `pack` found nonzero somewhere. An interior row reads its packed blocks.
  void subtract_row_product(int r, int c, const double* x, double* sum, bool skip_diagonal) const {
    if (packed_valid_ && interior(r, c)) {
      subtract_packed_row_product(r, c, x, sum, skip_diagonal);
      return;
    }
    const Window w = window(r, c);
    const double* row = row_blocks(r, c);
    for (const Offset& offset : couplings_) {
      const int r2 = r + offset.rows, c2 = c + offset.cols;
      if (r2 < w.row_begin || r2 >= w.row_end || c2 < w.col_begin || c2 >= w.col_end) continue;
      if (skip_diagonal && offset.rows == 0 && offset.cols == 0) continue;
      const double* a = row + 9 * ((r2 - w.row_begin) * w.width() + (c2 - w.col_begin));
      const double* xj = &x[3 * node(r2, c2)];
      for (int k = 0; k < 3; ++k)
        sum[k] -= a[3 * k] * xj[0] + a[3 * k + 1] * xj[1] + a[3 * k + 2] * xj[2];
    }
  }

  // Records which window offsets hold a nonzero block in some row (the fine Provot level
  // couples 13 of the 25), so products skip the others; call after the blocks change. A
  // Blocks::single level also rounds its off-diagonal blocks to single precision and packs the
  // interior rows' off-diagonal blocks of those offsets contiguously: a product then streams 36
  // bytes per block, not 72, and every path (packed, windowed, the Galerkin product from this
  // level) sees the one rounded matrix. The diagonal blocks stay exact: on a fine cloth the
  // mass term is below single precision's resolution of the diagonal.
  void pack() {
    std::array<bool, kWindow * kWindow> used{};
    for (int r = 0; r < rows_; ++r)
      for (int c = 0; c < cols_; ++c) {
        const Window w = window(r, c);
        double* a = row_blocks(r, c);
        for (int r2 = w.row_begin; r2 < w.row_end; ++r2)
          for (int c2 = w.col_begin; c2 < w.col_end; ++c2, a += 9) {
            if (std::any_of(a, a + 9, [](double value) { return value != 0.0; }))
              used[static_cast<std::size_t>((r2 - r + reach) * kWindow + (c2 - c + reach))] = true;
            if (single_ && (r2 != r || c2 != c))
              for (int k = 0; k < 9; ++k) a[k] = static_cast<double>(static_cast<PackedReal>(a[k]));
          }
      }
    couplings_.clear();
    coupling_steps_.clear();
    diagonal_coupling_ = kNoDiagonal;
    for (int k = 0; k < kWindow * kWindow; ++k)
      if (used[static_cast<std::size_t>(k)]) {
        const Offset offset{k / kWindow - reach, k % kWindow - reach};
        if (offset.rows == 0 && offset.cols == 0) diagonal_coupling_ = couplings_.size();
        couplings_.push_back(offset);
        coupling_steps_.push_back(3 *
                                  (static_cast<std::ptrdiff_t>(offset.rows) * cols_ + offset.cols));
      }
    packed_valid_ = false;
    if (!single_ || packed_.empty()) return;
    PackedReal* out = packed_.data();
    for (int r = reach; r < rows_ - reach; ++r)
      for (int c = reach; c < cols_ - reach; ++c) {
        const double* row = row_blocks(r, c);
        for (const Offset& offset : couplings_) {
          if (offset.rows == 0 && offset.cols == 0) continue;
          const double* a = row + 9 * ((offset.rows + reach) * kWindow + offset.cols + reach);
          for (int k = 0; k < 9; ++k) *out++ = static_cast<PackedReal>(a[k]);
        }
      }
    packed_valid_ = true;
  }

 private:
  using PackedReal = float;

  bool interior(int r, int c) const {
    return r >= reach && r < rows_ - reach && c >= reach && c < cols_ - reach;
  }
  std::size_t interior_count() const {
    return rows_ > 2 * reach && cols_ > 2 * reach
               ? static_cast<std::size_t>(rows_ - 2 * reach) * (cols_ - 2 * reach)
               : 0;
  }

  // subtract_row_product for an interior row: the same sums in the same order, the off-
  // diagonal blocks from the packed ones at fixed steps from the row's own node, the diagonal
  // from the row's exact block.
  void subtract_packed_row_product(int r, int c, const double* x, double* sum,
                                   bool skip_diagonal) const {
    const std::size_t count = couplings_.size();
    const std::size_t packed_count = count - (diagonal_coupling_ == kNoDiagonal ? 0 : 1);
    const std::size_t index =
        static_cast<std::size_t>(r - reach) * (cols_ - 2 * reach) + (c - reach);
    const PackedReal* packed = &packed_[9 * packed_count * index];
    const double* diagonal = row_blocks(r, c) + 9 * (reach * kWindow + reach);
    const double* x_row = &x[3 * node(r, c)];
    for (std::size_t j = 0; j < count; ++j) {
      const double* xj = x_row + coupling_steps_[j];
      if (j == diagonal_coupling_) {
        if (!skip_diagonal)
          for (int k = 0; k < 3; ++k)
            sum[k] -=
                diagonal[3 * k] * xj[0] + diagonal[3 * k + 1] * xj[1] + diagonal[3 * k + 2] * xj[2];
        continue;
      }
      for (int k = 0; k < 3; ++k)
        sum[k] -= static_cast<double>(packed[3 * k]) * xj[0] +
                  static_cast<double>(packed[3 * k + 1]) * xj[1] +
                  static_cast<double>(packed[3 * k + 2]) * xj[2];
      packed += 9;
    }
  }

  std::size_t slot(int r, int c, int r2, int c2) const {
    return offsets_[node(r, c)] + window_slot(window(r, c), r2, c2);
  }

  static constexpr int kWindow = 2 * reach + 1;
  static constexpr std::size_t kNoDiagonal = ~std::size_t{0};
  static constexpr std::size_t kNodesWorthATeam = 4096;

  int rows_, cols_;
  bool single_;  // Blocks::single
  std::vector<uint8_t> fixed_;
  std::vector<Offset> couplings_;                // window offsets with a nonzero block somewhere
  std::vector<std::ptrdiff_t> coupling_steps_;   // per coupling: its x index less the row's
  std::size_t diagonal_coupling_ = kNoDiagonal;  // the diagonal's place among the couplings
  bool packed_valid_ = false;                    // packed_ holds the current blocks
  std::vector<PackedReal> packed_;    // interior rows' coupled off-diagonal blocks, 9 floats each
  std::vector<std::size_t> offsets_;  // node_count + 1: where each row's blocks begin
  std::vector<double> blocks_;        // 9 per window entry
};

// out = a^-1 for a symmetric 3x3 block (row-major); false unless a is positive definite.
inline bool invert_positive_definite(const double* a, double* out) {
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

// inverse (9 per node, row-major) = the level's diagonal blocks inverted on free nodes; false
// where one is not positive definite. Rows split among `threads`, each node's inverse its own.
inline bool invert_diagonal_blocks(const GridLevel& level, std::vector<double>& inverse,
                                   int threads = 1) {
  std::vector<uint8_t> definite(static_cast<std::size_t>(level.rows()), 1);
  level.for_each_index(level.rows(), threads, [&](int r) {
    for (int c = 0; c < level.cols(); ++c) {
      const std::size_t i = level.node(r, c);
      if (level.fixed(i)) continue;
      if (!invert_positive_definite(level.block(r, c, r, c), &inverse[9 * i]))
        return void(definite[static_cast<std::size_t>(r)] = 0);
    }
  });
  return std::all_of(definite.begin(), definite.end(), [](uint8_t row) { return row != 0; });
}

}  // namespace clothlab::builtin
