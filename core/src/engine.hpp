// Precision-independent face of a cloth's state and force pipeline, behind Cloth.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <memory>
#include <span>
#include <vector>

namespace clothlab::detail {

class Engine {
 public:
  virtual ~Engine() = default;

  virtual const clothlab_system& system() const = 0;
  virtual int threads() const = 0;
  virtual void begin_step() = 0;
  virtual void end_step() = 0;
  virtual StageCounters& counters() = 0;

  virtual void positions(std::vector<double>& out) const = 0;
  virtual void velocities(std::vector<double>& out) const = 0;
  virtual void positions(std::vector<float>& out) const = 0;
  virtual void velocities(std::vector<float>& out) const = 0;
  virtual void set_state(const std::vector<double>& x, const std::vector<double>& v) = 0;
  virtual void copy_raw_state(Cloth::RawState& out) const = 0;
  virtual void set_raw_state(const Cloth::RawState& state) = 0;
  virtual bool state_is_finite() const = 0;
  virtual Cloth::Energy energy() const = 0;
  virtual Cloth::Stretch stretch(Cloth::Springs springs) const = 0;
  virtual double stretch_percentile(Cloth::Springs springs, double fraction) const = 0;
  virtual Cloth::LongestSpring longest_spring(Cloth::Springs springs) const = 0;
  virtual void set_colliders(std::span<const Collider> colliders, double t) = 0;
  virtual Cloth::Contacts contacts() const = 0;
  virtual std::span<const Collider> colliders() const = 0;
  virtual void set_attachments(std::span<const uint32_t> particles, AttachmentSource& source) = 0;
  virtual bool move_attachments(double t) = 0;
  virtual void pin_loads(Cloth::PinLoads& out) const = 0;
  virtual Cloth::Momentum free_momentum() const = 0;
  virtual double contact_work() const = 0;
};

std::unique_ptr<Engine> make_engine(const Scene& scene, std::shared_ptr<const ClothModel> model,
                                    Precision precision, PipelineOptions options);

}  // namespace clothlab::detail
