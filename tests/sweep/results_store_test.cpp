#include "clothlab/sweep/results_store.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

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

std::vector<std::string> files_in(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(ResultsStore, AppendStoresRowsAndExportsWriteCompleteJsonAndCsv) {
  ScratchFolder scratch;
  {
    ResultsStore store(scratch.path() / "sub" / "results", false);
    store.append(row("a", 1.5), 0);
    Row second = row("b", 2.0);
    second["note"] = "x, \"quoted\"";
    store.append(second, 1);
    EXPECT_EQ(read_results(store.database_path()).rows.size(), 2u);  // stored before any export
    store.write_exports();
    const auto document = nlohmann::json::parse(read_text(store.json_path()));
    ASSERT_EQ(document["rows"].size(), 2u);
    EXPECT_EQ(document["rows"][1]["key"], "b");
    EXPECT_EQ(read_text(store.csv_path()), "key,value,note\na,1.5,\nb,2,\"x, \"\"quoted\"\"\"\n");
  }
  // No temporary file left behind; the WAL is folded back into the database on close.
  EXPECT_EQ(
      files_in(scratch.path() / "sub"),
      (std::vector<std::string>{"results.csv", "results.json", "results.lock", "results.sqlite"}));
}

// --slurm counts the shards' rows while their tasks run: a store whose task has created the
// file but not yet its tables counts as none done, not as an error that ends the wait.
TEST(ResultsStore, AStoreWithoutItsTablesYetCountsNoCases) {
  ScratchFolder folder;
  const std::filesystem::path path = folder.path() / "shard-1-of-4.sqlite";
  EXPECT_EQ(stored_case_count(path), 0u);
  std::ofstream(path).close();  // an empty file is an SQLite database without tables
  EXPECT_EQ(stored_case_count(path), 0u);
}

TEST(ResultsStore, ExportsOrderRowsByCaseIndexWhateverOrderTheyWereStoredIn) {
  ScratchFolder scratch;
  ResultsStore store(scratch.path() / "results", false);
  store.append(row("c", 3.0), 2);
  store.append(row("a", 1.0), 0);
  store.append(row("a2", 1.1), 0);
  store.append(row("b", 2.0), 1);
  store.write_exports();
  EXPECT_EQ(read_text(store.csv_path()), "key,value\na,1\na2,1.1\nb,2\nc,3\n");
}

TEST(ResultsStore, ExportsReplaceFilesByRenameSoOpenReadersKeepTheOldCompleteVersion) {
  ScratchFolder scratch;
  ResultsStore store(scratch.path() / "results", false);
  store.append(row("a", 1.0), 0);
  store.write_exports();
  const std::string before = read_text(store.json_path());
  std::ifstream old_reader(store.json_path());  // opened on the old version
  store.append(row("b", 2.0), 1);
  store.write_exports();
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
    first.append(row("a", 1.0), 0);
    first.append(row("b", 2.0), 1);
  }
  ResultsStore resumed(scratch.path() / "results", true);
  EXPECT_EQ(resumed.resumed_rows(), 2u);
  EXPECT_TRUE(resumed.contains("a"));
  EXPECT_TRUE(resumed.contains("b"));
  EXPECT_FALSE(resumed.contains("c"));
  resumed.append(row("c", 3.0), 2);
  resumed.write_exports();
  const auto document = nlohmann::json::parse(read_text(resumed.json_path()));
  EXPECT_EQ(document["rows"].size(), 3u);
  EXPECT_EQ(document["sweep"]["name"], "demo");
}

TEST(ResultsStore, WithoutResumeOldResultsAreReplaced) {
  ScratchFolder scratch;
  {
    ResultsStore first(scratch.path() / "results", false);
    first.append(row("a", 1.0), 0);
  }
  ResultsStore fresh(scratch.path() / "results", false);
  EXPECT_FALSE(fresh.contains("a"));
  fresh.append(row("b", 2.0), 0);
  EXPECT_EQ(read_results(fresh.database_path()).rows.size(), 1u);
}

TEST(ResultsStore, ResumeFromACorruptStoreIsAnError) {
  ScratchFolder scratch;
  std::ofstream(scratch.path() / "results.sqlite") << "{\"rows\": [";
  EXPECT_THROW(ResultsStore(scratch.path() / "results", true), SweepError);
}

TEST(ResultsStore, DuplicateOrMissingKeysAreRejected) {
  ScratchFolder scratch;
  ResultsStore store(scratch.path() / "results", false);
  store.append(row("a", 1.0), 0);
  EXPECT_THROW(store.append(row("a", 2.0), 1), SweepError);
  EXPECT_THROW(store.append(Row{{"value", 1}}, 1), SweepError);
  EXPECT_EQ(store.rows().size(), 1u);
  EXPECT_EQ(read_results(store.database_path()).rows.size(), 1u);
}

TEST(ResultsStore, ResumeWithAChangedFingerprintIsRefusedNamingWhatChanged) {
  ScratchFolder scratch;
  const Fingerprint original = {{"setting.duration", "3"}, {"plugin.rk4", "librk4.so 1a2b"}};
  {
    ResultsStore first(scratch.path() / "results", false, original);
    first.append(row("a", 1.0), 0);
  }
  Fingerprint edited = original;
  edited["setting.duration"] = "0.3";
  try {
    ResultsStore resumed(scratch.path() / "results", true, edited);
    FAIL() << "a changed sweep was resumed";
  } catch (const SweepError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("cannot resume"), std::string::npos) << message;
    EXPECT_NE(message.find("setting.duration '3' -> '0.3'"), std::string::npos) << message;
    EXPECT_EQ(message.find("plugin.rk4"), std::string::npos) << message;  // unchanged
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  // The refusal left the stored rows alone: the unchanged sweep still resumes them.
  ResultsStore resumed(scratch.path() / "results", true, original);
  EXPECT_TRUE(resumed.contains("a"));
}

TEST(ResultsStore, ASecondWriterOfTheSameStoreIsRefusedWithAOneLineError) {
  ScratchFolder scratch;
  const auto base = scratch.path() / "results";
  int opened[2], release[2];
  ASSERT_EQ(::pipe(opened), 0);
  ASSERT_EQ(::pipe(release), 0);
  const pid_t first = ::fork();
  ASSERT_GE(first, 0);
  if (first == 0) {  // the first writer: holds the store until told to finish
    int status = 1;
    try {
      ResultsStore store(base, false);
      store.append(row("first", 1.0), 0);
      char byte = 1;
      status = ::write(opened[1], &byte, 1) == 1 && ::read(release[0], &byte, 1) == 1 ? 0 : 1;
      store.append(row("first-after", 2.0), 1);
    } catch (...) {
      status = 2;
    }
    ::_exit(status);
  }
  char byte = 0;
  ASSERT_EQ(::read(opened[0], &byte, 1), 1);
  std::string refusal;
  try {
    ResultsStore second(base, true);
  } catch (const SweepError& error) {
    refusal = error.what();
  }
  ASSERT_EQ(::write(release[1], &byte, 1), 1);
  int status = 0;
  ASSERT_EQ(::waitpid(first, &status, 0), first);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_NE(refusal.find("another clothlab process (pid " + std::to_string(first) + ")"),
            std::string::npos)
      << refusal;
  EXPECT_EQ(refusal.find('\n'), std::string::npos) << refusal;
  // Nothing the first writer stored was lost to the second attempt.
  EXPECT_EQ(read_results(base.string() + ".sqlite").rows.size(), 2u);
  // Once the first is done the store is free again.
  ResultsStore later(base, true);
  EXPECT_EQ(later.resumed_rows(), 2u);
}

}  // namespace
}  // namespace clothlab::sweep
