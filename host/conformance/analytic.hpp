// Closed-form solutions of the test problems the numerics checks measure against.
#pragma once

#include <array>
#include <cmath>

namespace clothlab::conformance {

struct Oscillation {
  double position;  // extension u
  double velocity;  // du/dt
};

// m u'' = -k u - c u', u(0) = u0, u'(0) = v0, underdamped (c^2 < 4 k m).
inline Oscillation damped_oscillator(double k, double c, double m, double u0, double v0, double t) {
  const double decay = c / (2.0 * m);
  const double frequency = std::sqrt(k / m - decay * decay);
  const double a = u0;
  const double b = (v0 + decay * u0) / frequency;
  const double envelope = std::exp(-decay * t);
  const double cos_term = std::cos(frequency * t);
  const double sin_term = std::sin(frequency * t);
  return {
      envelope * (a * cos_term + b * sin_term),
      envelope * ((b * frequency - decay * a) * cos_term - (a * frequency + decay * b) * sin_term)};
}

struct Motion {
  std::array<double, 3> position, velocity;
};

// x'' = g from x0, v0.
inline Motion free_fall(const std::array<double, 3>& x0, const std::array<double, 3>& v0,
                        const std::array<double, 3>& g, double t) {
  Motion motion{};
  for (int k = 0; k < 3; ++k) {
    motion.position[k] = x0[k] + v0[k] * t + 0.5 * g[k] * t * t;
    motion.velocity[k] = v0[k] + g[k] * t;
  }
  return motion;
}

}  // namespace clothlab::conformance
