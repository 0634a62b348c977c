// Coloured block Gauss-Seidel on a grid level: x_i = A_ii^-1 (b_i - sum_{j != i} A_ij x_j), one
// colour of nodes at a time. A row couples nodes up to GridLevel::reach = 2 spacings away, so
// the colour (r mod 3, c mod 3) leaves no two coupled nodes in one colour: nine colours (red/
// black or four colours would need nearest-neighbour coupling only, which the flexion springs
// break). Nodes of one colour are independent, so the result is the same whatever order or
// thread updates them. The rows of one class r mod 3 do not couple either, so each row goes
// through its three colours in turn, and the sweeps of a pass run as a wave over the rows
// (`run`), split among `threads` (the same bits on any count).
// `forward` sweeps the colours 0..8, `backward` 8..0: the backward sweep is the forward one's
// adjoint in the A inner product, which makes a V-cycle with forward pre- and backward
// post-smoothing a symmetric preconditioner. A single-precision level (the V-cycle's) runs the
// passes on its lanes (multigrid_lanes.hpp): the same updates, a column class of a row at once.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <vector>

#include "multigrid_lanes.hpp"
#include "multigrid_level.hpp"

namespace clothlab::builtin {

class BlockGaussSeidel {
 public:
  static constexpr int kPeriod = GridLevel::reach + 1;

  // lanes: the precision a single level's passes run in (multigrid_lanes.hpp).
  explicit BlockGaussSeidel(const GridLevel& level, LanePrecision lanes = LanePrecision::float64)
      : inverse_diagonal_(9 * level.node_count()) {
    if (level.single() && lanes == LanePrecision::float32) float_lanes_.emplace(level);
    if (level.single() && lanes == LanePrecision::float64) double_lanes_.emplace(level);
    set_steps_per_chunk(level, 0);
  }

  // Inverts the level's diagonal blocks; false where one of a free node is not positive definite.
  bool factor(const GridLevel& level) {
    for (int r = 0; r < level.rows(); ++r)
      for (int c = 0; c < level.cols(); ++c) {
        const std::size_t i = level.node(r, c);
        if (level.fixed(i)) continue;
        if (!invert_positive_definite(level.block(r, c, r, c), &inverse_diagonal_[9 * i]))
          return false;
      }
    if (float_lanes_) float_lanes_->load(level, inverse_diagonal_);
    if (double_lanes_) double_lanes_->load(level, inverse_diagonal_);
    return true;
  }

  // The inverted diagonal blocks, 9 per node (row-major), as `factor` left them.
  const std::vector<double>& inverse_diagonal() const { return inverse_diagonal_; }

  std::size_t storage_bytes() const {
    return inverse_diagonal_.size() * sizeof(double) +
           (float_lanes_ ? float_lanes_->storage_bytes() : 0) +
           (double_lanes_ ? double_lanes_->storage_bytes() : 0);
  }

  // `sweeps` forward sweeps from x, then out = b - A x where out is not null.
  void forward(const GridLevel& level, const double* b, double* x, long sweeps, double* out,
               int threads = 1) const {
    run(level, Pass{false, sweeps, out != nullptr}, b, x, out, threads);
  }
  // `sweeps` backward sweeps from x.
  void backward(const GridLevel& level, const double* b, double* x, long sweeps,
                int threads = 1) const {
    run(level, Pass{true, sweeps, false}, b, x, nullptr, threads);
  }

  // Steps of the wave per chunk (see `run`): the steps whose rows fill about kChunkNodes
  // nodes, at least one; 0 passes the chunk size back to that default.
  void set_steps_per_chunk(const GridLevel& level, int steps) {
    steps_per_chunk_ =
        steps > 0
            ? steps
            : std::max(1, static_cast<int>(kChunkNodes / (kPeriod * std::max(level.cols(), 1))));
  }

 private:
  // A pass's sweeps and residual run as a wave down the rows, so that a row's blocks are read
  // from memory once per pass and not once per sweep: at step t, sweep s updates the row of
  // class k that is 3 (t - lag) + k, lag = 2 s + k forward and s backward, and the residual
  // the three rows from 3 (t - 2 sweeps). These lags are the least for which every row sees
  // exactly the values of the colour order: forward, sweep s + 1 updates a row of class 0 from
  // sweep s's value of the class 2 row two rows below it, which sweep s updates two steps
  // after the class 0 row. Each (sweep, class) and the residual is a phase; the steps go in
  // chunks, each chunk runs its phases in order, and a phase's rows (of one class, 3 apart, or
  // residual rows) split among the threads. Every update that must precede another (a value
  // it writes is read, or a value it reads is overwritten) belongs to an earlier phase at the
  // same or an earlier step, so every chunk size gives the same bits.
  struct Pass {
    bool backward;
    long sweeps;
    bool residual;
    long phases() const { return kPeriod * sweeps + (residual ? 1 : 0); }
  };

  void run(const GridLevel& level, const Pass& pass, const double* b, double* x, double* out,
           int threads) const {
    if (float_lanes_) return run_on_lanes(*float_lanes_, level, pass, b, x, out, threads);
    if (double_lanes_) return run_on_lanes(*double_lanes_, level, pass, b, x, out, threads);
    wave(
        level, pass, threads,
        [&](int r, int col_class) { update_colour(level, r, col_class, b, x); },
        [&](int r) { level.residual_row(r, b, x, out); });
  }

  template <class Real>
  void run_on_lanes(LaneLevel<Real>& lanes, const GridLevel& level, const Pass& pass,
                    const double* b, double* x, double* out, int threads) const {
    lanes.gather(level, b, x, threads);
    wave(
        level, pass, threads, [&](int r, int col_class) { lanes.update(r, col_class); },
        [&](int r) { lanes.residual_row(r); });
    lanes.scatter(level, x, out, threads);
  }

  // The pass's wave: update(r, col_class) for the nodes of row r in columns col_class, col_class
  // + 3, ..., residual_row(r) for the residual's rows.
  template <class Update, class ResidualRow>
  void wave(const GridLevel& level, const Pass& pass, int threads, Update&& update,
            ResidualRow&& residual_row) const {
    const int rows = level.rows();
    const int steps = (rows + kPeriod - 1) / kPeriod + static_cast<int>(2 * pass.sweeps);
    const auto phase = [&](int t0, int t1, long p, auto&& for_each) {
      if (p == kPeriod * pass.sweeps) {  // the residual, rows [3 (t0 - lag), 3 (t1 - lag))
        const int lag = static_cast<int>(2 * pass.sweeps);
        const int begin = std::max(kPeriod * (t0 - lag), 0),
                  end = std::min(kPeriod * (t1 - lag), rows);
        for_each(std::max(end - begin, 0), [&](int k) { residual_row(begin + k); });
        return;
      }
      const int sweep = static_cast<int>(p / kPeriod), position = static_cast<int>(p % kPeriod);
      const int row_class = pass.backward ? kPeriod - 1 - position : position;
      const int lag = pass.backward ? sweep : 2 * sweep + position;
      // t in [t0, t1) with 0 <= 3 (t - lag) + row_class < rows
      const int first = std::max(t0, lag),
                last = std::min(t1, lag + (rows - row_class + kPeriod - 1) / kPeriod);
      for_each(std::max(last - first, 0), [&](int k) {
        const int r = kPeriod * (first + k - lag) + row_class;
        for (int step = 0; step < kPeriod; ++step)
          update(r, pass.backward ? kPeriod - 1 - step : step);
      });
    };
    // The chunks' phases in order, each phase's rows through for_each(count, body).
    const long phases = pass.phases();
    const auto run_chunks = [&](int chunk, auto&& for_each) {
      for (int t0 = 0; t0 < steps; t0 += chunk)
        for (long p = 0; p < phases; ++p) phase(t0, std::min(t0 + chunk, steps), p, for_each);
    };
    if (level.splits(threads)) {
      // A multiple of the thread count, so that a whole phase's rows split evenly.
      const int chunk = std::max(threads, steps_per_chunk_ - steps_per_chunk_ % threads);
#pragma omp parallel num_threads(threads)
      run_chunks(chunk, [](int count, auto&& body) {
        if (count == 0) return;  // every thread skips it alike: no barrier
#pragma omp for schedule(static)
        for (int k = 0; k < count; ++k) body(k);
      });
    } else {
      run_chunks(steps_per_chunk_, [](int count, auto&& body) {
        for (int k = 0; k < count; ++k) body(k);
      });
    }
  }

  // x_i for the nodes of row r in columns col_class, col_class + 3, ...
  void update_colour(const GridLevel& level, int r, int col_class, const double* b,
                     double* x) const {
    for (int c = col_class; c < level.cols(); c += kPeriod) {
      const std::size_t i = level.node(r, c);
      if (level.fixed(i)) continue;
      double sum[3] = {b[3 * i], b[3 * i + 1], b[3 * i + 2]};
      level.subtract_row_product(r, c, x, sum, true);
      const double* d = &inverse_diagonal_[9 * i];
      for (int j = 0; j < 3; ++j)
        x[3 * i + j] = d[3 * j] * sum[0] + d[3 * j + 1] * sum[1] + d[3 * j + 2] * sum[2];
    }
  }

  // out = a^-1 for a symmetric 3x3 block (row-major); false unless a is positive definite.
  static bool invert_positive_definite(const double* a, double* out) {
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

  // Nodes in the rows of a chunk's steps. Its phases also touch the rows the lags span (at
  // 300 x 300 with 2 sweeps, about 21 000 nodes): read once per pass from the cache where each
  // sweep of the whole level streamed it from memory.
  static constexpr int kChunkNodes = 16384;

  std::vector<double> inverse_diagonal_;  // 9 per node
  // A single level's lanes, in one precision; their vectors are the passes' scratch (a smoother
  // runs one pass at a time).
  mutable std::optional<LaneLevel<float>> float_lanes_;
  mutable std::optional<LaneLevel<double>> double_lanes_;
  int steps_per_chunk_ = 1;
};

}  // namespace clothlab::builtin
