// --frames: the run's frames written by an io::FrameWriter, with run.json describing the run.
#pragma once

#include <clothlab/io/frame_writer.hpp>

#include "simulation.hpp"

namespace clothlab::cli {

class FramesOutput : public StepObserver {
 public:
  // Creates the folder and writes run.json (InputError if it cannot: before the run).
  FramesOutput(const RunConfig& config, const Simulation& simulation);
  void observe(const Cloth& cloth, uint64_t step, double t) override;
  // Writes the remaining frames and run.json with the run's summary.
  void finish(const RunRecord& record);

 private:
  io::FrameWriter writer_;
};

}  // namespace clothlab::cli
