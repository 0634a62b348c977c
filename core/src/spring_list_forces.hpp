// The general force evaluation over a ClothModel's spring and triangle lists: the path for any
// mesh, and for a grid when PipelineOptions::force_general_path asks (so a test holds it equal
// to the grid's row pipeline, force_pipeline.hpp).
//
// Threaded by gather, so the result is the same bits on any thread count and needs no atomics:
// one pass computes each spring's force once (and each triangle's wind and air share), each into
// its own slot; a second pass sums, for each particle, the slots of its springs and triangles in
// a fixed order and turns the sum into an acceleration. The springs' passes run on the lanes of
// SpringLanes (spring_lanes.hpp). Scratch is sized at construction (the Runge-Kutta-Nystrom
// stages' in reserve_stages): a step allocates nothing.
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
  void spring_pass(const Real* x, const Real* v);
  void triangle_pass(const Real* x, const Real* v);
  // Sums the slots into accelerations; returns the sum of 0 * a (NaN when some a is not finite).
  Real gather(Real* a, bool springs, bool triangles);

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

  Real gravity_[3] = {0, 0, 0};
  Real wind_direction_[3] = {0, 0, 0};
  Real wind_strength_sixth_ = 0;
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
