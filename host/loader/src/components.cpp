#include "clothlab/host/components.hpp"

#include <utility>
#include <vector>

#include "clothlab/host/errors.hpp"

namespace clothlab::host {

namespace {

// Throws PluginError unless status is OK: "<label> <action> failed (<status>): <message>".
void check(clothlab_status status, clothlab_message& message, const std::string& label,
           const char* action) {
  if (status == CLOTHLAB_OK) return;
  message.text[CLOTHLAB_MESSAGE_CAPACITY - 1] = '\0';
  throw PluginError(
      status, label + " " + action + " failed (" + status_name(status) + "): " + message.text);
}

std::string label_of(std::string_view kind, const char* id) { return std::string(kind) + " " + id; }

// The component's clothlab.text-parameters/1 table, or nullptr when it offers none (or one
// too small to read).
const clothlab_text_parameters_extension* text_parameters(const void* table) {
  const auto* texts = static_cast<const clothlab_text_parameters_extension*>(table);
  return texts != nullptr && texts->struct_size >= CLOTHLAB_TEXT_PARAMETERS_SIZE_1 ? texts
                                                                                   : nullptr;
}

// The table's specs; throws PluginError for one the host cannot read (a null name, help or
// default, a size below the published one, no room for a text), naming the component.
std::span<const clothlab_text_param_spec> text_specs(const void* table, const std::string& label) {
  const clothlab_text_parameters_extension* texts = text_parameters(table);
  if (texts == nullptr) return {};
  if (texts->count > 0 && (texts->specs == nullptr || texts->create == nullptr))
    throw PluginError(CLOTHLAB_ERROR_INTERNAL,
                      label + ": clothlab.text-parameters/1 has no specs or no create");
  for (uint32_t i = 0; i < texts->count; ++i) {
    const clothlab_text_param_spec& spec = texts->specs[i];
    if (spec.struct_size < CLOTHLAB_TEXT_PARAM_SPEC_SIZE_1 || spec.name == nullptr ||
        spec.help == nullptr || spec.default_text == nullptr || spec.max_length == 0)
      throw PluginError(CLOTHLAB_ERROR_INTERNAL,
                        label + ": clothlab.text-parameters/1 spec " + std::to_string(i) +
                            " is malformed (a null name, help or default, or no length)");
  }
  return {texts->specs, texts->count};
}

// Calls a component's `create` with validated values, through its text-parameters table when
// it has one; the object keeps the library loaded.
template <class Descriptor>
PluginObject create_object(const std::shared_ptr<const LibraryHandle>& library,
                           const Descriptor& descriptor, const void* text_table,
                           const ParamSet& params, const std::string& label, PluginCallSite site) {
  clothlab_message message{};
  void* object = nullptr;
  clothlab_status status;
  const clothlab_text_parameters_extension* texts = text_parameters(text_table);
  {
    const PluginCallMark mark(site, "create");
    const uint32_t value_count = static_cast<uint32_t>(params.values().size());
    if (texts != nullptr) {
      std::vector<const char*> text_values;
      for (const std::string& text : params.texts()) text_values.push_back(text.c_str());
      status = texts->create(params.values().data(), value_count, text_values.data(),
                             static_cast<uint32_t>(text_values.size()), &object, &message);
    } else {
      status = descriptor.create(params.values().data(), value_count, &object, &message);
    }
  }
  check(status, message, label, "create");
  if (object == nullptr)
    throw PluginError(CLOTHLAB_ERROR_INTERNAL, label + " create returned no instance");
  return PluginObject(library, object, descriptor.destroy, std::move(site));
}

}  // namespace

PluginObject::PluginObject(std::shared_ptr<const LibraryHandle> library, void* object,
                           void (*destroy)(void*), PluginCallSite site)
    : library_(std::move(library)), object_(object), destroy_(destroy), site_(std::move(site)) {}

PluginObject::~PluginObject() { release(); }

PluginObject::PluginObject(PluginObject&& other) noexcept
    : library_(std::move(other.library_)),
      object_(std::exchange(other.object_, nullptr)),
      destroy_(other.destroy_),
      site_(std::move(other.site_)) {}

PluginObject& PluginObject::operator=(PluginObject&& other) noexcept {
  if (this != &other) {
    release();
    library_ = std::move(other.library_);
    object_ = std::exchange(other.object_, nullptr);
    destroy_ = other.destroy_;
    site_ = std::move(other.site_);
  }
  return *this;
}

void PluginObject::release() noexcept {
  // Destroyed before the library reference drops, so the code is still mapped.
  if (object_ != nullptr) {
    const PluginCallMark mark(site_, "destroy");
    destroy_(object_);
  }
  object_ = nullptr;
  library_.reset();
}

// ------------------------------------------------------------------ integrator

IntegratorInstance::IntegratorInstance(const clothlab_integrator& descriptor, std::string label,
                                       PluginObject object)
    : descriptor_(&descriptor), label_(std::move(label)), object_(std::move(object)) {
  if (CLOTHLAB_HAS_FIELD(descriptor_, clothlab_integrator, get_extension) &&
      descriptor_->get_extension != nullptr)
    statistics_ = static_cast<const clothlab_solver_statistics_extension*>(
        descriptor_->get_extension(CLOTHLAB_EXT_SOLVER_STATISTICS));
}

void IntegratorInstance::prepare(const clothlab_system& system) {
  clothlab_message message{};
  steps_since_prepare_ = 0;
  clothlab_status status;
  {
    const PluginCallMark mark(object_.site(), "prepare");
    status = descriptor_->prepare(object_.get(), &system, &message);
  }
  check(status, message, label_, "prepare");
}

void IntegratorInstance::step(const clothlab_system& system, double t, double dt) {
  clothlab_message message{};
  clothlab_status status;
  {
    const PluginCallMark mark(object_.site(), "step", ++steps_since_prepare_);
    status = descriptor_->step(object_.get(), &system, t, dt, &message);
  }
  check(status, message, label_, "step");
}

std::optional<clothlab_solver_step_statistics> IntegratorInstance::last_step_statistics() const {
  if (statistics_ == nullptr || statistics_->last_step == nullptr) return std::nullopt;
  clothlab_solver_step_statistics statistics{};
  statistics.struct_size = sizeof statistics;
  clothlab_status status;
  {
    const PluginCallMark mark(object_.site(), "statistics", steps_since_prepare_);
    status = statistics_->last_step(object_.get(), &statistics);
  }
  if (status != CLOTHLAB_OK)
    throw PluginError(status, label_ + " solver statistics failed (" + status_name(status) + ")");
  return statistics;
}

IntegratorPlugin::IntegratorPlugin(std::shared_ptr<const LibraryHandle> library,
                                   std::filesystem::path path,
                                   const clothlab_integrator& descriptor)
    : library_(std::move(library)), path_(std::move(path)), descriptor_(&descriptor) {}

ComponentInfo IntegratorPlugin::info() const {
  return {"integrator",
          descriptor_->id,
          descriptor_->name,
          descriptor_->version,
          descriptor_->description,
          {descriptor_->params, descriptor_->param_count},
          path_};
}

const void* IntegratorPlugin::extension(const char* id) const {
  return clothlab_integrator_extension(descriptor_, id);
}

bool IntegratorPlugin::uses_velocity_forces() const {
  return (descriptor_->flags & CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES) != 0;
}

bool IntegratorPlugin::supports_precision(uint32_t precision) const {
  return precision < 32 && (descriptor_->precisions & (1u << precision)) != 0;
}

ParamSet IntegratorPlugin::default_params() const {
  return ParamSet(
      info().params, "integrator",
      text_specs(extension(CLOTHLAB_EXT_TEXT_PARAMETERS), label_of("integrator", descriptor_->id)));
}

IntegratorInstance IntegratorPlugin::create(const ParamSet& params) const {
  const std::string label = label_of("integrator", descriptor_->id);
  return IntegratorInstance(
      *descriptor_, label,
      create_object(library_, *descriptor_, extension(CLOTHLAB_EXT_TEXT_PARAMETERS), params, label,
                    {path_, descriptor_->id}));
}

// -------------------------------------------------------------------- scenario

ScenarioInstance::ScenarioInstance(const clothlab_scenario& descriptor, std::string label,
                                   PluginObject object)
    : descriptor_(&descriptor), label_(std::move(label)), object_(std::move(object)) {}

clothlab_scene ScenarioInstance::describe() const {
  clothlab_scene scene{};
  scene.struct_size = sizeof(clothlab_scene);
  clothlab_message message{};
  clothlab_status status;
  {
    const PluginCallMark mark(object_.site(), "describe");
    status = descriptor_->describe(object_.get(), &scene, &message);
  }
  check(status, message, label_, "describe");
  return scene;
}

ScenarioPlugin::ScenarioPlugin(std::shared_ptr<const LibraryHandle> library,
                               std::filesystem::path path, const clothlab_scenario& descriptor)
    : library_(std::move(library)), path_(std::move(path)), descriptor_(&descriptor) {}

ComponentInfo ScenarioPlugin::info() const {
  return {"scenario",
          descriptor_->id,
          descriptor_->name,
          descriptor_->version,
          descriptor_->description,
          {descriptor_->params, descriptor_->param_count},
          path_};
}

const void* ScenarioPlugin::extension(const char* id) const {
  return clothlab_scenario_extension(descriptor_, id);
}

ParamSet ScenarioPlugin::default_params() const {
  return ParamSet(
      info().params, "scenario",
      text_specs(extension(CLOTHLAB_EXT_TEXT_PARAMETERS), label_of("scenario", descriptor_->id)));
}

ScenarioInstance ScenarioPlugin::create(const ParamSet& params) const {
  const std::string label = label_of("scenario", descriptor_->id);
  return ScenarioInstance(
      *descriptor_, label,
      create_object(library_, *descriptor_, extension(CLOTHLAB_EXT_TEXT_PARAMETERS), params, label,
                    {path_, descriptor_->id}));
}

}  // namespace clothlab::host
