// Transfer between a grid level and the next coarser one: prolongation P, bilinear
// interpolation (each weight times the 3x3 identity), restriction R = P^T, and the Galerkin
// coarse operator R A P.
//
// Along an axis of n >= 3 nodes the coarse level keeps every m-th node (m, the coarsening: 2,
// or 3 where fewer coarse nodes pay: multigrid_preconditioner.hpp), (n - 2) / m + 2 of them:
// coarse node k sits on fine node m k, the last one on fine node n - 1 (its interval may be
// shorter). A fine node on a coarse node takes it with weight 1; one between two takes each by
// linear interpolation (1/2 and 1/2; 2/3 and 1/3). A coarse node on a fixed fine node is fixed,
// and P has no weight into or out of a fixed node, so the pins are Dirichlet on every level.
//
// Reach: a fine coupling spans at most 2 fine spacings, no more than one coarse interval, so
// R A P couples coarse nodes at most 2 coarse spacings apart (GridLevel::reach).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "multigrid_level.hpp"

namespace clothlab::builtin {

// The coarsenings a transfer takes: every other node, or every third.
constexpr int kMinCoarsening = 2, kMaxCoarsening = 3;

// Nodes along a coarse axis for a fine one of n nodes (n >= 3), every m-th kept.
inline uint32_t coarse_axis_size(uint32_t n, int m = kMinCoarsening) {
  return (n - 2) / static_cast<uint32_t>(m) + 2;
}

// The fine nodes' parents along one axis, every m-th node kept: first[f], and first[f] + 1 too
// where two[f], weight(f, k) on parent k.
struct AxisParents {
  AxisParents(int n, int m)
      : first(static_cast<std::size_t>(n)),
        two(static_cast<std::size_t>(n)),
        weights(2 * static_cast<std::size_t>(n)) {
    const int coarse = static_cast<int>(coarse_axis_size(static_cast<uint32_t>(n), m));
    const auto at = [&](int k) { return std::min(m * k, n - 1); };  // coarse node k's fine node
    for (int f = 0; f < n; ++f) {
      int k = std::min(f / m, coarse - 1);
      while (k + 1 < coarse && at(k + 1) <= f) ++k;
      const auto i = static_cast<std::size_t>(f);
      first[i] = k;
      if (at(k) == f) {
        two[i] = 0, weights[2 * i] = 1.0;
      } else {
        const double t = static_cast<double>(f - at(k)) / (at(k + 1) - at(k));
        two[i] = 1, weights[2 * i] = 1.0 - t, weights[2 * i + 1] = t;
      }
    }
  }
  int count(int f) const { return two[static_cast<std::size_t>(f)] ? 2 : 1; }
  int parent(int f, int k) const { return first[static_cast<std::size_t>(f)] + k; }
  double weight(int f, int k) const { return weights[2 * static_cast<std::size_t>(f) + k]; }

  std::vector<int> first;
  std::vector<uint8_t> two;
  std::vector<double> weights;  // 2 per fine node
};

class GridTransfer {
 public:
  // coarsening: every m-th node kept (kMinCoarsening to kMaxCoarsening).
  explicit GridTransfer(const GridLevel& fine, int coarsening = kMinCoarsening)
      : coarsening_(coarsening),
        row_parents_(fine.rows(), coarsening),
        col_parents_(fine.cols(), coarsening) {
    if (coarsening < kMinCoarsening || coarsening > kMaxCoarsening)
      throw std::invalid_argument("multigrid: a coarsening of " + std::to_string(coarsening) +
                                  " (takes 2 to 3)");
    plan_classes(fine);
  }

  // Every coarsening-th node is kept.
  int coarsening() const { return coarsening_; }

  // Fine nodes whose rows of the Galerkin product follow their class's plan (the rest take the
  // general path).
  std::size_t planned_nodes() const {
    return static_cast<std::size_t>(std::count(planned_.begin(), planned_.end(), uint8_t{1}));
  }
  // The general path on every row from now on (for comparing the two).
  void drop_plan() { std::fill(planned_.begin(), planned_.end(), uint8_t{0}); }
  // The Galerkin product's coarse rows per band (kBandRows unless set; for comparing band plans).
  void set_band_rows(int rows) { band_rows_ = std::max(rows, 1); }

  // The coarse level's fixed nodes: those on a fixed fine node.
  std::vector<uint8_t> coarse_fixed(const GridLevel& fine) const {
    const int coarse_cols =
        static_cast<int>(coarse_axis_size(static_cast<uint32_t>(fine.cols()), coarsening_));
    const int coarse_rows =
        static_cast<int>(coarse_axis_size(static_cast<uint32_t>(fine.rows()), coarsening_));
    std::vector<uint8_t> fixed(static_cast<std::size_t>(coarse_rows) * coarse_cols, 0);
    for (int r = 0; r < fine.rows(); ++r)
      for (int c = 0; c < fine.cols(); ++c)
        if (row_parents_.count(r) == 1 && col_parents_.count(c) == 1 && fine.fixed(fine.node(r, c)))
          fixed[static_cast<std::size_t>(row_parents_.parent(r, 0)) * coarse_cols +
                col_parents_.parent(c, 0)] = 1;
    return fixed;
  }

  // Fine columns a transfer handles at once (a chunk's rows summed on the stack).
  static constexpr int kChunk = 64;
  // A chunk of one fine row, component-major: value[k][c - c0] for the chunk's columns from c0.
  using ChunkRow = double[3][kChunk];

  // coarse_b = R fine_r, a coarse row at a time from the fine rows under it; both 3 doubles per
  // node.
  void restrict_to(const GridLevel& fine, const double* fine_r, const GridLevel& coarse,
                   double* coarse_b, int threads = 1) const {
    restrict_from(fine, coarse, coarse_b, threads,
                  [&](int r, int c0, int c1, double weight, ChunkRow& sum) {
                    for (int c = c0; c < c1; ++c) {
                      const std::size_t f = fine.node(r, c);
                      if (fine.fixed(f)) continue;
                      for (int k = 0; k < 3; ++k) sum[k][c - c0] += weight * fine_r[3 * f + k];
                    }
                  });
  }
  // As restrict_to, the fine vector read by add_row(r, c0, c1, weight, sum): sum[k][c - c0] +=
  // weight r_(r, c) component k for the columns [c0, c1), 0 on fixed nodes (for a caller whose
  // fine vectors have another layout, the system's, read without a copy). Separable: a coarse
  // row sums its fine rows' weighted chunks, then each coarse node its chunk columns in order,
  // so any split of the coarse rows among `threads` gives the same bits.
  template <class AddRow>
  void restrict_from(const GridLevel& fine, const GridLevel& coarse, double* coarse_b, int threads,
                     AddRow&& add_row) const {
    fine.for_each_index(coarse.rows(), threads, [&](int pr) {
      double* const out = coarse_b + 3 * coarse.node(pr, 0);
      std::fill_n(out, 3 * coarse.cols(), 0.0);
      for (int c0 = 0; c0 < fine.cols(); c0 += kChunk) {
        const int c1 = std::min(c0 + kChunk, fine.cols());
        ChunkRow sum{};
        for (int r = std::max(coarsening_ * (pr - 1), 0);
             r <= std::min(coarsening_ * (pr + 1), fine.rows() - 1); ++r)
          for (int i = 0; i < row_parents_.count(r); ++i)
            if (row_parents_.parent(r, i) == pr) add_row(r, c0, c1, row_parents_.weight(r, i), sum);
        for (int c = c0; c < c1; ++c)
          for (int j = 0; j < col_parents_.count(c); ++j) {
            const double w = col_parents_.weight(c, j);
            double* const parent = out + 3 * col_parents_.parent(c, j);
            for (int k = 0; k < 3; ++k) parent[k] += w * sum[k][c - c0];
          }
      }
      for (int pc = 0; pc < coarse.cols(); ++pc)  // the pins are Dirichlet: nothing reaches them
        if (coarse.fixed(coarse.node(pr, pc))) std::fill_n(out + 3 * pc, 3, 0.0);
    });
  }

  // fine_x += P coarse_x, fine rows split among `threads`.
  void prolong_add(const GridLevel& fine, const GridLevel& coarse, const double* coarse_x,
                   double* fine_x, int threads = 1) const {
    prolong_to(fine, coarse, coarse_x, threads, [&](int r, int c0, int c1, const ChunkRow& value) {
      for (int c = c0; c < c1; ++c) {
        const std::size_t f = fine.node(r, c);
        if (fine.fixed(f)) continue;
        for (int k = 0; k < 3; ++k) fine_x[3 * f + k] += value[k][c - c0];
      }
    });
  }
  // (P coarse_x) on fine row r's columns [c0, c1) handed to add_row(r, c0, c1, value), value as
  // restrict_from's sum (the caller skips fixed fine nodes). Separable: the coarse rows
  // interpolated along the column first, then along the row; fine rows split among `threads`.
  template <class AddRow>
  void prolong_to(const GridLevel& fine, const GridLevel& coarse, const double* coarse_x,
                  int threads, AddRow&& add_row) const {
    fine.for_each_index(fine.rows(), threads, [&](int r) {
      for (int c0 = 0; c0 < fine.cols(); c0 += kChunk) {
        const int c1 = std::min(c0 + kChunk, fine.cols());
        // The chunk's parent columns, interpolated between the row's parent rows.
        const int first = col_parents_.parent(c0, 0);
        const int last = col_parents_.parent(c1 - 1, col_parents_.count(c1 - 1) - 1);
        double along[3][kChunk / kMinCoarsening + 2]{};
        for (int i = 0; i < row_parents_.count(r); ++i) {
          const int pr = row_parents_.parent(r, i);
          const double w = row_parents_.weight(r, i);
          for (int pc = first; pc <= last; ++pc) {
            const std::size_t parent = coarse.node(pr, pc);
            if (coarse.fixed(parent)) continue;
            for (int k = 0; k < 3; ++k) along[k][pc - first] += w * coarse_x[3 * parent + k];
          }
        }
        ChunkRow value{};
        for (int c = c0; c < c1; ++c)
          for (int j = 0; j < col_parents_.count(c); ++j) {
            const double w = col_parents_.weight(c, j);
            const int at = col_parents_.parent(c, j) - first;
            for (int k = 0; k < 3; ++k) value[k][c - c0] += w * along[k][at];
          }
        add_row(r, c0, c1, static_cast<const ChunkRow&>(value));
      }
    });
  }

  // What the Galerkin product (multigrid_galerkin.hpp, compiled per SIMD target) reads.
  static constexpr int kSpan = 5;  // a fine row's A P: 5 x 5 coarse blocks
  int band_rows() const { return band_rows_; }
  const AxisParents& row_parents() const { return row_parents_; }
  const AxisParents& col_parents() const { return col_parents_; }

  // The plan of a class of interior fine rows. Every m-th node kept, a fine node f whose
  // window's nodes all lie at the regular spacing (none on the last, nearer coarse node) has
  // parents and weights that depend only on (r mod m, c mod m), and so does each term of its
  // row of A P: the fine block's window place, the A P block it adds to (a place in the 5 x 5
  // span from f's first parent less 2) and its weight. A planned row's window holds no fixed
  // fine node, and the span no fixed coarse node, so no term is skipped.
  struct ClassTerm {
    uint8_t place;  // the fine block's: row place / 5, column place % 5 of f's window
    double weight;
  };
  struct ClassBlock {
    int local;            // the A P block: row local / 5, column local % 5 of the span
    uint16_t begin, end;  // its terms, in the fine blocks' order
  };
  struct ClassParent {
    int row, col;  // from f's first parent
    double weight;
  };
  struct ClassPlan {
    std::vector<ClassBlock> blocks;
    std::vector<ClassTerm> terms;
    std::vector<ClassParent> parents;  // f's own, in the general path's order
  };

  // Whether fine node (r, c)'s row follows its class's plan, and that plan.
  bool planned(const GridLevel& fine, int r, int c) const { return planned_[fine.node(r, c)]; }
  const ClassPlan& plan(int r, int c) const {
    return plans_[static_cast<std::size_t>((r % coarsening_) * coarsening_ + c % coarsening_)];
  }

 private:
  static constexpr int kBandRows = 8;  // coarse rows per band of the Galerkin product

  // Marks the fine nodes whose rows follow a plan, and forms each class's plan from its first
  // such node, by the general path's rules (the same order of terms).
  void plan_classes(const GridLevel& fine) {
    const int m = coarsening_;
    plans_.assign(static_cast<std::size_t>(m * m), {});
    planned_.assign(fine.node_count(), 0);
    if (fine.rows() < 3 || fine.cols() < 3) return;
    const std::vector<uint8_t> coarse_fixed_nodes = coarse_fixed(fine);
    const int coarse_rows =
        static_cast<int>(coarse_axis_size(static_cast<uint32_t>(fine.rows()), m));
    const int coarse_cols =
        static_cast<int>(coarse_axis_size(static_cast<uint32_t>(fine.cols()), m));
    std::vector<uint8_t> planned_class(plans_.size(), 0);
    for (int r = kSpan / 2; r + kSpan / 2 < fine.rows(); ++r)
      for (int c = kSpan / 2; c + kSpan / 2 < fine.cols(); ++c) {
        const int pr = row_parents_.parent(r, 0), pc = col_parents_.parent(c, 0);
        // The span (and f's second parent's window) inside the coarse grid, short of its last
        // node: only that node's interval may be shorter, so every parent of the window's nodes
        // is at the regular spacing.
        if (pr < 2 || pr + 3 >= coarse_rows || pc < 2 || pc + 3 >= coarse_cols) continue;
        bool plain = true;
        for (int r2 = r - 2; r2 <= r + 2 && plain; ++r2)
          for (int c2 = c - 2; c2 <= c + 2 && plain; ++c2) plain = !fine.fixed(fine.node(r2, c2));
        for (int r2 = pr - 2; r2 <= pr + 2 && plain; ++r2)
          for (int c2 = pc - 2; c2 <= pc + 2 && plain; ++c2)
            plain = !coarse_fixed_nodes[static_cast<std::size_t>(r2) * coarse_cols + c2];
        if (!plain) continue;
        planned_[fine.node(r, c)] = 1;
        const auto at = static_cast<std::size_t>((r % m) * m + c % m);
        if (planned_class[at]) continue;
        planned_class[at] = 1;
        ClassPlan& plan = plans_[at];
        const int row0 = pr - 2, col0 = pc - 2;
        std::array<std::vector<ClassTerm>, kSpan * kSpan> by_block;
        for (int place = 0; place < kSpan * kSpan; ++place) {
          const int r2 = r + place / kSpan - 2, c2 = c + place % kSpan - 2;
          for (int i = 0; i < row_parents_.count(r2); ++i)
            for (int j = 0; j < col_parents_.count(c2); ++j)
              by_block[static_cast<std::size_t>((row_parents_.parent(r2, i) - row0) * kSpan +
                                                (col_parents_.parent(c2, j) - col0))]
                  .push_back({static_cast<uint8_t>(place),
                              row_parents_.weight(r2, i) * col_parents_.weight(c2, j)});
        }
        for (int local = 0; local < kSpan * kSpan; ++local) {
          const std::vector<ClassTerm>& terms = by_block[static_cast<std::size_t>(local)];
          if (terms.empty()) continue;
          const auto begin = static_cast<uint16_t>(plan.terms.size());
          plan.terms.insert(plan.terms.end(), terms.begin(), terms.end());
          plan.blocks.push_back({local, begin, static_cast<uint16_t>(plan.terms.size())});
        }
        for (int i = 0; i < row_parents_.count(r); ++i)
          for (int j = 0; j < col_parents_.count(c); ++j)
            plan.parents.push_back({i, j, row_parents_.weight(r, i) * col_parents_.weight(c, j)});
      }
  }

  int coarsening_;
  int band_rows_ = kBandRows;
  AxisParents row_parents_, col_parents_;
  std::vector<ClassPlan> plans_;  // per class (r mod m) m + c mod m
  std::vector<uint8_t> planned_;  // per fine node: its row follows its class's plan
};

}  // namespace clothlab::builtin
