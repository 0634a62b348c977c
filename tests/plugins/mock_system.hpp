// A stand-in for the core: a clothlab_system over plain aligned arrays with a force law
// written in the test, so integrators can be checked without the real cloth.
//
// Vector helpers follow plugin.h: axpy and lincomb touch active particles only, copy
// touches all, alloc_vector works only while `allocation_allowed` (the harness sets it
// around prepare), so a step that allocates fails. eval_acceleration_at forms the stage
// state in two vectors of its own, then evaluates. Arithmetic is done in double and
// rounded once to Real.
#pragma once

#include <clothlab/plugin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>
#include <new>
#include <vector>

namespace clothlab::test {

using Vec3 = std::array<double, 3>;

// The largest difference of any coordinate between two lists of vectors of the same length.
inline double largest_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double largest = 0.0;
  for (std::size_t p = 0; p < a.size(); ++p)
    for (int k = 0; k < 3; ++k) largest = std::max(largest, std::abs(a[p][k] - b[p][k]));
  return largest;
}

// Acceleration of active particle i at time t. v is nullptr when the integrator does not
// want velocity-dependent forces. Vectors are SoA: component k of particle i at k*stride+i.
template <class Real>
using ForceLaw =
    std::function<Vec3(double t, uint32_t i, const Real* x, const Real* v, uint32_t stride)>;

template <class Real>
class MockSystem {
 public:
  MockSystem(uint32_t particle_count, std::vector<uint32_t> pinned, ForceLaw<Real> law)
      : n_(particle_count), stride_((particle_count + 15) / 16 * 16), law_(std::move(law)) {
    x_ = new_vector();
    v_ = new_vector();
    stage_x_ = new_vector();
    stage_v_ = new_vector();
    inverse_mass_ = new_buffer(n_);
    for (uint32_t i = 0; i < n_; ++i) inverse_mass_[i] = 1;
    for (uint32_t i : pinned) inverse_mass_[i] = 0;
    for (uint32_t i = 0; i < n_; ++i) {
      if (inverse_mass_[i] == 0) continue;
      if (!active_.empty() && active_.back().end == i)
        ++active_.back().end;
      else
        active_.push_back({i, i + 1});
    }
    raw_ = {sizeof(clothlab_system),
            sizeof(Real) == 4 ? CLOTHLAB_FLOAT32 : CLOTHLAB_FLOAT64,
            n_,
            stride_,
            x_,
            v_,
            inverse_mass_,
            active_.data(),
            static_cast<uint32_t>(active_.size()),
            0,
            this,
            &MockSystem::eval,
            &MockSystem::axpy,
            &MockSystem::lincomb,
            &MockSystem::copy,
            &MockSystem::alloc,
            &MockSystem::eval_at,
            &MockSystem::reserve_rkn,
            &MockSystem::step_rkn,
            &MockSystem::get_extension};  // none unless a test sets `extensions`
  }
  MockSystem(const MockSystem&) = delete;
  MockSystem& operator=(const MockSystem&) = delete;

  const clothlab_system& raw() const { return raw_; }
  uint32_t stride() const { return stride_; }
  Real* x() { return x_; }
  Real* v() { return v_; }

  void set_position(uint32_t i, Vec3 p) { set(x_, i, p); }
  void set_velocity(uint32_t i, Vec3 p) { set(v_, i, p); }
  // A free particle's mass (pins stay pinned: the active ranges do not change).
  void set_mass(uint32_t i, double mass) {
    if (inverse_mass_[i] != 0) inverse_mass_[i] = static_cast<Real>(1.0 / mass);
  }
  Vec3 position(uint32_t i) const { return get(x_, i); }
  Vec3 velocity(uint32_t i) const { return get(v_, i); }

  // Host extensions a test offers (by clothlab/ext/ id; none by default). Their functions
  // receive this system as context and reach their own data through extension_data.
  std::function<const void*(const char* id)> extensions;
  void* extension_data = nullptr;

  bool allocation_allowed = false;
  int evaluations = 0;
  int rkn_steps = 0;
  int evaluations_without_velocity = 0;

 private:
  struct Free {
    void operator()(Real* p) const { std::free(p); }
  };

  Real* new_buffer(size_t count) {
    const size_t bytes = (count * sizeof(Real) + 63) / 64 * 64;
    Real* p = static_cast<Real*>(std::aligned_alloc(64, bytes));
    if (p == nullptr) throw std::bad_alloc();
    for (size_t i = 0; i < bytes / sizeof(Real); ++i) p[i] = 0;
    buffers_.emplace_back(p);
    return p;
  }
  Real* new_vector() { return new_buffer(3 * size_t{stride_}); }

  void set(Real* vector, uint32_t i, Vec3 p) {
    for (int k = 0; k < 3; ++k) vector[k * stride_ + i] = static_cast<Real>(p[k]);
  }
  Vec3 get(const Real* vector, uint32_t i) const {
    return {vector[i], vector[stride_ + i], vector[2 * stride_ + i]};
  }

  template <class Body>
  void for_active(Body&& body) const {
    for (const clothlab_range& range : active_)
      for (uint32_t i = range.begin; i < range.end; ++i)
        for (uint32_t k = 0; k < 3; ++k) body(k * stride_ + i);
  }

  static MockSystem& self(void* context) { return *static_cast<MockSystem*>(context); }

  static clothlab_status eval(void* context, double t, const void* x, const void* v, void* a) {
    MockSystem& s = self(context);
    ++s.evaluations;
    if (v == nullptr) ++s.evaluations_without_velocity;
    Real* out = static_cast<Real*>(a);
    for (size_t j = 0; j < 3 * size_t{s.stride_}; ++j) out[j] = 0;
    bool finite = true;
    for (const clothlab_range& range : s.active_)
      for (uint32_t i = range.begin; i < range.end; ++i) {
        const Vec3 acc =
            s.law_(t, i, static_cast<const Real*>(x), static_cast<const Real*>(v), s.stride_);
        for (int k = 0; k < 3; ++k) {
          out[k * s.stride_ + i] = static_cast<Real>(acc[k]);
          finite = finite && std::isfinite(out[k * s.stride_ + i]);
        }
      }
    return finite ? CLOTHLAB_OK : CLOTHLAB_ERROR_NUMERICAL;
  }

  static clothlab_status eval_at(void* context, double t, const clothlab_combination* x,
                                 const clothlab_combination* v, void* a) {
    MockSystem& s = self(context);
    const auto form = [&](const clothlab_combination& state, Real* out) {
      copy(context, out, state.base);
      lincomb(context, out, state.base, state.count, state.coefficients, state.vectors);
    };
    form(*x, s.stage_x_);
    if (v != nullptr) form(*v, s.stage_v_);
    return eval(context, t, s.stage_x_, v == nullptr ? nullptr : s.stage_v_, a);
  }

  // Stage by stage, in double: X_i, V_i formed whole, then evaluated (see plugin.h).
  static clothlab_status reserve_rkn(void* context, uint32_t stages) {
    MockSystem& s = self(context);
    if (!s.allocation_allowed || stages == 0 || stages > CLOTHLAB_RKN_MAX_STAGES)
      return CLOTHLAB_ERROR_INVALID_ARGUMENT;
    while (s.stage_accelerations_.size() < stages) s.stage_accelerations_.push_back(s.new_vector());
    return CLOTHLAB_OK;
  }

  static clothlab_status step_rkn(void* context, double t, double h,
                                  const clothlab_rkn_scheme* scheme) {
    MockSystem& s = self(context);
    const uint32_t n = scheme->stages;
    if (n == 0 || n > s.stage_accelerations_.size()) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
    ++s.rkn_steps;
    const auto& a = s.stage_accelerations_;
    for (uint32_t i = 0; i < n; ++i) {
      copy(context, s.stage_x_, s.x_);
      copy(context, s.stage_v_, s.v_);
      s.for_active([&](size_t j) {
        double x = s.x_[j] + h * scheme->alpha[i] * s.v_[j], v = s.v_[j];
        for (uint32_t k = 0; k < i; ++k) {
          x += h * h * scheme->x_coupling[i * n + k] * a[k][j];
          v += h * scheme->v_coupling[i * n + k] * a[k][j];
        }
        s.stage_x_[j] = static_cast<Real>(x);
        s.stage_v_[j] = static_cast<Real>(v);
      });
      const clothlab_status status =
          eval(context, t + scheme->c[i] * h, s.stage_x_, s.stage_v_, a[i]);
      if (status != CLOTHLAB_OK) return status;
    }
    s.for_active([&](size_t j) {
      double x = s.x_[j] + h * s.v_[j], v = s.v_[j];
      for (uint32_t k = 0; k < n; ++k) {
        x += h * h * scheme->x_weights[k] * a[k][j];
        v += h * scheme->v_weights[k] * a[k][j];
      }
      s.x_[j] = static_cast<Real>(x);
      s.v_[j] = static_cast<Real>(v);
    });
    return CLOTHLAB_OK;
  }

  static void axpy(void* context, void* y, double alpha, const void* x) {
    Real* out = static_cast<Real*>(y);
    const Real* in = static_cast<const Real*>(x);
    self(context).for_active(
        [&](size_t j) { out[j] = static_cast<Real>(static_cast<double>(out[j]) + alpha * in[j]); });
  }

  static void lincomb(void* context, void* out, const void* base, uint32_t count,
                      const double* coefficients, const void* const* vectors) {
    Real* result = static_cast<Real*>(out);
    self(context).for_active([&](size_t j) {
      double sum = static_cast<const Real*>(base)[j];
      for (uint32_t m = 0; m < count; ++m)
        sum += coefficients[m] * static_cast<const Real*>(vectors[m])[j];
      result[j] = static_cast<Real>(sum);
    });
  }

  static void copy(void* context, void* dst, const void* src) {
    const MockSystem& s = self(context);
    for (size_t j = 0; j < 3 * size_t{s.stride_}; ++j)
      static_cast<Real*>(dst)[j] = static_cast<const Real*>(src)[j];
  }

  static const void* get_extension(void* context, const char* id) {
    const MockSystem& s = self(context);
    return s.extensions && id != nullptr ? s.extensions(id) : nullptr;
  }

  static void* alloc(void* context) {
    MockSystem& s = self(context);
    return s.allocation_allowed ? s.new_vector() : nullptr;
  }

  uint32_t n_;
  uint32_t stride_;
  ForceLaw<Real> law_;
  std::vector<std::unique_ptr<Real, Free>> buffers_;
  Real* x_;
  Real* v_;
  Real* stage_x_;
  Real* stage_v_;
  std::vector<Real*> stage_accelerations_;
  Real* inverse_mass_;
  std::vector<clothlab_range> active_;
  clothlab_system raw_;
};

}  // namespace clothlab::test
