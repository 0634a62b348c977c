#include "clothlab/sweep/trajectory_cache.hpp"

#include <clothlab/config/mesh_sides.hpp>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/run_summary.hpp>
#include <clothlab/io/atomic_file.hpp>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "clothlab/sweep/sweep_error.hpp"

namespace clothlab::sweep {

TrajectoryCache::TrajectoryCache(std::filesystem::path folder, PluginIdentity plugin_identity,
                                 std::string host_identity)
    : folder_(std::move(folder)),
      plugin_identity_(std::move(plugin_identity)),
      host_identity_(std::move(host_identity)) {}

std::string TrajectoryCache::identity(const CaseSpec& c) const {
  std::map<std::string, std::string> effective;
  for (const Setting& setting : c.settings) {
    if (setting.key == "timeout") continue;
    // "mesh" sets scenario.rows and scenario.cols: the same run however it is spelt (--choose
    // gives its error mesh as "mesh" over the scene's rows and cols, so the error run of a
    // 200 x 200 and of a 300 x 300 scene is one run).
    if (setting.key == "mesh") {
      const config::MeshSides sides = config::mesh_sides(setting.value);
      effective["scenario.rows"] = sides.rows;
      effective["scenario.cols"] = sides.cols;
    } else {
      effective[setting.key] = setting.value;
    }
  }
  std::string text = "host=" + host_identity_ + "\n";
  for (const auto& [key, value] : effective) {
    text += key + "=" + value + "\n";
    // A setting that names a file (a mesh) stands for what the file holds now.
    std::error_code error;
    if (!value.empty() && std::filesystem::is_regular_file(value, error))
      text += "file." + key + "=" + file_hash(value) + "\n";
  }
  if (plugin_identity_)
    for (const std::string& id : {c.integrator, c.scenario})
      text += "plugin." + id + "=" + plugin_identity_(id) + "\n";
  return text;
}

std::filesystem::path TrajectoryCache::path_of(const CaseSpec& c) const {
  return folder_ / (text_hash(identity(c)) + ".json");
}

Trajectory TrajectoryCache::run(const TrajectoryRunner& runner, const CaseSpec& c) {
  const std::string id = identity(c);
  const std::filesystem::path path = path_of(c);
  if (std::ifstream stored(path); stored) {
    // A file that does not parse or lacks a field is a miss (the run is computed again).
    try {
      const nlohmann::json cached = nlohmann::json::parse(stored);
      if (cached.at("identity").get<std::string>() == id) {
        Trajectory run;
        run.positions = cached.at("positions").get<std::vector<double>>();
        run.diagonal = cached.at("diagonal").get<double>();
        run.summary = host::run_summary_from_json(cached.at("summary"), path.string());
        ++hits_;
        return run;
      }
    } catch (const nlohmann::json::exception&) {
    } catch (const host::InputError&) {
    }
  }
  const Trajectory run = runner(c);
  if (!run.verdict.stable() || !std::isfinite(run.summary.max_stretch.over_run)) return run;
  const nlohmann::json record = {{"identity", id},
                                 {"positions", run.positions},
                                 {"diagonal", run.diagonal},
                                 {"summary", host::to_json(run.summary)}};
  try {
    std::filesystem::create_directories(folder_);
    io::write_file_atomically(path, record.dump());
  } catch (const std::exception& error) {
    throw SweepError("reference cache: " + std::string(error.what()));
  }
  return run;
}

}  // namespace clothlab::sweep
