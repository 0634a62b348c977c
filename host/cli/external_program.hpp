// Runs another program (sbatch, squeue) and collects what it prints. Unlike run_isolated
// (isolation.hpp), which forks this process to run our own code, this executes a program.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace clothlab::cli {

struct ProgramOutput {
  int exit_status = -1;  // -1 when it died of a signal
  std::string out, err;
};

// The program's path on PATH, or nothing.
std::optional<std::filesystem::path> find_on_path(const std::string& name);

// Runs argv[0] (a path) with argv, waits for it. Throws std::runtime_error if it cannot start.
ProgramOutput run_program(const std::vector<std::string>& argv);

}  // namespace clothlab::cli
