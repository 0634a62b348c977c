#include "command_line.hpp"

#include <boost/program_options.hpp>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/subcommand_line.hpp>
#include <sstream>

#include "run_keys.hpp"

namespace po = boost::program_options;

namespace clothlab::cli {

namespace {

po::options_description describe_options() {
  po::options_description options("Options");
  options.add_options()("help,h", "show this help and exit");
  // The flags that stand for a key, described by the key table.
  for (const KeyInfo& info : run_keys())
    if (info.flag)
      options.add_options()(
          info.flag, po::value<std::string>(),
          (std::string(info.help) + " (key " + info.key + ": " + describe_allowed(info) +
           (info.default_value ? std::string(", default ") + info.default_value : std::string()) +
           ")")
              .c_str());
  options.add_options()("config", po::value<std::string>(),
                        "YAML config file; command-line values override it")(
      "set", po::value<std::vector<std::string>>()->composing(),
      "KEY=VALUE, repeatable; plugin parameters are integrator.KEY / scenario.KEY")(
      "plugin-path", po::value<std::vector<std::string>>()->composing(),
      "folders searched for plugins first (repeatable, ':'-separated); then "
      "CLOTHLAB_PLUGIN_PATH, then ../lib/clothlab/plugins beside the executable")(
      "json", po::value<std::string>(), "write the run summary as JSON to FILE")(
      "state-out", po::value<std::string>(), "write the final state as CSV to FILE")(
      "energy-out", po::value<std::string>(),
      "write the energy at t = 0 and at every stability check as CSV to FILE "
      "(integrator,t,kinetic,spring,gravity,total; tools/plot.py energy draws it)")(
      "list-plugins",
      "list the plugins on the search path with their parameters, traits and extensions; with "
      "--json FILE (or - for stdout) as JSON (docs/reference/plugin-listing.md)")(
      "find-max-dt",
      "bisect dt to the largest stable step for the configured duration (keys "
      "find_max_dt.tolerance, .dt_min, .dt_max) and print the predicted dt_max beside it")(
      "choose",
      "which integrator for this scene: for each integrator on the plugin path the cheapest "
      "substeps (and iterations) at --frame-rate that stay stable, within choose.stretch_limit "
      "and within choose.error_tolerance of a converged reference at T = choose.duration (see "
      "Keys below); ranked table to stdout and choose.output")(
      "out", po::value<std::string>(), "sweep: folder for the results files")(
      "resume",
      "sweep: keep the results already written and run only the missing cases (with --slurm: "
      "resubmit only the shards with missing cases); refused if the sweep changed")(
      "shard", po::value<std::string>(),
      "sweep: run only shard K/N of the cases (case i is in shard i mod N + 1) into "
      "<output>.shard-K-of-N.sqlite; join the shards with `clothlab merge OUTPUT`")(
      "slurm",
      "sweep: submit as one Slurm job array, one task per shard (keys slurm.tasks, "
      "slurm.partition, slurm.time, slurm.cpus_per_task, slurm.sbatch), wait and merge")(
      "no-wait", "--slurm: return once the job array is submitted")("quiet", "print no summary")(
      "dry-run",
      "check everything and step nothing: settings, plugins loaded with their parameters, the "
      "scene and the integrator created (a sweep: every case; --choose: the scene and its "
      "candidates), output paths writable; prints what would run and exits 0");
  return options;
}

std::optional<std::string> string_option(const po::variables_map& values, const char* name) {
  if (!values.count(name)) return std::nullopt;
  return values[name].as<std::string>();
}

// A file or folder option: an empty value would show up later as an error naming no path.
std::optional<std::string> path_option(const po::variables_map& values, const char* name) {
  std::optional<std::string> path = string_option(values, name);
  if (path && path->empty())
    throw host::InputError(std::string("--") + name + " = '': an empty path; allowed: a path");
  return path;
}

Setting parse_set(const std::string& assignment) {
  const size_t equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0)
    throw host::InputError("--set " + assignment + ": expected KEY=VALUE, e.g. scenario.rows=50");
  return {canonical_key(assignment.substr(0, equals)), assignment.substr(equals + 1), "--set"};
}

// A flag and a --set naming the same key (--dt 0.001 --set dt=0.002) have no sensible order
// between them, so neither wins: it is an error.
void reject_flag_and_set_conflicts(const std::vector<Setting>& settings) {
  for (const Setting& flag : settings) {
    if (flag.source == "--set") continue;
    for (const Setting& set : settings)
      if (set.source == "--set" && set.key == flag.key)
        throw host::InputError(flag.source + " " + flag.value + " conflicts with --set " + set.key +
                               "=" + set.value + "; allowed: one of them");
  }
}

// Options for the project's own tools, left out of --help.
po::options_description describe_hidden_options() {
  po::options_description options;
  options.add_options()("keys-markdown",
                        "print the key table as Markdown (tools/reference.py settings)");
  return options;
}

po::options_description describe_merge_options() {
  po::options_description options("clothlab merge options");
  options.add_options()("help,h", "show this help and exit");
  return options;
}

}  // namespace

CommandLine parse_command_line(int argc, const char* const argv[]) {
  po::variables_map values;
  // Declared empty so a stray word is an error instead of being ignored.
  const po::positional_options_description no_positional_arguments;
  try {
    po::options_description options = describe_options();
    options.add(describe_hidden_options());
    po::store(po::command_line_parser(argc, argv)
                  .options(options)
                  .positional(no_positional_arguments)
                  .run(),
              values);
    po::notify(values);
  } catch (const po::error& error) {
    throw host::InputError(std::string("command line: ") + error.what() + "; see --help");
  }

  CommandLine command_line;
  command_line.help = values.count("help") > 0;
  command_line.list_plugins = values.count("list-plugins") > 0;
  command_line.quiet = values.count("quiet") > 0;
  command_line.config_file = path_option(values, "config");
  command_line.json_file = path_option(values, "json");
  command_line.state_file = path_option(values, "state-out");
  command_line.energy_file = path_option(values, "energy-out");
  command_line.find_max_dt = values.count("find-max-dt") > 0;
  command_line.resume = values.count("resume") > 0;
  command_line.choose = values.count("choose") > 0;
  command_line.out_folder = path_option(values, "out");
  command_line.shard = string_option(values, "shard");
  command_line.slurm = values.count("slurm") > 0;
  command_line.no_wait = values.count("no-wait") > 0;
  command_line.keys_markdown = values.count("keys-markdown") > 0;
  command_line.dry_run = values.count("dry-run") > 0;
  if (values.count("plugin-path"))
    command_line.plugin_paths = values["plugin-path"].as<std::vector<std::string>>();
  for (const KeyInfo& info : run_keys())
    if (info.flag)
      if (const auto value = string_option(values, info.flag))
        command_line.settings.push_back({info.key, *value, std::string("--") + info.flag});
  if (values.count("set"))
    for (const std::string& assignment : values["set"].as<std::vector<std::string>>())
      command_line.settings.push_back(parse_set(assignment));
  check_one_length(command_line.settings, "command line");
  reject_flag_and_set_conflicts(command_line.settings);
  return command_line;
}

std::string usage_text() {
  std::ostringstream text;
  text << "Usage: clothlab [options]\n"
          "       clothlab view RUN_DIR... [--out DIR]   (see clothlab view --help)\n"
          "       clothlab merge OUTPUT...   (joins sweep shards; see clothlab merge --help)\n"
          "Runs one cloth simulation with an integrator plugin on a scenario plugin and prints\n"
          "a summary, or a sweep when the --config file has a `sweep:` section.\n"
          "Every run is judged by the stability monitor (keys stability.interval,\n"
          "stability.max_stretch, stability.energy_margin); a failed check stops the run.\n"
          "Runs and sweep cases run in a child process, killed after `timeout` seconds\n"
          "(key timeout). Command-line values override the config file; a flag\n"
          "and a --set for the same key are an error. A sweep checks every case (settings,\n"
          "plugins, parameter values) before the first one runs.\n"
          "Exit codes: 0 ok (a sweep: finished, whatever its cases did), 1 bad input (also\n"
          "a sweep case's), 2 plugin error (also a crash or timeout of a single run), 3 the\n"
          "run diverged or failed a stability check, 130 a run stopped by Ctrl-C (SIGINT)\n"
          "or SIGTERM, its outputs written.\n\n"
       << describe_options() << "\n"
       << keys_help_text();
  return text.str();
}

MergeCommandLine parse_merge_command_line(int argc, const char* const argv[]) {
  po::options_description options = describe_merge_options();
  options.add_options()("outputs", po::value<std::vector<std::string>>());
  const po::variables_map values = host::parse_subcommand_line(
      argc, argv, options, "outputs",
      "merge: ", "; allowed: --help and OUTPUT names (see clothlab merge --help)");
  MergeCommandLine merge;
  merge.help = values.count("help") > 0;
  if (values.count("outputs")) merge.outputs = values["outputs"].as<std::vector<std::string>>();
  if (!merge.help && merge.outputs.empty())
    throw host::InputError("merge: no OUTPUT given; allowed: OUTPUT..., e.g. results/stress");
  return merge;
}

std::string merge_usage_text() {
  std::ostringstream text;
  text << "Usage: clothlab merge OUTPUT...\n"
          "Joins the shard results of each sweep output (OUTPUT.shard-K-of-N.sqlite, written by\n"
          "--shard K/N) into OUTPUT.sqlite, OUTPUT.csv and OUTPUT.json. Every shard must be\n"
          "complete and of the same sweep. An OUTPUT that starts with '-' follows '--'.\n\n"
       << describe_merge_options();
  return text.str();
}

}  // namespace clothlab::cli
