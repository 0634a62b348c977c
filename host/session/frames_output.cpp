#include "frames_output.hpp"

#include <clothlab/host/errors.hpp>

#include "run_report.hpp"

namespace clothlab::cli {

namespace {

io::FrameWriterOptions writer_options(const RunConfig& config, const Simulation& simulation) {
  io::FrameWriterOptions options;
  options.dir = config.frames.dir;
  options.formats = config.frames.formats;
  options.every_steps = config.frames.every_steps;
  options.last_step = config.steps;
  const Scene& scene = simulation.cloth().scene();
  options.run = {{"integrator", simulation.integrator_id()},
                 {"scenario", simulation.scenario_id()},
                 {"integrator_params", simulation.integrator_params()},
                 {"scenario_params", simulation.scenario_params()},
                 {"precision", to_string(simulation.cloth().precision())},
                 {"rows", scene.rows},
                 {"cols", scene.cols},
                 {"dt", config.dt},
                 {"steps_requested", config.steps}};
  return options;
}

// The frame writer lays its vertices out as the grid (io::GridMesh): a cloth that is not one is
// refused rather than written wrongly.
const Scene& grid_scene(const Simulation& simulation) {
  const Scene& scene = simulation.cloth().scene();
  if (scene.rows == 0)
    throw host::InputError("frames: scenario " + simulation.scenario_id() +
                           " is a triangle mesh (clothlab.mesh/1), and frames are written for "
                           "grid cloths only so far");
  return scene;
}

}  // namespace

FramesOutput::FramesOutput(const RunConfig& config, const Simulation& simulation)
    : writer_(grid_scene(simulation), simulation.cloth().precision(),
              writer_options(config, simulation)) {}

void FramesOutput::observe(const Cloth& cloth, uint64_t step, double t) {
  if (writer_.is_frame_step(step)) writer_.submit(cloth, step, t);
}

void FramesOutput::finish(const RunRecord& record) { writer_.finish(summary_json(record)); }

}  // namespace clothlab::cli
