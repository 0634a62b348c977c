#include "cloth_engine.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "spring_kernel.hpp"
#include "vector_kernels.hpp"
#include "wind_kernel.hpp"

namespace clothlab::detail {
namespace {

constexpr std::size_t kChunk = 2048;         // particles per thread work item
constexpr std::size_t kBlock = 512;          // particles per accumulation block (in L1)
constexpr std::size_t kParallelFrom = 4096;  // smaller clouds run on the calling thread

std::size_t round_up_16(std::size_t value) { return (value + 15) / 16 * 16; }

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void append_chunks(std::vector<std::pair<std::size_t, std::size_t>>& out, std::size_t begin,
                   std::size_t end, std::size_t size) {
  for (std::size_t b = begin; b < end; b += size) out.emplace_back(b, std::min(end, b + size));
}

}  // namespace

template <class Real>
ClothEngine<Real>::ClothEngine(const Scene& scene, PipelineOptions options)
    : scene_(scene), n_(std::size_t{scene.rows} * scene.cols), stride_(round_up_16(n_)) {
  if (options.threads < 0) {
    throw std::invalid_argument("threads = " + std::to_string(options.threads) +
                                ": allowed 0 (all hardware threads) or >= 1");
  }
  threads_ = options.threads == 0 ? omp_get_max_threads() : options.threads;
  parallel_ = threads_ > 1 && n_ >= kParallelFrom;
  padding_ = round_up_16(2 * std::size_t{scene.cols} + 2);
  mass_ = static_cast<Real>(scene.total_mass / static_cast<double>(n_));
  for (int k = 0; k < 3; ++k) {
    gravity_[k] = static_cast<Real>(scene.gravity[k]);
    wind_direction_[k] = static_cast<Real>(scene.wind_direction[k]);
  }
  wind_strength_ = static_cast<Real>(scene.wind_strength);

  x_ = AlignedBuffer<Real>(3 * stride_);
  v_ = AlignedBuffer<Real>(3 * stride_);
  inverse_mass_ = AlignedBuffer<Real>(stride_);
  for (uint32_t r = 0; r < scene.rows; ++r) {
    for (uint32_t c = 0; c < scene.cols; ++c) {
      const Vec3 p = initial_position(scene, r, c);
      const std::size_t i = std::size_t{r} * scene.cols + c;
      for (int k = 0; k < 3; ++k) x_[k * stride_ + i] = static_cast<Real>(p[k]);
    }
  }
  const Real inverse_mass = static_cast<Real>(static_cast<double>(n_) / scene.total_mass);
  for (std::size_t i = 0; i < n_; ++i) inverse_mass_[i] = inverse_mass;
  for (uint32_t pinned : scene.pinned) inverse_mass_[pinned] = 0;

  // Active ranges: maximal runs between pinned indices (scene.pinned is sorted, unique).
  std::size_t begin = 0;
  for (std::size_t i = 0; i <= n_; ++i) {
    if (i == n_ || inverse_mass_[i] == 0) {
      if (i > begin) active_.push_back({static_cast<uint32_t>(begin), static_cast<uint32_t>(i)});
      begin = i + 1;
    }
  }
  std::vector<std::pair<std::size_t, std::size_t>> pieces;
  for (const clothlab_range& range : active_) {
    append_chunks(pieces, range.begin, range.end, kChunk);
    active_particles_ += range.end - range.begin;
  }
  for (auto [b, e] : pieces) active_chunks_.push_back({b, e});
  pieces.clear();
  append_chunks(pieces, 0, n_, kBlock);
  for (auto [b, e] : pieces) all_chunks_.push_back({b, e});

  for (const Stencil& stencil : kProvotStencils) {
    const SpringFamily& family = scene.*stencil.family;
    const bool damped = options.velocity_forces && family.kd > 0.0;
    SpringStage stage;
    stage.extent = stencil_extent(stencil, scene.rows, scene.cols);
    stage.count = stage.extent.count();
    if (stage.count == 0 || (family.ks == 0.0 && !damped)) continue;
    stage.offset = static_cast<std::size_t>(stencil_offset(stencil, scene.cols));
    stage.rest = static_cast<Real>(stencil_rest_length(scene, stencil));
    stage.ks = static_cast<Real>(family.ks);
    stage.kd = static_cast<Real>(family.kd);
    stage.damped = damped;
    stage.force = AlignedBuffer<Real>(3 * (padding_ + stride_));
    springs_per_eval_ += stage.count;
    damped_per_eval_ += damped ? stage.count : 0;
    stages_.push_back(std::move(stage));
  }
  if (scene.has_wind() && scene.rows > 1 && scene.cols > 1) {
    wind_first_ = AlignedBuffer<Real>(3 * (padding_ + stride_));
    wind_second_ = AlignedBuffer<Real>(3 * (padding_ + stride_));
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
}

template <class Real>
Real* ClothEngine<Real>::component(AlignedBuffer<Real>& scratch, int k) {
  return scratch.data() + k * (padding_ + stride_) + padding_;
}

template <class Real>
clothlab_status ClothEngine<Real>::evaluate(const Real* x, const Real* v, Real* a) {
  const auto start = std::chrono::steady_clock::now();
  compute_springs(x, v);
  counters_.internal_forces_s += seconds_since(start);

  const auto wind_start = std::chrono::steady_clock::now();
  if (wind_first_.size() != 0) {
    compute_wind(x);
    counters_.normals_computed += 2 * uint64_t{scene_.rows - 1} * (scene_.cols - 1);
  }
  counters_.external_forces_s += seconds_since(wind_start);

  // Gathering forces, adding gravity and scaling by 1/m is counted as internal work:
  // its cost is dominated by the spring stencils it sums.
  const auto combine_start = std::chrono::steady_clock::now();
  const bool finite = combine(a);
  counters_.internal_forces_s += seconds_since(combine_start);

  ++counters_.force_evals;
  counters_.springs_evaluated += springs_per_eval_;
  if (v != nullptr) counters_.springs_damped += damped_per_eval_;
  return finite ? CLOTHLAB_OK : CLOTHLAB_ERROR_NUMERICAL;
}

template <class Real>
void ClothEngine<Real>::compute_springs(const Real* x, const Real* v) {
#pragma omp parallel num_threads(threads_) if (parallel_)
  for (SpringStage& stage : stages_) {
    SpringStencilJob<Real> job{};
    for (int k = 0; k < 3; ++k) {
      job.x[k] = x + k * stride_;
      job.v[k] = v != nullptr ? v + k * stride_ : nullptr;
      job.f[k] = component(stage.force, k);
    }
    job.cols = scene_.cols;
    job.col_begin = stage.extent.col_begin;
    job.col_end = stage.extent.col_end;
    job.offset = stage.offset;
    job.rest = stage.rest;
    job.ks = stage.ks;
    job.kd = stage.kd;
    const bool damped = stage.damped && v != nullptr;
    const auto rows = static_cast<std::ptrdiff_t>(stage.extent.row_end);
#pragma omp for schedule(static) nowait
    for (std::ptrdiff_t row = 0; row < rows; ++row) {
      if (damped) {
        spring_row_forces<Real, true>(job, static_cast<std::size_t>(row));
      } else {
        spring_row_forces<Real, false>(job, static_cast<std::size_t>(row));
      }
    }
  }
}

template <class Real>
void ClothEngine<Real>::compute_wind(const Real* x) {
  WindJob<Real> job{};
  for (int k = 0; k < 3; ++k) {
    job.x[k] = x + k * stride_;
    job.first[k] = component(wind_first_, k);
    job.second[k] = component(wind_second_, k);
    job.direction[k] = wind_direction_[k];
  }
  job.cols = scene_.cols;
  job.strength = wind_strength_;
  const auto rows = static_cast<std::ptrdiff_t>(scene_.rows - 1);
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t row = 0; row < rows; ++row) {
    wind_row_forces(job, static_cast<std::size_t>(row));
  }
}

template <class Real>
bool ClothEngine<Real>::combine(Real* a) {
  const auto chunks = static_cast<std::ptrdiff_t>(all_chunks_.size());
  const std::size_t cols = scene_.cols;
  const bool wind = wind_first_.size() != 0;
  // Sum of 0 * a over every particle: NaN exactly when some acceleration is not finite.
  Real probe = 0;
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_) reduction(+ : probe)
  for (std::ptrdiff_t chunk = 0; chunk < chunks; ++chunk) {
    const std::size_t begin = all_chunks_[chunk].begin;
    const std::size_t count = all_chunks_[chunk].end - begin;
    for (int k = 0; k < 3; ++k) {
      Real sum[kBlock];
#pragma omp simd
      for (std::size_t t = 0; t < count; ++t) sum[t] = 0;
      for (SpringStage& stage : stages_) {
        // Spring i -> i + offset pushes i by f[i] and its partner by -f[i].
        const Real* __restrict f = component(stage.force, k) + begin;
        const Real* __restrict f_back = f - stage.offset;
#pragma omp simd
        for (std::size_t t = 0; t < count; ++t) sum[t] += f[t] - f_back[t];
      }
      if (wind) {
        // A particle is corner a of its own cell, b of the cell to its left, c of the
        // cell above and d of the cell above-left.
        const Real* __restrict first = component(wind_first_, k) + begin;
        const Real* __restrict second = component(wind_second_, k) + begin;
        const Real* __restrict first_left = first - 1;
        const Real* __restrict second_left = second - 1;
        const Real* __restrict first_above = first - cols;
        const Real* __restrict second_above = second - cols;
        const Real* __restrict second_above_left = second - cols - 1;
#pragma omp simd
        for (std::size_t t = 0; t < count; ++t) {
          sum[t] += first[t] + first_left[t] + second_left[t] + first_above[t] + second_above[t] +
                    second_above_left[t];
        }
      }
      const Real* __restrict inverse_mass = inverse_mass_.data() + begin;
      Real* __restrict out = a + k * stride_ + begin;
      const Real g = gravity_[k];
#pragma omp simd reduction(+ : probe)
      for (std::size_t t = 0; t < count; ++t) {
        const Real value = inverse_mass[t] > Real(0) ? sum[t] * inverse_mass[t] + g : Real(0);
        out[t] = value;
        probe += value * Real(0);
      }
    }
  }
  return probe == Real(0);
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
  return static_cast<ClothEngine*>(context)->evaluate(
      static_cast<const Real*>(x), static_cast<const Real*>(v), static_cast<Real*>(a));
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
  std::memmove(dst, src, 3 * self->stride_ * sizeof(Real));
}

template <class Real>
void* ClothEngine<Real>::alloc_callback(void* context) {
  return static_cast<ClothEngine*>(context)->alloc_vector();
}

template class ClothEngine<float>;
template class ClothEngine<double>;

std::unique_ptr<Engine> make_engine(const Scene& scene, Precision precision,
                                    PipelineOptions options) {
  if (precision == Precision::Float32) return std::make_unique<ClothEngine<float>>(scene, options);
  return std::make_unique<ClothEngine<double>>(scene, options);
}

}  // namespace clothlab::detail
