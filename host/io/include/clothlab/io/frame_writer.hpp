// Writes a run's frames off the stepping thread.
//
// The stepping thread copies the state as the cloth stores it into the next slot of a ring
// of four (two memcpy's; it waits only when the writer is four frames behind) and goes on; a
// writer thread decodes it, computes the per-vertex stretch and the energy, writes the
// frame files atomically and rewrites the .pvd index after every frame, so a run that stops
// at any point leaves a complete sequence and an index of exactly the frames written. Memory
// is the four slots, whatever the number of frames. The folder holds:
//   run.json          the run: integrator, scenario, parameters, mesh (vertices; rows and cols
//                     for a grid), dt, frame times; its
//                     verdict and summary once finished ("status": running | finished)
//   frames.pvd        index of frame_NNNNNN.vtp with their times        (format vtp); each
//                     .vtp holds the scene's colliders at the frame's poses
//   frame_NNNNNN.obj  one OBJ per frame                                 (format obj)
//   frames.pc2        point cache of every frame, written when the run ends (format pc2)
#pragma once

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace clothlab::io {

struct FrameWriterOptions {
  std::filesystem::path dir;
  std::vector<std::string> formats{"vtp"};  // vtp, obj, pc2
  uint64_t every_steps = 1;
  uint64_t last_step = 0;  // always a frame, so the sequence ends with the final state
  nlohmann::json run;      // what run.json says about the run before it ends
};

class FrameWriter {
 public:
  // Creates the folder, removes the frame files of an earlier run there and writes
  // run.json: throws host::InputError (one line naming the folder) if that fails, so an
  // unwritable folder is reported before the run starts. Starts the writer thread. The frames
  // draw `model` (the run's Cloth::model()), their energy is that of a cloth built from it.
  FrameWriter(const Scene& scene, const std::shared_ptr<const ClothModel>& model,
              Precision precision, FrameWriterOptions options);
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  bool is_frame_step(uint64_t step) const;
  // Copies the cloth's raw state for the writer thread. Rethrows a failure of the writer.
  void submit(const Cloth& cloth, uint64_t step, double t);
  // Writes what is queued, the point cache and run.json with the summary added.
  void finish(const nlohmann::json& summary);
  uint64_t frames_written() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothlab::io
