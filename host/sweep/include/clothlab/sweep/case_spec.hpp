// One case of a sweep: the settings a single run needs, and a stable key that names it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "clothlab/sweep/sweep_spec.hpp"

namespace clothlab::sweep {

struct CaseSpec {
  // "integrator=rk4;scenario=flag;mesh=50x50;dt=0.001": the matrix coordinates, numbers in
  // canonical form, in matrix order. Stable across runs and independent of number spelling.
  std::string key;
  std::size_t index = 0;  // position in the expanded matrix
  // Matrix coordinates (axis name, canonical value), for result columns.
  std::vector<std::pair<std::string, std::string>> coordinates;
  // Everything a single run needs, fixed settings first, then the case's axes (later wins).
  // Keys as in single-run configs: integrator.plugin, scenario.plugin, mesh, dt, precision,
  // steps or duration, integrator.<param>, scenario.<param>...
  std::vector<Setting> settings;

  // Convenience views of the settings above (empty / 0 when not set).
  std::string integrator;
  std::string scenario;
  std::string precision;  // "float32" when not set
  double dt = 0.0;
  double duration = 0.0;  // s; 0 when given as steps
  uint64_t steps = 0;     // 0 when given as duration
  // Simulated time the case covers (duration, or steps * dt).
  double simulated_time() const { return duration > 0.0 ? duration : steps * dt; }
  // The value of a setting key, or empty.
  std::string setting(const std::string& key) const;
};

// The most cases one sweep may expand to.
inline constexpr std::size_t max_cases = 100000;

// Every combination of the matrix axes, first axis outermost. Throws SweepError for more
// than max_cases cases or a fixed setting with a bad value (dt, steps, duration, precision).
std::vector<CaseSpec> expand_cases(const SweepSpec& spec);

// The case with one axis replaced (or added): settings, coordinates, views and key follow.
// With as_coordinate = false only the settings (and views) change, not the key.
CaseSpec with_setting(const CaseSpec& base, const std::string& key, const std::string& value,
                      bool as_coordinate = true);
// The case with the dt axis set (used by the work-precision and stability drivers).
CaseSpec with_dt(const CaseSpec& base, double dt);

}  // namespace clothlab::sweep
