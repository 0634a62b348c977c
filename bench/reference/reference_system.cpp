#include "reference_system.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <new>

namespace clothlab::reference {

template <class Real>
ReferenceSystem<Real>::ReferenceSystem(const Scene& scene, bool velocity_forces)
    : cloth_(scene),
      velocity_forces_(velocity_forces),
      n_(std::size_t{scene.rows} * scene.cols),
      stride_((n_ + 15) / 16 * 16),
      x_(make_vector()),
      v_(make_vector()),
      inverse_mass_(make_vector()),
      x_aos_(3 * n_),
      v_aos_(3 * n_),
      a_aos_(3 * n_) {
  const std::vector<Real>& start = cloth_.initial_positions();
  for (std::size_t i = 0; i < n_; ++i) {
    for (std::size_t k = 0; k < 3; ++k) x_[k * stride_ + i] = start[3 * i + k];
    inverse_mass_[i] = static_cast<Real>(static_cast<double>(n_) / scene.total_mass);
  }
  for (uint32_t pinned : scene.pinned) inverse_mass_[pinned] = 0;
  for (std::size_t i = 0; i < n_;) {
    if (inverse_mass_[i] == 0) {
      ++i;
      continue;
    }
    const std::size_t begin = i;
    while (i < n_ && inverse_mass_[i] != 0) ++i;
    active_.push_back({static_cast<uint32_t>(begin), static_cast<uint32_t>(i)});
  }

  system_.struct_size = sizeof(clothlab_system);
  system_.precision = sizeof(Real) == sizeof(float) ? CLOTHLAB_FLOAT32 : CLOTHLAB_FLOAT64;
  system_.particle_count = static_cast<uint32_t>(n_);
  system_.stride = static_cast<uint32_t>(stride_);
  system_.x = x_.get();
  system_.v = v_.get();
  system_.inverse_mass = inverse_mass_.get();
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
  wind_ = scene.has_wind() || scene.has_air();

  // The Jacobian's block pattern: each row's particle and spring partners, ascending.
  product_.assign(3 * n_, 0.0);
  std::vector<std::vector<uint32_t>> rows(n_);
  for (std::size_t i = 0; i < n_; ++i) rows[i].push_back(static_cast<uint32_t>(i));
  for (const Spring<Real>& spring : cloth_.springs()) {
    rows[spring.i].push_back(spring.j);
    rows[spring.j].push_back(spring.i);
  }
  row_offsets_.push_back(0);
  for (std::vector<uint32_t>& row : rows) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    columns_.insert(columns_.end(), row.begin(), row.end());
    row_offsets_.push_back(static_cast<uint32_t>(columns_.size()));
  }
  blocks_.assign(9 * columns_.size(), 0.0);
  build_topology(scene);
}

template <class Real>
typename ReferenceSystem<Real>::Vector ReferenceSystem<Real>::make_vector() const {
  const std::size_t bytes = (3 * stride_ * sizeof(Real) + 63) / 64 * 64;
  Vector vector(static_cast<Real*>(std::aligned_alloc(64, bytes)));
  if (!vector) throw std::bad_alloc();
  std::memset(vector.get(), 0, bytes);
  return vector;
}

template <class Real>
void ReferenceSystem<Real>::positions(std::vector<double>& out) const {
  out.resize(3 * n_);
  for (std::size_t i = 0; i < n_; ++i) {
    for (std::size_t k = 0; k < 3; ++k) out[3 * i + k] = x_[k * stride_ + i];
  }
}

template <class Real>
Real ReferenceSystem<Real>::combined(const clothlab_combination& state, std::size_t i,
                                     std::size_t k) const {
  const std::size_t e = k * stride_ + i;
  Real value = static_cast<const Real*>(state.base)[e];
  if (inverse_mass_[i] == Real(0)) return value;  // pinned: the base value
  for (uint32_t j = 0; j < state.count; ++j) {
    value +=
        static_cast<Real>(state.coefficients[j]) * static_cast<const Real*>(state.vectors[j])[e];
  }
  return value;
}

template <class Real>
clothlab_status ReferenceSystem<Real>::evaluate(const clothlab_combination& x,
                                                const clothlab_combination* v, Real* a) {
  const auto start = std::chrono::steady_clock::now();
  const bool damping = velocity_forces_ && v != nullptr;
  for (std::size_t i = 0; i < n_; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      x_aos_[3 * i + k] = combined(x, i, k);
      if (damping) v_aos_[3 * i + k] = combined(*v, i, k);
    }
  }
  cloth_.acceleration(x_aos_.data(), damping ? v_aos_.data() : nullptr, a_aos_.data());
  bool finite = true;
  for (std::size_t i = 0; i < n_; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      a[k * stride_ + i] = a_aos_[3 * i + k];
      finite = finite && std::isfinite(a_aos_[3 * i + k]);
    }
  }
  ++force_evals_;
  force_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return finite ? CLOTHLAB_OK : CLOTHLAB_ERROR_NUMERICAL;
}

template <class Real>
clothlab_status ReferenceSystem<Real>::eval_callback(void* context, double, const void* x,
                                                     const void* v, void* a) {
  const clothlab_combination x_state{x, 0, 0, nullptr, nullptr};
  const clothlab_combination v_state{v, 0, 0, nullptr, nullptr};
  return static_cast<ReferenceSystem*>(context)->evaluate(
      x_state, v == nullptr ? nullptr : &v_state, static_cast<Real*>(a));
}

template <class Real>
clothlab_status ReferenceSystem<Real>::eval_at_callback(void* context, double,
                                                        const clothlab_combination* x,
                                                        const clothlab_combination* v, void* a) {
  const auto valid = [](const clothlab_combination* state) {
    return state->base != nullptr && state->count <= CLOTHLAB_COMBINATION_MAX_TERMS;
  };
  if (x == nullptr || !valid(x) || (v != nullptr && !valid(v))) {
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  }
  return static_cast<ReferenceSystem*>(context)->evaluate(*x, v, static_cast<Real*>(a));
}

template <class Real>
clothlab_status ReferenceSystem<Real>::reserve_rkn_callback(void* context, uint32_t stages) {
  auto* self = static_cast<ReferenceSystem*>(context);
  if (stages == 0 || stages > CLOTHLAB_RKN_MAX_STAGES) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  try {
    if (!self->stage_x_) self->stage_x_ = self->make_vector();
    if (!self->stage_v_) self->stage_v_ = self->make_vector();
    while (self->accelerations_.size() < stages)
      self->accelerations_.push_back(self->make_vector());
    return CLOTHLAB_OK;
  } catch (const std::bad_alloc&) {
    return CLOTHLAB_ERROR_OUT_OF_MEMORY;
  }
}

// Stage by stage, as a straightforward implementation would: each stage state formed as
// whole vectors, evaluated, and the update applied at the end (see plugin.h).
template <class Real>
clothlab_status ReferenceSystem<Real>::step_rkn_callback(void* context, double t, double h,
                                                         const clothlab_rkn_scheme* scheme) {
  auto* self = static_cast<ReferenceSystem*>(context);
  const uint32_t n = scheme->stages;
  if (n == 0 || n > self->accelerations_.size()) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  const auto for_active = [&](auto&& body) {
    for (const clothlab_range& range : self->active_)
      for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t i = range.begin; i < range.end; ++i) body(k * self->stride_ + i);
  };
  Real* x = self->x_.get();
  Real* v = self->v_.get();
  for (uint32_t stage = 0; stage < n; ++stage) {
    bool in_place = scheme->alpha[stage] == 0.0;  // a stage at (x, v) itself: no copies
    for (uint32_t j = 0; j < stage; ++j) {
      in_place = in_place && scheme->x_coupling[stage * n + j] == 0.0 &&
                 scheme->v_coupling[stage * n + j] == 0.0;
    }
    if (!in_place) {
      copy_callback(context, self->stage_x_.get(), x);
      copy_callback(context, self->stage_v_.get(), v);
      for_active([&](std::size_t e) {
        Real xs = x[e] + static_cast<Real>(h * scheme->alpha[stage]) * v[e], vs = v[e];
        for (uint32_t j = 0; j < stage; ++j) {
          const Real a = self->accelerations_[j][e];
          xs += static_cast<Real>(h * h * scheme->x_coupling[stage * n + j]) * a;
          vs += static_cast<Real>(h * scheme->v_coupling[stage * n + j]) * a;
        }
        self->stage_x_[e] = xs;
        self->stage_v_[e] = vs;
      });
    }
    const clothlab_status status =
        eval_callback(context, t + scheme->c[stage] * h, in_place ? x : self->stage_x_.get(),
                      in_place ? v : self->stage_v_.get(), self->accelerations_[stage].get());
    if (status != CLOTHLAB_OK) return status;
  }
  for_active([&](std::size_t e) {
    Real dx = static_cast<Real>(h) * v[e], dv = 0;
    for (uint32_t j = 0; j < n; ++j) {
      const Real a = self->accelerations_[j][e];
      dx += static_cast<Real>(h * h * scheme->x_weights[j]) * a;
      dv += static_cast<Real>(h * scheme->v_weights[j]) * a;
    }
    x[e] += dx;
    v[e] += dv;
  });
  return CLOTHLAB_OK;
}

template <class Real>
void ReferenceSystem<Real>::axpy_callback(void* context, void* y, double alpha, const void* x) {
  const auto* self = static_cast<const ReferenceSystem*>(context);
  Real* out = static_cast<Real*>(y);
  const Real* in = static_cast<const Real*>(x);
  for (const clothlab_range& range : self->active_) {
    for (std::size_t k = 0; k < 3; ++k) {
      for (std::size_t i = range.begin; i < range.end; ++i) {
        out[k * self->stride_ + i] += static_cast<Real>(alpha) * in[k * self->stride_ + i];
      }
    }
  }
}

template <class Real>
void ReferenceSystem<Real>::lincomb_callback(void* context, void* out, const void* base,
                                             uint32_t count, const double* coefficients,
                                             const void* const* vectors) {
  const auto* self = static_cast<const ReferenceSystem*>(context);
  for (const clothlab_range& range : self->active_) {
    for (std::size_t k = 0; k < 3; ++k) {
      for (std::size_t i = range.begin; i < range.end; ++i) {
        const std::size_t e = k * self->stride_ + i;
        Real sum = static_cast<const Real*>(base)[e];
        for (uint32_t j = 0; j < count; ++j) {
          sum += static_cast<Real>(coefficients[j]) * static_cast<const Real*>(vectors[j])[e];
        }
        static_cast<Real*>(out)[e] = sum;
      }
    }
  }
}

template <class Real>
void ReferenceSystem<Real>::copy_callback(void* context, void* dst, const void* src) {
  const auto* self = static_cast<const ReferenceSystem*>(context);
  std::memmove(dst, src, 3 * self->stride_ * sizeof(Real));
}

template <class Real>
void* ReferenceSystem<Real>::alloc_callback(void* context) {
  auto* self = static_cast<ReferenceSystem*>(context);
  try {
    self->vectors_.push_back(self->make_vector());
    return self->vectors_.back().get();
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}

template class ReferenceSystem<float>;
template class ReferenceSystem<double>;

}  // namespace clothlab::reference
