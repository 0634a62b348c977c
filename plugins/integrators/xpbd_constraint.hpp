// XPBD's constraint law: one spring as a compliant distance constraint with Rayleigh damping
// (Macklin, Mueller, Chentanez 2016, "XPBD: position-based simulation of compliant constrained
// dynamics", eq. 26), projected on the positions x + dx of a substep of length h.
//
// One spring k joining i and j at positions p = x + dx, C = |p_i - p_j| - rest,
// n = (p_i - p_j) / |p_i - p_j|:
// compliance alpha = 1 / ks and Rayleigh damping beta = kd (the spring's damping force
// -kd (n . (v_i - v_j)) n is -beta grad C dC/dt), so with alpha~ = alpha / h^2,
// beta~ = h^2 beta and gamma = alpha~ beta~ / h = alpha beta / h the paper's eq. 26 reads
//   dlambda = (-C - alpha~ lambda - gamma n.(dx_i - dx_j)) / ((1 + gamma)(w_i + w_j) + alpha~)
// with dx the substep's displacement. Multiplied through by ks h^2 it needs no division by ks (a
// spring with ks = 0 is a pure damper) and its denominator is >= 1:
//   dlambda = (-ks h^2 C - lambda - kd h n.(dx_i - dx_j)) / ((ks h^2 + kd h)(w_i + w_j) + 1)
//   dx_i += w_i dlambda n,  dx_j -= w_j dlambda n.
// lambda accumulates over the iterations of a substep and is reset once per substep, never
// per iteration: resetting it per iteration would make the stiffness grow with the iteration
// count (the peer bug newton#2933).
//
// This is the law one spring at a time (the general sweep); the grid's row kernels
// (xpbd_row_kernel.hpp) compute the same update a grid row at a time.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace clothlab::builtin {

// One spring as the projection reads it, stored colour by colour.
template <class Real>
struct Constraint {
  uint32_t first, second;
  Real rest, ks, kd;
  Real first_weight, second_weight;  // inverse masses; 0 for a pinned end
};

// lambda is reset at the substep's first iteration (`fresh`), then accumulates.
template <class Real>
inline void project_constraint(const Constraint<Real>& spring, Real& lambda, bool fresh,
                               const Real* x, Real* displacement, std::size_t stride, Real h,
                               Real h_squared) {
  std::array<Real, 3> d, moved;
  for (std::size_t c = 0; c < 3; ++c) {
    const std::size_t i = c * stride + spring.first, j = c * stride + spring.second;
    moved[c] = displacement[i] - displacement[j];
    d[c] = (x[i] - x[j]) + moved[c];
  }
  const Real accumulated = fresh ? Real(0) : lambda;
  lambda = accumulated;
  const Real length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(length > 0)) return;  // coincident ends: no direction to push along
  const Real inverse_length = 1 / length;
  const Real stiffness = spring.ks * h_squared, damping = spring.kd * h;
  const Real closing = (d[0] * moved[0] + d[1] * moved[1] + d[2] * moved[2]) * inverse_length;
  const Real delta = (-stiffness * (length - spring.rest) - lambda - damping * closing) /
                     ((stiffness + damping) * (spring.first_weight + spring.second_weight) + 1);
  lambda += delta;
  const Real push_first = spring.first_weight * delta * inverse_length;
  const Real push_second = spring.second_weight * delta * inverse_length;
  for (std::size_t c = 0; c < 3; ++c) {
    const std::size_t i = c * stride + spring.first, j = c * stride + spring.second;
    if (spring.first_weight != 0) {
      displacement[i] += push_first * d[c];
    }
    if (spring.second_weight != 0) {
      displacement[j] -= push_second * d[c];
    }
  }
}

}  // namespace clothlab::builtin
