// ForcePipeline's construction for a scene (the spring stencils that exert force, wind or
// none), its per-thread scratch and the threads' blocks of rows.
#include "force_pipeline.hpp"

#include <type_traits>

#include "float_lanes.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {
namespace {

using namespace scratch;

#if defined(CLOTHLAB_FLOAT_LANES)
constexpr bool kInteriorKernel = true;
#else
constexpr bool kInteriorKernel = false;
#endif

std::size_t round_up_16(std::size_t value) { return (value + 15) / 16 * 16; }

}  // namespace

template <class Real>
ForcePipeline<Real>::ForcePipeline(const Scene& scene, std::size_t stride, const Real* inverse_mass,
                                   bool velocity_forces, int threads, bool parallel,
                                   std::size_t col_pitch)
    : rows_(scene.rows),
      cols_(scene.cols),
      stride_(stride),
      col_pitch_(col_pitch),
      inverse_mass_(inverse_mass),
      threads_(threads),
      parallel_(parallel) {
  if (col_pitch_ != 1) {
    turned_inverse_mass_ = AlignedBuffer<Real>(rows_ * cols_);
    for (std::size_t r = 0; r < rows_; ++r)
      for (std::size_t c = 0; c < cols_; ++c)
        turned_inverse_mass_[r * cols_ + c] = inverse_mass[r + c * col_pitch_];
    inverse_mass_ = turned_inverse_mass_.data();
  }
  for (int k = 0; k < 3; ++k) {
    gravity_[k] = static_cast<Real>(scene.gravity[k]);
    wind_direction_[k] = static_cast<Real>(scene.wind_direction[k]);
  }
  wind_strength_ = static_cast<Real>(scene.wind_strength);
  wind_ = scene.has_wind() && rows_ > 1 && cols_ > 1;
  air_ = scene.has_air() && rows_ > 1 && cols_ > 1;
  cell_forces_ = wind_ || air_;
  for (int k = 0; k < 3; ++k) air_wind_[k] = static_cast<Real>(scene.air.wind_velocity[k]);
  air_drag_twelfth_ = static_cast<Real>(scene.air.density * scene.air.drag_coefficient / 12.0);
  air_lift_twelfth_ = static_cast<Real>(scene.air.density * scene.air.lift_coefficient / 12.0);

  for (const Stencil& stencil : kProvotStencils) {
    const SpringFamily& family = scene.*stencil.family;
    SpringStage stage;
    stage.extent = stencil_extent(stencil, scene.rows, scene.cols);
    stage.count = stage.extent.count();
    stage.damped = velocity_forces && family.kd > 0.0;
    if (stage.count == 0 || (family.ks == 0.0 && !stage.damped)) continue;
    stage.row_step = stencil.row_step;
    stage.col_step = stencil.col_step;
    stage.rest = static_cast<Real>(stencil_rest_length(scene, stencil));
    stage.ks = static_cast<Real>(family.ks);
    stage.kd = static_cast<Real>(family.kd);
    springs_per_eval_ += stage.count;
    damped_per_eval_ += stage.damped ? stage.count : 0;
    stages_.push_back(stage);
  }
  normals_per_eval_ = cell_forces_ ? 2 * uint64_t{rows_ - 1} * (cols_ - 1) : 0;

  // The interior kernel carries the wind, not the air: air scenes take the row stages.
  interior_kernel_ = kInteriorKernel && std::is_same_v<Real, float> && stages_.size() == 6 && !air_;
  row_span_ = kMargin + round_up_16(cols_ + kMargin + 2);
  reserve_stages(1);
  for (std::size_t t = 0; t <= static_cast<std::size_t>(threads_); ++t) {
    split_.push_back(rows_ * t / static_cast<std::size_t>(threads_));
  }
  busy_.assign(static_cast<std::size_t>(threads_), 0.0);
  const std::size_t gap = kGapBytes / sizeof(Real);
  external_stride_ = (kExternalRows * row_span_ + gap - 1) / gap * gap + gap;
  external_scratch_ = AlignedBuffer<Real>(static_cast<std::size_t>(threads_) * external_stride_);
}

template <class Real>
void ForcePipeline<Real>::reserve_stages(uint32_t stages) {
  if (stages <= reserved_stages_) return;
  reserved_stages_ = stages;
  // Per thread: a ring per stage, then the rows of the fused step and of a turned grid's
  // copies (scratch_layout.hpp).
  const std::size_t rows = thread_rows(reserved_stages_, StateCombination<Real>::kMaxTerms);
  // Each thread's scratch starts 64 KiB after the end of the previous one's: closer, the
  // second thread ran slower (likely prefetch or cache-set sharing between the cores' hot
  // rows; lab/performance.md, "What made it fast").
  const std::size_t gap = kGapBytes / sizeof(Real);
  thread_stride_ = (rows * row_span_ + gap - 1) / gap * gap + gap;
  scratch_ = AlignedBuffer<Real>(static_cast<std::size_t>(threads_) * thread_stride_);
}

// Moves each block boundary a row toward the thread that finished first, so a slower core
// (or the halo prelude that only later blocks run) does not leave the other one waiting at
// the barrier. Results do not depend on the boundaries: every block is exact.
template <class Real>
void ForcePipeline<Real>::balance_split() {
  constexpr double kTolerance = 1.02;
  for (std::size_t b = 1; b + 1 < split_.size(); ++b) {
    const double upper = busy_[b - 1], lower = busy_[b];
    if (upper > kTolerance * lower && split_[b] > split_[b - 1] + 1) {
      --split_[b];
    } else if (lower > kTolerance * upper && split_[b] + 1 < split_[b + 1]) {
      ++split_[b];
    }
  }
}

template class ForcePipeline<float>;
template class ForcePipeline<double>;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
