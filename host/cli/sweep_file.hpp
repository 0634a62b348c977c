// A sweep file (format: clothlab/sweep/sweep_spec.hpp): the matrix is read here, item by item
// with its place in the file; every other key, sweep.* and slurm.* included, goes through the
// one key table like a single run's.
#pragma once

#include <clothlab/sweep/sweep_spec.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "settings.hpp"

namespace YAML {
class Node;
}

namespace clothlab::cli {

// `overrides` (the command line's --set) come after the file's settings and win. Throws
// InputError (SweepError for the file's structure) naming the source, key, value and what is
// allowed.
sweep::SweepSpec parse_sweep(const std::string& yaml_text, const std::string& source,
                             const std::vector<Setting>& overrides = {});
sweep::SweepSpec parse_sweep(const YAML::Node& root, const std::string& source,
                             const std::vector<Setting>& overrides = {});
sweep::SweepSpec load_sweep(const std::filesystem::path& path,
                            const std::vector<Setting>& overrides = {});

// Whether a YAML file has a `sweep:` section (so it is a sweep, not a single run).
bool is_sweep_file(const std::filesystem::path& path);

}  // namespace clothlab::cli
