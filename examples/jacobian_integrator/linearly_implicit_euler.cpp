// Linearly implicit (Baraff-Witkin) Euler, a third-party plugin on the host's jacobian,
// reductions extensions (ABI 1.2) and the installed SDK only. One Newton step of backward
// Euler, linearised at the current state:
//
//   (I - h J_v - h^2 J_x) dv = h (a + h J_x v),   v += dv,   x += h v,
//
// with J_x = da/dx, J_v = da/dv from clothlab.jacobian/1 (matrix-free: one apply per CG
// iteration gives h^2 J_x u + h J_v u). The system is solved by conjugate gradients to a
// relative residual of 1e-10; a step that does not get there is an error, never silent.
// Pinned particles: the Jacobian's pinned rows are zero and the vector helpers touch only
// active particles, so dv stays 0 there. One force evaluation per step; first order.
#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <string>

namespace example {

struct LinearlyImplicitEuler {
  static constexpr const char* id = "linearly-implicit-euler";
  static constexpr const char* name = "Linearly implicit Euler (Baraff-Witkin)";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "One Newton step of backward Euler on the host's analytic Jacobian, solved by CG; "
      "first order, one force evaluation";
  static constexpr uint32_t order = 1;
  static constexpr uint32_t evals_per_step = 1;
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 0> params{};
  // CG stops at this residual relative to the right-hand side. In exact arithmetic CG ends
  // within the system's dimension 3 n; the cap allows rounding a few times that.
  static constexpr double tolerance = 1e-10;

  explicit LinearlyImplicitEuler(const clothlab::sdk::Params&) {}

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    system.jacobian().reserve();  // may allocate: here, never in step
    for (void*& vector : vectors_) vector = system.alloc_vector();
  }

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double h) {
    if (vectors_[0] == nullptr)
      throw clothlab::sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, "step before prepare");
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
    // A u = u - (h^2 J_x + h J_v) u, into ap.
    const auto apply_system = [&](const Real* u) {
      jacobian.apply(t, x, v, h * h, h, u, ap);
      system.template lincomb<1>(ap, u, {-1.0}, {ap});
    };

    system.template lincomb<1>(dv, dv, {-1.0}, {dv});  // dv = 0
    system.copy(r, b);
    system.copy(p, b);
    const double target = tolerance * tolerance * reductions.dot(b, b);
    const long max_iterations = 4 * 3 * static_cast<long>(system.particle_count()) + 10;
    double rr = reductions.dot(r, r);
    long iterations = 0;
    for (; rr > target && iterations < max_iterations; ++iterations) {
      apply_system(p);
      const double alpha = rr / reductions.dot(p, ap);
      system.axpy(dv, alpha, p);
      system.axpy(r, -alpha, ap);
      const double next = reductions.dot(r, r);
      system.template lincomb<1>(p, r, {next / rr}, {p});
      rr = next;
    }
    if (!(rr <= target))
      throw clothlab::sdk::Error(
          CLOTHLAB_ERROR_NUMERICAL,
          "CG did not reach the tolerance in " + std::to_string(iterations) + " iterations");
    system.axpy(v, 1.0, dv);
    system.axpy(x, h, v);
  }

 private:
  std::array<void*, 6> vectors_{};  // a, b, dv, r, p, A p: host-owned
};

}  // namespace example

CLOTHLAB_PLUGIN_ENTRY("example-linearly-implicit-euler", "1.0.0",
                      clothlab::sdk::integrators<example::LinearlyImplicitEuler>,
                      clothlab::sdk::scenarios<>)
