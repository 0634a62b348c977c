// Chebyshev semi-iterative acceleration (Wang 2015, "A Chebyshev semi-iterative approach for
// accelerating projective and position-based dynamics") of a fixed-point iteration whose
// error shrinks by about rho per iteration: with x^ the plain iterate,
//   x_{k+1} = omega_{k+1} (x^_{k+1} - x_{k-1}) + x_{k-1},
//   omega = 1 for the first `delay` iterations, then 2 / (2 - rho^2), then
//   omega_{k+1} = 4 / (4 - rho^2 omega_k).
// The weights tend to 2 / (1 + sqrt(1 - rho^2)): the error then shrinks by about
// rho / (1 + sqrt(1 - rho^2)) per iteration instead of rho. A rho above the iteration's true
// spectral radius overshoots (and can diverge); below it, it accelerates less. The delay lets
// the plain iteration settle first, where its first iterations contract faster than rho.
#pragma once

namespace clothlab::builtin {

class ChebyshevWeights {
 public:
  // rho = 0: no acceleration (every weight is 1). rho in [0, 1), delay >= 1.
  ChebyshevWeights(double rho, long delay) : rho_squared_(rho * rho), delay_(delay) {}

  bool active() const { return rho_squared_ > 0.0; }
  void restart() { iteration_ = 0, omega_ = 1.0; }

  // The weight omega of the iterate about to be formed.
  double next() {
    const long k = iteration_++;
    if (!active() || k < delay_)
      omega_ = 1.0;
    else if (k == delay_)
      omega_ = 2.0 / (2.0 - rho_squared_);
    else
      omega_ = 4.0 / (4.0 - rho_squared_ * omega_);
    return omega_;
  }

 private:
  double rho_squared_;
  long delay_;
  long iteration_ = 0;
  double omega_ = 1.0;
};

}  // namespace clothlab::builtin
