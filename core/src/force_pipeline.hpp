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
// The state is read either straight from x and v or, for a stage of a multi-stage method,
// as combinations formed row by row into a ring of three staged rows (r, r+1, r+2: all a
// spring or cell starting in row r reaches), so a stage state is never stored.
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

  // Per-thread scratch rows: 3 accumulators x 3 components, a force row per component,
  // the two wind share rows per component, then 3 staged rows of x and of v.
  Real* accumulator(int thread, std::size_t row, int k);
  Real* force_row(int thread, int k);
  Real* wind_row(int thread, int triangle, int k);
  Real* staged_row(int thread, std::size_t row, int quantity, int k);

  // Component k of a grid row of x (quantity 0) or v (1): in place, or staged.
  const Real* state_row(int thread, const Pass& pass, int quantity, std::size_t row, int k);
  void stage_row(int thread, const Pass& pass, std::size_t row);

  void add_springs(int thread, std::size_t row, const Pass& pass);
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
  std::size_t row_span_ = 0;  // margin + columns + margin
  AlignedBuffer<Real> scratch_;
  uint64_t springs_per_eval_ = 0;
  uint64_t damped_per_eval_ = 0;
  uint64_t normals_per_eval_ = 0;
};

}  // namespace clothlab::detail
