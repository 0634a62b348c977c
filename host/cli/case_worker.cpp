#include "case_worker.hpp"

#include <memory>
#include <string>
#include <vector>

#include "case_execution.hpp"
#include "resident_plugins.hpp"
#include "run_config.hpp"

namespace clothlab::cli {
namespace {

// A request: {"task": "run" | "positions" | "predict" | "local-solve", "settings": [[key, value,
// source]...]}.
nlohmann::json serve_case(const nlohmann::json& request, const host::PluginSearchPath& search_path,
                          ResidentPlugins& resident) {
  std::vector<Setting> settings;
  for (const nlohmann::json& setting : request.at("settings"))
    settings.push_back({setting.at(0), setting.at(1), setting.at(2)});
  const RunConfig config = resolve_run_config(settings);
  const std::string task = request.at("task");
  LoadedPlugins plugins = resident.load(config, search_path);
  if (task == "predict") return predict_case(config, std::move(plugins));
  if (task == "local-solve") return local_solve_case(config, std::move(plugins));
  return run_case(config, std::move(plugins), task == "positions");
}

}  // namespace

CaseWorker::CaseWorker(const host::PluginSearchPath& search_path)
    : worker_([&search_path,
               resident = std::make_shared<ResidentPlugins>()](const nlohmann::json& request) {
        return serve_case(request, search_path, *resident);
      }) {}

nlohmann::json CaseWorker::ask(const std::string& task, const sweep::CaseSpec& c) {
  nlohmann::json settings = nlohmann::json::array();
  for (const Setting& setting : c.settings)
    settings.push_back({setting.key, setting.value, setting.source});
  return worker_.ask({{"task", task}, {"settings", settings}},
                     resolve_run_config(c.settings).timeout_s);
}

CaseRun CaseWorker::run(const sweep::CaseSpec& c, bool with_positions) {
  return case_run_from_json(ask(with_positions ? "positions" : "run", c));
}

nlohmann::json CaseWorker::predict(const sweep::CaseSpec& c) { return ask("predict", c); }

nlohmann::json CaseWorker::local_solve(const sweep::CaseSpec& c) { return ask("local-solve", c); }

}  // namespace clothlab::cli
