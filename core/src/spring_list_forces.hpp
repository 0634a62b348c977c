// The general force evaluation over a ClothModel's spring and triangle lists: the path for any
// mesh, and for a grid when PipelineOptions::force_general_path asks (so a test holds it equal
// to the grid's row pipeline, force_pipeline.hpp).
//
// Threaded by gather, so the result is the same bits on any thread count and needs no atomics:
// one pass computes each spring's force once (and each triangle's wind and air share), each into
// its own slot; a second pass sums, for each particle, the slots of its springs and triangles in
// a fixed order and turns the sum into an acceleration. The springs' passes run on the lanes of
// SpringLanes (spring_lanes.hpp), tile by tile (SpringLanes::sweep). Scratch is sized at
// construction (the Runge-Kutta-Nystrom stages' in reserve_stages): a step allocates nothing.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "aligned_buffer.hpp"
#include "rkn_step.hpp"
#include "simd_namespace.hpp"
#include "spring_lanes.hpp"
#include "state_combination.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
class SpringListForces {
 public:
  SpringListForces(const ClothModel& model, const Scene& scene, std::size_t stride,
                   const Real* inverse_mass, bool velocity_forces, int threads, bool parallel);

  void set_parallel(bool parallel) { parallel_ = parallel; }

  // As ForcePipeline's: a = M^-1 F(x, v) + gravity, 0 where pinned; v == nullptr: no damping.
  bool evaluate(const StateCombination<Real>& x, const StateCombination<Real>* v, Real* a,
                StageCounters& counters);
  bool evaluate_external(const Real* x, const Real* v, Real* a);
  bool has_cell_forces() const { return wind_ || air_; }

  void reserve_stages(uint32_t stages);
  uint32_t reserved_stages() const { return reserved_stages_; }
  bool step_rkn(Real* x, Real* v, const RknStep<Real>& step, StageCounters& counters);

 private:
  // Whole state vectors (3 x stride) formed as combinations, into `out`; the base itself when
  // there is no term.
  const Real* form(const StateCombination<Real>& state, Real* out);
  // Orders the triangles by shape (each rotated, winding kept, to start at its smallest
  // corner; by the offsets of the others from it) and then by first corner: on a mesh numbered
  // along rows, runs whose corners follow in order, which the wind reads with plain loads.
  void order_triangles();
  void triangle_pass(const Real* x, const Real* v);
  // The wind and air shares of triangles [begin, end).
  void triangle_shares(const Real* x, const Real* v, std::size_t begin, std::size_t end);
#if defined(CLOTHLAB_FLOAT_LANES)
  // The wind's shares of the block of triangles from t, whose corners follow in order.
  void wind_block_lanes(const Real* x, std::size_t t);
#endif
  // The springs' forces and the particles' sums of them (and of the triangles' shares), tile by
  // tile (SpringLanes::sweep); returns the sum of 0 * a (NaN when some a is not finite).
  Real spring_sweep(const Real* x, const Real* v, Real* a, bool triangles);
  // The triangles' shares alone into accelerations; returns as spring_sweep.
  Real gather_external(Real* a, bool triangles);
  // Particle block b's sum into accelerations; returns its sum of 0 * a.
  Real gather_block(std::size_t block, Real* a, bool springs, bool triangles) const;

  std::size_t n_ = 0;
  std::size_t stride_ = 0;
  const Real* inverse_mass_ = nullptr;
  int threads_ = 1;
  bool parallel_ = false;
  bool velocity_forces_ = true;

  SpringLanes<Real> springs_;
  std::size_t spring_count_ = 0;
  std::vector<uint32_t> triangles_;
  std::vector<uint32_t> triangle_offsets_, adjacent_triangles_;  // particle -> triangle lists
  std::size_t lane_triangles_ = 0;  // the leading triangles, in blocks that follow in order

  Real gravity_[3] = {0, 0, 0};
  Real wind_direction_[3] = {0, 0, 0};
  Real wind_strength_ = 0;
  Real wind_pressure_[3] = {0, 0, 0};  // of the scalar path (wind_kernel.hpp)
  bool wind_ = false;
  Real air_wind_[3] = {0, 0, 0};
  Real air_drag_twelfth_ = 0, air_lift_twelfth_ = 0;
  bool air_ = false;

  AlignedBuffer<Real> spring_force_;    // by slot (SpringLanes): the force on the first particle
  AlignedBuffer<Real> triangle_share_;  // 3 per triangle: the force on each of its corners
  AlignedBuffer<Real> formed_x_, formed_v_;
  uint32_t reserved_stages_ = 0;
  std::vector<AlignedBuffer<Real>> stage_a_;  // the stages' accelerations
};

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
