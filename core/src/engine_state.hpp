// The cloth's state in one precision (SoA, 64-byte aligned, stride a multiple of 16) and what
// reads or sets it outside the force pipeline: conversions, diagnostics (engine_state.cpp),
// colliders and contacts (engine_contacts.cpp), attachments (engine_attachments.cpp). Compiled
// once, with the build's flags: none of it is wide arithmetic, so the engine's copies per SIMD
// target (ClothEngine, cloth_engine.hpp) derive from it instead of compiling it again.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <clothlab/core/collider.hpp>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "aligned_buffer.hpp"
#include "engine.hpp"

namespace clothlab::detail {

template <class Real>
class EngineState : public Engine {
 public:
  void positions(std::vector<double>& out) const override;
  void velocities(std::vector<double>& out) const override;
  void positions(std::vector<float>& out) const override;
  void velocities(std::vector<float>& out) const override;
  void set_state(const std::vector<double>& x, const std::vector<double>& v) override;
  void copy_raw_state(Cloth::RawState& out) const override;
  void set_raw_state(const Cloth::RawState& state) override;
  bool state_is_finite() const override;
  Cloth::Energy energy() const override;
  Cloth::Stretch stretch(Cloth::Springs springs) const override;
  double stretch_percentile(Cloth::Springs springs, double fraction) const override;
  Cloth::LongestSpring longest_spring(Cloth::Springs springs) const override;
  void set_colliders(std::span<const Collider> colliders, double t) override;
  Cloth::Contacts contacts() const override;
  std::span<const Collider> colliders() const override { return colliders_; }
  void set_attachments(std::span<const uint32_t> particles, AttachmentSource& source) override;
  bool move_attachments(double t) override;
  void pin_loads(Cloth::PinLoads& out) const override;
  Cloth::Momentum free_momentum() const override;
  double contact_work() const override { return contact_work_; }

 protected:
  struct Span {
    std::size_t begin, end;
  };

  // The state at the model's rest positions, the active ranges and the thread count
  // (options.threads: 0 for all hardware threads).
  EngineState(const Scene& scene, std::shared_ptr<const ClothModel> model,
              const PipelineOptions& options);

  const ClothModel& topology() const { return *model_; }
  // The grid's row pipeline computes the forces (else the spring list), and the grid's stencils
  // give the diagnostics' springs.
  bool on_grid_path() const { return grid_path_; }

  // clothlab.contacts/1 (engine_contacts.cpp) on the state x, v of the system's precision.
  clothlab_status resolve_contacts(double t, void* x, void* v);
  // clothlab.attachment-targets/1 (engine_attachments.cpp).
  uint32_t attachment_count() const { return static_cast<uint32_t>(attached_.size()); }
  clothlab_status move_attached(double t, void* x, void* v);

  Scene scene_;
  std::shared_ptr<const ClothModel> model_;
  std::size_t n_ = 0;
  std::size_t stride_ = 0;
  int threads_ = 1;
  bool parallel_capable_ = false;  // the cloth is large enough for the team
  bool parallel_ = false;          // this step runs on the team
  bool velocity_forces_ = true;

  AlignedBuffer<Real> x_, v_, inverse_mass_;
  std::vector<clothlab_range> active_;
  std::vector<Span> active_chunks_;  // active ranges cut into pieces for threads
  uint64_t active_particles_ = 0;

 private:
  // Diagnostics over the spring list (the general path; engine_state.cpp).
  double list_spring_energy() const;
  // visit(length / rest length, first, second) for each spring (structural ones alone).
  template <class Visit>
  void for_each_ratio(Cloth::Springs which, Visit&& visit) const;
  // The energy of particle i's springs with x_i at `position` and its partners in px.
  double spring_energy_at(const Real* px, std::size_t i, const Vec3& position) const;

  bool grid_path_ = false;
  // 1 where a pinned particle lies within two rows and two columns (on a mesh: two springs):
  // the springs that Stretch::max_away_from_pins leaves out.
  std::vector<uint8_t> near_pin_;
  mutable std::vector<double> stretch_ratios_;  // stretch_percentile's selection

  std::vector<Collider> step_colliders_;   // as the host set them at the step's start
  double step_start_time_ = 0;             // when
  std::vector<Collider> colliders_;        // at the last resolution (or the step's start)
  std::vector<Collider> moved_colliders_;  // the resolution's scratch: at its time
  AlignedBuffer<Real> path_start_;  // where each particle was at the last resolution or step start
  AlignedBuffer<Real> step_start_x_;         // where each particle was at the step's start
  uint32_t particles_crossed_ = 0;           // in the step before the last set_colliders
  std::vector<uint32_t> attached_;           // particles moved to the source's targets
  std::vector<double> target_x_, target_v_;  // their targets, 3 per particle
  AttachmentSource* attachment_source_ = nullptr;
  double contact_work_ = 0;  // energy the contact resolution has added (J)
};

}  // namespace clothlab::detail
