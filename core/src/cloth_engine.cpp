#include "cloth_engine.hpp"

#include <cmath>
#include <cstring>
#include <new>
#include <utility>

#include "grid_colors.hpp"
#include "simd_namespace.hpp"
#include "vector_kernels.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {
namespace {

// The force pipeline streams grid rows, with a fixed cost per row (staging, accumulator rings,
// kernels whose SIMD lanes fill only from 16 columns on). A grid narrower than that and taller
// than wide is handed over turned a quarter, as `cols` long rows instead of `rows` short ones
// (lab/performance.md, "Narrow tall grids"); the pipeline then reads each of
// its rows as a column of the state, particles `cols` apart (for one column: contiguous).
constexpr uint32_t kNarrowGrid = 16;

bool turned_for_pipeline(const Scene& scene) {
  return scene.cols < kNarrowGrid && scene.rows > scene.cols;
}

Scene pipeline_scene(const Scene& scene) {
  if (!turned_for_pipeline(scene)) return scene;
  Scene turned = scene;
  std::swap(turned.rows, turned.cols);
  std::swap(turned.width, turned.height);
  std::swap(turned.col_axis, turned.row_axis);
  return turned;
}

template <class Real>
StateCombination<Real> in_place(const void* base) {
  StateCombination<Real> state;
  state.base = static_cast<const Real*>(base);
  return state;
}

template <class Real>
bool convert(const clothlab_combination& from, StateCombination<Real>& to) {
  if (from.count > StateCombination<Real>::kMaxTerms || from.base == nullptr) return false;
  to.base = static_cast<const Real*>(from.base);
  to.count = from.count;
  for (uint32_t term = 0; term < from.count; ++term) {
    to.coefficients[term] = static_cast<Real>(from.coefficients[term]);
    to.vectors[term] = static_cast<const Real*>(from.vectors[term]);
  }
  return true;
}

}  // namespace

template <class Real>
ClothEngine<Real>::ClothEngine(const Scene& scene, std::shared_ptr<const ClothModel> model,
                               PipelineOptions options)
    : Base(scene, std::move(model), options) {
  governor_ = TeamGovernor(threads_, options.adaptive_threads && parallel_capable_);
  if (on_grid_path()) {
    forces_ = std::make_unique<ForcePipeline<Real>>(
        pipeline_scene(scene), stride_, inverse_mass_.data(), options.velocity_forces, threads_,
        parallel_, turned_for_pipeline(scene) ? scene.cols : 1);
    grid_colors_ = grid_stencil_colors(model_->grid->rows, model_->grid->cols);
  } else {
    general_ =
        std::make_unique<SpringListForces<Real>>(*model_, scene, stride_, inverse_mass_.data(),
                                                 options.velocity_forces, threads_, parallel_);
  }
  chunk_sums_.assign(active_chunks_.size(), 0.0);
  chunk_sums_z_.assign(active_chunks_.size(), 0.0);
  mass_.assign(n_, 0.0);
  real_mass_ = AlignedBuffer<Real>(stride_);
  for (std::size_t i = 0; i < n_; ++i) {
    if (inverse_mass_[i] > 0) mass_[i] = 1.0 / double{inverse_mass_[i]};
    real_mass_[i] = static_cast<Real>(mass_[i]);
  }

  system_.struct_size = sizeof(clothlab_system);
  system_.precision = sizeof(Real) == sizeof(float) ? CLOTHLAB_FLOAT32 : CLOTHLAB_FLOAT64;
  system_.particle_count = static_cast<uint32_t>(n_);
  system_.stride = static_cast<uint32_t>(stride_);
  system_.x = x_.data();
  system_.v = v_.data();
  system_.inverse_mass = inverse_mass_.data();
  system_.active = active_.data();
  system_.active_count = static_cast<uint32_t>(active_.size());
  system_.context = this;
  system_.eval_acceleration = &eval_callback;
  system_.axpy = &axpy_callback;
  system_.lincomb = &lincomb_callback;
  system_.copy = &copy_callback;
  system_.alloc_vector = &alloc_callback;
  system_.eval_acceleration_at = &eval_at_callback;
  system_.reserve_rkn = &reserve_rkn_callback;
  system_.step_rkn = &step_rkn_callback;
  system_.get_extension = &get_extension_callback;
}

template <class Real>
void ClothEngine<Real>::begin_step() {
  if (!parallel_capable_) return;
  parallel_ = governor_.team_step();
  counters_.steps_on_one_thread += parallel_ ? 0 : 1;
  if (forces_) forces_->set_parallel(parallel_);
  if (general_) general_->set_parallel(parallel_);
  if (jacobian_) jacobian_->set_parallel(parallel_);
  step_start_ = std::chrono::steady_clock::now();
}

template <class Real>
void ClothEngine<Real>::end_step() {
  if (!parallel_capable_) return;
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - step_start_).count();
  governor_.finished(wall_s);
}

template <class Real>
clothlab_status ClothEngine<Real>::evaluate(const StateCombination<Real>& x,
                                            const StateCombination<Real>* v, Real* a) {
  // The air needs velocities: a call without them gets the system's current ones
  // (clothlab/ext/air.h); no spring is damped by them, as the pipeline was built undamped.
  const StateCombination<Real> current = in_place<Real>(v_.data());
  if (v == nullptr && scene_.has_air()) v = &current;
  const bool finite =
      forces_ ? forces_->evaluate(x, v, a, counters_) : general_->evaluate(x, v, a, counters_);
  return finite ? CLOTHLAB_OK : CLOTHLAB_ERROR_NUMERICAL;
}

template <class Real>
void ClothEngine<Real>::axpy(Real* y, Real alpha, const Real* x) {
  const auto chunks = static_cast<std::ptrdiff_t>(active_chunks_.size());
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    for (int k = 0; k < 3; ++k) {
      axpy_span(y + k * stride_, alpha, x + k * stride_, active_chunks_[chunk].begin,
                active_chunks_[chunk].end);
    }
  }
  counters_.particles_integrated += active_particles_;
}

template <class Real>
void ClothEngine<Real>::lincomb(Real* out, const Real* base, uint32_t count,
                                const double* coefficients, const void* const* vectors) {
  const auto chunks = static_cast<std::ptrdiff_t>(active_chunks_.size());
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    for (int k = 0; k < 3; ++k) {
      const std::size_t shift = k * stride_;
      lincomb_span(out, base, count, coefficients, vectors, shift + active_chunks_[chunk].begin,
                   shift + active_chunks_[chunk].end);
    }
  }
  counters_.particles_integrated += active_particles_;
}

template <class Real>
void* ClothEngine<Real>::alloc_vector() noexcept {
  try {
    vectors_.emplace_back(3 * stride_);
    return vectors_.back().data();
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}

template <class Real>
clothlab_status ClothEngine<Real>::eval_callback(void* context, double, const void* x,
                                                 const void* v, void* a) {
  const StateCombination<Real> x_state = in_place<Real>(x);
  const StateCombination<Real> v_state = in_place<Real>(v);
  return static_cast<ClothEngine*>(context)->evaluate(x_state, v == nullptr ? nullptr : &v_state,
                                                      static_cast<Real*>(a));
}

template <class Real>
clothlab_status ClothEngine<Real>::eval_at_callback(void* context, double,
                                                    const clothlab_combination* x,
                                                    const clothlab_combination* v, void* a) {
  StateCombination<Real> x_state, v_state;
  if (x == nullptr || !convert(*x, x_state) || (v != nullptr && !convert(*v, v_state))) {
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  }
  return static_cast<ClothEngine*>(context)->evaluate(x_state, v == nullptr ? nullptr : &v_state,
                                                      static_cast<Real*>(a));
}

template <class Real>
clothlab_status ClothEngine<Real>::reserve_rkn_callback(void* context, uint32_t stages) {
  if (stages == 0 || stages > CLOTHLAB_RKN_MAX_STAGES) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  try {
    auto* self = static_cast<ClothEngine*>(context);
    if (self->forces_) self->forces_->reserve_stages(stages);
    if (self->general_) self->general_->reserve_stages(stages);
    return CLOTHLAB_OK;
  } catch (const std::bad_alloc&) {
    return CLOTHLAB_ERROR_OUT_OF_MEMORY;
  }
}

template <class Real>
clothlab_status ClothEngine<Real>::step_rkn_callback(void* context, double, double h,
                                                     const clothlab_rkn_scheme* scheme) {
  auto* self = static_cast<ClothEngine*>(context);
  if (scheme == nullptr || scheme->stages == 0 ||
      scheme->stages >
          (self->forces_ ? self->forces_->reserved_stages() : self->general_->reserved_stages()) ||
      !std::isfinite(h)) {
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  }
  const uint32_t stages = scheme->stages;
  RknStep<Real> step;
  step.stages = stages;
  step.h = static_cast<Real>(h);
  for (uint32_t i = 0; i < stages; ++i) {
    step.x_velocity[i] = static_cast<Real>(h * scheme->alpha[i]);
    for (uint32_t j = 0; j < i; ++j) {
      step.x_stage[i][j] = static_cast<Real>(h * h * scheme->x_coupling[i * stages + j]);
      step.v_stage[i][j] = static_cast<Real>(h * scheme->v_coupling[i * stages + j]);
    }
    step.x_weights[i] = static_cast<Real>(h * h * scheme->x_weights[i]);
    step.v_weights[i] = static_cast<Real>(h * scheme->v_weights[i]);
  }
  const bool finite =
      self->forces_
          ? self->forces_->step_rkn(self->x_.data(), self->v_.data(), step, self->counters_)
          : self->general_->step_rkn(self->x_.data(), self->v_.data(), step, self->counters_);
  self->counters_.particles_integrated += self->active_particles_;
  return finite ? CLOTHLAB_OK : CLOTHLAB_ERROR_NUMERICAL;
}

template <class Real>
void ClothEngine<Real>::axpy_callback(void* context, void* y, double alpha, const void* x) {
  static_cast<ClothEngine*>(context)->axpy(static_cast<Real*>(y), static_cast<Real>(alpha),
                                           static_cast<const Real*>(x));
}

template <class Real>
void ClothEngine<Real>::lincomb_callback(void* context, void* out, const void* base, uint32_t count,
                                         const double* coefficients, const void* const* vectors) {
  static_cast<ClothEngine*>(context)->lincomb(
      static_cast<Real*>(out), static_cast<const Real*>(base), count, coefficients, vectors);
}

template <class Real>
void ClothEngine<Real>::copy_callback(void* context, void* dst, const void* src) {
  const auto* self = static_cast<const ClothEngine*>(context);
  if (dst == src) return;
  const std::size_t elements = 3 * self->stride_;
  const std::size_t pieces = self->parallel_ ? static_cast<std::size_t>(self->threads_) : 1;
#pragma omp parallel for num_threads(self->threads_) if (self->parallel_)
  for (std::size_t piece = 0; piece < pieces; ++piece) {
    const std::size_t begin = elements * piece / pieces;
    const std::size_t end = elements * (piece + 1) / pieces;
    std::memcpy(static_cast<Real*>(dst) + begin, static_cast<const Real*>(src) + begin,
                (end - begin) * sizeof(Real));
  }
}

template <class Real>
void* ClothEngine<Real>::alloc_callback(void* context) {
  return static_cast<ClothEngine*>(context)->alloc_vector();
}

template class ClothEngine<float>;
template class ClothEngine<double>;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE

namespace clothlab::detail {

// make_engine_<target> (engine_targets.hpp): this copy's engine.
std::unique_ptr<Engine> CLOTHLAB_SIMD_ENTRY(make_engine)(const Scene& scene,
                                                         std::shared_ptr<const ClothModel> model,
                                                         Precision precision,
                                                         PipelineOptions options) {
  if (precision == Precision::Float32)
    return std::make_unique<ClothEngine<float>>(scene, std::move(model), options);
  return std::make_unique<ClothEngine<double>>(scene, std::move(model), options);
}

}  // namespace clothlab::detail
