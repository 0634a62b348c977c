// clothlab-conformance [options] PLUGIN.so... — validates integrator and scenario plugins.
#include <boost/program_options.hpp>
#include <clothlab/host/subcommand_line.hpp>
#include <clothlab/io/atomic_file.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "fixtures.hpp"
#include "report.hpp"
#include "runner.hpp"

namespace po = boost::program_options;
using namespace clothlab::conformance;

namespace {

constexpr int exit_usage = 2;

struct CommandLine {
  RunOptions options;
  std::vector<std::string> plugins;
  std::string json_path, junit_path;
  std::vector<std::string> params;
  std::vector<std::string> texts;
  std::string filter_text;
};

[[noreturn]] void usage_error(const std::string& message) {
  std::cerr << "clothlab-conformance: " << message << "\n";
  std::exit(exit_usage);
}

po::options_description option_list(CommandLine& line, double& timeout, std::string& filter,
                                    std::string& seed) {
  po::options_description described("clothlab-conformance [options] PLUGIN.so...\nOptions");
  described.add_options()("help,h", "print this help")(
      "timeout", po::value(&timeout)->default_value(10.0),
      "seconds one check may run before it fails as hung (> 0)")(
      "in-process", po::bool_switch(&line.options.in_process),
      "run checks in this process (for a debugger): a crash then ends the run")(
      "filter", po::value(&filter),
      "run only checks whose \"plugin:component check\" matches this POSIX extended regex")(
      "seed", po::value(&seed), "fuzzing seed (default: random; always printed)")(
      "json", po::value(&line.json_path), "also write the results as JSON to FILE")(
      "junit", po::value(&line.junit_path), "also write the results as JUnit XML to FILE")(
      "param", po::value(&line.params)->composing(),
      "ID.NAME=VALUE[,Y,Z]: start every check of component ID from this value instead of "
      "the default (repeatable)")(
      "text", po::value(&line.texts)->composing(),
      "ID.NAME=TEXT: the same for a text parameter (clothlab.text-parameters/1), e.g. "
      "mesh.file=assets/meshes/disc.obj (repeatable)");
  return described;
}

// "verlet.damping=0" or "flag.wind.direction=1,0,0": the component id is up to the first dot.
ParameterOverride parse_override(const std::string& text) {
  const size_t dot = text.find('.');
  const size_t equals = text.find('=');
  if (dot == std::string::npos || equals == std::string::npos || dot == 0 || equals < dot + 2)
    usage_error("--param \"" + text + "\": expected ID.NAME=VALUE[,Y,Z]");
  ParameterOverride override{text.substr(0, dot), text.substr(dot + 1, equals - dot - 1), {}};
  std::string rest = text.substr(equals + 1);
  for (int k = 0; k < 3; ++k) {
    size_t used = 0;
    try {
      override.value.v[k] = std::stod(rest, &used);
    } catch (const std::exception&) {
      usage_error("--param \"" + text + "\": value \"" + rest + "\" is not a number");
    }
    rest = rest.substr(used);
    if (rest.empty()) {
      for (int j = k + 1; j < 3; ++j) override.value.v[j] = override.value.v[k];
      return override;
    }
    if (rest[0] != ',' || k == 2) usage_error("--param \"" + text + "\": expected VALUE[,Y,Z]");
    rest = rest.substr(1);
  }
  return override;
}

CommandLine parse(int argc, char** argv) {
  CommandLine line;
  double timeout = 10.0;
  std::string filter, seed;
  const po::options_description described = option_list(line, timeout, filter, seed);
  po::options_description hidden;
  hidden.add_options()("plugin", po::value(&line.plugins));
  po::options_description all;
  all.add(described).add(hidden);
  po::variables_map values;
  try {
    values = clothlab::host::parse_subcommand_line(argc, argv, all, "plugin", "", " (see --help)");
  } catch (const clothlab::host::InputError& error) {
    usage_error(error.what());
  }
  if (values.count("help")) {
    std::cout << described << "\n";
    std::exit(0);
  }
  if (!(timeout > 0) || timeout > 86400)
    usage_error("--timeout = " + std::to_string(timeout) + ": allowed (0, 86400] seconds");
  line.options.timeout_s = timeout;
  line.filter_text = filter;
  if (!filter.empty()) {
    try {
      line.options.filter = std::make_shared<const CheckFilter>(filter);
    } catch (const std::invalid_argument& e) {
      usage_error("--filter = \"" + filter + "\": not a valid regular expression (" + e.what() +
                  ")");
    }
  }
  if (seed.empty()) {
    line.options.settings.seed = std::random_device{}();
  } else {
    size_t used = 0;
    try {
      line.options.settings.seed = std::stoull(seed, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != seed.size() || seed[0] == '-')
      usage_error("--seed = \"" + seed + "\": allowed an integer in [0, 2^64)");
  }
  std::vector<ParameterOverride> overrides;
  for (const std::string& text : line.params) overrides.push_back(parse_override(text));
  set_parameter_overrides(std::move(overrides));
  std::vector<TextOverride> text_overrides;
  for (const std::string& text : line.texts) {
    const size_t dot = text.find('.'), equals = text.find('=');
    if (dot == std::string::npos || equals == std::string::npos || dot == 0 || equals < dot + 2)
      usage_error("--text \"" + text + "\": expected ID.NAME=TEXT");
    text_overrides.push_back(
        {text.substr(0, dot), text.substr(dot + 1, equals - dot - 1), text.substr(equals + 1)});
  }
  set_text_overrides(std::move(text_overrides));
  if (line.plugins.empty()) usage_error("no plugin given (see --help)");
  for (std::string& plugin : line.plugins) {
    if (!std::filesystem::is_regular_file(plugin))
      usage_error("plugin \"" + plugin + "\": no such file");
    // A name without '/' would go to dlopen's library search, not to the file just checked.
    plugin = std::filesystem::absolute(plugin).lexically_normal().string();
  }
  return line;
}

}  // namespace

int main(int argc, char** argv) {
  const CommandLine line = parse(argc, argv);
  // A report that cannot be written is known before the checks run.
  try {
    for (const std::string& path : {line.json_path, line.junit_path})
      if (!path.empty()) clothlab::io::check_output_path(path);
  } catch (const clothlab::io::WriteError& e) {
    usage_error(e.what());
  }
  RunReport report;
  report.seed = line.options.settings.seed;
  report.timeout_s = line.options.timeout_s;
  std::cout << "clothlab-conformance: seed " << report.seed << " (rerun with --seed " << report.seed
            << "), timeout " << report.timeout_s << " s"
            << (line.options.in_process ? ", in-process" : "") << std::endl;
  try {
    for (const std::string& plugin : line.plugins)
      run_plugin(plugin, line.options, [&](const CheckResult& result) {
        std::cout << result_line(result) << std::endl;
        report.results.push_back(result);
      });
  } catch (const std::invalid_argument& e) {
    usage_error(e.what());
  }
  std::cout << summary_line(report) << std::endl;
  if (line.options.filter && report.results.empty())
    usage_error("--filter = \"" + line.filter_text +
                "\" matched no check (see the names in a run "
                "without --filter)");
  try {
    if (!line.json_path.empty())
      clothlab::io::write_file_atomically(line.json_path, to_json(report));
    if (!line.junit_path.empty())
      clothlab::io::write_file_atomically(line.junit_path, to_junit(report));
  } catch (const std::exception& e) {
    std::cerr << "clothlab-conformance: " << e.what() << "\n";
    return exit_usage;
  }
  return report.failed() == 0 ? 0 : 1;
}
