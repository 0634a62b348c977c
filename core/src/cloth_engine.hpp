// The cloth state in one precision (SoA, 64-byte aligned, stride a multiple of 16) and
// the force pipeline built for it once: only the spring stencils that exert force, the
// damping terms only when the integrator uses velocity forces, wind only when it blows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "aligned_buffer.hpp"
#include "engine.hpp"
#include "grid.hpp"

namespace clothlab::detail {

template <class Real>
class ClothEngine final : public Engine {
 public:
  ClothEngine(const Scene& scene, PipelineOptions options);

  const clothlab_system& system() const override { return system_; }
  int threads() const override { return threads_; }
  StageCounters& counters() override { return counters_; }

  void positions(std::vector<double>& out) const override;
  void velocities(std::vector<double>& out) const override;
  void set_state(const std::vector<double>& x, const std::vector<double>& v) override;
  bool state_is_finite() const override;
  Cloth::Energy energy() const override;
  double max_stretch() const override;

 private:
  // One spring stencil of the pipeline with its per-spring force scratch.
  struct SpringStage {
    StencilExtent extent;
    std::size_t offset = 0;
    Real rest = 0, ks = 0, kd = 0;
    bool damped = false;
    uint64_t count = 0;
    AlignedBuffer<Real> force;  // 3 components of padding_ + stride_ elements
  };
  struct Span {
    std::size_t begin, end;
  };

  Real* component(AlignedBuffer<Real>& scratch, int k);
  clothlab_status evaluate(const Real* x, const Real* v, Real* a);
  void compute_springs(const Real* x, const Real* v);
  void compute_wind(const Real* x);
  bool combine(Real* a);
  void axpy(Real* y, Real alpha, const Real* x);
  void lincomb(Real* out, const Real* base, uint32_t count, const double* coefficients,
               const void* const* vectors);
  void* alloc_vector() noexcept;

  static clothlab_status eval_callback(void* context, double t, const void* x, const void* v,
                                       void* a);
  static void axpy_callback(void* context, void* y, double alpha, const void* x);
  static void lincomb_callback(void* context, void* out, const void* base, uint32_t count,
                               const double* coefficients, const void* const* vectors);
  static void copy_callback(void* context, void* dst, const void* src);
  static void* alloc_callback(void* context);

  Scene scene_;
  std::size_t n_ = 0;
  std::size_t stride_ = 0;
  std::size_t padding_ = 0;  // zeros in front of scratch so index - offset stays inside
  int threads_ = 1;
  bool parallel_ = false;
  Real mass_ = 0;
  Real gravity_[3] = {0, 0, 0};
  Real wind_direction_[3] = {0, 0, 0};
  Real wind_strength_ = 0;

  AlignedBuffer<Real> x_, v_, inverse_mass_;
  std::vector<clothlab_range> active_;
  std::vector<Span> active_chunks_;  // active ranges cut into pieces for threads
  std::vector<Span> all_chunks_;     // [0, n) cut into pieces for threads
  uint64_t active_particles_ = 0;

  std::vector<SpringStage> stages_;
  uint64_t damped_per_eval_ = 0;
  uint64_t springs_per_eval_ = 0;
  AlignedBuffer<Real> wind_first_, wind_second_;

  std::vector<AlignedBuffer<Real>> vectors_;  // handed out by alloc_vector
  clothlab_system system_{};
  StageCounters counters_;
};

}  // namespace clothlab::detail
