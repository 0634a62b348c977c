// C++ handles on the components a plugin library provides. Every handle and instance
// shares ownership of its library, so the code stays loaded while any of them lives.
#pragma once

#include <clothlab/ext/solver_statistics.h>
#include <clothlab/plugin.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "clothlab/host/param_set.hpp"
#include "clothlab/host/plugin_call_marker.hpp"

namespace clothlab::host {

// Keeps one loaded shared library open (library_handle.hpp).
class LibraryHandle;

// An object a plugin created, destroyed through the plugin when the owner goes.
class PluginObject {
 public:
  PluginObject(std::shared_ptr<const LibraryHandle> library, void* object, void (*destroy)(void*),
               PluginCallSite site);
  ~PluginObject();
  PluginObject(PluginObject&& other) noexcept;
  PluginObject& operator=(PluginObject&& other) noexcept;
  PluginObject(const PluginObject&) = delete;
  PluginObject& operator=(const PluginObject&) = delete;

  void* get() const { return object_; }
  // Where calls on the object go, for plugin_call_marker.hpp.
  const PluginCallSite& site() const { return site_; }

 private:
  void release() noexcept;

  std::shared_ptr<const LibraryHandle> library_;
  void* object_;
  void (*destroy_)(void*);
  PluginCallSite site_;
};

// Metadata every component shares.
struct ComponentInfo {
  std::string_view kind;  // "integrator" or "scenario"
  std::string_view id, name, version, description;
  std::span<const clothlab_param_spec> params;
  std::filesystem::path library_path;
};

class IntegratorInstance {
 public:
  IntegratorInstance(const clothlab_integrator& descriptor, std::string label, PluginObject object);

  // Both throw PluginError carrying the plugin's status and message.
  void prepare(const clothlab_system& system);
  void step(const clothlab_system& system, double t, double dt);

  // The last step's solver figures when the integrator offers
  // clothlab.solver-statistics/1 (iterative and factorising integrators), else nullopt.
  // Throws PluginError if the plugin fails to report.
  std::optional<clothlab_solver_step_statistics> last_step_statistics() const;

 private:
  const clothlab_integrator* descriptor_;
  const clothlab_solver_statistics_extension* statistics_ = nullptr;
  std::string label_;
  PluginObject object_;
  uint64_t steps_since_prepare_ = 0;
};

class IntegratorPlugin {
 public:
  IntegratorPlugin(std::shared_ptr<const LibraryHandle> library, std::filesystem::path path,
                   const clothlab_integrator& descriptor);

  ComponentInfo info() const;
  uint32_t flags() const { return descriptor_->flags; }
  bool uses_velocity_forces() const;
  uint32_t order() const { return descriptor_->order; }
  uint32_t evals_per_step() const { return descriptor_->evals_per_step; }
  // CLOTHLAB_FLOAT32 or CLOTHLAB_FLOAT64.
  bool supports_precision(uint32_t precision) const;
  // The integrator extension `id` (clothlab/ext/), or nullptr when the plugin predates
  // ABI 1.2 or does not offer it.
  const void* extension(const char* id) const;
  const clothlab_integrator& descriptor() const { return *descriptor_; }

  ParamSet default_params() const;
  // Throws PluginError if the plugin refuses the values.
  IntegratorInstance create(const ParamSet& params) const;

 private:
  std::shared_ptr<const LibraryHandle> library_;
  std::filesystem::path path_;
  const clothlab_integrator* descriptor_;
};

class ScenarioInstance {
 public:
  ScenarioInstance(const clothlab_scenario& descriptor, std::string label, PluginObject object);

  // The scene; its pinned array stays valid while this instance lives. Throws PluginError.
  clothlab_scene describe() const;
  // The plugin's instance, the first argument of its extensions' functions.
  void* get() const { return object_.get(); }

 private:
  const clothlab_scenario* descriptor_;
  std::string label_;
  PluginObject object_;
};

class ScenarioPlugin {
 public:
  ScenarioPlugin(std::shared_ptr<const LibraryHandle> library, std::filesystem::path path,
                 const clothlab_scenario& descriptor);

  ComponentInfo info() const;
  const clothlab_scenario& descriptor() const { return *descriptor_; }
  // The scenario extension `id` (clothlab/ext/), or nullptr when the plugin predates
  // ABI 1.3 or does not offer it.
  const void* extension(const char* id) const;
  ParamSet default_params() const;
  ScenarioInstance create(const ParamSet& params) const;

 private:
  std::shared_ptr<const LibraryHandle> library_;
  std::filesystem::path path_;
  const clothlab_scenario* descriptor_;
};

}  // namespace clothlab::host
