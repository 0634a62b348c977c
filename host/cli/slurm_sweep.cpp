#include "slurm_sweep.hpp"

#include <unistd.h>

#include <chrono>
#include <clothlab/host/errors.hpp>
#include <clothlab/io/atomic_file.hpp>
#include <clothlab/process/program.hpp>
#include <clothlab/sweep/progress.hpp>
#include <clothlab/sweep/results_store.hpp>
#include <clothlab/sweep/shard.hpp>
#include <clothlab/sweep/sweep_error.hpp>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace clothlab::cli {

namespace {

using process::find_on_path;
using process::ProgramOutput;
using process::run_program;

std::filesystem::path slurm_program(const std::string& name) {
  const auto found = find_on_path(name);
  if (!found)
    throw host::InputError("--slurm: " + name +
                           " not found on PATH: this machine has no Slurm (Debian: slurm-client)");
  return *found;
}

std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string joined(const std::set<std::size_t>& shards) {
  std::string text;
  for (std::size_t k : shards) {
    if (!text.empty()) text += ',';
    text += std::to_string(k);
  }
  return text;
}

// The batch script every array task runs: this clothlab, this sweep, shard $SLURM_ARRAY_TASK_ID.
// Tasks always resume their own store: a requeued task continues where it stopped.
std::string task_script(const SweepRequest& request, std::size_t shard_count) {
  std::string command = shell_quoted(std::filesystem::read_symlink("/proc/self/exe").string()) +
                        " --config " + shell_quoted(request.config_file.string()) +
                        " --shard \"$SLURM_ARRAY_TASK_ID/" + std::to_string(shard_count) +
                        "\" --resume";
  if (request.out_folder) command += " --out " + shell_quoted(request.out_folder->string());
  for (const std::string& entry : request.plugin_paths)
    command += " --plugin-path " + shell_quoted(entry);
  for (const Setting& setting : request.overrides)
    command += " --set " + shell_quoted(setting.key + "=" + setting.value);
  return "#!/bin/sh\n# Written by clothlab --slurm: array task K runs shard K of the "
         "sweep.\nexec " +
         command + "\n";
}

// squeue's %K with -r is one task id; a pending array not yet split may show "1-4,7%2".
std::set<std::size_t> task_ids(std::string text) {
  std::set<std::size_t> ids;
  text = text.substr(0, text.find('%'));
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find(',', start), text.size());
    const std::string part = text.substr(start, end - start);
    const std::size_t dash = part.find('-');
    try {
      const std::size_t first = std::stoul(part.substr(0, dash));
      const std::size_t last =
          dash == std::string::npos ? first : std::stoul(part.substr(dash + 1));
      for (std::size_t id = first; id <= last; ++id) ids.insert(id);
    } catch (const std::exception&) {
      // Not an array task id (e.g. "N/A"): nothing to count.
    }
    start = end + 1;
  }
  return ids;
}

struct QueueState {
  std::set<std::size_t> pending, running;
};

QueueState queue_state(const std::filesystem::path& squeue, const std::string& job) {
  for (int attempt = 0;; ++attempt) {
    const ProgramOutput listing =
        run_program({squeue.string(), "-h", "-r", "-j", job, "-o", "%K %T"});
    if (listing.exit_status == 0) {
      QueueState state;
      std::istringstream lines(listing.out);
      std::string ids, status;
      while (lines >> ids >> status)
        for (std::size_t id : task_ids(ids))
          (status == "PENDING" || status == "CONFIGURING" ? state.pending : state.running)
              .insert(id);
      return state;
    }
    // A job that ended long ago is no longer known to the controller: nothing is queued.
    if (listing.err.find("Invalid job id") != std::string::npos) return {};
    if (attempt == 10) throw std::runtime_error("squeue -j " + job + " failed: " + listing.err);
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
}

bool shard_complete(const std::filesystem::path& store) {
  try {
    return std::filesystem::exists(store) && sweep::read_results(store).complete;
  } catch (const sweep::SweepError&) {
    return false;  // being created right now, or damaged: not complete
  }
}

}  // namespace

std::string slurm_progress_line(std::size_t done, std::size_t total, std::size_t pending,
                                std::size_t running, std::size_t failed, double elapsed_s,
                                double eta_s) {
  const double percent = total > 0 ? 100.0 * static_cast<double>(done) / total : 100.0;
  char line[160];
  std::snprintf(line, sizeof line,
                "[%zu/%zu] %5.1f%%  tasks %zu pending, %zu running, %zu failed  elapsed %s  ETA %s",
                done, total, percent, pending, running, failed,
                sweep::Progress::format_duration(elapsed_s).c_str(),
                sweep::Progress::format_duration(eta_s).c_str());
  return line;
}

void run_sweep_on_slurm(const SweepRequest& request, const sweep::SweepSpec& spec,
                        std::size_t case_count, const sweep::Fingerprint& fingerprint,
                        std::ostream& out) {
  const std::filesystem::path sbatch = slurm_program("sbatch");
  const std::filesystem::path squeue = slurm_program("squeue");
  if (request.shard) throw host::InputError("--slurm chooses the shards itself: drop --shard");
  const std::size_t shard_count = std::max<std::size_t>(1, std::min(spec.slurm.tasks, case_count));
  const std::filesystem::path& base = spec.output;
  const auto store_of = [&](std::size_t k) { return sweep::shard_store(base, {k, shard_count}); };

  if (base.has_parent_path()) std::filesystem::create_directories(base.parent_path());
  std::set<std::size_t> to_submit;
  if (!request.resume) {
    sweep::remove_shard_results(base);
    for (std::size_t k = 1; k <= shard_count; ++k) to_submit.insert(k);
  } else {
    for (std::size_t k = 1; k <= shard_count; ++k) {
      if (!std::filesystem::exists(store_of(k))) {
        to_submit.insert(k);
        continue;
      }
      const sweep::StoredResults stored = sweep::read_results(store_of(k));
      const std::string changes = sweep::describe_changes(stored.fingerprint, fingerprint);
      if (!changes.empty())
        throw host::InputError(store_of(k).string() +
                               ": cannot resume: the sweep changed since these results were "
                               "written: " +
                               changes +
                               "; run without --resume to replace them, or use another --out");
      if (!stored.complete) to_submit.insert(k);
    }
  }

  std::string job;
  if (!to_submit.empty()) {
    const std::filesystem::path script = base.string() + ".slurm.sh";
    io::write_file_atomically(script, task_script(request, shard_count));
    std::vector<std::string> argv = {sbatch.string(),
                                     "--parsable",
                                     "--job-name=clothlab-" + spec.name,
                                     "--array=" + joined(to_submit),
                                     "--chdir=" + std::filesystem::current_path().string(),
                                     "--output=" + std::filesystem::absolute(base).string() +
                                         ".shard-%a-of-" + std::to_string(shard_count) + ".log",
                                     "--cpus-per-task=" + std::to_string(spec.slurm.cpus_per_task)};
    if (!spec.slurm.partition.empty()) argv.push_back("--partition=" + spec.slurm.partition);
    if (!spec.slurm.time.empty()) argv.push_back("--time=" + spec.slurm.time);
    argv.insert(argv.end(), spec.slurm.sbatch_options.begin(), spec.slurm.sbatch_options.end());
    argv.push_back(script.string());
    const ProgramOutput submitted = run_program(argv);
    job = submitted.out.substr(0, submitted.out.find_first_of(";\n"));
    if (submitted.exit_status != 0 || job.empty()) {
      std::string reason = submitted.err.empty() ? submitted.out : submitted.err;
      while (!reason.empty() && reason.back() == '\n') reason.pop_back();
      for (char& c : reason) c = c == '\n' ? ' ' : c;
      throw host::InputError("--slurm: sbatch refused the job array: " + reason);
    }
    out << "slurm job " << job << ": " << to_submit.size() << " of " << shard_count
        << " shard tasks submitted (--array=" << joined(to_submit) << "), " << case_count
        << " cases\n";
    out.flush();
  }
  if (!request.wait) {
    out << "  when it has finished: clothlab merge " << base.string() << "\n";
    return;
  }

  const bool terminal = sweep::stderr_is_terminal();
  const auto start = std::chrono::steady_clock::now();
  std::size_t done_at_start = 0;
  for (std::size_t k = 1; k <= shard_count; ++k)
    done_at_start += sweep::stored_case_count(store_of(k));
  std::map<std::size_t, bool> finished;  // shard -> complete, once its task has left the queue
  std::string last_counts;
  while (!job.empty()) {
    const QueueState queue = queue_state(squeue, job);
    std::size_t done = 0;
    for (std::size_t k = 1; k <= shard_count; ++k) done += sweep::stored_case_count(store_of(k));
    for (std::size_t k : to_submit)
      if (!queue.pending.count(k) && !queue.running.count(k) && !finished.count(k))
        finished[k] = shard_complete(store_of(k));
    std::size_t failed = 0;
    for (const auto& [k, complete] : finished) failed += complete ? 0 : 1;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::size_t done_now = done - std::min(done, done_at_start);
    const double eta =
        done_now > 0 ? elapsed / done_now * (case_count - std::min(done, case_count)) : -1;
    const std::string line = slurm_progress_line(done, case_count, queue.pending.size(),
                                                 queue.running.size(), failed, elapsed, eta);
    const std::string counts = line.substr(0, line.find("  elapsed"));
    if (terminal) {
      std::cerr << '\r' << line << std::flush;
    } else if (counts != last_counts) {
      std::cerr << line << '\n' << std::flush;
    }
    last_counts = counts;
    if (queue.pending.empty() && queue.running.empty()) break;
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
  if (terminal && !job.empty()) std::cerr << '\n';

  std::set<std::size_t> failed;
  for (std::size_t k = 1; k <= shard_count; ++k)
    if (!shard_complete(store_of(k))) failed.insert(k);
  if (!failed.empty())
    throw std::runtime_error(
        "slurm job " + job + ": shard tasks " + joined(failed) + " of " +
        std::to_string(shard_count) + " did not finish (logs: " + base.string() + ".shard-K-of-" +
        std::to_string(shard_count) + ".log); rerun with --slurm --resume to submit only those");
  const sweep::MergeSummary merged = sweep::merge_shards(base);
  out << "sweep " << spec.name << " (" << sweep::to_string(spec.mode) << "): " << case_count
      << " cases in " << merged.shards << " Slurm shards, " << merged.rows << " rows merged"
      << "\n  results: " << base.string() << ".csv, " << base.string() << ".json\n";
}

}  // namespace clothlab::cli
