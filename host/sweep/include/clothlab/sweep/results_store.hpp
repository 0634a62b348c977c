// Sweep results, one row per case, in an SQLite database (WAL mode) with CSV and JSON exports.
//
//   <base>.sqlite: the store. Each row is one INSERT in its own transaction, so appending costs
//                  the same at 10 rows as at 10^5, and a crash loses at most the case that was
//                  running. Tables: meta(name, value) holds the format, the sweep's fingerprint
//                  (fingerprint.hpp), its metadata and whether it is complete; rows(seq,
//                  case_index, key, row) holds each row as JSON.
//   <base>.lock  : held (flock) by the one process writing the store; a second writer is
//                  refused with a one-line error instead of silently losing rows.
//   <base>.csv / <base>.json: exports written by write_exports(), rows ordered by case index
//                  (then by when they were stored), so a merged set of shards exports exactly
//                  what one unsharded run does.
//     <base>.json: {"sweep": {metadata...}, "rows": [{"key": ..., ...}, ...]}
//     <base>.csv : header = union of row fields in first-seen order; missing fields left empty.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

#include "clothlab/sweep/fingerprint.hpp"

namespace clothlab::sweep {

using Row = nlohmann::ordered_json;  // an object with at least a string "key"

class SqliteDatabase;
class SqliteStatement;

class ResultsStore {
 public:
  // Takes the writer lock. Without resume an existing store at base is replaced. With resume
  // its rows are loaded (a store that does not exist yet is created) and a store written with
  // another fingerprint is refused, naming what changed. Throws SweepError.
  ResultsStore(std::filesystem::path base, bool resume, const Fingerprint& fingerprint = {});
  ~ResultsStore();
  ResultsStore(const ResultsStore&) = delete;
  ResultsStore& operator=(const ResultsStore&) = delete;

  const std::filesystem::path& database_path() const { return database_path_; }
  const std::filesystem::path& csv_path() const { return csv_path_; }
  const std::filesystem::path& json_path() const { return json_path_; }

  void set_metadata(const nlohmann::ordered_json& metadata);
  bool contains(const std::string& key) const;
  // Read back from the database: only the keys are held in memory, because every case's fork
  // copies the page tables of all the memory this process holds.
  // All rows in the order they were stored (resumed rows first).
  std::vector<Row> rows() const;
  std::optional<Row> find(const std::string& key) const;
  std::size_t size() const { return keys_.size(); }
  std::size_t resumed_rows() const { return resumed_; }

  // Stores a row (its "key" must be new) for the case at case_index of the expanded sweep.
  // Throws SweepError on a bad row or when the database cannot be written.
  void append(Row row, std::size_t case_index);
  // Records that every case this store was meant to hold has its row (merge checks it).
  void mark_complete();
  // Writes <base>.csv and <base>.json atomically (clothlab/io) from the stored rows, in case
  // order. Throws io::WriteError when they cannot be written.
  void write_exports() const;

 private:
  std::filesystem::path database_path_, lock_path_, csv_path_, json_path_;
  int lock_fd_ = -1;
  std::unique_ptr<SqliteDatabase> database_;
  std::unique_ptr<SqliteStatement> insert_;
  nlohmann::ordered_json metadata_ = nlohmann::ordered_json::object();
  std::unordered_set<std::string> keys_;
  std::size_t resumed_ = 0;

  std::vector<Row> select_rows(const std::string& sql) const;
};

// A store read back without taking its lock (merge, progress of running shards).
struct StoredResults {
  Fingerprint fingerprint;
  nlohmann::ordered_json metadata = nlohmann::ordered_json::object();
  bool complete = false;
  std::vector<std::pair<std::size_t, Row>> rows;  // (case index, row), in case order
};
// Throws SweepError if the file is missing or not a results store.
StoredResults read_results(const std::filesystem::path& database);
// How many distinct cases have rows; 0 if the file or its tables do not exist yet (a shard
// task that has only just started: --slurm counts progress while the tasks run).
std::size_t stored_case_count(const std::filesystem::path& database);

// JSON and CSV export texts of rows (in the order given).
std::string rows_to_json(const nlohmann::ordered_json& metadata, const std::vector<Row>& rows);
std::string rows_to_csv(const std::vector<Row>& rows);

}  // namespace clothlab::sweep
