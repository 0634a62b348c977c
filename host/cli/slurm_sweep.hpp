// `clothlab --config sweep.yaml --slurm`: the sweep as one Slurm job array. Task K of N runs
// `clothlab --shard K/N` (SLURM_ARRAY_TASK_ID) into its own store; this process waits with a
// progress line (cases done, tasks pending/running/failed, ETA), then merges the shards into
// the files an unsharded run writes. With --resume only the shards with missing cases are
// submitted again.
#pragma once

#include <clothlab/sweep/fingerprint.hpp>
#include <clothlab/sweep/sweep_spec.hpp>
#include <cstddef>
#include <ostream>
#include <string>

#include "sweep_mode.hpp"

namespace clothlab::cli {

// Throws InputError without sbatch/squeue on PATH, for a changed sweep on --resume, or when
// sbatch refuses the job; std::runtime_error when tasks failed (naming them and their logs).
void run_sweep_on_slurm(const SweepRequest& request, const sweep::SweepSpec& spec,
                        std::size_t case_count, const sweep::Fingerprint& fingerprint,
                        std::ostream& out);

// "[120/200]  60.0%  tasks 1 pending, 3 running, 0 failed  elapsed 0:12  ETA 0:08"
std::string slurm_progress_line(std::size_t done, std::size_t total, std::size_t pending,
                                std::size_t running, std::size_t failed, double elapsed_s,
                                double eta_s);

}  // namespace clothlab::cli
