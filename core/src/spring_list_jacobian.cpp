// SpringJacobian's products on the spring list (spring_jacobian.hpp): the path of any mesh, and
// of a grid forced onto the general path. Two passes, as the spring-list forces: each spring's
// M (u_j - u_i) once into its own slot, then per particle the sum of its slots in adjacency
// order. No thread writes another's particles, so the result is the same bits on any thread
// count. The definite form's M, fixed by linearise, keeps 6 coefficients per spring for the CG
// products; the other products build M per spring as the block forms do (spring_block).
#include <omp.h>

#include <algorithm>

#include "simd_namespace.hpp"
#include "spring_jacobian.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {
namespace {

constexpr std::size_t kChunk = 2048;  // springs or particles per thread work item

std::ptrdiff_t chunks_of(std::size_t items) {
  return static_cast<std::ptrdiff_t>((items + kChunk - 1) / kChunk);
}

}  // namespace

template <class Real>
template <class Block>
void SpringJacobian<Real>::list_spring_products(const Real* u, Block&& block) const {
  const std::size_t springs = topology_.spring_count();
  const uint32_t* first = topology_.first.data();
  const uint32_t* second = topology_.second.data();
  Real* slots = spring_products_.data();
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks_of(springs); ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
    const std::size_t end = std::min(springs, begin + kChunk);
    for (std::size_t s = begin; s < end; ++s) {
      const std::size_t i = first[s], j = second[s];
      const bool i_active = inverse_mass_[i] > Real(0), j_active = inverse_mass_[j] > Real(0);
      Real du[3];
      for (std::size_t k = 0; k < 3; ++k)
        du[k] =
            (j_active ? u[k * stride_ + j] : Real(0)) - (i_active ? u[k * stride_ + i] : Real(0));
      Real m[9];
      block(s, m);
      for (std::size_t r = 0; r < 3; ++r)
        slots[3 * s + r] = m[3 * r] * du[0] + m[3 * r + 1] * du[1] + m[3 * r + 2] * du[2];
    }
  }
}

template <class Real>
template <bool Shifted>
void SpringJacobian<Real>::list_gather(const Real* u, Real* out) const {
  const uint32_t* offsets = topology_.adjacency_offsets.data();
  const uint32_t* adjacent = topology_.adjacent_springs.data();
  const uint32_t* first = topology_.first.data();
  const Real* slots = spring_products_.data();
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks_of(n_); ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
    const std::size_t end = std::min(n_, begin + kChunk);
    double dot = 0.0;
    for (std::size_t i = begin; i < end; ++i) {
      const Real inverse_mass = inverse_mass_[i];
      if (inverse_mass == Real(0)) {
        for (std::size_t k = 0; k < 3; ++k) out[k * stride_ + i] = Real(0);
        continue;
      }
      Real sum[3] = {0, 0, 0};
      for (uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
        const uint32_t s = adjacent[e];
        const Real sign = first[s] == i ? Real(1) : Real(-1);
        for (std::size_t k = 0; k < 3; ++k) sum[k] += sign * slots[3 * s + k];
      }
      Real term = 0;
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t at = k * stride_ + i;
        if constexpr (Shifted) {
          out[at] = u[at] + inverse_mass * sum[k];
          term += u[at] * out[at];
        } else {
          out[at] = inverse_mass * sum[k];
        }
      }
      if constexpr (Shifted) dot += double{mass_[i] * term};
    }
    if constexpr (Shifted) row_dots_[static_cast<std::size_t>(chunk)] = dot;
  }
}

template <class Real>
template <JacobianForm Form, bool Shifted>
void SpringJacobian<Real>::list_apply(const Real* x, const Real* v, const Weights& w, const Real* u,
                                      Real* out) const {
  if constexpr (Shifted) {  // the cg-step product, at the linearisation
    const Real* coefficients = spring_definite_.data();
    list_spring_products(u, [&](std::size_t s, Real* m) {
      const Real* c = coefficients + 6 * s;
      m[0] = c[0], m[1] = c[1], m[2] = c[2];
      m[3] = c[1], m[4] = c[3], m[5] = c[4];
      m[6] = c[2], m[7] = c[4], m[8] = c[5];
    });
  } else {
    Weights form = w;
    form.definite = Form == JacobianForm::kDefinite;
    list_spring_products(u, [&](std::size_t s, Real* m) {
      double block[9];
      spring_block(x, v, static_cast<uint32_t>(s), form, block);
      for (std::size_t k = 0; k < 9; ++k) m[k] = static_cast<Real>(block[k]);
    });
  }
  list_gather<Shifted>(u, out);
}

template <class Real>
void SpringJacobian<Real>::list_linearise(const Real* x, const Real* v, double c_x,
                                          double c_v) const {
  const Weights w{c_x, c_v, damping_ && v != nullptr, true};
  const std::size_t springs = topology_.spring_count();
  Real* coefficients = spring_definite_.data();
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
  for (std::ptrdiff_t chunk = 0; chunk < chunks_of(springs); ++chunk) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
    const std::size_t end = std::min(springs, begin + kChunk);
    for (std::size_t s = begin; s < end; ++s) {
      double m[9];
      spring_block(x, v, static_cast<uint32_t>(s), w, m);
      Real* c = coefficients + 6 * s;
      c[0] = static_cast<Real>(m[0]), c[1] = static_cast<Real>(m[1]);
      c[2] = static_cast<Real>(m[2]), c[3] = static_cast<Real>(m[4]);
      c[4] = static_cast<Real>(m[5]), c[5] = static_cast<Real>(m[8]);
    }
  }
}

template void SpringJacobian<float>::list_apply<JacobianForm::kExact, false>(
    const float*, const float*, const Weights&, const float*, float*) const;
template void SpringJacobian<float>::list_apply<JacobianForm::kDefinite, false>(
    const float*, const float*, const Weights&, const float*, float*) const;
template void SpringJacobian<float>::list_apply<JacobianForm::kDefinite, true>(
    const float*, const float*, const Weights&, const float*, float*) const;
template void SpringJacobian<double>::list_apply<JacobianForm::kExact, false>(
    const double*, const double*, const Weights&, const double*, double*) const;
template void SpringJacobian<double>::list_apply<JacobianForm::kDefinite, false>(
    const double*, const double*, const Weights&, const double*, double*) const;
template void SpringJacobian<double>::list_apply<JacobianForm::kDefinite, true>(
    const double*, const double*, const Weights&, const double*, double*) const;
template void SpringJacobian<float>::list_linearise(const float*, const float*, double,
                                                    double) const;
template void SpringJacobian<double>::list_linearise(const double*, const double*, double,
                                                     double) const;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
