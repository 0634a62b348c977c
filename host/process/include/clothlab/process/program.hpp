// Runs another program (sbatch, squeue) and collects what it prints, through the same
// supervision as run_isolated (isolation.hpp): its own process group, killed with its
// children at a deadline or when this process dies.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace clothlab::process {

struct ProgramOutput {
  int exit_status = -1;  // -1 when it died of a signal or was killed at the deadline
  bool timed_out = false;
  std::string out, err;
};

// The program's path on PATH, or nothing.
std::optional<std::filesystem::path> find_on_path(const std::string& name);

// Runs argv[0] (a path) with argv and this process's environment, waits for it (at most
// timeout_s). Throws std::runtime_error naming argv[0] if it cannot start.
ProgramOutput run_program(const std::vector<std::string>& argv, double timeout_s = 600.0);

}  // namespace clothlab::process
