// A run is described by dotted-key settings, whatever their origin: a config file or a sweep
// file (flattened YAML), the command-line flags and --set all produce the same keys.
//   integrator.plugin, scenario.plugin, dt, steps, duration, precision, threads, timeout,
//   integrator.<param>, scenario.<param>, plugin_params.<plugin id>.<param>, sweep.*
#pragma once

#include <string>
#include <vector>

namespace clothlab::config {

struct Setting {
  std::string key;     // "scenario.structural.ks"
  std::string value;   // text as written: "50", "[0, -9.81, 0]"
  std::string source;  // "configs/x.yaml:4:9", "--set", "--dt"
};

// "integrator" and "scenario" alone name the plugin: they become "<kind>.plugin".
std::string canonical_key(const std::string& key);

// Throws InputError if one layer (config file or command line) sets both steps and
// duration; across layers the later one simply wins.
void check_one_length(const std::vector<Setting>& layer, const std::string& layer_name);

}  // namespace clothlab::config
