#include "runner.hpp"

#include <chrono>
#include <clothlab/host/library_handle.hpp>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "fixtures.hpp"
#include "isolation.hpp"
#include "scene_validation.hpp"

namespace clothlab::conformance {
namespace {

constexpr int exercise_steps = 20;

std::string plugin_label(const std::string& path) {
  std::string name = std::filesystem::path(path).filename().string();
  if (name.size() > 3 && name.ends_with(".so")) name.resize(name.size() - 3);
  return name;
}

ParameterSubject subject_of(const clothlab_integrator& integrator) {
  const clothlab_integrator* c = &integrator;
  return {c->id, c->params, c->param_count,
          [c](const Values& values, clothlab_message& message) {
            void* instance = nullptr;
            const clothlab_status status =
                c->create(values.data(), static_cast<uint32_t>(values.size()), &instance, &message);
            if (status == CLOTHLAB_OK) c->destroy(instance);
            return status;
          },
          [c](const Values& values) {
            Cloth cloth(sheet_scene(3, 3, true), preferred_precision(*c), pipeline_for(*c));
            IntegratorInstance instance(*c, values);
            instance.prepare(cloth);
            instance.run(cloth, exercise_steps, 1e-3);
          }};
}

ParameterSubject subject_of(const clothlab_scenario& scenario) {
  const clothlab_scenario* c = &scenario;
  return {
      c->id, c->params, c->param_count,
      [c](const Values& values, clothlab_message& message) {
        void* instance = nullptr;
        const clothlab_status status = create_scenario(*c, values, &instance, message);
        if (status == CLOTHLAB_OK) c->destroy(instance);
        return status;
      },
      [c](const Values& values) { require_valid_scene(ScenarioInstance(*c, values).describe()); }};
}

class PluginRun {
 public:
  PluginRun(const std::string& path, const RunOptions& options, const ResultSink& sink)
      : label_(plugin_label(path)), options_(options), sink_(sink) {}

  // Runs `check`; reports it when it matches the filter. Returns whether it passed.
  bool run(const Check& check, bool report = true) {
    CheckResult result{label_, check.component, check.name, false, "", 0};
    const bool wanted = !options_.filter || options_.filter->matches(result.full_name());
    const auto start = std::chrono::steady_clock::now();
    const Verdict verdict =
        options_.in_process ? run_guarded(check.body)
                            : run_isolated(check.body, options_.timeout_s * check.timeout_scale);
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.passed = verdict.passed;
    result.reason = verdict.reason;
    if (wanted && report) sink_(result);
    return verdict.passed;
  }

  // Runs only the checks that match the filter; a skipped check counts as passed here.
  bool run_all(const std::vector<Check>& checks) {
    bool all_passed = true;
    for (const Check& check : checks) {
      CheckResult probe{label_, check.component, check.name, false, "", 0};
      if (options_.filter && !options_.filter->matches(probe.full_name())) continue;
      all_passed = run(check) && all_passed;
    }
    return all_passed;
  }

 private:
  std::string label_;
  const RunOptions& options_;
  const ResultSink& sink_;
};

// Rejects an override naming a parameter the component lacks or a value outside its range.
void validate_overrides(const std::string& component, const clothlab_param_spec* specs,
                        uint32_t count) {
  for (const ParameterOverride& override : parameter_overrides()) {
    if (override.component != component) continue;
    const std::string flag = "--param " + component + "." + override.name;
    const clothlab_param_spec* spec = nullptr;
    std::string known;
    for (uint32_t i = 0; i < count; ++i) {
      known += (i ? ", " : "") + std::string(specs[i].name);
      if (override.name == specs[i].name) spec = &specs[i];
    }
    if (spec == nullptr)
      throw std::invalid_argument(flag + ": " + component + " has no such parameter (it has: " +
                                  (known.empty() ? "none" : known) + ")");
    for (int k = 0; k < (spec->type == CLOTHLAB_PARAM_VEC3 ? 3 : 1); ++k)
      if (!(override.value.v[k] >= spec->min_value && override.value.v[k] <= spec->max_value))
        throw std::invalid_argument(flag + " = " + std::to_string(override.value.v[k]) +
                                    ": allowed [" + std::to_string(spec->min_value) + ", " +
                                    std::to_string(spec->max_value) + "]");
  }
}

// Only components whose parameter array is readable; a broken one fails descriptor.fields.
void validate_all_overrides(const clothlab_plugin_descriptor& library) {
  if (parameter_overrides().empty()) return;
  const auto readable = [](const clothlab_param_spec* specs, uint32_t count) {
    if (count > 0 && specs == nullptr) return false;
    for (uint32_t i = 0; i < count; ++i)
      if (specs[i].name == nullptr) return false;
    return true;
  };
  for (uint32_t i = 0; i < library.integrator_count && library.integrators; ++i)
    if (const clothlab_integrator* c = library.integrators[i];
        c != nullptr && c->id != nullptr && readable(c->params, c->param_count))
      validate_overrides(c->id, c->params, c->param_count);
  for (uint32_t i = 0; i < library.scenario_count && library.scenarios; ++i)
    if (const clothlab_scenario* c = library.scenarios[i];
        c != nullptr && c->id != nullptr && readable(c->params, c->param_count))
      validate_overrides(c->id, c->params, c->param_count);
}

void run_components(const clothlab_plugin_descriptor& library, PluginRun& run,
                    const RunOptions& options) {
  const std::vector<Check> descriptor = descriptor_checks(library);
  // Behaviour checks need sound metadata: a component whose fields fail is not called.
  auto fields_ok = [&](const char* id) {
    for (const Check& check : descriptor)
      if (check.component == id && check.name == "descriptor.fields") return run.run(check, false);
    return false;
  };
  run.run_all(descriptor);
  for (uint32_t i = 0; i < library.integrator_count && library.integrators; ++i) {
    const clothlab_integrator* integrator = library.integrators[i];
    if (integrator == nullptr || integrator->id == nullptr || !fields_ok(integrator->id)) continue;
    run.run_all(parameter_checks(subject_of(*integrator), options.settings));
    run.run_all(lifecycle_checks(*integrator));
    run.run_all(numerics_checks(*integrator));
    run.run_all(attachment_checks(*integrator));
    run.run_all(robustness_checks(*integrator));
    run.run_all(stability_checks(*integrator));
    run.run_all(contacts_checks(*integrator));
  }
  for (uint32_t i = 0; i < library.scenario_count && library.scenarios; ++i) {
    const clothlab_scenario* scenario = library.scenarios[i];
    if (scenario == nullptr || scenario->id == nullptr || !fields_ok(scenario->id)) continue;
    run.run_all(parameter_checks(subject_of(*scenario), options.settings));
    run.run_all(scenario_checks(*scenario));
  }
}

}  // namespace

void run_plugin(const std::string& path, const RunOptions& options, const ResultSink& sink) {
  PluginRun run(path, options, sink);
  const std::vector<Check> loading = loading_checks(path);
  // The runner opens the library itself only after a child has opened it safely, the version
  // gate accepts it (later checks read the descriptor's layout) and a child has loaded it
  // again after unloading it (the runner itself opens it twice).
  const auto gate = [&](const char* name) {
    for (const Check& check : loading)
      if (check.name == name) return run.run(check, false);
    return false;
  };
  if (!gate("loading.dlopen") || !gate("loading.abi-version") || !gate("loading.reload")) {
    run.run_all(loading);
    return;
  }
  {
    // A bad --param is found before any check runs, not after a dozen. Closed again while the
    // loading checks run: loading.reload's children must unload it for real.
    const auto library = host::LibraryHandle::open(path);
    validate_all_overrides(*library->descriptor());
  }
  run.run_all(loading);
  const auto library = host::LibraryHandle::open(path);
  run_components(*library->descriptor(), run, options);
}

}  // namespace clothlab::conformance
