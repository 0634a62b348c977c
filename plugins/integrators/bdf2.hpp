// BDF2, the two-step backward differentiation formula, on (x, v):
//   x1 = a1 x0 + a2 x_1 + b h v1,   v1 = a1 v0 + a2 v_1 + b h a(t + h, x1, v1),
// with x_1, v_1 the state a step before x0, v0. For the step ratio w = h / h_previous,
//   a1 = (1 + w)^2 / (1 + 2 w),   a2 = -w^2 / (1 + 2 w),   b = (1 + w) / (1 + 2 w)
// (4/3, -1/3, 2/3 at a constant step), exact for quadratics in t: second order. With
// x^ = a1 x0 + a2 x_1, v^ = a1 v0 + a2 v_1 and k = b h the step is backward Euler's equation
//   v1 = v^ + dv,   x1 = x^ + k v1,   dv = k a(t + h, x1, v1)
// from (x^, v^) with the step k, so the solve is implicit_euler's (implicit_step_solver.hpp).
// Its first Newton step starts from the prediction (x^ + k v^, v^): there the matrix (the
// definite one by default, not the exact Jacobian) multiplies only the correction, so one step
// keeps second order (its error is k times the linearisation's O(k^2)); more converge to BDF2
// proper. w = 0 gives (1, 0, 1): backward Euler,
// which starts the method after `prepare` and wherever the step grows by more than 1 + sqrt(2)
// (beyond which variable-step BDF2 is not zero-stable). A- and L-stable like backward Euler,
// its numerical damping of a mode of frequency omega falls as (omega h)^4 per step, not
// (omega h)^2 (docs/physics.md).
//
// The pinned particles take the same combination (the host's vector operations act on the
// active ones only), and the attached ones are then set to their targets at t + h: the solve
// holds every pinned particle where x^ has it (the Jacobian products ignore pinned entries), so
// that is where the springs to a moving attachment must see it.
#pragma once

#include <clothlab/ext/integrator_traits.h>
#include <clothlab/ext/solver_statistics.h>

#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstddef>
#include <utility>

#include "implicit_step_solver.hpp"
#include "scratch_vectors.hpp"

namespace clothlab::builtin {

// The weights of a step: x1 = previous x0 + before x_1 + derivative h v1 (and v alike).
struct StepWeights {
  double previous, before, derivative;
};

// BDF2's weights for the step ratio w = h / h_previous; w = 0: backward Euler's.
constexpr StepWeights bdf2_weights(double step_ratio) {
  const double w = step_ratio;
  return {(1.0 + w) * (1.0 + w) / (1.0 + 2.0 * w), -w * w / (1.0 + 2.0 * w),
          (1.0 + w) / (1.0 + 2.0 * w)};
}

// How a particle the contacts moved goes on: its history with the contact's jump added to it
// (bdf2), or restarted as if it had moved at its new velocity for a step (a mutant: it drops
// the forces' share the history carries).
enum class ContactHistory { kJumpAdded, kRestarted };

// The method over its weights and contact history, so that a mutant with other ones is the same
// code (tests/conformance/faulty).
template <StepWeights (*weights_of)(double),
          ContactHistory contact_history = ContactHistory::kJumpAdded>
struct MultistepImplicit {
  static constexpr const char* id = "bdf2";
  static constexpr const char* name = "BDF2 (second-order backward differentiation)";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Two-step backward differentiation formula started by backward Euler, on implicit_euler's "
      "Newton and preconditioned CG solver; second order, unconditionally stable";
  static constexpr uint32_t order = 2;
  static constexpr uint32_t evals_per_step = 1;  // one more per Newton step beyond the first
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 10> params = implicit_step_solver_params(
      "Newton steps per time step: 1 = linearised about the extrapolated state, more converge "
      "to BDF2 on the nonlinear springs");
  static constexpr clothlab_integrator_traits traits = implicit_step_solver_traits;

  explicit MultistepImplicit(const sdk::Params& values) : solver_(values) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    solver_.prepare(system);
    history_.allocate(system);
    previous_h_ = 0.0;
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double h) {
    solver_.begin_step();
    if (h == 0.0) return;
    const auto [x_start, v_start, x_before, v_before] = history_.bind(system);
    // Cleared until the step completes: a step that throws leaves no history to go on from.
    const double previous_h = std::exchange(previous_h_, 0.0);
    const double ratio = previous_h > 0.0 ? h / previous_h : 0.0;
    const StepWeights w = weights_of(ratio <= kLargestStepRatio ? ratio : 0.0);
    Real* x = system.x();
    Real* v = system.v();
    combine(system, x_start, w, x, x_before);
    combine(system, v_start, w, v, v_before);
    system.copy(x_before, x);
    system.copy(v_before, v);
    // The solve holds the attached particles at x^ (the products ignore pinned entries): put
    // them where they are at the step's end.
    system.move_attachments(t + h, x_start, v_start);

    const double k = w.derivative * h;
    const Real* dv =
        solver_.solve(system, t + h, t + h, k, x_start, v_start, FirstNewtonStep::kAtPrediction);
    system.template lincomb<1>(v, v_start, {1.0}, {dv});
    system.template lincomb<1>(x, x_start, {k}, {v});
    // x = x^ + k v moved only the free particles.
    system.move_attachments(t + h);
    // The state before the contacts, to tell what they changed.
    system.copy(x_start, x);
    system.copy(v_start, v);
    system.resolve_contacts(t + h);
    carry_contacts_into_history(system, h, x_start, v_start, x_before, v_before);
    previous_h_ = h;
  }

  void last_step_statistics(clothlab_solver_step_statistics& out) const {
    solver_.last_step_statistics(out);
  }

 private:
  // Variable-step BDF2 is zero-stable for step ratios below 1 + sqrt(2).
  static constexpr double kLargestStepRatio = 2.414;

  // out = previous weight x now + before weight x before, on every particle: the host's
  // combination on the active ones, the pinned ones here.
  template <class Real>
  static void combine(const sdk::System<Real>& system, Real* out, const StepWeights& w,
                      const Real* now, const Real* before) {
    system.template lincomb<2>(out, now, {w.previous - 1.0, w.before}, {now, before});
    const std::size_t stride = system.stride();
    uint32_t pinned_begin = 0;
    const auto combine_pinned = [&](uint32_t end) {
      for (std::size_t axis = 0; axis < 3; ++axis)
        for (std::size_t i = axis * stride + pinned_begin; i < axis * stride + end; ++i)
          out[i] = static_cast<Real>(w.previous * now[i] + w.before * before[i]);
    };
    for (const clothlab_range& range : system.active()) {
      combine_pinned(range.begin);
      pinned_begin = range.end;
    }
    combine_pinned(system.particle_count());
  }

  // A contact changes a particle's position and velocity at once. Combined with the history
  // from before it, BDF2 would carry the jump on (a blade's push overshot by a third: energy no
  // body gave). Restarted from the new state alone, it would lose the third of each step's
  // velocity change that the history carries: a particle resting on a body then meets it a third
  // slower each step, and friction, bounded by that normal velocity, drags it at two thirds of
  // friction x g. So the history of each particle the contacts moved takes the jump as if it had
  // always been there: the velocity jump added at both points, the position jump carried back a
  // step at the velocity jump. Its slope stays the forces', and the jump has none.
  template <class Real>
  static void carry_contacts_into_history(const sdk::System<Real>& system, double h,
                                          const Real* x_free, const Real* v_free, Real* x_before,
                                          Real* v_before) {
    const std::size_t stride = system.stride();
    const Real* x = system.x();
    const Real* v = system.v();
    for (const clothlab_range& range : system.active())
      for (std::size_t i = range.begin; i < range.end; ++i) {
        bool moved = false;
        for (std::size_t axis = 0; axis < 3; ++axis) {
          const std::size_t k = axis * stride + i;
          moved = moved || x[k] != x_free[k] || v[k] != v_free[k];
        }
        if (!moved) continue;
        for (std::size_t axis = 0; axis < 3; ++axis) {
          const std::size_t k = axis * stride + i;
          if constexpr (contact_history == ContactHistory::kRestarted) {
            x_before[k] = static_cast<Real>(x[k] - h * v[k]);
            v_before[k] = v[k];
          } else {
            const double jump = static_cast<double>(v[k]) - v_free[k];
            x_before[k] = static_cast<Real>(x_before[k] + (x[k] - x_free[k]) - h * jump);
            v_before[k] = static_cast<Real>(v_before[k] + jump);
          }
        }
      }
  }

  ImplicitStepSolver solver_;
  // x^ and v^ of the step, then the state a step back (x_1, v_1).
  ScratchVectors<4> history_;
  double previous_h_ = 0.0;  // the last step's h; 0: no step to go on from
};

}  // namespace clothlab::builtin
