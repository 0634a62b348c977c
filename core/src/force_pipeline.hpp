// The force evaluation built once for a scene: only the spring stencils that exert force,
// damping terms only when the integrator uses velocity forces, wind only when it blows.
//
// One fused pass per thread over its block of grid rows: for row r it computes every
// spring starting in r (and the wind on the cells below r) into a three-row ring of
// per-stencil scratch, then gathers the forces on row r's particles by shifted reads of
// rows r, r-1 and r-2, and writes the acceleration. Scratch stays in cache; there is no
// scatter and no atomic. Each thread first recomputes the two rows above its block.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "aligned_buffer.hpp"
#include "grid.hpp"

namespace clothlab::detail {

template <class Real>
class ForcePipeline {
 public:
  ForcePipeline(const Scene& scene, std::size_t stride, const Real* inverse_mass,
                bool velocity_forces, int threads, bool parallel);

  // a = M^-1 F(x, v) on every particle (0 where the inverse mass is 0). v == nullptr
  // skips damping. Returns false when some acceleration is not finite. No allocation.
  bool evaluate(const Real* x, const Real* v, Real* a, StageCounters& counters);

 private:
  struct SpringStage {
    StencilExtent extent;
    uint32_t row_step = 0;
    int32_t col_step = 0;
    std::size_t offset = 0;
    Real rest = 0, ks = 0, kd = 0;
    bool damped = false;
    uint64_t count = 0;
  };
  struct Pass {
    const Real* x;
    const Real* v;
    Real* a;
    double wind_seconds;  // measured on thread 0 only
  };

  Real* row_buffer(int thread, std::size_t channel, std::ptrdiff_t row, int k);
  void compute_row(int thread, std::size_t row, Pass& pass);
  void zero_row(int thread, std::ptrdiff_t row);
  // Adds (or, when assign, writes) M stages starting at `first` into out.
  template <std::size_t M>
  void gather_stages(int thread, std::ptrdiff_t row, int k, std::size_t first, bool assign,
                     Real* out);
  // Writes row's accelerations; returns the sum of 0 * a (NaN when one is not finite).
  Real accumulate_row(int thread, std::size_t row, Real* a);
  void run_rows(int thread, std::size_t begin, std::size_t end, Pass& pass, Real& probe);

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
  std::size_t channels_ = 0;  // one per stage, plus two for wind
  std::size_t row_span_ = 0;  // margin + columns + margin, per ring row
  AlignedBuffer<Real> ring_;  // threads x channels x 3 rows x 3 components
  uint64_t springs_per_eval_ = 0;
  uint64_t damped_per_eval_ = 0;
  uint64_t normals_per_eval_ = 0;
};

}  // namespace clothlab::detail
