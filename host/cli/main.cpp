// clothlab: runs one cloth simulation, a sweep, or a search for the largest stable dt, or
// lists the plugins it can find.
// Exit codes: 0 ok, 1 bad input, 2 plugin load or plugin error, 3 the run diverged, failed
// a stability check or its solver missed its tolerance (a sweep exits 0 whatever its cases did:
// they are results), 130 a single run stopped by SIGINT or SIGTERM (its outputs written).
#include <algorithm>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/plugin_search_path.hpp>
#include <clothlab/sweep/progress.hpp>
#include <exception>
#include <iostream>
#include <new>
#include <optional>

#include "choose_mode.hpp"
#include "command_line.hpp"
#include "config_file.hpp"
#include "dry_run.hpp"
#include "frames_output.hpp"
#include "interrupt.hpp"
#include "isolation.hpp"
#include "max_dt_search.hpp"
#include "output_file.hpp"
#include "plugin_listing.hpp"
#include "run_config.hpp"
#include "run_keys.hpp"
#include "run_report.hpp"
#include "simulation.hpp"
#include "sweep_file.hpp"
#include "sweep_mode.hpp"
#include "view_command.hpp"

namespace {

enum ExitCode {
  exit_ok = 0,
  exit_bad_input = 1,
  exit_plugin_error = 2,
  exit_diverged = 3,
  exit_interrupted = 130  // the shell's code for a SIGINT
};

int fail(int code, const std::string& message) {
  std::cerr << "clothlab: error: " << clothlab::host::one_line(message) << "\n";
  return code;
}

int run(int argc, const char* const argv[]) {
  using namespace clothlab::cli;
  if (argc > 1 && std::string_view(argv[1]) == "view") {
    clothlab::viewer::run_view_command(argc - 1, argv + 1, std::cout);
    return exit_ok;
  }
  if (argc >= 2 && std::string(argv[1]) == "merge") {
    const MergeCommandLine merge = parse_merge_command_line(argc - 1, argv + 1);
    if (merge.help)
      std::cout << merge_usage_text();
    else
      merge_sweep_outputs(merge.outputs, std::cout);
    return exit_ok;
  }
  const CommandLine command_line = parse_command_line(argc, argv);
  if (command_line.help) {
    std::cout << usage_text();
    return exit_ok;
  }
  if (command_line.keys_markdown) {
    std::cout << keys_markdown_table();
    return exit_ok;
  }
  const auto search_path = clothlab::host::PluginSearchPath::standard(command_line.plugin_paths);
  if (command_line.list_plugins) {
    // --json FILE writes the listing as JSON there instead of text to stdout; "-" is stdout.
    int errors = 0;
    if (command_line.json_file && *command_line.json_file != "-")
      write_file_atomically(*command_line.json_file, [&](std::ostream& out) {
        errors = list_plugins(search_path, true, out, std::cerr);
      });
    else
      errors = list_plugins(search_path, command_line.json_file.has_value(), std::cout, std::cerr);
    return errors == 0 ? exit_ok : exit_plugin_error;
  }

  if (command_line.config_file && is_sweep_file(*command_line.config_file)) {
    const bool frames = std::any_of(command_line.settings.begin(), command_line.settings.end(),
                                    [](const Setting& s) { return s.key.starts_with("frames."); });
    if (command_line.find_max_dt || command_line.json_file || command_line.state_file || frames)
      throw clothlab::host::InputError(
          "--config " + *command_line.config_file +
          " is a sweep: --find-max-dt, --json, --state-out and --frames are for single runs");
    SweepRequest request;
    request.config_file = *command_line.config_file;
    request.overrides = command_line.settings;
    request.resume = command_line.resume;
    if (command_line.out_folder) request.out_folder = *command_line.out_folder;
    request.shard = command_line.shard;
    request.slurm = command_line.slurm;
    request.wait = !command_line.no_wait;
    request.plugin_paths = command_line.plugin_paths;
    request.dry_run = command_line.dry_run;
    run_sweep_file(request, search_path, std::cout);
    return exit_ok;
  }
  if (command_line.resume || command_line.out_folder || command_line.shard || command_line.slurm ||
      command_line.no_wait)
    throw clothlab::host::InputError(
        "--resume, --out, --shard, --slurm and --no-wait need a sweep config (a `sweep:` section)");

  std::vector<Setting> settings;
  if (command_line.config_file) settings = read_config_file(*command_line.config_file);
  // Command-line values come after the file's, so they win.
  settings.insert(settings.end(), command_line.settings.begin(), command_line.settings.end());
  refuse_sweep_settings(settings);
  const Configuration whole = resolve_configuration(settings);
  const RunConfig& config = whole.run;
  for (const auto& output :
       {command_line.json_file, command_line.state_file, command_line.energy_file})
    if (output) check_output_path(*output);

  if (command_line.choose) {
    if (command_line.find_max_dt || command_line.json_file || command_line.state_file)
      throw clothlab::host::InputError(
          "--choose writes its own results (choose.output): no --find-max-dt, --json, --state-out");
    run_choose(settings, search_path, std::cout, command_line.dry_run);
    return exit_ok;
  }
  if (command_line.find_max_dt) {
    if (command_line.state_file || !config.frames.dir.empty())
      throw clothlab::host::InputError(
          "--state-out and --frames are for single runs, not --find-max-dt");
    if (command_line.dry_run) {
      const std::string described = check_single_run(config, search_path);
      std::cout << "dry run: --find-max-dt for " << described << "; nothing stepped\n";
      return exit_ok;
    }
    const nlohmann::json result =
        find_max_dt(whole, search_path, clothlab::sweep::stderr_is_terminal());
    if (command_line.json_file)
      write_file_atomically(*command_line.json_file,
                            [&](std::ostream& out) { out << result.dump(2) << "\n"; });
    std::cout << max_dt_summary(result);
    return exit_ok;
  }

  if (command_line.dry_run) {
    if (!config.frames.dir.empty()) check_creatable_folder(config.frames.dir, "--frames");
    const std::string described = check_single_run(config, search_path);
    std::cout << "dry run: " << described << ", " << config.steps << " steps; nothing stepped\n";
    return exit_ok;
  }
  // The run itself is plugin code: in a child, so a crash or hang is reported as one. Ctrl-C
  // reaches the child (forwarded), which stops stepping and still writes every output.
  install_interrupt_handler();
  const nlohmann::json run = run_isolated(
      [&] {
        Simulation simulation(config, search_path);
        std::optional<FramesOutput> frames;
        if (!config.frames.dir.empty()) frames.emplace(config, simulation);
        const RunRecord record =
            simulation.run({frames ? &*frames : nullptr, &interrupt_requested(),
                            command_line.energy_file.has_value()});
        if (frames) frames->finish(record);
        if (command_line.energy_file)
          write_file_atomically(*command_line.energy_file,
                                [&](std::ostream& out) { write_energy_csv(record, out); });
        if (command_line.json_file)
          write_file_atomically(*command_line.json_file, [&](std::ostream& out) {
            out << summary_json(record).dump(2) << "\n";
          });
        if (command_line.state_file)
          write_file_atomically(*command_line.state_file, [&](std::ostream& out) {
            write_state_csv(simulation.cloth(), out);
          });
        return nlohmann::json{{"summary", human_summary(summarize(record))},
                              {"stable", record.stable},
                              {"interrupted", record.interrupted},
                              {"unconverged", record.failed_check == unconverged_check},
                              {"verdict", record.verdict}};
      },
      config.timeout_s, /*forward_interrupt=*/true);
  if (!command_line.quiet) {
    std::cout << run["summary"].get<std::string>();
    if (!config.frames.dir.empty())
      std::cout << "  frames written to " << config.frames.dir << "\n  watch them: " << argv[0]
                << " view " << config.frames.dir << " (writes a page to open in a browser)\n";
  }
  if (run["interrupted"].get<bool>())
    return fail(exit_interrupted, run["verdict"].get<std::string>() + " (outputs written)");
  if (!run["stable"].get<bool>())
    return fail(exit_diverged, (run["unconverged"].get<bool>() ? "run " : "run diverged: ") +
                                   run["verdict"].get<std::string>());
  return exit_ok;
}

}  // namespace

int main(int argc, char* argv[]) {
  try {
    return run(argc, argv);
  } catch (const clothlab::host::InputError& error) {
    return fail(exit_bad_input, error.what());
  } catch (const clothlab::io::WriteError& error) {
    return fail(exit_bad_input, error.what());
  } catch (const clothlab::host::PluginLoadError& error) {
    return fail(exit_plugin_error, error.what());
  } catch (const clothlab::host::PluginError& error) {
    return fail(exit_plugin_error, error.what());
  } catch (const std::bad_alloc&) {
    return fail(exit_plugin_error, "out of memory");
  } catch (const std::exception& error) {
    // Also a run whose child process crashed or timed out: the plugin's fault.
    return fail(exit_plugin_error, error.what());
  }
}
