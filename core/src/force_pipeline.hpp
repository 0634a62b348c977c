// The force evaluation built once for a scene: only the spring stencils that exert force,
// damping terms only when the integrator uses velocity forces, wind only when it blows.
//
// One fused pass per thread over its block of grid rows, with per-row scratch that stays
// in cache. For row r it computes every spring starting in r once and the wind on the
// cells below r, and accumulates them onto a ring of three row accumulators (rows r, r+1,
// r+2) by shifted adds: within the row through a per-stencil force row, into later rows
// directly. Row r is then complete and becomes accelerations. No scatter, no atomics;
// each thread first runs the two rows above its block for their forces on it.
//
// The state is copied row by row into a ring of three staged rows (r, r+1, r+2: all a
// spring or cell starting in row r reaches) that stays in cache; for a stage of a
// multi-stage method each row is formed there as a combination, so a stage state is
// never stored. In every scratch row the three components lie one row span apart, which
// keeps the kernels to a few base pointers. (Reading the state in place instead measured
// ~10 % slower: the kernels then stream 18 rows from outside L1.)
#pragma once

#include <clothlab/core/cloth.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "aligned_buffer.hpp"
#include "grid.hpp"
#include "state_combination.hpp"

namespace clothlab::detail {

template <class Real>
class ForcePipeline {
 public:
  ForcePipeline(const Scene& scene, std::size_t stride, const Real* inverse_mass,
                bool velocity_forces, int threads, bool parallel);

  // a = M^-1 F(x, v) on every particle (0 where the inverse mass is 0). v == nullptr
  // skips damping. Returns false when some acceleration is not finite. No allocation.
  bool evaluate(const StateCombination<Real>& x, const StateCombination<Real>* v, Real* a,
                StageCounters& counters);

 private:
  struct SpringStage {
    StencilExtent extent;
    uint32_t row_step = 0;
    int32_t col_step = 0;
    Real rest = 0, ks = 0, kd = 0;
    bool damped = false;
    uint64_t count = 0;
  };
  struct Pass {
    const StateCombination<Real>* x;
    const StateCombination<Real>* v;  // nullptr: no damping
    Real* a;
    double wind_seconds;  // measured on thread 0 only
  };

  // Per-thread scratch rows: a ring of 3 rows of accumulators, a force row, the two wind
  // share rows, and a ring of 3 staged rows of x and of v; 3 components each.
  // Accumulators of a row for spring ends at the same column as the spring's start, or
  // shifted: separate so the interior kernel's stores of one block never overlap.
  // kFurtherColumn takes the ends one column left from the row above and two columns
  // right from the row itself: written in different sweeps, so they may share.
  enum Shift { kSameColumn, kNextColumn, kFurtherColumn };
  Real* accumulator(int thread, std::size_t row, int k, int shift = kSameColumn);
  Real* scratch_row(int thread, std::size_t index);
  Real* force_row(int thread, int k);
  Real* wind_row(int thread, int triangle, int k);
  Real* staged_row(int thread, std::size_t row, int quantity, int k);
  // Forms grid row `row` of x and v into the staged ring.
  void stage_row(int thread, const Pass& pass, std::size_t row);

  void add_springs(int thread, std::size_t row, const Pass& pass);
  // Rows whose springs, and cells, the interior kernel computes in one sweep.
  bool interior_row(std::size_t row) const { return interior_kernel_ && row + 2 < rows_; }
  void add_interior_springs(int thread, std::size_t row, const Pass& pass);
  void add_wind(int thread, std::size_t row, Pass& pass);
  // Turns row's accumulator into accelerations and clears it; returns the sum of 0 * a
  // (NaN exactly when some acceleration is not finite).
  Real finish_row(int thread, std::size_t row, Real* a);
  void clear_row(int thread, std::size_t row);
  Real run_rows(int thread, std::size_t begin, std::size_t end, Pass& pass);

  std::size_t rows_ = 0;
  std::size_t cols_ = 0;
  std::size_t stride_ = 0;
  const Real* inverse_mass_ = nullptr;
  int threads_ = 1;
  bool parallel_ = false;
  Real gravity_[3] = {0, 0, 0};
  Real wind_direction_[3] = {0, 0, 0};
  Real wind_strength_ = 0;
  bool wind_ = false;

  std::vector<SpringStage> stages_;
  bool interior_kernel_ = false;   // all six stencils, float, AVX-512
  std::size_t row_span_ = 0;       // margin + columns + margin
  std::size_t thread_stride_ = 0;  // elements from one thread's scratch to the next
  AlignedBuffer<Real> scratch_;
  uint64_t springs_per_eval_ = 0;
  uint64_t damped_per_eval_ = 0;
  uint64_t normals_per_eval_ = 0;
};

}  // namespace clothlab::detail
