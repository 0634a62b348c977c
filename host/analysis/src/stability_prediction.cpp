#include "clothlab/analysis/stability_prediction.hpp"

namespace clothlab::analysis {

namespace {

SpectralEstimate spectrum_of(const Scene& scene, int threads, const SpectralOptions& options) {
  PipelineOptions pipeline;
  pipeline.velocity_forces = true;
  pipeline.threads = threads;
  const Cloth cloth(scene, Precision::Float64, pipeline);
  return estimate_spectrum(cloth.system(), 0.0, options);
}

}  // namespace

StabilityPrediction predict_stability(const Scene& scene, Method method,
                                      const VerletDamping& verlet, int threads,
                                      const SpectralOptions& options) {
  StabilityPrediction prediction;
  prediction.spectrum = spectrum_of(scene, threads, options);
  prediction.dt_max = predict_dt_max(method, prediction.spectrum, verlet);
  return prediction;
}

StabilityPrediction predict_stability(const Scene& scene, const RknTable& table,
                                      bool velocity_forces, int threads,
                                      const SpectralOptions& options) {
  StabilityPrediction prediction;
  prediction.spectrum = spectrum_of(scene, threads, options);
  prediction.dt_max = predict_dt_max(table, prediction.spectrum, velocity_forces);
  return prediction;
}

}  // namespace clothlab::analysis
