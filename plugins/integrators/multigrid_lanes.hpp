// A single-precision grid level (GridLevel::Blocks::single) laid out for the smoother's lane
// kernels: the nodes of one column class c mod 3 of a row do not couple, so a kernel updates a
// whole class of a row at once, kLanes nodes per inner loop, from contiguous loads.
//
// Vectors: each row holds, per component, its three column classes one after the other, the
// node (r, c) at place (c + reach) / 3 of class (c + reach) mod 3, with `reach` zero rows above
// and below and zero nodes beyond both sides: a neighbour (r + dr, c + dc) of any node of a
// class sits at one fixed step from it, and no kernel tests for an edge. Blocks: per row, class
// and coupled window offset (GridLevel::couplings, the diagonal apart), the 9 entries of every
// node of the class in turn (run by run of kLanes nodes), zero where the offset leaves the grid,
// the node is fixed or it is a margin node. The diagonal blocks and the smoother's inverses of them
// are zero on fixed and margin nodes, so their x stays 0.
//
// Real: the precision of x, b, the residual and the diagonal blocks between `gather` and
// `scatter`, and of the sums: float for a float32 system's preconditioner (its CG cannot resolve
// more), double otherwise. The kernels sum a node's couplings in the level's order, so every
// thread count gives the same bits.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "multigrid_level.hpp"

namespace clothlab::builtin {

// The precision of a single level's smoothing (LaneLevel's Real).
enum class LanePrecision { float32, float64 };

template <class Real>
class LaneLevel {
 public:
  static constexpr int kPeriod = GridLevel::reach + 1;  // column classes
  static constexpr int kLanes = 8;                      // nodes per inner loop

  explicit LaneLevel(const GridLevel& level)
      : rows_(level.rows()),
        cols_(level.cols()),
        lanes_(round_up((cols_ + 2 * GridLevel::reach + kPeriod - 1) / kPeriod, kLanes)),
        span_(lanes_ + 2),
        component_(static_cast<std::ptrdiff_t>(kPeriod) * span_),
        class_nodes_(static_cast<std::size_t>(rows_) * kPeriod * lanes_),
        blocks_(9 * kMaxCouplings * class_nodes_, 0.0f),
        diagonal_(9 * class_nodes_, Real{0}),
        inverse_diagonal_(9 * class_nodes_, Real{0}),
        x_(vector_size(), Real{0}),
        b_(vector_size(), Real{0}),
        residual_(vector_size(), Real{0}),
        next_x_(vector_size(), Real{0}),
        direction_(vector_size(), Real{0}) {}

  // Bytes of the blocks in use, the diagonal blocks, their inverses and the five vectors.
  std::size_t storage_bytes() const {
    return 9 * couplings_ * class_nodes_ * sizeof(float) +
           (diagonal_.size() + inverse_diagonal_.size() + 5 * x_.size()) * sizeof(Real);
  }

  // The level's blocks and the smoother's inverted diagonal blocks (9 per node, row-major, 0 on
  // fixed nodes) into the lanes; after the level's `pack`.
  void load(const GridLevel& level, const std::vector<double>& inverse_diagonal, int threads = 1) {
    couplings_ = 0;
    for (const GridLevel::Offset& offset : level.couplings())
      if (offset.rows != 0 || offset.cols != 0) {
        for (int k = 0; k < kPeriod; ++k) {
          const int dc = k + offset.cols;
          const int shifted_class = (dc % kPeriod + kPeriod) % kPeriod;
          steps_[k][couplings_] =
              offset.rows * 3 * component_ + (shifted_class - k) * span_ + floor_div(dc, kPeriod);
        }
        offsets_[couplings_++] = offset;
      }
    std::fill_n(blocks_.begin(), 9 * couplings_ * class_nodes_, 0.0f);
    std::fill(diagonal_.begin(), diagonal_.end(), Real{0});
    std::fill(inverse_diagonal_.begin(), inverse_diagonal_.end(), Real{0});
    level.for_each_index(rows_, threads, [&](int r) {
      for (int c = 0; c < cols_; ++c) {
        const std::size_t i = level.node(r, c);
        if (level.fixed(i)) continue;
        const int k = (c + GridLevel::reach) % kPeriod, q = (c + GridLevel::reach) / kPeriod;
        const GridLevel::Window w = level.window(r, c);
        for (std::size_t j = 0; j < couplings_; ++j) {
          const int r2 = r + offsets_[j].rows, c2 = c + offsets_[j].cols;
          if (r2 < w.row_begin || r2 >= w.row_end || c2 < w.col_begin || c2 >= w.col_end) continue;
          const double* a = level.block(r, c, r2, c2);
          float* out = &blocks_[block_start(r, k, q, j)];
          for (std::size_t e = 0; e < 9; ++e) out[e * kLanes] = static_cast<float>(a[e]);
        }
        const double* d = level.block(r, c, r, c);
        for (std::size_t e = 0; e < 9; ++e) {
          diagonal_[diagonal_start(r, k, q) + e * kLanes] = static_cast<Real>(d[e]);
          inverse_diagonal_[diagonal_start(r, k, q) + e * kLanes] =
              static_cast<Real>(inverse_diagonal[9 * i + e]);
        }
      }
    });
  }

  // b, and x where it is not null (3 doubles per node), into the lanes, rows split among
  // `threads`.
  void gather(const GridLevel& level, const double* b, const double* x, int threads) {
    level.for_each_index(rows_, threads, [&](int r) {
      for (int c = 0; c < cols_; ++c)
        for (int d = 0; d < 3; ++d) {
          const std::size_t at = place(r, c, d), i = 3 * level.node(r, c) + d;
          b_[at] = static_cast<Real>(b[i]);
          if (x != nullptr) x_[at] = static_cast<Real>(x[i]);
        }
    });
  }
  // x, and the residual where `residual` is not null (0 on fixed nodes), out of the lanes.
  void scatter(const GridLevel& level, double* x, double* residual, int threads) const {
    level.for_each_index(rows_, threads, [&](int r) {
      for (int c = 0; c < cols_; ++c)
        for (int d = 0; d < 3; ++d) {
          const std::size_t at = place(r, c, d), i = 3 * level.node(r, c) + d;
          x[i] = x_[at];
          if (residual != nullptr) residual[i] = level.fixed(i / 3) ? 0.0 : double{residual_[at]};
        }
    });
  }

  // Gauss-Seidel on the nodes of row r in columns col_class, col_class + 3, ...:
  // x_i = A_ii^-1 (b_i - sum_{j != i} A_ij x_j).
  void update(int r, int col_class) {
    const int k = (col_class + GridLevel::reach) % kPeriod;
    for_lanes(r, k, [&](Real* x, int q, const Real(&sum)[3][kLanes]) {
      const Real* inverse = &inverse_diagonal_[diagonal_start(r, k, q)];
      for (int d = 0; d < 3; ++d) {
        const Real* row = inverse + 3 * d * kLanes;
#pragma omp simd
        for (int l = 0; l < kLanes; ++l)
          x[d * component_ + l] =
              row[l] * sum[0][l] + row[kLanes + l] * sum[1][l] + row[2 * kLanes + l] * sum[2][l];
      }
    });
  }

  // Chebyshev's first step from x = 0 on row r's nodes: direction = scale D^-1 b, x = direction.
  void start_chebyshev_row(int r, Real scale) {
    for (int k = 0; k < kPeriod; ++k) {
      const std::size_t start = lane_start(r, k);
      for (int q = 0; q < lanes_; q += kLanes) {
        const std::size_t at = start + static_cast<std::size_t>(q);
        const Real* inverse = &inverse_diagonal_[diagonal_start(r, k, q)];
        for (int d = 0; d < 3; ++d) {
          const Real* row = inverse + 3 * d * kLanes;
          const Real* b = &b_[at];
          Real* direction = &direction_[at + static_cast<std::size_t>(d * component_)];
          Real* x = &x_[at + static_cast<std::size_t>(d * component_)];
#pragma omp simd
          for (int l = 0; l < kLanes; ++l) {
            direction[l] = scale * (row[l] * b[l] + row[kLanes + l] * b[component_ + l] +
                                    row[2 * kLanes + l] * b[2 * component_ + l]);
            x[l] = direction[l];
          }
        }
      }
    }
  }

  // A Chebyshev step on row r's nodes, in one pass: direction = keep direction + scale D^-1
  // (b - A x), and the next iterate x + direction into the other iterate (`swap_iterates` after
  // the pass), so that every row reads the same x whatever order the rows go in.
  void chebyshev_row(int r, Real keep, Real scale) {
    for (int k = 0; k < kPeriod; ++k)
      for_lanes(r, k, [&](Real* x, int q, const Real(&sum)[3][kLanes]) {
        const Real* diagonal = &diagonal_[diagonal_start(r, k, q)];
        const Real* inverse = &inverse_diagonal_[diagonal_start(r, k, q)];
        const std::size_t at = static_cast<std::size_t>(x - x_.data());
        Real residual[3][kLanes];
        for (int d = 0; d < 3; ++d) {
          const Real* row = diagonal + 3 * d * kLanes;
#pragma omp simd
          for (int l = 0; l < kLanes; ++l)
            residual[d][l] = sum[d][l] - (row[l] * x[l] + row[kLanes + l] * x[component_ + l] +
                                          row[2 * kLanes + l] * x[2 * component_ + l]);
        }
        for (int d = 0; d < 3; ++d) {
          const Real* row = inverse + 3 * d * kLanes;
          const std::size_t component = at + static_cast<std::size_t>(d * component_);
          Real* direction = &direction_[component];
          Real* next = &next_x_[component];
          const Real* current = &x_[component];
#pragma omp simd
          for (int l = 0; l < kLanes; ++l) {
            direction[l] = keep * direction[l] +
                           scale * (row[l] * residual[0][l] + row[kLanes + l] * residual[1][l] +
                                    row[2 * kLanes + l] * residual[2][l]);
            next[l] = current[l] + direction[l];
          }
        }
      });
  }
  // The iterate `chebyshev_row` wrote becomes x.
  void swap_iterates() { x_.swap(next_x_); }

  // The residual b - A x of row r's nodes.
  void residual_row(int r) {
    for (int k = 0; k < kPeriod; ++k)
      for_lanes(r, k, [&](Real* x, int q, const Real(&sum)[3][kLanes]) {
        const Real* diagonal = &diagonal_[diagonal_start(r, k, q)];
        Real* out = &residual_[static_cast<std::size_t>(x - x_.data())];
        for (int d = 0; d < 3; ++d) {
          const Real* row = diagonal + 3 * d * kLanes;
#pragma omp simd
          for (int l = 0; l < kLanes; ++l)
            out[d * component_ + l] =
                sum[d][l] - (row[l] * x[l] + row[kLanes + l] * x[component_ + l] +
                             row[2 * kLanes + l] * x[2 * component_ + l]);
        }
      });
  }

 private:
  // Window offsets a row may couple to besides its own node.
  static constexpr std::size_t kMaxCouplings =
      (2 * GridLevel::reach + 1) * (2 * GridLevel::reach + 1) - 1;

  static int round_up(int n, int multiple) { return (n + multiple - 1) / multiple * multiple; }
  static int floor_div(int n, int d) { return n >= 0 ? n / d : -((-n + d - 1) / d); }

  std::size_t vector_size() const {
    return static_cast<std::size_t>(rows_ + 2 * GridLevel::reach) * 3 * component_;
  }
  // Where node (r, c)'s component d lives in a vector.
  std::size_t place(int r, int c, int d) const {
    const int padded = c + GridLevel::reach;
    return lane_start(r, padded % kPeriod) + static_cast<std::size_t>(d * component_) +
           static_cast<std::size_t>(padded / kPeriod);
  }
  // Component 0 of the first node of class k in row r.
  std::size_t lane_start(int r, int k) const {
    return static_cast<std::size_t>((r + GridLevel::reach) * 3 * component_ + k * span_ + 1);
  }
  // Blocks and diagonal blocks go run by run of kLanes nodes, so that a kernel streams them.
  std::size_t block_start(int r, int k, int q, std::size_t j) const {
    return ((static_cast<std::size_t>(r) * kPeriod + k) * lanes_ + q - q % kLanes) * 9 *
               couplings_ +
           j * 9 * kLanes + q % kLanes;
  }
  std::size_t diagonal_start(int r, int k, int q) const {
    return ((static_cast<std::size_t>(r) * kPeriod + k) * lanes_ + q - q % kLanes) * 9 + q % kLanes;
  }

  // body(x, q, sum) for each run of kLanes nodes of class k in row r from place q, with x at
  // the run's component 0 and sum = b - (the couplings but the diagonal) x.
  template <class Body>
  void for_lanes(int r, int k, Body&& body) {
    const std::size_t start = lane_start(r, k);
    for (int q = 0; q < lanes_; q += kLanes) {
      Real* x = &x_[start + static_cast<std::size_t>(q)];
      const Real* b = &b_[start + static_cast<std::size_t>(q)];
      Real sum[3][kLanes];
      for (int d = 0; d < 3; ++d)
        for (int l = 0; l < kLanes; ++l) sum[d][l] = b[d * component_ + l];
      for (std::size_t j = 0; j < couplings_; ++j) {
        const Real* xj = x + steps_[k][j];
        const float* a = &blocks_[block_start(r, k, q, j)];
        for (int d = 0; d < 3; ++d) {
          const float* row = a + 3 * d * kLanes;
#pragma omp simd
          for (int l = 0; l < kLanes; ++l)
            sum[d][l] -= static_cast<Real>(row[l]) * xj[l] +
                         static_cast<Real>(row[kLanes + l]) * xj[component_ + l] +
                         static_cast<Real>(row[2 * kLanes + l]) * xj[2 * component_ + l];
        }
      }
      body(x, q, sum);
    }
  }

  int rows_, cols_;
  int lanes_;                  // places per class row, a multiple of kLanes
  std::ptrdiff_t span_;        // a class row in a vector: lanes_ and a zero place each side
  std::ptrdiff_t component_;   // a component's three class rows
  std::size_t class_nodes_;    // rows x classes x lanes
  std::size_t couplings_ = 0;  // off-diagonal offsets in use
  GridLevel::Offset offsets_[kMaxCouplings]{};
  std::ptrdiff_t steps_[kPeriod][kMaxCouplings]{};  // per class and coupling: the x step
  std::vector<float> blocks_;  // 9 per class node and coupling, sized for the most couplings
  std::vector<Real> diagonal_, inverse_diagonal_;  // 9 per class node
  // 3 per vector place; next_x_ and direction_ only for Chebyshev.
  std::vector<Real> x_, b_, residual_, next_x_, direction_;
};

}  // namespace clothlab::builtin
