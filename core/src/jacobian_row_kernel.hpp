// The spring Jacobian's product along one grid row for one stencil: for each spring from
// column c of the row to its partner, p[c] = M (du) with du = u_partner - u_own (pinned
// entries of u count as 0) and M the spring's block of J (spring_jacobian.hpp). Each
// spring once, from the state; the caller moves p onto both ends by shifted adds.
//
// The formula is written once over a lane type (a scalar Real inside `omp simd`, or a block
// of SIMD lanes of float, float_lanes.hpp), in raw dot products of d = x_partner - x_own so that a
// zero-length spring (inverse length 0) gives exactly 0 without a branch:
//   q = 1/l^2, a = (1/l) (ks (l - l0) + kd (d.dv)/l), b = (1/l) (ks l0 - kd (d.dv)/l),
//   p = c_x a du + d [c_x q (b (d.du) + kd (dv.du - q (d.dv)(d.du))) + c_v kd q (d.du)].
// The definite form (Baraff & Witkin) keeps ks n n^T and the transverse ks (1 - l0/l) only
// where it is >= 0 (a compressed spring has none), and no x-derivative of the damping:
//   p = c_x t du + d q (d.du) (c_x (ks - t) + c_v kd),   t = max(0, ks (1 - l0/l)),
// two coefficients per spring that the state fixes (definite_coefficients).
#pragma once

#include <cstddef>
#include <type_traits>

#include "inverse_sqrt.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

enum class JacobianForm { kExact, kDefinite };

// Inputs are vectors of the system (component k of column c at [c + k * stride], already
// offset to the row; partner pointers shifted so that column c lines up with the partner).
// Stored: p holds its components `span` apart. Direct (a stencil reaching another row, both
// ends wanted): own[c] += p and partner[c] -= p straight into the product, a vector of the
// system like the inputs, with the same rounding as adding the stored p.
template <class Real>
struct JacobianRow {
  const Real* x;
  const Real* x_partner;
  const Real* v;  // read only when damped, by the exact form
  const Real* v_partner;
  const Real* u;
  const Real* u_partner;
  const Real* inverse_mass;  // of the row's particles, and of the partners
  const Real* inverse_mass_partner;
  Real* p;
  Real* own;
  Real* partner;
  std::size_t stride;
  std::size_t span;
  std::size_t col_begin;
  std::size_t col_end;
  Real rest, ks, kd, c_x, c_v;
};

inline float lane_max(float a, float b) { return a > b ? a : b; }
inline double lane_max(double a, double b) { return a > b ? a : b; }
#if defined(CLOTHLAB_FLOAT_LANES)
inline Floats lane_max(Floats a, Floats b) { return select(greater(a, b), a, b); }
#endif

// `value` where `test` > 0, else 0.
inline float lane_where_positive(float test, float value) { return test > 0 ? value : 0.0f; }
inline double lane_where_positive(double test, double value) { return test > 0 ? value : 0.0; }
#if defined(CLOTHLAB_FLOAT_LANES)
inline Floats lane_where_positive(Floats test, Floats value) {
  return keep(greater(test, zero_floats()), value);
}
#endif

// The definite form's two coefficients of a spring, fixed by the state, from its inverse
// length (0: no spring, or zero length; both coefficients are then 0):
// p = across du + (along (d.du)) d with across = c_x t, t = max(0, ks - (ks l0) / l) (clamped
// at 0 for a compressed spring) and along = (along_scale - across) / l^2, along_scale =
// c_x ks + c_v kd (kd 0 without damping). The row kernel (definite_row_kernel.hpp) stores 1/l.
template <class Lane>
inline void definite_coefficients(Lane inverse_length, Lane ks, Lane ks_rest, Lane along_scale,
                                  Lane c_x, Lane zero, Lane& across, Lane& along) {
  const Lane transverse =
      lane_where_positive(inverse_length, lane_max(ks - ks_rest * inverse_length, zero));
  across = c_x * transverse;
  along = inverse_length * inverse_length * (along_scale - across);
}

template <JacobianForm Form, bool Damped, class Lane>
inline void spring_product(const Lane (&d)[3], const Lane (&dv)[3], const Lane (&du)[3], Lane rest,
                           Lane ks, Lane kd, Lane c_x, Lane c_v, Lane zero, Lane (&p)[3]) {
  const Lane d_du = d[0] * du[0] + d[1] * du[1] + d[2] * du[2];
  Lane across, along;
  if constexpr (Form == JacobianForm::kDefinite) {
    const Lane inverse_length = inverse_sqrt_or_zero(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    definite_coefficients(inverse_length, ks, ks * rest, c_x * ks + (Damped ? c_v * kd : zero), c_x,
                          zero, across, along);
    along = along * d_du;
  } else {
    const Lane squared = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const Lane inverse_length = inverse_sqrt_or_zero(squared);
    const Lane q = inverse_length * inverse_length;
    Lane d_dv = zero, dv_du = zero;
    if constexpr (Damped) {
      d_dv = d[0] * dv[0] + d[1] * dv[1] + d[2] * dv[2];
      dv_du = dv[0] * du[0] + dv[1] * du[1] + dv[2] * du[2];
    }
    const Lane rate = kd * d_dv * inverse_length;  // kd (n . dv)
    const Lane a = inverse_length * (ks * (squared * inverse_length - rest) + rate);
    const Lane b = inverse_length * (ks * rest - rate);
    Lane bracket = b * d_du;
    if constexpr (Damped) bracket = bracket + kd * (dv_du - q * d_dv * d_du);
    across = c_x * a;
    along = q * (c_x * bracket + (Damped ? c_v * kd * d_du : zero));
  }
  for (int k = 0; k < 3; ++k) p[k] = across * du[k] + along * d[k];
}

template <class Real, JacobianForm Form, bool Damped, bool Direct>
inline void jacobian_row_portable(const JacobianRow<Real>& row) {
  const Real* __restrict x = row.x;
  const Real* __restrict xp = row.x_partner;
  const Real* __restrict v = row.v;
  const Real* __restrict vp = row.v_partner;
  const Real* __restrict u = row.u;
  const Real* __restrict up = row.u_partner;
  const Real* __restrict m = row.inverse_mass;
  const Real* __restrict mp = row.inverse_mass_partner;
  Real* __restrict p = row.p;
  Real* __restrict own = row.own;
  Real* __restrict partner = row.partner;
  const std::size_t stride = row.stride, span = row.span;
#pragma omp simd
  for (std::size_t c = row.col_begin; c < row.col_end; ++c) {
    Real d[3], dv[3] = {0, 0, 0}, du[3], out[3];
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t e = c + k * stride;
      d[k] = xp[e] - x[e];
      if constexpr (Damped && Form == JacobianForm::kExact) dv[k] = vp[e] - v[e];
      du[k] = (mp[c] > Real(0) ? up[e] : Real(0)) - (m[c] > Real(0) ? u[e] : Real(0));
    }
    spring_product<Form, Damped>(d, dv, du, row.rest, row.ks, row.kd, row.c_x, row.c_v, Real(0),
                                 out);
    for (std::size_t k = 0; k < 3; ++k) {
      if constexpr (Direct) {
        own[c + k * stride] += out[k];
        partner[c + k * stride] -= out[k];
      } else {
        p[c + k * span] = out[k];
      }
    }
  }
}

#if defined(CLOTHLAB_FLOAT_LANES)
template <JacobianForm Form, bool Damped, bool Direct>
inline void jacobian_row_lanes(const JacobianRow<float>& row) {
  const Floats rest = broadcast(row.rest), ks = broadcast(row.ks), kd = broadcast(row.kd),
               c_x = broadcast(row.c_x), c_v = broadcast(row.c_v), zero = zero_floats();
  const std::size_t stride = row.stride, span = row.span;
  for_each_lane_block(row.col_begin, row.col_end, [&](std::size_t c, auto lanes) {
    const LaneMask own_active = greater(lanes.load(row.inverse_mass + c), zero);
    const LaneMask partner_active = greater(lanes.load(row.inverse_mass_partner + c), zero);
    Floats d[3], dv[3] = {zero, zero, zero}, du[3], out[3];
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t e = c + k * stride;
      d[k] = lanes.load(row.x_partner + e) - lanes.load(row.x + e);
      if constexpr (Damped && Form == JacobianForm::kExact)
        dv[k] = lanes.load(row.v_partner + e) - lanes.load(row.v + e);
      du[k] = keep(partner_active, lanes.load(row.u_partner + e)) -
              keep(own_active, lanes.load(row.u + e));
    }
    spring_product<Form, Damped>(d, dv, du, rest, ks, kd, c_x, c_v, zero, out);
    for (std::size_t k = 0; k < 3; ++k) {
      if constexpr (Direct) {
        const std::size_t e = c + k * stride;
        lanes.store(row.own + e, lanes.load(row.own + e) + out[k]);
        lanes.store(row.partner + e, lanes.load(row.partner + e) - out[k]);
      } else {
        lanes.store(row.p + c + k * span, out[k]);
      }
    }
  });
}
#endif

template <class Real, JacobianForm Form, bool Damped, bool Direct>
inline void jacobian_row(const JacobianRow<Real>& row) {
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    jacobian_row_lanes<Form, Damped, Direct>(row);
    return;
  }
#endif
  jacobian_row_portable<Real, Form, Damped, Direct>(row);
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
