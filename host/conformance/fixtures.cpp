#include "fixtures.hpp"

#include <clothlab/ext/air.h>
#include <clothlab/ext/attachments.h>
#include <clothlab/ext/colliders.h>
#include <clothlab/ext/text_parameters.h>

#include <clothlab/core/triangle_mesh.hpp>
#include <cstring>
#include <iterator>

#include "verdict.hpp"

namespace clothlab::conformance {

namespace {
std::vector<ParameterOverride> overrides;
std::vector<TextOverride> text_overrides;
}  // namespace

void set_text_overrides(std::vector<TextOverride> values) { text_overrides = std::move(values); }

clothlab_status create_scenario(const clothlab_scenario& scenario,
                                const std::vector<clothlab_param_value>& values, void** instance,
                                clothlab_message& message) {
  const auto* table = static_cast<const clothlab_text_parameters_extension*>(
      clothlab_scenario_extension(&scenario, CLOTHLAB_EXT_TEXT_PARAMETERS));
  const uint32_t count = static_cast<uint32_t>(values.size());
  if (table == nullptr || table->struct_size < CLOTHLAB_TEXT_PARAMETERS_SIZE_1)
    return scenario.create(values.data(), count, instance, &message);
  std::vector<const char*> texts;
  for (uint32_t i = 0; i < table->count; ++i) {
    texts.push_back(table->specs[i].default_text);
    for (const TextOverride& override : text_overrides)
      if (override.component == scenario.id && override.name == table->specs[i].name)
        texts.back() = override.text.c_str();
  }
  return table->create(values.data(), count, texts.data(), table->count, instance, &message);
}

void set_parameter_overrides(std::vector<ParameterOverride> values) {
  overrides = std::move(values);
}

const std::vector<ParameterOverride>& parameter_overrides() { return overrides; }

std::vector<clothlab_param_value> default_values(const std::string& component,
                                                 const clothlab_param_spec* specs, uint32_t count) {
  std::vector<clothlab_param_value> values(count);
  for (uint32_t i = 0; i < count; ++i) {
    for (int k = 0; k < 3; ++k) values[i].v[k] = specs[i].default_value[k];
    for (const ParameterOverride& override : overrides)
      if (override.component == component && override.name == specs[i].name)
        values[i] = override.value;
  }
  return values;
}

std::vector<clothlab_param_value> default_values(const clothlab_integrator& integrator) {
  return default_values(integrator.id, integrator.params, integrator.param_count);
}

std::vector<clothlab_param_value> default_values(const clothlab_scenario& scenario) {
  return default_values(scenario.id, scenario.params, scenario.param_count);
}

std::string describe_status(clothlab_status status, const clothlab_message& message) {
  static const char* const names[] = {
      "OK", "INVALID_ARGUMENT", "UNSUPPORTED", "OUT_OF_MEMORY", "NUMERICAL", "INTERNAL"};
  const std::string name =
      status >= 0 && status <= 5 ? names[status] : "status " + std::to_string(status);
  return name + ": " + std::string(message.text, strnlen(message.text, sizeof message.text));
}

IntegratorInstance::IntegratorInstance(const clothlab_integrator& integrator,
                                       const std::vector<clothlab_param_value>& values)
    : integrator_(integrator) {
  clothlab_message message{};
  const clothlab_status status =
      integrator.create(values.data(), static_cast<uint32_t>(values.size()), &instance_, &message);
  require(status == CLOTHLAB_OK, "create failed: " + describe_status(status, message));
  require(instance_ != nullptr, "create returned OK but no instance");
}

IntegratorInstance::~IntegratorInstance() { integrator_.destroy(instance_); }

void IntegratorInstance::prepare(const Cloth& cloth) {
  clothlab_message message{};
  const clothlab_status status = integrator_.prepare(instance_, &cloth.system(), &message);
  require(status == CLOTHLAB_OK, "prepare failed: " + describe_status(status, message));
}

void IntegratorInstance::step(const Cloth& cloth, double t, double dt) {
  clothlab_message message{};
  const clothlab_status status = integrator_.step(instance_, &cloth.system(), t, dt, &message);
  require(status == CLOTHLAB_OK,
          "step at t = " + std::to_string(t) + " failed: " + describe_status(status, message));
  require(cloth.state_is_finite(), "non-finite state after the step at t = " + std::to_string(t));
}

void IntegratorInstance::run(const Cloth& cloth, int steps, double dt) {
  for (int i = 0; i < steps; ++i) step(cloth, i * dt, dt);
}

ScenarioInstance::ScenarioInstance(const clothlab_scenario& scenario,
                                   const std::vector<clothlab_param_value>& values)
    : scenario_(scenario) {
  clothlab_message message{};
  const clothlab_status status = create_scenario(scenario, values, &instance_, message);
  require(status == CLOTHLAB_OK, "create failed: " + describe_status(status, message));
  require(instance_ != nullptr, "create returned OK but no instance");
}

ScenarioInstance::~ScenarioInstance() { scenario_.destroy(instance_); }

clothlab_scene ScenarioInstance::describe() const {
  clothlab_scene scene{};
  scene.struct_size = sizeof scene;
  clothlab_message message{};
  const clothlab_status status = scenario_.describe(instance_, &scene, &message);
  require(status == CLOTHLAB_OK, "describe failed: " + describe_status(status, message));
  return scene;
}

std::vector<double> ScenarioInstance::colliders_at_start() const {
  const auto* table = static_cast<const clothlab_colliders_extension*>(
      clothlab_scenario_extension(&scenario_, CLOTHLAB_EXT_COLLIDERS));
  std::vector<double> fields;
  if (table == nullptr) return fields;
  for (uint32_t i = 0; i < table->count(instance_); ++i) {
    clothlab_collider collider{};
    collider.struct_size = sizeof collider;
    clothlab_pose pose{};
    clothlab_message message{};
    clothlab_status status = table->describe(instance_, i, &collider, &message);
    require(status == CLOTHLAB_OK, "collider describe failed: " + describe_status(status, message));
    status = table->pose(instance_, i, 0.0, &pose, &message);
    require(status == CLOTHLAB_OK, "collider pose failed: " + describe_status(status, message));
    fields.insert(fields.end(),
                  {static_cast<double>(collider.shape), collider.radius, collider.end_radius,
                   collider.half_length, collider.half_extents[0], collider.half_extents[1],
                   collider.half_extents[2], collider.friction, collider.thickness});
    fields.insert(fields.end(), std::begin(pose.position), std::end(pose.position));
    fields.insert(fields.end(), std::begin(pose.orientation), std::end(pose.orientation));
  }
  return fields;
}

std::vector<double> ScenarioInstance::motion() const {
  const auto* attachments = static_cast<const clothlab_attachments_extension*>(
      clothlab_scenario_extension(&scenario_, CLOTHLAB_EXT_ATTACHMENTS));
  const auto* colliders = static_cast<const clothlab_colliders_extension*>(
      clothlab_scenario_extension(&scenario_, CLOTHLAB_EXT_COLLIDERS));
  std::vector<double> fields;
  clothlab_message message{};
  const uint32_t attached = attachments ? attachments->count(instance_) : 0;
  std::vector<uint32_t> particles(attached);
  std::vector<double> positions(3 * attached), velocities(3 * attached);
  if (attached > 0) {
    const clothlab_status status = attachments->particles(instance_, particles.data(), &message);
    require(status == CLOTHLAB_OK, "attachments failed: " + describe_status(status, message));
    fields.assign(particles.begin(), particles.end());
  }
  // Every 1 ms over the first 2 s (a step a game or a run commonly takes), so a parameter whose
  // effect lasts a few milliseconds (a flick, a fast flutter) shows, then every 0.1 s to 20 s.
  std::vector<double> times;
  for (int k = 0; k <= 2000; ++k) times.push_back(1e-3 * k);
  for (int k = 21; k <= 200; ++k) times.push_back(0.1 * k);
  for (const double t : times) {
    if (attached > 0) {
      const clothlab_status status =
          attachments->targets(instance_, t, positions.data(), velocities.data(), &message);
      require(status == CLOTHLAB_OK,
              "attachment targets failed: " + describe_status(status, message));
      fields.insert(fields.end(), positions.begin(), positions.end());
      fields.insert(fields.end(), velocities.begin(), velocities.end());
    }
    for (uint32_t i = 0; colliders != nullptr && i < colliders->count(instance_); ++i) {
      clothlab_pose pose{};
      const clothlab_status status = colliders->pose(instance_, i, t, &pose, &message);
      require(status == CLOTHLAB_OK, "collider pose failed: " + describe_status(status, message));
      fields.insert(fields.end(), std::begin(pose.position), std::end(pose.position));
      fields.insert(fields.end(), std::begin(pose.orientation), std::end(pose.orientation));
    }
  }
  return fields;
}

std::vector<double> ScenarioInstance::air() const {
  const auto* table = static_cast<const clothlab_air_extension*>(
      clothlab_scenario_extension(&scenario_, CLOTHLAB_EXT_AIR));
  if (table == nullptr) return {};
  clothlab_air air{};
  air.struct_size = sizeof air;
  clothlab_message message{};
  const clothlab_status status = table->describe(instance_, &air, &message);
  require(status == CLOTHLAB_OK, "air describe failed: " + describe_status(status, message));
  return {air.wind_velocity[0], air.wind_velocity[1], air.wind_velocity[2],
          air.density,          air.drag_coefficient, air.lift_coefficient};
}

Scene sheet_scene(uint32_t rows, uint32_t cols, bool windy) {
  Scene scene;
  scene.rows = rows;
  scene.cols = cols;
  scene.width = 1.0;
  scene.height = 0.8;
  scene.total_mass = 0.5;
  scene.structural = {40.0, 0.05};
  scene.shear = {40.0, 0.05};
  scene.flexion = {10.0, 0.02};
  if (rows > 1)
    scene.pinned = cols > 1 ? std::vector<uint32_t>{0, cols - 1} : std::vector<uint32_t>{0};
  if (windy) {
    scene.wind_direction = {0, 0, 1};
    scene.wind_strength = 0.5;
  }
  return scene;
}

Cloth sheet_cloth(const Scene& scene, SheetShape shape, Precision precision,
                  PipelineOptions options) {
  if (shape == SheetShape::Grid) return Cloth(scene, precision, options);
  const TriangleMesh mesh = irregular_grid_mesh(scene);
  Scene mesh_scene = scene;
  mesh_scene.rows = mesh_scene.cols = 0;  // as the host describes a mesh: no grid layout
  return Cloth(mesh_scene, build_mesh_model(mesh, mesh_scene), precision, options);
}

namespace {

// Why `integrator` will not run on a mesh, or "" when it does: the refusal of its first
// prepare or step on a small irregular mesh with CLOTHLAB_ERROR_UNSUPPORTED.
std::string mesh_refusal(const clothlab_integrator& integrator) {
  const Cloth cloth = sheet_cloth(sheet_scene(4, 5, true), SheetShape::IrregularMesh,
                                  preferred_precision(integrator), pipeline_for(integrator));
  const std::vector<clothlab_param_value> values = default_values(integrator);
  void* instance = nullptr;
  clothlab_message message{};
  if (integrator.create(values.data(), static_cast<uint32_t>(values.size()), &instance, &message) !=
      CLOTHLAB_OK)
    return "";  // the body fails on the grid already
  clothlab_status status = integrator.prepare(instance, &cloth.system(), &message);
  if (status == CLOTHLAB_OK)
    status = integrator.step(instance, &cloth.system(), 0.0, 1e-3, &message);
  integrator.destroy(instance);
  return status == CLOTHLAB_ERROR_UNSUPPORTED ? describe_status(status, message) : "";
}

std::string joined(const std::string& grid, const std::string& mesh) {
  if (mesh.empty()) return grid;
  return grid.empty() ? "irregular mesh: " + mesh : grid + "; irregular mesh: " + mesh;
}

}  // namespace

Verdict on_every_shape(const clothlab_integrator& integrator,
                       const std::function<Verdict(SheetShape)>& body) {
  const Verdict grid = body(SheetShape::Grid);
  if (!grid.passed) return grid;
  if (const std::string refusal = mesh_refusal(integrator); !refusal.empty())
    return {true, joined(grid.reason, "not run, the integrator refuses meshes (" + refusal + ")")};
  Verdict mesh;
  try {
    mesh = body(SheetShape::IrregularMesh);
  } catch (const CheckFailure& failure) {
    throw CheckFailure(std::string("on the irregular mesh: ") + failure.what());
  }
  if (!mesh.passed) return {false, "on the irregular mesh: " + mesh.reason};
  return {true, joined(grid.reason, mesh.reason)};
}

bool uses_velocity_forces(const clothlab_integrator& integrator) {
  return (integrator.flags & CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES) != 0;
}

const clothlab_integrator_traits* integrator_traits(const clothlab_integrator& integrator) {
  const auto* traits = static_cast<const clothlab_integrator_traits*>(
      clothlab_integrator_extension(&integrator, CLOTHLAB_EXT_INTEGRATOR_TRAITS));
  if (traits == nullptr || traits->struct_size < sizeof(clothlab_integrator_traits)) return nullptr;
  return traits;
}

bool has_trait(const clothlab_integrator& integrator, uint32_t trait) {
  const clothlab_integrator_traits* traits = integrator_traits(integrator);
  return traits != nullptr && (traits->flags & trait) != 0;
}

Precision preferred_precision(const clothlab_integrator& integrator) {
  return (integrator.precisions & (1u << CLOTHLAB_FLOAT64)) != 0 ? Precision::Float64
                                                                 : Precision::Float32;
}

PipelineOptions pipeline_for(const clothlab_integrator& integrator, int threads) {
  PipelineOptions options;
  options.velocity_forces = uses_velocity_forces(integrator);
  options.threads = threads;
  return options;
}

State state_of(const Cloth& cloth) {
  State state;
  cloth.positions(state.x);
  cloth.velocities(state.v);
  return state;
}

State simulate(const clothlab_integrator& integrator, const Scene& scene, Precision precision,
               int threads, int steps, double dt, SheetShape shape) {
  Cloth cloth = sheet_cloth(scene, shape, precision, pipeline_for(integrator, threads));
  IntegratorInstance instance(integrator, default_values(integrator));
  instance.prepare(cloth);
  instance.run(cloth, steps, dt);
  return state_of(cloth);
}

}  // namespace clothlab::conformance
