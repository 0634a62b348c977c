#include "clothlab/analysis/stability_prediction.hpp"

namespace clothlab::analysis {

StabilityPrediction predict_stability(const Scene& scene, Method method,
                                      const VerletDamping& verlet, int threads,
                                      const SpectralOptions& options) {
  PipelineOptions pipeline;
  pipeline.velocity_forces = true;
  pipeline.threads = threads;
  const Cloth cloth(scene, Precision::Float64, pipeline);
  StabilityPrediction prediction;
  prediction.spectrum = estimate_spectrum(cloth.system(), 0.0, options);
  prediction.dt_max = predict_dt_max(method, prediction.spectrum, verlet);
  return prediction;
}

}  // namespace clothlab::analysis
