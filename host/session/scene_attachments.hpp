// The attached particles a scenario offers (clothlab.attachments/1), read and checked before the
// run, and the source of their targets during it.
#pragma once

#include <clothlab/ext/attachments.h>

#include <clothlab/core/cloth.hpp>
#include <clothlab/host/components.hpp>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace clothlab::cli {

class SceneAttachments final : public AttachmentSource {
 public:
  // None: a scenario without the extension.
  SceneAttachments() = default;
  // Reads the attached particles and their targets at each step start t = k dt, k = 0 .. steps,
  // and at samples_per_step - 1 times evenly between (the integrator's substeps, where it asks),
  // before the run (clothlab/core/attachment_path.hpp): a particle out of range (`particles` on
  // the cloth), a non-finite target, or a jump is an InputError naming the scenario, the
  // attachment, the time, the value and what is allowed; a failing call is the plugin's
  // PluginError. `instance` must outlive this object.
  SceneAttachments(const host::ScenarioPlugin& scenario, const host::ScenarioInstance& instance,
                   uint32_t particles, double dt, uint64_t steps, uint32_t samples_per_step = 1);

  // Throws an InputError naming the scenario and the attachment when a target at t = 0 lies
  // far from where its particle starts on `cloth` (check_attachment_start), which the host would
  // otherwise snap there, starting the cloth stretched.
  void check_start(const Cloth& cloth);

  bool empty() const { return particles_.empty(); }
  std::span<const uint32_t> particles() const { return particles_; }
  bool targets(double t, std::span<double> positions,
               std::span<double> velocities) noexcept override;

 private:
  const clothlab_attachments_extension* table_ = nullptr;
  void* instance_ = nullptr;
  std::string scenario_id_;
  std::vector<uint32_t> particles_;
};

}  // namespace clothlab::cli
