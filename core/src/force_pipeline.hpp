// The force evaluation built once for a scene: only the spring stencils that exert force,
// damping terms only when the integrator uses velocity forces, wind only when it blows, air
// (drag and lift, air_kernel.hpp) only when the scene has some.
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
// never stored. Where a row is a plain copy (no combination, col_pitch 1), row r's far sweep
// stages row r + 3 into row r's slot as it goes (interior_row_kernel.hpp). In every scratch row the
// three components lie one row span apart, which keeps the kernels to a few base pointers. (Reading
// the state in place instead was slower: the kernels then stream 18 rows from outside L1;
// lab/performance.md.)
//
// A pipeline row is a row of the state (col_pitch 1) or, for a grid the engine hands over
// turned a quarter (narrow and tall: few long rows instead of many short ones), a column of
// it: its particles lie col_pitch = the grid's cols apart. Only the copies between the state
// and the scratch rows (staging, halo, finished accelerations, the update) see the pitch.
//
// Where its parts are: scratch_layout.hpp (which scratch row holds what); force_pipeline.cpp
// (construction, the scratch, the threads' row blocks); a row's stages in the order they run:
// row_staging.cpp (state rows into scratch rows and back), spring_stage.cpp, wind_stage.cpp
// (with air_stage.cpp), finish_stage.cpp (accumulators into accelerations); the passes that run
// the stages over a thread's rows: force_pass.cpp (evaluate) and rkn_sweep.cpp (step_rkn); and
// external_pass.cpp (evaluate_external: gravity, wind and air alone, with its own ring of cell
// rows).
#pragma once

#include <clothlab/core/cloth.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "aligned_buffer.hpp"
#include "grid.hpp"
#include "rkn_step.hpp"
#include "scratch_layout.hpp"
#include "simd_namespace.hpp"
#include "state_combination.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
class ForcePipeline {
 public:
  // `scene` as the pipeline sweeps it (turned or not); particle c of pipeline row r is at
  // r * cols + c of the state (col_pitch 1) or at r + c * col_pitch (a turned grid).
  ForcePipeline(const Scene& scene, std::size_t stride, const Real* inverse_mass,
                bool velocity_forces, int threads, bool parallel, std::size_t col_pitch = 1);

  // Whether the passes run on the thread team (false: on the calling thread alone); the engine
  // sets it per step (TeamGovernor). Results are the same bits either way.
  void set_parallel(bool parallel) { parallel_ = parallel; }

  // a = M^-1 F(x, v) on every particle (0 where the inverse mass is 0). v == nullptr
  // skips damping. Returns false when some acceleration is not finite. No allocation.
  bool evaluate(const StateCombination<Real>& x, const StateCombination<Real>* v, Real* a,
                StageCounters& counters);

  // a = gravity + M^-1 (wind + air) at x (no springs), through the same cell kernels as
  // evaluate, the air at the velocities v (nullptr: at rest); 0 where the inverse mass is 0.
  // Returns false when some value is not finite. One pass per thread over its block: a row's
  // cells, then its accelerations (below).
  bool evaluate_external(const Real* x, const Real* v, Real* a);
  // The same on pipeline rows [begin, end) alone, on the calling thread with `slot`'s scratch
  // (slot < thread_slots(); calls with different slots may run at once): the bits
  // evaluate_external writes there, as each row's cells are computed as there.
  bool evaluate_external_rows(int slot, std::size_t begin, std::size_t end, const Real* x,
                              const Real* v, Real* a);
  // Whether the external forces depend on the state: wind on x, air on x and v.
  bool has_cell_forces() const { return cell_forces_; }
  bool has_air() const { return air_; }
  // Whether pipeline rows are the grid's rows (col_pitch 1), not its columns.
  bool rows_are_grid_rows() const { return col_pitch_ == 1; }
  int thread_slots() const { return threads_; }

  // Scratch for step_rkn with up to `stages` stages. Allocates: not during a step.
  void reserve_stages(uint32_t stages);
  uint32_t reserved_stages() const { return reserved_stages_; }
  // One step of an explicit Runge-Kutta-Nystrom scheme (stages <= reserved_stages()) as a
  // single sweep over the rows, the stages following each other a few rows apart: x and
  // v are read and written once, stage states and accelerations live only in per-thread
  // row windows. Returns false when some stage acceleration is not finite (the state is
  // then partly advanced). No allocation.
  bool step_rkn(Real* x, Real* v, const RknStep<Real>& step, StageCounters& counters);

 private:
  struct SpringStage {
    StencilExtent extent;
    uint32_t row_step = 0;
    int32_t col_step = 0;
    Real rest = 0, ks = 0, kd = 0;
    bool damped = false;
    uint64_t count = 0;
  };
  // A thread's rows: from the balanced split when the team is the one it was made for,
  // else an even share.
  struct Block {
    std::size_t begin, end;
    bool balanced;
  };
  Block block_of(std::size_t thread, std::size_t team) const {
    if (team + 1 == split_.size()) return {split_[thread], split_[thread + 1], true};
    return {rows_ * thread / team, rows_ * (thread + 1) / team, false};
  }
  struct Pass {
    bool damped;          // damping terms wanted
    bool timed;           // time the separate wind stage (thread 0)
    double wind_seconds;  // that time
  };
  using StatePair = const StateCombination<Real>* const (&)[2];  // x, v (nullptr: none)

  // Scratch addresses (rows as scratch_layout.hpp lays them out, each at its column 0). A ring:
  // the scratch of one force pass of one thread; accumulators of a row for spring ends at the
  // same column as the spring's start, or shifted: separate so the interior kernel's stores of
  // one block never overlap. kFurtherColumn takes the ends one column left from the row above
  // and two columns right from the row itself: written in different sweeps, so they may share.
  enum Shift { kSameColumn, kNextColumn, kFurtherColumn };
  Real* ring(int thread, std::size_t stage) {
    return scratch_.data() + static_cast<std::size_t>(thread) * thread_stride_ +
           stage * scratch::kRowsPerRing * row_span_;
  }
  Real* thread_row(int thread, std::size_t index) {  // rows after the rings
    return scratch_.data() + static_cast<std::size_t>(thread) * thread_stride_ + index * row_span_ +
           scratch::kMargin;
  }
  Real* accumulator(Real* ring, std::size_t row, int k, int shift = kSameColumn) {
    const std::size_t index =
        (row % 3 * scratch::kAccumulatorShifts + static_cast<std::size_t>(shift)) * 3 +
        static_cast<std::size_t>(k);
    return ring + index * row_span_ + scratch::kMargin;
  }
  Real* force_row(Real* ring, int k) {
    return ring + (scratch::kForceRowFrom + static_cast<std::size_t>(k)) * row_span_ +
           scratch::kMargin;
  }
  Real* wind_row(Real* ring, int triangle, int k) {
    return ring +
           (scratch::kWindRowsFrom + static_cast<std::size_t>(triangle * 3 + k)) * row_span_ +
           scratch::kMargin;
  }
  Real* staged_row(Real* ring, std::size_t row, int quantity, int k) {
    const std::size_t index =
        scratch::kStagedRowsFrom + row % 3 * 6 + static_cast<std::size_t>(quantity * 3 + k);
    return ring + index * row_span_ + scratch::kMargin;
  }
  // The fused step's acceleration window rows and halo rows (rkn_sweep.cpp).
  Real* window_row(int thread, std::size_t stage, std::size_t row) {
    const std::size_t window = scratch::window_rows(reserved_stages_);
    return thread_row(
        thread, scratch::windows_from(reserved_stages_) + (stage * window + row % window) * 3);
  }
  Real* halo_row(int thread, std::size_t slot, int quantity) {
    return thread_row(thread, scratch::halo_from(reserved_stages_) + slot * 6 +
                                  static_cast<std::size_t>(quantity) * 3);
  }
  // Halo slot of grid row `row` outside the block [begin, end) of a `stages`-stage step:
  // the 2 * stages rows above it first, then those below.
  std::size_t halo_slot(std::size_t row, std::size_t begin, std::size_t end,
                        std::size_t stages) const {
    const std::size_t reach = 2 * stages;
    return row < begin ? row - (begin > reach ? begin - reach : 0)
                       : scratch::halo_rows(reserved_stages_) / 2 + (row - end);
  }
  // A row of the thread's external pass scratch (external_pass.cpp).
  Real* external_row(int thread, std::size_t index) {
    return external_scratch_.data() + static_cast<std::size_t>(thread) * external_stride_ +
           index * row_span_ + scratch::kMargin;
  }
  // The first of the rows for a turned grid's contiguous copies.
  std::size_t turned_from() const { return scratch::turned_from(reserved_stages_); }

  // Row staging (row_staging.cpp): forms grid row `row` of x and v into the staged rows.
  void stage_row(int thread, Real* ring, StatePair state, std::size_t row);
  // Where pipeline row `row` starts in a state vector.
  std::size_t row_start(std::size_t row) const { return col_pitch_ == 1 ? row * cols_ : row; }
  // The 3 components of pipeline row `row` of a state vector to a scratch row (components
  // row_span_ apart), and back.
  void gather_row(const Real* state, std::size_t row, Real* to) const;
  // One component: `cols_` particles col_pitch_ apart to a contiguous row.
  void gather_component(const Real* from, Real* to) const;
  void scatter_row(const Real* from, Real* state, std::size_t row) const;

  // The spring stage (spring_stage.cpp): the springs starting in `row`. With `next` (x and v of
  // the state at row + 3, v null where not staged; an interior row only), the interior kernel
  // also stages row + 3, a plain copy, into row's slot.
  void add_springs(Real* ring, std::size_t row, const Pass& pass,
                   const Real* const* next = nullptr);
  // Rows whose springs, and cells, the interior kernel computes in one sweep.
  bool interior_row(std::size_t row) const { return interior_kernel_ && row + 2 < rows_; }
  void add_interior_springs(Real* ring, std::size_t row, const Pass& pass, const Real* const* next);
  // The wind stage (wind_stage.cpp): the wind and the air on the cells starting in `row`.
  void add_wind(Real* ring, std::size_t row, Pass& pass);
  // The air's shares (air_kernel.hpp) of cell row `row` from its corners' rows, added to
  // `first` and `second` (components span apart).
  void add_air(const Real* x, const Real* below, const Real* v, const Real* v_below,
               std::size_t position_span, Real* first, Real* second, std::size_t span) const;
  // The finish stage (finish_stage.cpp): turns row's accumulators into accelerations at out
  // (components `span` apart); returns the sum of 0 * a (NaN exactly when some a is not finite).
  Real finish_row(Real* ring, std::size_t row, Real* out, std::size_t span);
  // Readies row's accumulators for row + 3, which reuses them: clears those that no interior
  // sweep will store into first (the aligned ones are stored by row + 1's, the shifted ones by
  // row + 2's; interior_row_kernel.hpp). A pass starts from cleared ones (clear_accumulators).
  void recycle_row(Real* ring, std::size_t row);
  void clear_accumulators(Real* ring);

  // The force pass (force_pass.cpp): a thread's block of rows through all stages.
  Real run_rows(int thread, std::size_t begin, std::size_t end, StatePair state, Real* a,
                Pass& pass);

  // The external pass (external_pass.cpp): the wind shares of cell row q (triangle 0: abc',
  // 1: bdc') in a ring of two, read in place from x where col_pitch is 1; a row's particles
  // then sum the shares of the cells above and beside them. Rows without cells read the zero
  // rows.
  Real* cell_shares(int thread, std::ptrdiff_t q, int triangle);
  void compute_cells(int thread, const Real* x, const Real* v, std::size_t q);
  Real finish_external_row(int thread, std::size_t row, Real* a);
  Real external_rows(int thread, std::size_t begin, std::size_t end, const Real* x, const Real* v,
                     Real* a, bool backward);

  // The fused step (rkn_sweep.cpp): a thread's block of rows through all stages of a step.
  Real rkn_rows(int thread, std::size_t begin, std::size_t end, Real* x, Real* v,
                const RknStep<Real>& step, Pass& pass);
  // Moves each boundary of the threads' row blocks a row toward the thread that finished
  // first in the last pass (results do not depend on the boundaries).
  void balance_split();

  std::size_t rows_ = 0;
  std::size_t cols_ = 0;
  std::size_t stride_ = 0;
  std::size_t col_pitch_ = 1;
  const Real* inverse_mass_ = nullptr;       // in pipeline row order
  AlignedBuffer<Real> turned_inverse_mass_;  // a turned grid's inverse masses, row by row
  int threads_ = 1;
  bool parallel_ = false;  // set_parallel
  Real gravity_[3] = {0, 0, 0};
  Real wind_direction_[3] = {0, 0, 0};
  Real wind_strength_ = 0;
  bool wind_ = false;
  Real air_wind_[3] = {0, 0, 0};
  Real air_drag_twelfth_ = 0, air_lift_twelfth_ = 0;
  bool air_ = false;
  bool cell_forces_ = false;  // wind_ or air_

  std::vector<SpringStage> stages_;
  bool interior_kernel_ = false;   // all six stencils, float, SIMD lanes
  std::size_t row_span_ = 0;       // margin + columns + margin
  std::size_t thread_stride_ = 0;  // elements from one thread's scratch to the next
  uint32_t reserved_stages_ = 0;
  std::vector<std::size_t> split_;  // first row of each thread's block, then rows
  std::vector<double> busy_;        // each thread's time in the last pass
  AlignedBuffer<Real> scratch_;
  std::size_t external_stride_ = 0;  // elements from one thread's external scratch to the next
  AlignedBuffer<Real> external_scratch_;
  uint64_t springs_per_eval_ = 0;
  uint64_t damped_per_eval_ = 0;
  uint64_t normals_per_eval_ = 0;
};

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
