// Objective stability verdict of a run, checked every few steps.
//
// Checks, in this order, at each check step:
//  1. non-finite state (any NaN/inf in x or v);
//  2. stretch: the longest spring over its rest length beyond stretch_limit (default 2);
//  3. energy: total energy (kinetic + spring + gravity; gravity is a potential, so it is inside)
//     above E0 + W_wind + W_attachments + W_contacts + margin, where
//       W_wind bounds the work the wind can have done. A triangle's wind force has magnitude at
//         most S A (S = wind strength, A = its area), so the power on the cloth is at most
//         P = S A_cloth v_max. A_cloth is at most the rest area times max_stretch^2 (every grid
//         triangle's edges are springs), v_max is the fastest particle. Both come from the same
//         pass as the other checks, so the bound costs one sweep of the velocities. Between checks
//         the bound is integrated as dt_interval * max(P_before, P_after) * wind_work_safety (the
//         speed may peak between samples); this over-estimates the true work by the cos factors
//         and by v_max against mean speeds, which is fine: a divergence grows without limit and
//         crosses any such bound, while a calm run stays far below it. The air's drag and lift
//         (clothlab/ext/air.h) add at most rho (C_d + C_l / 2) (|w| + v_max)^2 / 2 to S.
//       W_attachments is the work the moving attachments have done on the cloth, summed over
//         every observed step as the impulse the pins (attached or held still) gave the free
//         cloth times their displacement over the step, over dt. Where gravity is the only
//         other force on the cloth (no wind, air or colliders, and an integrator whose own
//         forces come in pairs: MonitorOptions::momentum_measures_pins), the impulse is the free
//         particles' change of momentum less gravity's: measured, so whatever pulled inside the
//         step (springs, constraints, an integrator's tethers) is counted, at every step size.
//         It moves with the pins' mean displacement; where pins move differently, each pin's
//         share of it relative to that mean, and the whole impulse where it is not measured,
//         is sampled from the springs at the pins (trapezoid rule over the step). A dragged
//         cape gains the energy its shoulders give it, and loses it again when they stop. An
//         unstable method's internal forces still come in pairs: the energy it adds carries no
//         momentum, so none of it is credited as work;
//       W_contacts is the energy the contact resolution has added (Cloth::contact_work: a
//         moving collider pushing the cloth);
//       margin = energy_margin * scale, scale = M |g| diagonal + |E0 parts|: the energy the
//         whole cloth would gain by falling its own diagonal, a size that damped dynamics never
//         approach in error but divergent ones overshoot within a few steps.
// The first failure is kept: later observations do not change the verdict.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace clothlab::analysis {

struct MonitorOptions {
  uint64_t check_interval = 10;  // steps between checks; 1 checks every step
  // Times rest length. Not 2: the default 50x50 sheet hangs its whole weight on two
  // corner particles and settles at ~3.6x rest in equilibrium (ks is per spring, so the
  // corner load does not spread); 5x separates that from a blow-up, which grows without
  // bound. Set 2 (stability.max_stretch) to flag super-elastic cloth as well.
  double stretch_limit = 5.0;
  double energy_margin = 1.0;  // times the energy scale (see above)
  double wind_work_safety = 2.0;
  // Whether the attachments' pull may be measured from the free particles' momentum: false
  // for an integrator that declares CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST.
  bool momentum_measures_pins = true;
};

enum class StabilityCheck { None, NonFinite, Stretch, Energy };
const char* to_string(StabilityCheck check);

struct Verdict {
  bool stable = true;
  StabilityCheck fired = StabilityCheck::None;
  uint64_t step = 0;   // step at which the check fired
  double time = 0.0;   // simulated time then, s
  double value = 0.0;  // what was measured (stretch ratio or energy in J)
  double limit = 0.0;  // what it was compared against
  std::string reason;  // one line, empty while stable
};

class StabilityMonitor {
 public:
  // Takes the initial energy from the cloth's current state (time t0), and from its colliders,
  // wind and air then how the attachments' pull is counted for the whole run (set the colliders
  // first). Throws std::invalid_argument for options out of range.
  StabilityMonitor(const Cloth& cloth, double t0, const MonitorOptions& options = {});

  // Checks when step is a multiple of check_interval; otherwise returns the current verdict.
  const Verdict& observe(const Cloth& cloth, uint64_t step, double t);
  // Checks now, whatever the interval (e.g. after the last step).
  const Verdict& check(const Cloth& cloth, uint64_t step, double t);

  const Verdict& verdict() const { return verdict_; }
  double initial_energy() const { return initial_energy_; }
  double energy_scale() const { return energy_scale_; }
  double wind_work_bound() const { return wind_work_; }
  double attachment_work() const { return attachment_work_; }
  uint64_t checks() const { return checks_; }

 private:
  double wind_power_bound(const Cloth& cloth, double stretch);
  void add_attachment_work(const Cloth& cloth, double t);
  void fail(StabilityCheck check, uint64_t step, double t, double value, double limit,
            std::string reason);

  MonitorOptions options_;
  double initial_energy_ = 0.0;
  double energy_scale_ = 0.0;
  double rest_area_ = 0.0;
  double wind_work_ = 0.0;
  double last_time_ = 0.0;
  double last_power_ = 0.0;
  double attachment_work_ = 0.0;
  Cloth::PinLoads pins_before_, pins_now_;  // pins_before_ at attachment_time_
  bool measures_momentum_ = false;          // the pins' impulse from the free cloth's momentum
  Cloth::Momentum momentum_before_;         // at attachment_time_, where measured
  double attachment_time_ = 0.0;
  uint64_t checks_ = 0;
  std::vector<double> velocities_;  // reused between checks
  Verdict verdict_;
};

}  // namespace clothlab::analysis
