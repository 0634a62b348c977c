// One value per parameter spec of a component, starting from the defaults and changed
// by validated user text.
#pragma once

#include <clothlab/plugin.h>

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace clothlab::host {

class ParamSet {
 public:
  // prefix ("integrator", "scenario") names the parameters in error messages.
  ParamSet(std::span<const clothlab_param_spec> specs, std::string prefix);

  // Parses text by the key's type and checks its range. source is "file:line:column" or
  // "--set"; every error (InputError) names source, key, value and what is allowed. An
  // unknown key lists the valid ones.
  void set(std::string_view key, std::string_view text, std::string_view source);

  std::span<const clothlab_param_spec> specs() const { return specs_; }
  const std::vector<clothlab_param_value>& values() const { return values_; }
  const std::string& prefix() const { return prefix_; }
  // Value of a known key; throws InputError for an unknown one.
  const clothlab_param_value& value(std::string_view key) const;

 private:
  size_t index_of(std::string_view key, std::string_view source) const;

  std::span<const clothlab_param_spec> specs_;
  std::string prefix_;
  std::vector<clothlab_param_value> values_;
};

}  // namespace clothlab::host
