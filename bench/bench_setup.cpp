#include "bench_setup.hpp"

#include <clothlab/ext/colliders.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace clothlab::bench {
namespace {

host::PluginLibrary find_plugin(const std::string& id) {
  return host::PluginLibrary::find(id, host::PluginSearchPath::standard({}));
}

}  // namespace

Scene make_scene(const std::string& id, const ParamTexts& params) {
  return make_scene(id, [&](host::ParamSet& values) {
    for (const auto& [key, text] : params) values.set(key, text, "bench");
  });
}

Scene make_scene(const std::string& id, const std::function<void(host::ParamSet&)>& set_params) {
  const host::PluginLibrary library = find_plugin(id);
  host::ParamSet values = library.scenario().default_params();
  set_params(values);
  const host::ScenarioInstance instance = library.scenario().create(values);
  return scene_from_abi(instance.describe());
}

std::vector<Collider> make_colliders(const std::string& id, const ParamTexts& params) {
  const host::PluginLibrary library = find_plugin(id);
  host::ParamSet values = library.scenario().default_params();
  for (const auto& [key, text] : params) values.set(key, text, "bench");
  const host::ScenarioInstance instance = library.scenario().create(values);
  const auto* table = static_cast<const clothlab_colliders_extension*>(
      library.scenario().extension(CLOTHLAB_EXT_COLLIDERS));
  std::vector<Collider> colliders;
  if (table == nullptr) return colliders;
  for (uint32_t i = 0; i < table->count(instance.get()); ++i) {
    clothlab_collider raw{};
    raw.struct_size = sizeof raw;
    clothlab_pose pose{};
    clothlab_message message{};
    if (table->describe(instance.get(), i, &raw, &message) != CLOTHLAB_OK ||
        table->pose(instance.get(), i, 0.0, &pose, &message) != CLOTHLAB_OK)
      throw std::runtime_error(id + ": collider " + std::to_string(i) + ": " + message.text);
    colliders.push_back(collider_from_abi(raw));
    colliders.back().pose = pose_from_abi(pose);
  }
  return colliders;
}

ParamTexts bench_cloth_params(int side) {
  const double size_m = 6.0 * side / 300.0;  // 2 cm spacing at 300 x 300
  const double mass_kg = 0.6 * size_m * size_m;
  return {{"rows", std::to_string(side)},    {"cols", std::to_string(side)},
          {"width", std::to_string(size_m)}, {"height", std::to_string(size_m)},
          {"mass", std::to_string(mass_kg)}, {"gravity", "[0, -1.62, 0]"}};
}

bool integrator_uses_velocity_forces(const std::string& id) {
  return find_plugin(id).integrator().uses_velocity_forces();
}

double integrator_param_maximum(const std::string& id, const std::string& name) {
  const host::PluginLibrary library = find_plugin(id);  // holds the table while it is read
  const host::ParamSet values = library.integrator().default_params();
  for (const clothlab_param_spec& spec : values.specs())
    if (spec.name == name) return spec.max_value;
  throw std::runtime_error(id + ": no parameter " + name);
}

namespace {
host::ParamSet integrator_values(const host::PluginLibrary& library, const ParamTexts& params) {
  host::ParamSet values = library.integrator().default_params();
  for (const auto& [key, text] : params) values.set(key, text, "bench");
  return values;
}
}  // namespace

BoundIntegrator::BoundIntegrator(const std::string& id, const Cloth& cloth,
                                 const ParamTexts& params)
    : library_(find_plugin(id)),
      instance_(library_.integrator().create(integrator_values(library_, params))),
      system_(&cloth.system()),
      uses_velocity_forces_(library_.integrator().uses_velocity_forces()) {
  instance_.prepare(*system_);
}

void BoundIntegrator::step(double t, double dt) { instance_.step(*system_, t, dt); }

// An option's value as a number, or an error naming the option and the text.
double number_of(const std::string& option, const char* text) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(value))
    throw std::runtime_error(option + " '" + text + "' is not a number");
  return value;
}

}  // namespace clothlab::bench
