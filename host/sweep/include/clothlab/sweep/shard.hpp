// Shard K of N of a sweep: a deterministic split of the expanded cases, so that any machine
// (or a Slurm array task) can run its part. Case i goes to shard (i mod N) + 1, which spreads
// neighbouring, similarly expensive cases (one mesh size, one dt) over all shards. A shard
// writes its own store, <base>.shard-K-of-N.sqlite; merge_shards joins them into <base>.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "clothlab/sweep/case_spec.hpp"

namespace clothlab::sweep {

struct Shard {
  std::size_t index = 1;  // K, in [1, count]
  std::size_t count = 1;  // N
};

// "K/N" with 1 <= K <= N <= 100000; source names the flag in messages. Throws SweepError.
Shard parse_shard(const std::string& text, const std::string& source);
std::vector<CaseSpec> shard_cases(const std::vector<CaseSpec>& cases, Shard shard);
// <base>.shard-K-of-N (the store adds .sqlite).
std::filesystem::path shard_base(const std::filesystem::path& base, Shard shard);

// <base>.shard-K-of-N.sqlite
std::filesystem::path shard_store(const std::filesystem::path& base, Shard shard);
// Removes every <base>.shard-K-of-N.* file (stores of any shard count, their logs and locks),
// so that a fresh sharded run does not meet stale shards at the merge.
void remove_shard_results(const std::filesystem::path& base);

struct MergeSummary {
  std::size_t shards = 0;
  std::size_t rows = 0;
};

// Merges <base>.shard-K-of-N.sqlite, K = 1..N, into <base>.sqlite, <base>.csv and <base>.json,
// rows in case order: the same files an unsharded run writes. Throws SweepError when no shard
// store exists, stores of two shard counts exist, a shard is missing or incomplete, or the
// shards' fingerprints differ (naming what differs).
MergeSummary merge_shards(const std::filesystem::path& base);

}  // namespace clothlab::sweep
