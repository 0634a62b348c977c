// Faulty: linearly implicit Euler with a sign error in its Jacobian term: the system matrix
// is I + h^2 J_x - h J_v (the author took K as -da/dx, so c_x = +h^2), not I - h^2 J_x - h J_v.
// It is still a consistent first-order method and declares no unconditional stability, so
// the order, rest and grid checks pass; on the default sheet at the default dt its stiff modes
// (h w > 1/sqrt(2)) grow every step. stability.default-sheet catches it. It offers float64 only:
// in float32 the 64 x 48 grid's 20 steps overflow at step 19 or 20 depending on the build's
// rounding, and lifecycle.grid-64x48-f32 would catch it on some builds and not on others.
#include <array>
#include <clothlab/sdk.hpp>

#include "edited_library.hpp"

struct FlipsTheStiffnessSign {
  static constexpr const char* id = "flips-the-stiffness-sign";
  static constexpr const char* name =
      "Linearly implicit Euler with the stiffness term's sign flipped";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* description = "faulty: (I + h^2 J_x - h J_v) dv = h (a + h J_x v)";
  static constexpr uint32_t order = 1;
  static constexpr uint32_t evals_per_step = 1;
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 0> params{};
  // A loose solve, as a game's would be: kept cheap, so that the checks it should pass do not
  // time out on a shared machine.
  static constexpr double tolerance = 1e-6;
  static constexpr long max_iterations = 25;

  explicit FlipsTheStiffnessSign(const clothlab::sdk::Params&) {}

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    system.jacobian().reserve();
    for (void*& vector : vectors_) vector = system.alloc_vector();
  }

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double h) {
    if (h == 0.0) return;
    Real* const a = static_cast<Real*>(vectors_[0]);
    Real* const b = static_cast<Real*>(vectors_[1]);
    Real* const dv = static_cast<Real*>(vectors_[2]);
    Real* const r = static_cast<Real*>(vectors_[3]);
    Real* const p = static_cast<Real*>(vectors_[4]);
    Real* const ap = static_cast<Real*>(vectors_[5]);
    const clothlab::sdk::Jacobian<Real> jacobian = system.jacobian();
    const clothlab::sdk::Reductions<Real> reductions = system.reductions();
    Real* const x = system.x();
    Real* const v = system.v();

    system.acceleration(t, x, v, a);
    jacobian.apply(t, x, v, h * h, 0.0, v, b);   // b = h^2 J_x v
    system.template lincomb<1>(b, b, {h}, {a});  // b = h a + h^2 J_x v
    system.template lincomb<1>(dv, dv, {-1.0}, {dv});
    system.copy(r, b);
    system.copy(p, b);
    const double target = tolerance * tolerance * reductions.dot(b, b);
    double rr = reductions.dot(r, r);
    // CG on (I + h^2 J_x - h J_v) dv = b; the fault is the sign of h^2 below. What CG has after
    // its cap is taken as it is.
    for (long iterations = 0; rr > target && iterations < max_iterations; ++iterations) {
      jacobian.apply(t, x, v, -h * h, h, p, ap);
      system.template lincomb<1>(ap, p, {-1.0}, {ap});
      const double alpha = rr / reductions.dot(p, ap);
      system.axpy(dv, alpha, p);
      system.axpy(r, -alpha, ap);
      const double next = reductions.dot(r, r);
      system.template lincomb<1>(p, r, {next / rr}, {p});
      rr = next;
    }
    system.axpy(v, 1.0, dv);
    system.axpy(x, h, v);
  }

 private:
  std::array<void*, 6> vectors_{};  // a, b, dv, r, p, A p: host-owned
};

extern "C" CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  return clothlab::faulty::edited_library<FlipsTheStiffnessSign>(
      "faulty-flips-the-stiffness-sign",
      [](clothlab_integrator& integrator) { integrator.precisions = 1u << CLOTHLAB_FLOAT64; });
}
