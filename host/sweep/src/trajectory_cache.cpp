#include "clothlab/sweep/trajectory_cache.hpp"

#include <clothlab/config/mesh_sides.hpp>
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
        run.wall_s = cached.at("wall_s").get<double>();
        run.force_evals = cached.at("force_evals").get<uint64_t>();
        run.max_stretch = cached.at("max_stretch").get<double>();
        run.max_stretch_away_from_pins = cached.at("max_stretch_away_from_pins").get<double>();
        run.p99_stretch = cached.at("p99_stretch").get<double>();
        run.ms_per_frame = cached.at("ms_per_frame").get<double>();
        run.attached_particles = cached.at("attached_particles").get<uint32_t>();
        run.colliders = cached.at("colliders").get<uint32_t>();
        ++hits_;
        return run;
      }
    } catch (const nlohmann::json::exception&) {
    }
  }
  const Trajectory run = runner(c);
  if (!run.verdict.stable() || !std::isfinite(run.max_stretch)) return run;
  const nlohmann::json record = {{"identity", id},
                                 {"positions", run.positions},
                                 {"diagonal", run.diagonal},
                                 {"wall_s", run.wall_s},
                                 {"force_evals", run.force_evals},
                                 {"max_stretch", run.max_stretch},
                                 {"max_stretch_away_from_pins", run.max_stretch_away_from_pins},
                                 {"p99_stretch", run.p99_stretch},
                                 {"ms_per_frame", run.ms_per_frame},
                                 {"attached_particles", run.attached_particles},
                                 {"colliders", run.colliders}};
  try {
    std::filesystem::create_directories(folder_);
    io::write_file_atomically(path, record.dump());
  } catch (const std::exception& error) {
    throw SweepError("reference cache: " + std::string(error.what()));
  }
  return run;
}

}  // namespace clothlab::sweep
