// The general force evaluation over a ClothModel's spring and triangle lists: the path for any
// mesh, and for a grid when PipelineOptions::force_general_path asks (so a test holds it equal
// to the grid's row pipeline, force_pipeline.hpp).
//
// Threaded by gather, so the result is the same bits on any thread count and needs no atomics:
// one pass computes each spring's force once (and each triangle's wind and air share), each into
// its own slot; a second pass sums, for each particle, the slots of its springs and triangles in
// a fixed order and turns the sum into an acceleration. The springs and the triangles are laid
// out in bands for the lanes (SpringLanes and LaneBands, spring_lanes.hpp) and both passes run
// tile by tile (LaneBands::sweep). Scratch is sized at construction (the Runge-Kutta-Nystrom
// stages' in reserve_stages): a step allocates nothing.
#pragma once

#include <array>
#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <cstddef>
#include <cstdint>
#include <optional>
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
  // What a sweep does with a tile's particles once their accelerations are final: form the next
  // Runge-Kutta-Nystrom stage's state (each of x and v into its buffer where it has terms), or,
  // with `step`, advance x and v.
  struct TileEpilogue {
    StateCombination<Real> x, v;
    Real *formed_x = nullptr, *formed_v = nullptr;
    const RknStep<Real>* step = nullptr;
    Real *advanced_x = nullptr, *advanced_v = nullptr;
  };

  // Whole state vectors (3 x stride) formed as combinations, into `out`; the base itself when
  // there is no term.
  const Real* form(const StateCombination<Real>& state, Real* out);
  // The same for the particles [begin, begin + count).
  void form_range(const StateCombination<Real>& state, Real* out, std::size_t begin,
                  std::size_t count) const;
  // x += h v + sum_s x_weights[s] A_s, v += sum_s v_weights[s] A_s on the active particles of
  // [begin, begin + count), count <= kChunk.
  void advance_range(Real* x, Real* v, const RknStep<Real>& step, std::size_t begin,
                     std::size_t count) const;
  // Stage s's combination of x (velocity false) or v, without the terms of coefficient 0 (as the
  // grid's).
  StateCombination<Real> stage_state(const Real* x, const Real* v, const RknStep<Real>& step,
                                     uint32_t s, bool velocity) const;
  // The sweep of evaluate at formed states, then `after` on each tile; as evaluate.
  bool sweep_stage(const Real* x, const Real* v, Real* a, const TileEpilogue* after,
                   StageCounters& counters);
  // The triangles (each rotated, its winding kept, to start at its smallest corner) in the slots
  // of LaneBands: on a mesh numbered along rows, bands whose corners follow in order.
  void lay_out_triangles(const ClothModel& model);
  void triangle_pass(const Real* x, const Real* v);
  // The wind and air shares of the triangle slot blocks [begin, end), component k of slot
  // begin * kSpringBlock + i to out[k * out_stride + i].
  void triangle_shares(const Real* x, const Real* v, std::size_t begin, std::size_t end, Real* out,
                       std::size_t out_stride) const;
  // The springs' forces (and the triangles' shares) and the particles' sums of them, tile by
  // tile (LaneBands::sweep); returns the sum of 0 * a (NaN when some a is not finite), and adds
  // thread 0's time on the triangles to triangle_seconds.
  Real spring_sweep(const Real* x, const Real* v, Real* a, bool triangles, double& triangle_seconds,
                    const TileEpilogue* after);
  // The triangles' shares alone into accelerations; returns as spring_sweep.
  Real gather_external(Real* a, bool triangles);
  // Particle block b's sum into accelerations (the bands' slots from the rings where given, a
  // sweep's); returns its sum of 0 * a.
  Real gather_block(std::size_t block, Real* a, const Real* spring_ring, const Real* triangle_ring,
                    bool springs, bool triangles) const;

  std::size_t n_ = 0;
  std::size_t stride_ = 0;
  const Real* inverse_mass_ = nullptr;
  int threads_ = 1;
  bool parallel_ = false;
  bool velocity_forces_ = true;

  SpringLanes<Real> springs_;
  std::size_t spring_count_ = 0;
  std::size_t triangle_count_ = 0;
  std::optional<LaneBands> triangles_;  // with the wind or the air
  // What a triangle slot block reads, in one place (the ends' arrays, one cache line per corner
  // and block, are read only by the blocks gathered one triangle at a time): live, bit l set where
  // lane l lives; chosen, its masks in triangle_lanes_ where it lies in a chosen band and its
  // corners do not follow in order, else kNotChosen; corner, where its corners follow in order
  // (in_order), lane 0's three, and where chosen, lane 0's four corners of its band (in order:
  // lane l's lie at corner[c] + l).
  static constexpr uint32_t kNotChosen = 0xffffffffu;
  struct TriangleBlock {
    std::array<uint32_t, 4> corner{};
    uint32_t chosen = kNotChosen;
    uint16_t live = 0;
    bool in_order = false;
  };
  static_assert(kSpringBlock <= 16, "TriangleBlock::live holds a bit per lane");
  std::vector<TriangleBlock> triangle_blocks_;
  std::vector<ChosenLanes<3>> triangle_lanes_;

  Real gravity_[3] = {0, 0, 0};
  // The wind as triangle_wind_share reads it (wind_kernel.hpp), at the scalar kernel's scale and
  // at the lanes' (float_lanes.hpp), each built once.
  Real wind_pressure_[3] = {0, 0, 0};
  Real lane_wind_pressure_[3] = {0, 0, 0};
  bool wind_ = false;
  Real air_wind_[3] = {0, 0, 0};
  Real air_drag_twelfth_ = 0, air_lift_twelfth_ = 0;
  bool air_ = false;

  AlignedBuffer<Real> spring_force_;  // by slot (SpringLanes): the force on the first particle
  // By triangle slot, laid out as spring_force_: the force on each of the triangle's corners.
  AlignedBuffer<Real> triangle_share_;
  AlignedBuffer<Real> spring_rings_, triangle_rings_;  // per thread (SlotBuffers)
  AlignedBuffer<Real> formed_x_, formed_v_;
  uint32_t reserved_stages_ = 0;
  std::vector<AlignedBuffer<Real>> stage_a_;  // the stages' accelerations
};

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
