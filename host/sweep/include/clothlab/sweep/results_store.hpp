// Sweep results as CSV (spreadsheets) and JSON (tools), one row per case.
//
// Every append rewrites both files whole through a temporary file and a rename, so a reader
// (or a crash) never sees a partial file: either the previous complete version or the new one.
// The JSON file is the source of truth for --resume: its rows are loaded and their keys skipped.
//   <base>.json: {"sweep": {metadata...}, "rows": [{"key": ..., ...}, ...]}
//   <base>.csv : header = union of row fields in first-seen order; missing fields left empty.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <unordered_set>
#include <vector>

namespace clothlab::sweep {

using Row = nlohmann::ordered_json;  // an object with at least a string "key"

class ResultsStore {
 public:
  // Creates base's folder. Without resume, existing files are replaced at the first write. With
  // resume, rows are loaded from <base>.json if it exists; throws SweepError if it cannot be read
  // or parsed.
  ResultsStore(std::filesystem::path base, bool resume);

  const std::filesystem::path& csv_path() const { return csv_path_; }
  const std::filesystem::path& json_path() const { return json_path_; }

  void set_metadata(const nlohmann::ordered_json& metadata);
  bool contains(const std::string& key) const;
  const std::vector<Row>& rows() const { return rows_; }
  std::size_t resumed_rows() const { return resumed_; }

  // Adds a row (its "key" must be new) and rewrites both files atomically. Throws SweepError
  // on a bad row, io::WriteError when the files cannot be written (clothlab/io).
  void append(Row row);
  // Rewrites both files atomically from the rows held (e.g. after set_metadata).
  void flush() const;

 private:
  std::filesystem::path csv_path_, json_path_;
  nlohmann::ordered_json metadata_ = nlohmann::ordered_json::object();
  std::vector<Row> rows_;
  std::unordered_set<std::string> keys_;
  std::size_t resumed_ = 0;
};

// CSV text of rows: header from the union of fields, RFC 4180 quoting.
std::string rows_to_csv(const std::vector<Row>& rows);

}  // namespace clothlab::sweep
