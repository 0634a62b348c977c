// One vertex block of vertex block descent (Chen, Macklin et al. 2024): a Newton step on the
// incremental potential in the displacement d_i = x_i - x0_i of one particle, the others held.
//
// With d the step's displacements, y_i = h v_i + h^2 a_ext,i the inertial target, e = x_i - x_j
// = (x0_i - x0_j) + (d_i - d_j), l = |e| and n = e / l for each spring (i, j):
//   E(d_i) = m_i / (2 h^2) |d_i - y_i|^2 + sum_s ks/2 (l - l0)^2 + D_s,
// where D_s = kd / (2 h) (n . (d_i - d_j))^2 is the spring's damping, -kd n n^T (v_i - v_j)
// with v = d / h, as a dissipation potential with n held (so its gradient is the force).
// Gradient and Hessian of the block:
//   g = m_i / h^2 (d_i - y_i) + sum_s (ks (l - l0) + kd / h n.(d_i - d_j)) n
//   H = m_i / h^2 I + sum_s (ks + kd / h) n n^T + ks max(0, 1 - l0 / l) (I - n n^T)
// The clamp drops a compressed spring's transverse term -ks (l0 / l - 1) (I - n n^T), the only
// indefinite part, so H is positive definite and -H^-1 g a descent direction. A fixed point
// has g = 0 at every particle: m (v - v0) / h = f_springs(x, v) + m a_ext, backward Euler with
// the external forces taken at x0.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

namespace clothlab::builtin {

// A spring as seen from one of its ends.
template <class Real>
struct SpringEnd {
  uint32_t other;
  Real rest, ks, kd;
};

// The step's arrays, particle-major (x, y, z of particle i at 3 i).
template <class Real>
struct BlockArrays {
  const Real* start;     // x0
  const Real* inertial;  // y = h v0 + h^2 a_ext: the displacement inertia pulls toward
  Real* displacement;    // d, updated in place
  Real inverse_h;
  Real inverse_h_squared;
};

// H^-1 g by the adjugate, H symmetric (xx, xy, xz, yy, yz, zz) and positive definite.
template <class Real>
inline std::array<Real, 3> solve_symmetric(const std::array<Real, 6>& H,
                                           const std::array<Real, 3>& g) {
  const Real c00 = H[3] * H[5] - H[4] * H[4];
  const Real c01 = H[2] * H[4] - H[1] * H[5];
  const Real c02 = H[1] * H[4] - H[2] * H[3];
  const Real c11 = H[0] * H[5] - H[2] * H[2];
  const Real c12 = H[1] * H[2] - H[0] * H[4];
  const Real c22 = H[0] * H[3] - H[1] * H[1];
  const Real inverse_determinant = 1 / (H[0] * c00 + H[1] * c01 + H[2] * c02);
  return {(c00 * g[0] + c01 * g[1] + c02 * g[2]) * inverse_determinant,
          (c01 * g[0] + c11 * g[1] + c12 * g[2]) * inverse_determinant,
          (c02 * g[0] + c12 * g[1] + c22 * g[2]) * inverse_determinant};
}

// Moves d_i by -H^-1 g; returns the largest component of that correction.
template <class Real>
inline Real descend_block(uint32_t i, Real mass, std::span<const SpringEnd<Real>> springs,
                          const BlockArrays<Real>& a) {
  Real* d = a.displacement + 3 * std::size_t{i};
  const Real* x = a.start + 3 * std::size_t{i};
  const Real* y = a.inertial + 3 * std::size_t{i};
  const Real inertia = mass * a.inverse_h_squared;
  std::array<Real, 3> g{inertia * (d[0] - y[0]), inertia * (d[1] - y[1]), inertia * (d[2] - y[2])};
  std::array<Real, 6> H{inertia, 0, 0, inertia, 0, inertia};
  for (const SpringEnd<Real>& spring : springs) {
    const Real* d_other = a.displacement + 3 * std::size_t{spring.other};
    const Real* x_other = a.start + 3 * std::size_t{spring.other};
    std::array<Real, 3> moved, e;
    for (std::size_t k = 0; k < 3; ++k) {
      moved[k] = d[k] - d_other[k];
      e[k] = (x[k] - x_other[k]) + moved[k];
    }
    const Real squared = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
    if (!(squared > 0)) continue;  // coincident ends: no direction, no force (as the core)
    const Real inverse_length = 1 / std::sqrt(squared);
    const std::array<Real, 3> n{e[0] * inverse_length, e[1] * inverse_length,
                                e[2] * inverse_length};
    const Real damping = spring.kd * a.inverse_h;
    const Real pull = spring.ks * (squared * inverse_length - spring.rest) +
                      damping * (n[0] * moved[0] + n[1] * moved[1] + n[2] * moved[2]);
    const Real across = spring.ks * std::max(Real(0), 1 - spring.rest * inverse_length);
    const Real along = spring.ks + damping - across;
    for (std::size_t k = 0; k < 3; ++k) g[k] += pull * n[k];
    H[0] += along * n[0] * n[0] + across;
    H[1] += along * n[0] * n[1];
    H[2] += along * n[0] * n[2];
    H[3] += along * n[1] * n[1] + across;
    H[4] += along * n[1] * n[2];
    H[5] += along * n[2] * n[2] + across;
  }
  const std::array<Real, 3> step = solve_symmetric(H, g);
  Real largest = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    d[k] -= step[k];
    largest = std::max(largest, std::abs(step[k]));
  }
  return largest;
}

}  // namespace clothlab::builtin
