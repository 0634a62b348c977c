// One step of an explicit Runge-Kutta-Nystrom scheme with its coefficients scaled by the
// step size, in the precision of the state (see clothlab_rkn_scheme in plugin.h):
//   X_s = x + x_velocity[s] v + sum_k x_stage[s][k] A_k,  V_s = v + sum_k v_stage[s][k] A_k,
//   A_s = a(X_s, V_s),   x += h v + sum_k x_weights[k] A_k,   v += sum_k v_weights[k] A_k.
#pragma once

#include <clothlab/plugin.h>

#include <cstdint>

namespace clothlab::detail {

template <class Real>
struct RknStep {
  static constexpr uint32_t kMaxStages = CLOTHLAB_RKN_MAX_STAGES;
  uint32_t stages = 0;
  Real h = 0;
  Real x_velocity[kMaxStages] = {};           // h alpha_s
  Real x_stage[kMaxStages][kMaxStages] = {};  // h^2 times the scheme's x coupling
  Real v_stage[kMaxStages][kMaxStages] = {};  // h times its v coupling
  Real x_weights[kMaxStages] = {};            // h^2 times its x weights
  Real v_weights[kMaxStages] = {};            // h times its v weights
};

}  // namespace clothlab::detail
