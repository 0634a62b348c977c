// What the benchmark programs share: a scene built by a real scenario plugin and a loaded
// integrator plugin, both found beside the executable like the host finds them.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <clothlab/host/param_set.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace clothlab::bench {

using ParamTexts = std::vector<std::pair<std::string, std::string>>;

// The scene of scenario `id` ("sheet", "flag") with the given parameter texts set.
Scene make_scene(const std::string& id, const ParamTexts& params);
// The scene of scenario `id` with its parameters' defaults changed by set_params.
Scene make_scene(const std::string& id, const std::function<void(host::ParamSet&)>& set_params);

// The colliders (clothlab.colliders/1) of scenario `id` with the given parameter texts set, at
// their poses at t = 0; none when it offers no colliders.
std::vector<Collider> make_colliders(const std::string& id, const ParamTexts& params);

// Parameters of the benchmark cloth at side x side particles: the material of
// configs/bench-300.yaml (2 cm spacing, 0.6 kg/m^2, lunar gravity), so every size has
// the same per-particle dynamics and the 300 x 300 one is exactly that file's.
ParamTexts bench_cloth_params(int side);

// A command-line option's value as a number; throws std::runtime_error naming the option and
// the text when it is not a finite number.
double number_of(const std::string& option, const char* text);

// An integrator plugin instance with default parameters (but for `params`), bound to a cloth.
class BoundIntegrator {
 public:
  BoundIntegrator(const std::string& id, const Cloth& cloth, const ParamTexts& params = {});
  void step(double t, double dt);
  bool uses_velocity_forces() const { return uses_velocity_forces_; }

 private:
  host::PluginLibrary library_;
  host::IntegratorInstance instance_;
  const clothlab_system* system_;
  bool uses_velocity_forces_;
};

// Whether integrator `id` needs damping forces (decides the Cloth's pipeline).
bool integrator_uses_velocity_forces(const std::string& id);

// The largest value integrator `id`'s parameter `name` takes, from its parameter table.
double integrator_param_maximum(const std::string& id, const std::string& name);

}  // namespace clothlab::bench
