// Every key of every mode is a row of the one key table (host/session/run_keys.cpp): a setting read
// anywhere else drifts from it (sweep.monitor.wind_work_safety was parsed, fingerprinted and
// never applied). These tests read the host's sources, so a second reader fails them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "run_keys.hpp"

namespace clothlab::cli {
namespace {

const std::filesystem::path host_sources = std::filesystem::path(CLOTHLAB_SOURCE_DIR) / "host";

std::map<std::string, std::string> host_files() {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(host_sources)) {
    const std::string extension = entry.path().extension().string();
    if (!entry.is_regular_file() || (extension != ".cpp" && extension != ".hpp")) continue;
    std::ifstream in(entry.path());
    std::ostringstream text;
    text << in.rdbuf();
    files[std::filesystem::relative(entry.path(), host_sources).string()] = text.str();
  }
  return files;
}

TEST(OneKeyTable, EveryDottedKeyInTheHostsSourcesIsARowOfTheTable) {
  const std::regex dotted_key(
      "\"((integrator|scenario|stability|find_max_dt|frames|choose|material|plugin_params|sweep|"
      "slurm|work_precision)\\.[a-z_.]+)\"");
  const auto files = host_files();
  ASSERT_GT(files.size(), 50u) << host_sources;
  size_t keys_seen = 0;
  for (const auto& [name, text] : files) {
    if (name == "session/run_keys.cpp") continue;
    for (auto match = std::sregex_iterator(text.begin(), text.end(), dotted_key);
         match != std::sregex_iterator(); ++match) {
      const std::string key = (*match)[1];
      ++keys_seen;
      // The matrix is not a setting: its items become the cases' settings, read by one file.
      if (key.starts_with("sweep.matrix")) {
        EXPECT_EQ(name, "cli/sweep_file.cpp") << key << " read outside the sweep file reader";
        continue;
      }
      // File names: "frames.pvd", "material.hpp".
      if (key.ends_with(".pvd") || key.ends_with(".hpp") || key.ends_with(".cpp")) continue;
      EXPECT_NE(find_run_key(key), nullptr) << name << " names " << key << ", not in the table";
    }
  }
  EXPECT_GT(keys_seen, 5u);
}

TEST(OneKeyTable, OnlyTheTableTurnsASettingsTextIntoANumber) {
  const std::regex number_parser(
      "parse_real\\(|from_chars|std::sto[dfilu]|strto[dfl]|"
      "parse_param_text\\(");
  // Files that parse numbers that are not settings, each with the reason.
  const std::map<std::string, std::string> not_settings = {
      {"session/run_keys.cpp", "the table itself"},
      {"sweep/src/shard.cpp", "the --shard K/N flag"},
      {"cli/slurm_sweep.cpp", "sacct's answer"},
      // Labels and the drivers' arithmetic on cases the table has already checked, through the
      // same parse_real the table uses.
      {"sweep/src/case_expansion.cpp", "views of checked cases"},
  };
  for (const auto& [name, text] : host_files()) {
    const bool reads_settings = name.starts_with("cli/") || name.starts_with("session/") ||
                                name.starts_with("sweep/") || name.starts_with("config/");
    if (!reads_settings || not_settings.contains(name)) continue;
    EXPECT_FALSE(std::regex_search(text, number_parser))
        << name << " parses a number: settings are read by the key table (run_keys.cpp)";
  }
}

}  // namespace
}  // namespace clothlab::cli
