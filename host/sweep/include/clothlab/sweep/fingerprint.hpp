// A sweep's fingerprint: every input that changes a case's result, as "name" -> "value".
// --resume and merge compare fingerprints so that rows of two different sweeps never mix.
//   mode, setting.<key> (fixed settings and --set, last one wins), matrix.<axis>,
//   monitor.*, work_precision.* / stability.* (in their mode), plugin.<id> (file identity)
#pragma once

#include <functional>
#include <map>
#include <string>
#include <string_view>

#include "clothlab/sweep/sweep_spec.hpp"

namespace clothlab::sweep {

using Fingerprint = std::map<std::string, std::string>;

// The identity of a plugin file for an id ("rk4"): e.g. its path, size and content hash.
using PluginIdentity = std::function<std::string(const std::string& plugin_id)>;

// plugin_identity is called once per integrator and scenario id the matrix uses; null leaves
// plugins out (tests without plugin files).
Fingerprint sweep_fingerprint(const SweepSpec& spec, const PluginIdentity& plugin_identity);

// "setting.duration '3' -> '0.3'; plugin.rk4 changed ('a' -> 'b')"; empty when equal.
std::string describe_changes(const Fingerprint& before, const Fingerprint& after);

// 64-bit FNV-1a of a file's bytes, as 16 hex digits. Throws SweepError if it cannot be read.
std::string file_hash(const std::string& path);
// The same hash of a text.
std::string text_hash(std::string_view text);

}  // namespace clothlab::sweep
