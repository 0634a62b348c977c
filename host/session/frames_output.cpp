#include "frames_output.hpp"

#include "run_report.hpp"

namespace clothlab::cli {

namespace {

io::FrameWriterOptions writer_options(const RunConfig& config, const Simulation& simulation) {
  io::FrameWriterOptions options;
  options.dir = config.frames.dir;
  options.formats = config.frames.formats;
  options.every_steps = config.frames.every_steps;
  options.last_step = config.steps;
  const Cloth& cloth = simulation.cloth();
  const ClothModel& model = *cloth.model();
  options.run = {{"integrator", simulation.integrator_id()},
                 {"scenario", simulation.scenario_id()},
                 {"integrator_params", simulation.integrator_params()},
                 {"scenario_params", simulation.scenario_params()},
                 {"precision", to_string(cloth.precision())},
                 {"vertices", model.particle_count},
                 {"dt", config.dt},
                 {"steps_requested", config.steps}};
  if (model.grid) {
    options.run["rows"] = model.grid->rows;
    options.run["cols"] = model.grid->cols;
  }
  return options;
}

}  // namespace

FramesOutput::FramesOutput(const RunConfig& config, const Simulation& simulation)
    : writer_(simulation.cloth().scene(), simulation.cloth().model(),
              simulation.cloth().precision(), writer_options(config, simulation)) {}

void FramesOutput::observe(const Cloth& cloth, uint64_t step, double t) {
  if (writer_.is_frame_step(step)) writer_.submit(cloth, step, t);
}

void FramesOutput::finish(const RunRecord& record) { writer_.finish(summary_json(record)); }

}  // namespace clothlab::cli
