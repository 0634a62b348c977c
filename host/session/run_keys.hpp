// The keys of a run (config file, sweep case, --set KEY=VALUE and the flags that stand for a
// key): one table, from which --help, the unknown-key message, each value's validation and the
// defaults all come. A key added to the table is documented, checked and applied.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "settings.hpp"

namespace clothlab::cli {

struct Configuration;

enum class KeyType {
  Real,             // a number in [min_value, max_value]
  PositiveReal,     // a number in (0, max_value]
  Whole,            // a whole number in [min_value, max_value]
  Choice,           // one of `allowed` ("float32, float64")
  ChoiceList,       // one or a list of `allowed`, each once: "[vtp, obj]"
  Names,            // one or a list of names: "[rk4, verlet]"; `allowed` says what they name
  Mesh,             // ROWSxCOLS or N, each a whole number in [min_value, max_value]
  Text,             // any text; `allowed` says what
  NonEmptyText,     // text that is not empty; `allowed` says what
  PluginParameter,  // a family ("integrator.<parameter>"), checked by the plugin once loaded
};

// A value checked against its key's type.
struct KeyValue {
  double number = 0;               // Real, PositiveReal, Whole
  std::string text;                // Choice, Mesh (as ROWSxCOLS), Text, NonEmptyText
  std::vector<std::string> words;  // ChoiceList, Names
  Setting setting;                 // as given, with its key and source
};

struct KeyInfo {
  const char* key;  // "dt"; a family: "integrator.<parameter>"
  KeyType type;
  double min_value, max_value;
  const char* unit;     // "s"; "" for none
  const char* allowed;  // the choices, what a text or name is, or a number's rule beyond its range
  const char* default_value;  // applied before any setting; nullptr: unset (`help` says why)
  const char* help;
  const char* flag;  // the command-line flag that stands for the key ("frame-rate"), or nullptr
  void (*apply)(Configuration& config, const KeyValue& value);
};

std::span<const KeyInfo> run_keys();

// The key's entry (a family's for "integrator.damping"), or nullptr.
const KeyInfo* find_run_key(const std::string& key);

// "real in (0, 10] s", "float32, float64": said by --help and by every error for the key.
std::string describe_allowed(const KeyInfo& info);

// Throws InputError "SOURCE: KEY = VALUE: PROBLEM; allowed: ..." for a value the key refuses.
KeyValue check_value(const KeyInfo& info, const Setting& setting);

// "SOURCE: unknown key K (did you mean D?); valid: ..." for a key not in the table.
std::string unknown_key_message(const Setting& setting);

// The "Keys" section of --help: each key with what it allows, its default and what it does.
std::string keys_help_text();

// The same keys as a Markdown table (key, allowed, default, flag, what it does): the body of
// docs/reference/settings.md, printed by the hidden option --keys-markdown.
std::string keys_markdown_table();

}  // namespace clothlab::cli
