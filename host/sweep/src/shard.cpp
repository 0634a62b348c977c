#include "clothlab/sweep/shard.hpp"

#include <algorithm>
#include <clothlab/host/param_text.hpp>
#include <map>
#include <optional>
#include <string_view>
#include <unordered_set>

#include "clothlab/sweep/results_store.hpp"
#include "clothlab/sweep/sweep_error.hpp"

namespace clothlab::sweep {

namespace {

// A run of 1 to 6 decimal digits, the whole of text; nullopt otherwise.
std::optional<std::size_t> parse_digits(std::string_view text) {
  if (text.empty() || text.size() > 6 ||
      !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  return static_cast<std::size_t>(*host::parse_real(text));
}

}  // namespace

Shard parse_shard(const std::string& text, const std::string& source) {
  const std::size_t slash = text.find('/');
  if (slash != std::string::npos) {
    const auto index = parse_digits(std::string_view(text).substr(0, slash));
    const auto count = parse_digits(std::string_view(text).substr(slash + 1));
    if (index && count) {
      const Shard shard{*index, *count};
      if (shard.index >= 1 && shard.index <= shard.count && shard.count <= 100000) return shard;
    }
  }
  throw SweepError(source + " " + text + ": allowed K/N with 1 <= K <= N <= 100000, e.g. 2/8");
}

std::vector<CaseSpec> shard_cases(const std::vector<CaseSpec>& cases, Shard shard) {
  std::vector<CaseSpec> mine;
  for (const CaseSpec& c : cases)
    if (c.index % shard.count + 1 == shard.index) mine.push_back(c);
  return mine;
}

std::filesystem::path shard_base(const std::filesystem::path& base, Shard shard) {
  return base.string() + ".shard-" + std::to_string(shard.index) + "-of-" +
         std::to_string(shard.count);
}

std::filesystem::path shard_store(const std::filesystem::path& base, Shard shard) {
  return shard_base(base, shard).string() + ".sqlite";
}

namespace {

std::filesystem::path folder_of(const std::filesystem::path& base) {
  return base.has_parent_path() ? base.parent_path() : std::filesystem::path(".");
}

// The shard of a file named <base>.shard-K-of-N.<extension>, with its extension; nullopt for
// any other name.
struct ShardFile {
  Shard shard;
  std::string_view extension;
};

std::optional<ShardFile> parse_shard_file(const std::filesystem::path& base,
                                          std::string_view name) {
  const std::string prefix = base.filename().string() + ".shard-";
  if (name.substr(0, prefix.size()) != prefix) return std::nullopt;
  name.remove_prefix(prefix.size());
  const std::size_t of = name.find("-of-");
  if (of == std::string_view::npos) return std::nullopt;
  const std::size_t dot = name.find('.', of);
  if (dot == std::string_view::npos) return std::nullopt;
  const auto index = parse_digits(name.substr(0, of));
  const auto count = parse_digits(name.substr(of + 4, dot - of - 4));
  if (!index || !count) return std::nullopt;
  return ShardFile{{*index, *count}, name.substr(dot)};
}

}  // namespace

void remove_shard_results(const std::filesystem::path& base) {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder_of(base), error))
    if (parse_shard_file(base, entry.path().filename().string()))
      std::filesystem::remove_all(entry.path(), error);
}

MergeSummary merge_shards(const std::filesystem::path& base) {
  const std::filesystem::path folder = folder_of(base);
  std::map<std::size_t, std::map<std::size_t, std::filesystem::path>> by_count;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    const auto file = parse_shard_file(base, name);
    if (file && file->extension == ".sqlite")
      by_count[file->shard.count][file->shard.index] = entry.path();
  }
  const std::string what = base.string() + ".shard-K-of-N.sqlite";
  if (by_count.empty()) throw SweepError(what + ": no shard results to merge");
  if (by_count.size() > 1)
    throw SweepError(what + ": shard results of " + std::to_string(by_count.begin()->first) +
                     " and " + std::to_string(by_count.rbegin()->first) +
                     " shards lie side by side; remove the stale ones");
  const auto& [count, stores] = *by_count.begin();
  std::vector<StoredResults> shards;
  for (std::size_t k = 1; k <= count; ++k) {
    const Shard shard{k, count};
    const auto found = stores.find(k);
    const std::string name = shard_store(base, shard).string();
    if (found == stores.end())
      throw SweepError(name + ": missing; run shard " + std::to_string(k) + "/" +
                       std::to_string(count));
    shards.push_back(read_results(found->second));
    if (!shards.back().complete)
      throw SweepError(name + ": shard " + std::to_string(k) + "/" + std::to_string(count) +
                       " is incomplete; rerun it with --resume");
    const std::string changes =
        describe_changes(shards.front().fingerprint, shards.back().fingerprint);
    if (!changes.empty()) throw SweepError(name + ": not the same sweep as shard 1: " + changes);
  }
  // Every shard's rows are in case order; interleave them by case index. A row two shards
  // both wrote (a work-precision reference shared by their cases) is kept once, at its
  // first case: where an unsharded run writes it.
  std::vector<std::pair<std::size_t, const Row*>> ordered;
  for (const StoredResults& shard : shards)
    for (const auto& [case_index, row] : shard.rows) ordered.emplace_back(case_index, &row);
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  ResultsStore merged(base, false, shards.front().fingerprint);
  merged.set_metadata(shards.front().metadata);
  for (const auto& [case_index, row] : ordered)
    if (!merged.contains((*row)["key"].get<std::string>())) merged.append(*row, case_index);
  merged.mark_complete();
  merged.write_exports();
  return {count, merged.size()};
}

}  // namespace clothlab::sweep
