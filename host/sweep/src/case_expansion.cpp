#include <algorithm>
#include <clothlab/host/param_text.hpp>
#include <cmath>

#include "clothlab/sweep/case_spec.hpp"
#include "clothlab/sweep/sweep_error.hpp"

namespace clothlab::sweep {
namespace {

// Axis name in keys and result columns: "integrator" rather than "integrator.plugin".
std::string coordinate_name(const std::string& key) {
  if (key == "integrator.plugin") return "integrator";
  if (key == "scenario.plugin") return "scenario";
  return key;
}

std::string make_key(const std::vector<std::pair<std::string, std::string>>& coordinates) {
  std::string key;
  for (const auto& [name, value] : coordinates) {
    key += (key.empty() ? "" : ";") + name + "=" + value;
  }
  return key;
}

// Fills the convenience fields from the settings (later settings win). Values are not checked
// here: every case goes through the run's one key table before the first case runs, so a value
// that does not parse leaves its field at the default and never reaches a run.
void derive_views(CaseSpec& spec) {
  spec.precision = "float32";
  spec.duration = 0.0;
  spec.steps = 0;
  for (const Setting& setting : spec.settings) {
    const auto number = host::parse_real(setting.value);
    const bool whole = number && *number >= 1 && *number <= 1e15 && *number == std::floor(*number);
    if (setting.key == "integrator.plugin") {
      spec.integrator = setting.value;
    } else if (setting.key == "scenario.plugin") {
      spec.scenario = setting.value;
    } else if (setting.key == "precision") {
      spec.precision = setting.value;
    } else if (setting.key == "dt" && number) {
      spec.dt = *number;
    } else if (setting.key == "duration" && number) {
      spec.duration = *number;
      spec.steps = 0;
    } else if (setting.key == "steps" && whole) {
      spec.steps = static_cast<uint64_t>(*number);
      spec.duration = 0.0;
    }
  }
}

}  // namespace

std::string CaseSpec::setting(const std::string& key) const {
  for (auto it = settings.rbegin(); it != settings.rend(); ++it) {
    if (it->key == key) return it->value;
  }
  return {};
}

std::vector<CaseSpec> expand_cases(const SweepSpec& spec) {
  // Checked as it grows: 64 two-valued axes wrapped the product to 0.
  std::size_t total = 1;
  for (const Axis& axis : spec.axes) {
    total *= axis.values.size();
    if (total > max_cases)
      throw SweepError(spec.source + ": sweep.matrix has more than " + std::to_string(max_cases) +
                       " cases (at axis " + axis.key + "); allowed: at most " +
                       std::to_string(max_cases));
  }
  std::vector<CaseSpec> cases;
  cases.reserve(total);
  std::vector<std::size_t> digit(spec.axes.size(), 0);  // mixed-radix counter, last axis fastest
  for (std::size_t index = 0; index < total; ++index) {
    CaseSpec c;
    c.index = index;
    c.settings = spec.fixed;
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      const Setting& value = spec.axes[a].values[digit[a]];
      c.coordinates.emplace_back(coordinate_name(spec.axes[a].key),
                                 host::canonical_value(value.value));
      c.settings.push_back(value);
    }
    c.key = make_key(c.coordinates);
    derive_views(c);
    cases.push_back(std::move(c));
    for (std::size_t a = spec.axes.size(); a-- > 0;) {
      if (++digit[a] < spec.axes[a].values.size()) break;
      digit[a] = 0;
    }
  }
  return cases;
}

CaseSpec with_setting(const CaseSpec& base, const std::string& key, const std::string& value,
                      bool as_coordinate) {
  CaseSpec c = base;
  c.settings.push_back({key, value, "sweep"});
  derive_views(c);
  if (!as_coordinate) return c;
  const std::string name = coordinate_name(key);
  const std::string canonical = host::canonical_value(value);
  auto found = std::find_if(c.coordinates.begin(), c.coordinates.end(),
                            [&](const auto& coordinate) { return coordinate.first == name; });
  if (found != c.coordinates.end()) {
    found->second = canonical;
  } else {
    c.coordinates.emplace_back(name, canonical);
  }
  c.key = make_key(c.coordinates);
  return c;
}

CaseSpec with_dt(const CaseSpec& base, double dt) {
  return with_setting(base, "dt", host::format_number(dt));
}

}  // namespace clothlab::sweep
