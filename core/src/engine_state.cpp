// The engine's state (engine_state.hpp): its setup, conversions to and from double, finiteness,
// energy and stretch. None of this runs inside a step.
#include "engine_state.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include "grid.hpp"

namespace clothlab::detail {
namespace {

template <class Real, class Out>
void to_particle_major(const Real* soa, std::size_t n, std::size_t stride, std::vector<Out>& out) {
  out.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < 3; ++k) out[3 * i + k] = static_cast<Out>(soa[k * stride + i]);
  }
}

template <class Real>
double spring_length(const Real* x, std::size_t stride, std::size_t i, std::size_t offset) {
  const double dx = double{x[i + offset]} - double{x[i]};
  const double dy = double{x[stride + i + offset]} - double{x[stride + i]};
  const double dz = double{x[2 * stride + i + offset]} - double{x[2 * stride + i]};
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

constexpr std::size_t kChunk = 2048;  // particles per thread work item

std::size_t round_up_16(std::size_t value) { return (value + 15) / 16 * 16; }

}  // namespace

template <class Real>
EngineState<Real>::EngineState(const Scene& scene, std::shared_ptr<const ClothModel> model,
                               const PipelineOptions& options)
    : scene_(scene),
      model_(std::move(model)),
      n_(model_->particle_count),
      stride_(round_up_16(n_)),
      velocity_forces_(options.velocity_forces),
      grid_path_(model_->grid && !options.force_general_path) {
  if (options.threads < 0) {
    throw std::invalid_argument("threads = " + std::to_string(options.threads) +
                                ": allowed 0 (all hardware threads) or >= 1");
  }
  if (n_ < 1) throw std::invalid_argument("cloth: no particles (allowed: at least 1)");
  threads_ = options.threads == 0 ? omp_get_max_threads() : options.threads;
  parallel_capable_ = threads_ > 1 && n_ >= parallel_from_particles;
  parallel_ = parallel_capable_;
  if (parallel_) {
    // Start the thread team now: its first start allocates, which a step must not do.
#pragma omp parallel num_threads(threads_)
    { (void)omp_get_thread_num(); }
  }

  x_ = AlignedBuffer<Real>(3 * stride_);
  v_ = AlignedBuffer<Real>(3 * stride_);
  inverse_mass_ = AlignedBuffer<Real>(stride_);
  for (std::size_t i = 0; i < n_; ++i) {
    for (std::size_t k = 0; k < 3; ++k)
      x_[k * stride_ + i] = static_cast<Real>(model_->rest_positions[3 * i + k]);
    inverse_mass_[i] = static_cast<Real>(model_->inverse_masses[i]);
  }
  near_pin_.assign(n_, 0);
  if (model_->grid) {
    const GridShape grid = *model_->grid;
    for (uint32_t pinned : model_->pinned) {
      const uint32_t row = pinned / grid.cols, col = pinned % grid.cols;
      for (uint32_t r = row > 2 ? row - 2 : 0; r <= std::min(row + 2, grid.rows - 1); ++r)
        for (uint32_t c = col > 2 ? col - 2 : 0; c <= std::min(col + 2, grid.cols - 1); ++c)
          near_pin_[std::size_t{r} * grid.cols + c] = 1;
    }
  } else {
    // Two springs from a pin: on a grid's springs, about its two rows and columns.
    for (uint32_t pinned : model_->pinned) near_pin_[pinned] = 1;
    for (int hop = 0; hop < 2; ++hop) {
      std::vector<uint8_t> reached = near_pin_;
      for (std::size_t i = 0; i < n_; ++i) {
        if (near_pin_[i] == 0) continue;
        for (uint32_t e = model_->adjacency_offsets[i]; e < model_->adjacency_offsets[i + 1]; ++e) {
          const uint32_t s = model_->adjacent_springs[e];
          reached[model_->first[s] == i ? model_->second[s] : model_->first[s]] = 1;
        }
      }
      near_pin_ = std::move(reached);
    }
  }

  // Active ranges: maximal runs between pinned indices (scene.pinned is sorted, unique).
  std::size_t begin = 0;
  for (std::size_t i = 0; i <= n_; ++i) {
    if (i == n_ || inverse_mass_[i] == 0) {
      if (i > begin) active_.push_back({static_cast<uint32_t>(begin), static_cast<uint32_t>(i)});
      begin = i + 1;
    }
  }
  for (const clothlab_range& range : active_) {
    for (std::size_t b = range.begin; b < range.end; b += kChunk) {
      active_chunks_.push_back({b, std::min<std::size_t>(range.end, b + kChunk)});
    }
    active_particles_ += range.end - range.begin;
  }
}

template <class Real>
void EngineState<Real>::positions(std::vector<double>& out) const {
  to_particle_major(x_.data(), n_, stride_, out);
}

template <class Real>
void EngineState<Real>::velocities(std::vector<double>& out) const {
  to_particle_major(v_.data(), n_, stride_, out);
}

template <class Real>
void EngineState<Real>::positions(std::vector<float>& out) const {
  to_particle_major(x_.data(), n_, stride_, out);
}

template <class Real>
void EngineState<Real>::velocities(std::vector<float>& out) const {
  to_particle_major(v_.data(), n_, stride_, out);
}

template <class Real>
void EngineState<Real>::set_state(const std::vector<double>& x, const std::vector<double>& v) {
  if (x.size() != 3 * n_ || v.size() != 3 * n_) {
    throw std::invalid_argument("set_state: got " + std::to_string(x.size()) + " positions and " +
                                std::to_string(v.size()) + " velocities, expected " +
                                std::to_string(3 * n_) + " each (3 per particle)");
  }
  for (std::size_t i = 0; i < n_; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      x_[k * stride_ + i] = static_cast<Real>(x[3 * i + k]);
      v_[k * stride_ + i] = static_cast<Real>(v[3 * i + k]);
    }
  }
}

template <class Real>
void EngineState<Real>::copy_raw_state(Cloth::RawState& out) const {
  const std::size_t bytes = x_.size() * sizeof(Real);
  out.x.resize(bytes);
  out.v.resize(bytes);
  std::memcpy(out.x.data(), x_.data(), bytes);
  std::memcpy(out.v.data(), v_.data(), bytes);
}

template <class Real>
void EngineState<Real>::set_raw_state(const Cloth::RawState& state) {
  const std::size_t bytes = x_.size() * sizeof(Real);
  if (state.x.size() != bytes || state.v.size() != bytes) {
    throw std::invalid_argument("set_raw_state: got " + std::to_string(state.x.size()) + " and " +
                                std::to_string(state.v.size()) + " bytes, expected " +
                                std::to_string(bytes) + " each (a state of another cloth)");
  }
  std::memcpy(x_.data(), state.x.data(), bytes);
  std::memcpy(v_.data(), state.v.data(), bytes);
}

template <class Real>
bool EngineState<Real>::state_is_finite() const {
  for (std::size_t k = 0; k < 3; ++k) {
    for (std::size_t i = 0; i < n_; ++i) {
      if (!std::isfinite(x_[k * stride_ + i]) || !std::isfinite(v_[k * stride_ + i])) return false;
    }
  }
  return true;
}

template <class Real>
Cloth::Energy EngineState<Real>::energy() const {
  Cloth::Energy energy;
  for (std::size_t i = 0; i < n_; ++i) {
    if (inverse_mass_[i] == 0) continue;  // pinned: does not move, no finite mass
    const double mass = model_->masses[i];
    for (std::size_t k = 0; k < 3; ++k) {
      const double velocity = v_[k * stride_ + i];
      energy.kinetic += 0.5 * mass * velocity * velocity;
      energy.gravity -=
          mass * scene_.gravity[k] * (x_[k * stride_ + i] - model_->rest_positions[3 * i + k]);
    }
  }
  if (!on_grid_path()) {
    energy.spring = list_spring_energy();
    return energy;
  }
  const Real* x = x_.data();
  const std::size_t cols = scene_.cols;
  double spring = 0.0;
  for (const Stencil& stencil : kProvotStencils) {
    const double ks = (scene_.*stencil.family).ks;
    if (ks == 0.0) continue;
    const StencilExtent extent = stencil_extent(stencil, scene_.rows, scene_.cols);
    const double rest = stencil_rest_length(scene_, stencil);
    const auto offset = static_cast<std::size_t>(stencil_offset(stencil, scene_.cols));
    const auto rows = static_cast<std::ptrdiff_t>(extent.row_end);
#pragma omp parallel for num_threads(threads_) if (parallel_) reduction(+ : spring)
    for (std::ptrdiff_t r = 0; r < rows; ++r) {
      const std::size_t first = static_cast<std::size_t>(r) * cols;
#pragma omp simd reduction(+ : spring)
      for (std::size_t c = extent.col_begin; c < extent.col_end; ++c) {
        const double stretch = spring_length(x, stride_, first + c, offset) - rest;
        spring += 0.5 * ks * stretch * stretch;
      }
    }
  }
  energy.spring = spring;
  return energy;
}

template <class Real>
double EngineState<Real>::list_spring_energy() const {
  const ClothModel& m = *model_;
  double spring = 0.0;
  for (std::size_t s = 0; s < m.spring_count(); ++s) {
    const double stretch =
        spring_length(x_.data(), stride_, m.first[s], m.second[s] - m.first[s]) - m.rest_length[s];
    spring += 0.5 * m.ks[s] * stretch * stretch;
  }
  return spring;
}

template <class Real>
template <class Visit>
void EngineState<Real>::for_each_ratio(Cloth::Springs which, Visit&& visit) const {
  const ClothModel& m = *model_;
  for (std::size_t s = 0; s < m.spring_count(); ++s) {
    if (which == Cloth::Springs::Structural && m.family[s] != CLOTHLAB_SPRING_STRUCTURAL) continue;
    const uint32_t i = m.first[s], j = m.second[s];
    visit(spring_length(x_.data(), stride_, i, j - i) / m.rest_length[s], i, j);
  }
}

template <class Real>
Cloth::Stretch EngineState<Real>::stretch(Cloth::Springs which) const {
  if (!on_grid_path()) {
    double worst = 0.0, worst_away = 0.0, sum = 0.0;
    std::size_t springs = 0, away = 0;
    for_each_ratio(which, [&](double ratio, uint32_t i, uint32_t j) {
      worst = std::max(worst, ratio);
      sum += ratio;
      ++springs;
      if ((near_pin_[i] | near_pin_[j]) != 0) return;
      worst_away = std::max(worst_away, ratio);
      ++away;
    });
    if (springs == 0) return {};
    return {worst, sum / static_cast<double>(springs), away > 0 ? worst_away : 1.0};
  }
  const Real* x = x_.data();
  const uint8_t* near_pin = near_pin_.data();
  const std::size_t cols = scene_.cols;
  double worst = 0.0, worst_away = 0.0;
  double sum = 0.0;
  std::size_t springs = 0, away = 0;
  for (const Stencil& stencil : kProvotStencils) {
    const StencilExtent extent = stencil_extent(stencil, scene_.rows, scene_.cols);
    if (extent.count() == 0) continue;
    if (which == Cloth::Springs::Structural && stencil.family != &Scene::structural) continue;
    springs += extent.count();
    const double inverse_rest = 1.0 / stencil_rest_length(scene_, stencil);
    const auto offset = static_cast<std::size_t>(stencil_offset(stencil, scene_.cols));
    const auto rows = static_cast<std::ptrdiff_t>(extent.row_end);
#pragma omp parallel for num_threads(threads_) if (parallel_) reduction(max : worst, worst_away) \
    reduction(+ : sum, away)
    for (std::ptrdiff_t r = 0; r < rows; ++r) {
      const std::size_t first = static_cast<std::size_t>(r) * cols;
#pragma omp simd reduction(max : worst, worst_away) reduction(+ : sum, away)
      for (std::size_t c = extent.col_begin; c < extent.col_end; ++c) {
        const double ratio = spring_length(x, stride_, first + c, offset) * inverse_rest;
        worst = std::max(worst, ratio);
        sum += ratio;
        const bool counted = (near_pin[first + c] | near_pin[first + c + offset]) == 0;
        worst_away = std::max(worst_away, counted ? ratio : 0.0);
        away += counted;
      }
    }
  }
  if (springs == 0) return {};
  return {worst, sum / static_cast<double>(springs), away > 0 ? worst_away : 1.0};
}

template <class Real>
double EngineState<Real>::stretch_percentile(Cloth::Springs which, double fraction) const {
  if (!(fraction > 0.0 && fraction <= 1.0))
    throw std::invalid_argument("stretch_percentile: fraction " + std::to_string(fraction) +
                                " outside (0, 1]");
  const Real* x = x_.data();
  const std::size_t cols = scene_.cols;
  stretch_ratios_.clear();
  if (!on_grid_path())
    for_each_ratio(which,
                   [&](double ratio, uint32_t, uint32_t) { stretch_ratios_.push_back(ratio); });
  for (const Stencil& stencil :
       on_grid_path() ? std::span(kProvotStencils) : std::span<const Stencil>()) {
    if (which == Cloth::Springs::Structural && stencil.family != &Scene::structural) continue;
    const StencilExtent extent = stencil_extent(stencil, scene_.rows, scene_.cols);
    const double inverse_rest = 1.0 / stencil_rest_length(scene_, stencil);
    const auto offset = static_cast<std::size_t>(stencil_offset(stencil, scene_.cols));
    for (uint32_t r = 0; r < extent.row_end; ++r)
      for (uint32_t c = extent.col_begin; c < extent.col_end; ++c)
        stretch_ratios_.push_back(spring_length(x, stride_, r * cols + c, offset) * inverse_rest);
  }
  if (stretch_ratios_.empty()) return 1.0;
  // Nearest rank: the ceil(fraction n)-th smallest (1-based).
  const auto count = static_cast<double>(stretch_ratios_.size());
  const auto rank = static_cast<std::size_t>(std::max(1.0, std::ceil(fraction * count)));
  const auto nth = stretch_ratios_.begin() + static_cast<std::ptrdiff_t>(rank - 1);
  std::nth_element(stretch_ratios_.begin(), nth, stretch_ratios_.end());
  return *nth;
}

template <class Real>
Cloth::LongestSpring EngineState<Real>::longest_spring(Cloth::Springs which) const {
  Cloth::LongestSpring longest;
  double worst = -1.0;  // below any length ratio: the first spring is taken
  if (!on_grid_path()) {
    for_each_ratio(which, [&](double ratio, uint32_t i, uint32_t j) {
      if (ratio <= worst) return;
      worst = ratio;
      longest = {ratio, i, j};
    });
    return longest;
  }
  const Real* x = x_.data();
  const std::size_t cols = scene_.cols;
  for (const Stencil& stencil : kProvotStencils) {
    if (which == Cloth::Springs::Structural && stencil.family != &Scene::structural) continue;
    const StencilExtent extent = stencil_extent(stencil, scene_.rows, scene_.cols);
    const double inverse_rest = 1.0 / stencil_rest_length(scene_, stencil);
    const auto offset = static_cast<std::size_t>(stencil_offset(stencil, scene_.cols));
    for (uint32_t r = 0; r < extent.row_end; ++r) {
      for (uint32_t c = extent.col_begin; c < extent.col_end; ++c) {
        const double ratio = spring_length(x, stride_, r * cols + c, offset) * inverse_rest;
        if (ratio <= worst) continue;
        worst = ratio;
        const auto first = static_cast<uint32_t>(r * cols + c);
        longest = {
            ratio,           first, static_cast<uint32_t>(first + offset), r, c, stencil.row_step,
            stencil.col_step};
      }
    }
  }
  return longest;
}

template class EngineState<float>;
template class EngineState<double>;

}  // namespace clothlab::detail
