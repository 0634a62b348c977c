// Chebyshev acceleration (Wang 2015; the weights: chebyshev_weights.hpp) of the Gauss-Seidel
// sweeps of an XPBD substep (xpbd_general_sweep.hpp). The iteration's state is the pair
// (displacement dx, multipliers lambda), and both are extrapolated with the same weight:
//   dx_{k+1} = omega_{k+1} (dx^_{k+1} - dx_{k-1}) + dx_{k-1},  likewise lambda.
// Each projection moves dx by M^-1 grad C dlambda, so dx - dx_predicted = M^-1 sum grad C lambda
// holds for every iterate while the directions grad C stand still; an affine combination of
// iterates keeps that relation, so the extrapolated lambda is the multiplier the extrapolated
// positions carry, and the next sweep's compliance term (alpha~ lambda in eq. 26) sees the
// force the positions hold. Extrapolating dx alone would leave lambda behind the positions: the
// sweeps would settle where each spring's lambda is not the force its displacement carries, off
// backward Euler.
//
// An extrapolation with a rho above what the sweeps allow can grow the error from sweep to
// sweep instead of shrinking it (finite for many sweeps: 1e45 m after 1000 on a stiff net).
// So the substep's first and last sweeps' changes are measured, and a last change larger than
// the first, which the plain sweeps' shrinking changes never give, is reported as divergence.
//
// Every loop is an element-wise `omp for` (orphaned on one thread), so any thread count gives
// the same bits. The weights and the two saved iterates are set up in `build`; a step allocates
// nothing.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "chebyshev_weights.hpp"

namespace clothlab::builtin {

template <class Real>
class XpbdChebyshev {
 public:
  // rho = 0: off. The displacements are 3 rows of `particles` values, `stride` apart.
  void build(double rho, long delay, int iterations, std::size_t particles, std::size_t stride,
             std::size_t springs) {
    particles_ = static_cast<long>(particles);
    stride_ = stride;
    ChebyshevWeights weights(rho, delay);
    active_ = weights.active();
    weights.restart();
    omegas_.clear();
    for (int k = 0; k < iterations; ++k) omegas_.push_back(static_cast<Real>(weights.next()));
    for (std::vector<Real>& saved : saved_displacement_)
      saved.assign(active_ ? 3 * particles : 0, 0);
    for (std::vector<Real>& saved : saved_lambda_) saved.assign(active_ ? springs : 0, 0);
  }

  bool active() const { return active_; }

  // Before sweep `iteration`: keep its starting iterate. The multipliers start each substep at
  // 0 (the first sweep resets them), so iterate 0's are 0, not the last substep's.
  void save(int iteration, const Real* displacement, const Real* lambda) {
    std::vector<Real>& dx = saved_displacement_[iteration % 2];
    std::vector<Real>& multipliers = saved_lambda_[iteration % 2];
    const auto springs = static_cast<long>(multipliers.size());
#pragma omp for schedule(static) nowait
    for (long i = 0; i < particles_; ++i)
      for (std::size_t c = 0; c < 3; ++c)
        dx[3 * static_cast<std::size_t>(i) + c] =
            displacement[c * stride_ + static_cast<std::size_t>(i)];
#pragma omp for schedule(static)
    for (long k = 0; k < springs; ++k) multipliers[k] = iteration == 0 ? Real(0) : lambda[k];
  }

  // This thread's share of the largest change of a displacement component over sweep
  // `iteration` (after its extrapolation): from the iterate it started from to `displacement`.
  Real change(int iteration, const Real* displacement) const {
    const std::vector<Real>& dx = saved_displacement_[iteration % 2];
    Real largest = 0;
#pragma omp for schedule(static)
    for (long i = 0; i < particles_; ++i)
      for (std::size_t c = 0; c < 3; ++c)
        largest =
            std::max(largest, std::abs(displacement[c * stride_ + static_cast<std::size_t>(i)] -
                                       dx[3 * static_cast<std::size_t>(i) + c]));
    return largest;
  }

  // After sweep `iteration`: extrapolate from the iterate before the one it started from.
  // Pinned particles' displacements are 0 in both and stay 0.
  void extrapolate(int iteration, Real* displacement, Real* lambda) const {
    const Real omega = omegas_[static_cast<std::size_t>(iteration)];
    if (omega == 1) return;
    const std::vector<Real>& dx = saved_displacement_[(iteration + 1) % 2];
    const std::vector<Real>& multipliers = saved_lambda_[(iteration + 1) % 2];
    const auto springs = static_cast<long>(multipliers.size());
#pragma omp for schedule(static) nowait
    for (long i = 0; i < particles_; ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        Real& value = displacement[c * stride_ + static_cast<std::size_t>(i)];
        const Real older = dx[3 * static_cast<std::size_t>(i) + c];
        value = omega * (value - older) + older;
      }
#pragma omp for schedule(static)
    for (long k = 0; k < springs; ++k)
      lambda[k] = omega * (lambda[k] - multipliers[k]) + multipliers[k];
  }

 private:
  bool active_ = false;
  long particles_ = 0;
  std::size_t stride_ = 0;
  std::vector<Real> omegas_;  // the weight of each sweep's iterate
  // The iterates that started sweeps k (slot k % 2) and k - 1.
  std::vector<Real> saved_displacement_[2];
  std::vector<Real> saved_lambda_[2];
};

}  // namespace clothlab::builtin
