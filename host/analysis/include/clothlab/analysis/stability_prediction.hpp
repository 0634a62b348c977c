// Predicted largest stable dt of an integrator on a scene, from the spectrum of the cloth
// linearised about its rest layout (the scene's initial state), in float64 with damping.
#pragma once

#include <clothlab/core/cloth.hpp>

#include "clothlab/analysis/spectral_estimate.hpp"

namespace clothlab::analysis {

struct StabilityPrediction {
  double dt_max = 0.0;  // s; 0: unstable at any dt, +inf: never unstable
  SpectralEstimate spectrum;
};

// Builds its own float64 Cloth of the scene (velocity forces on, `threads` as for the core).
StabilityPrediction predict_stability(const Scene& scene, Method method,
                                      const VerletDamping& verlet = {}, int threads = 0,
                                      const SpectralOptions& options = {});
// For an integrator's declared explicit scheme (see predict_dt_max for the table).
StabilityPrediction predict_stability(const Scene& scene, const RknTable& table,
                                      bool velocity_forces, int threads = 0,
                                      const SpectralOptions& options = {});

}  // namespace clothlab::analysis
