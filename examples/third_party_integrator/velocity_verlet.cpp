// Velocity Verlet (kick-drift-kick), a method the built-ins lack, written as a third-party
// plugin against the installed SDK only.
//
//   v_half = v_n + dt/2 a(x_n, v_n)
//   x_n+1  = x_n + dt v_half
//   v_n+1  = v_half + dt/2 a(x_n+1, v_pred),   v_pred = v_half + dt/2 a(x_n, v_n)
//
// Without velocity-dependent forces this is the classic symplectic, second-order method.
// With damping, evaluating the last kick at v_half would drop it to first order (the
// error dt/2 * da/dv * (v_n+1 - v_half) is O(dt^2) per step); the predicted velocity
// v_pred = v_n + dt a_n is within O(dt^2) of v_n+1, so the method stays second order.
// Two force evaluations per step; no history, so the host may change the state freely.
#include <array>
#include <clothlab/sdk.hpp>

namespace example {

struct VelocityVerlet {
  static constexpr const char* id = "velocity-verlet";
  static constexpr const char* name = "Velocity Verlet (kick-drift-kick)";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Kick-drift-kick velocity Verlet with a predicted velocity for damping; second order, "
      "two force evaluations";
  static constexpr uint32_t order = 2;
  static constexpr uint32_t evals_per_step = 2;
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 0> params{};

  explicit VelocityVerlet(const clothlab::sdk::Params&) {}

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    acceleration_ = system.alloc_vector();
    predicted_velocity_ = system.alloc_vector();
  }

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    Real* a = static_cast<Real*>(acceleration_);
    Real* v_pred = static_cast<Real*>(predicted_velocity_);
    Real* x = system.x();
    Real* v = system.v();
    system.acceleration(t, x, v, a);
    system.axpy(v, 0.5 * dt, a);  // kick: v = v_half
    system.axpy(x, dt, v);        // drift
    system.copy(v_pred, v);       // pinned entries too: damping reads their velocities
    system.axpy(v_pred, 0.5 * dt, a);
    system.acceleration(t + dt, x, v_pred, a);
    system.axpy(v, 0.5 * dt, a);  // kick
  }

  void* acceleration_ = nullptr;
  void* predicted_velocity_ = nullptr;
};

}  // namespace example

CLOTHLAB_PLUGIN_ENTRY("example-velocity-verlet", "1.0.0",
                      clothlab::sdk::integrators<example::VelocityVerlet>,
                      clothlab::sdk::scenarios<>)
