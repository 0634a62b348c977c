#include "clothlab/sweep/results_store.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "clothlab/sweep/sweep_error.hpp"
#include "sweep_test_support.hpp"

namespace clothlab::sweep {
namespace {

using testing::read_text;
using testing::ScratchFolder;

Row row(const std::string& key, double value) {
  Row r;
  r["key"] = key;
  r["value"] = value;
  return r;
}

std::size_t files_in(const std::filesystem::path& folder) {
  std::size_t count = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder)) ++count;
  return count;
}

TEST(ResultsStore, AppendWritesCompleteJsonAndCsvWithoutLeftovers) {
  ScratchFolder scratch;
  ResultsStore store(scratch.path() / "sub" / "results", false);
  store.append(row("a", 1.5));
  Row second = row("b", 2.0);
  second["note"] = "x, \"quoted\"";
  store.append(second);

  const auto document = nlohmann::json::parse(read_text(store.json_path()));
  ASSERT_EQ(document["rows"].size(), 2u);
  EXPECT_EQ(document["rows"][1]["key"], "b");
  EXPECT_EQ(read_text(store.csv_path()), "key,value,note\na,1.5,\nb,2,\"x, \"\"quoted\"\"\"\n");
  EXPECT_EQ(files_in(scratch.path() / "sub"), 2u);  // no temporary file left behind
}

TEST(ResultsStore, ReplacesFilesByRenameSoOpenReadersKeepTheOldCompleteVersion) {
  ScratchFolder scratch;
  ResultsStore store(scratch.path() / "results", false);
  store.append(row("a", 1.0));
  const std::string before = read_text(store.json_path());
  std::ifstream old_reader(store.json_path());  // opened on the old version
  store.append(row("b", 2.0));
  std::stringstream seen;
  seen << old_reader.rdbuf();
  // Writing in place would have truncated the file under the reader; a rename leaves the
  // old version whole for it, and the path now names the new version.
  EXPECT_EQ(seen.str(), before);
  EXPECT_EQ(nlohmann::json::parse(read_text(store.json_path()))["rows"].size(), 2u);
}

TEST(ResultsStore, ResumeLoadsRowsAndKnowsTheirKeys) {
  ScratchFolder scratch;
  {
    ResultsStore first(scratch.path() / "results", false);
    first.set_metadata({{"name", "demo"}});
    first.append(row("a", 1.0));
    first.append(row("b", 2.0));
  }
  ResultsStore resumed(scratch.path() / "results", true);
  EXPECT_EQ(resumed.resumed_rows(), 2u);
  EXPECT_TRUE(resumed.contains("a"));
  EXPECT_TRUE(resumed.contains("b"));
  EXPECT_FALSE(resumed.contains("c"));
  resumed.append(row("c", 3.0));
  const auto document = nlohmann::json::parse(read_text(resumed.json_path()));
  EXPECT_EQ(document["rows"].size(), 3u);
  EXPECT_EQ(document["sweep"]["name"], "demo");
}

TEST(ResultsStore, WithoutResumeOldResultsAreReplaced) {
  ScratchFolder scratch;
  {
    ResultsStore first(scratch.path() / "results", false);
    first.append(row("a", 1.0));
  }
  ResultsStore fresh(scratch.path() / "results", false);
  EXPECT_FALSE(fresh.contains("a"));
  fresh.append(row("b", 2.0));
  EXPECT_EQ(nlohmann::json::parse(read_text(fresh.json_path()))["rows"].size(), 1u);
}

TEST(ResultsStore, ResumeFromACorruptFileIsAnError) {
  ScratchFolder scratch;
  std::ofstream(scratch.path() / "results.json") << "{\"rows\": [";
  EXPECT_THROW(ResultsStore(scratch.path() / "results", true), SweepError);
}

TEST(ResultsStore, DuplicateOrMissingKeysAreRejected) {
  ScratchFolder scratch;
  ResultsStore store(scratch.path() / "results", false);
  store.append(row("a", 1.0));
  EXPECT_THROW(store.append(row("a", 2.0)), SweepError);
  EXPECT_THROW(store.append(Row{{"value", 1}}), SweepError);
  EXPECT_EQ(store.rows().size(), 1u);
}

}  // namespace
}  // namespace clothlab::sweep
