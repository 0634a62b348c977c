// One value per parameter spec of a component, starting from the defaults and changed
// by validated user text: the numbers of plugin.h, and the texts of
// clothlab.text-parameters/1 when the component offers it.
#pragma once

#include <clothlab/ext/text_parameters.h>
#include <clothlab/plugin.h>

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace clothlab::host {

class ParamSet {
 public:
  // prefix ("integrator", "scenario") names the parameters in error messages.
  ParamSet(std::span<const clothlab_param_spec> specs, std::string prefix,
           std::span<const clothlab_text_param_spec> text_specs = {});

  // Parses text by the key's type and checks its range. source is "file:line:column" or
  // "--set"; every error (InputError) names source, key, value and what is allowed. An
  // unknown key lists the valid ones. A CLOTHLAB_TEXT_PATH text given as a relative path is
  // stored resolved: against the folder of the file a "file:line:column" source names, else
  // against the working directory.
  void set(std::string_view key, std::string_view text, std::string_view source);

  std::span<const clothlab_param_spec> specs() const { return specs_; }
  const std::vector<clothlab_param_value>& values() const { return values_; }
  std::span<const clothlab_text_param_spec> text_specs() const { return text_specs_; }
  // One per text spec, in spec order.
  const std::vector<std::string>& texts() const { return texts_; }
  const std::string& prefix() const { return prefix_; }
  // Value of a known key; throws InputError for an unknown one.
  const clothlab_param_value& value(std::string_view key) const;
  // Text of a known text key; throws InputError for an unknown or numeric one.
  const std::string& text(std::string_view key) const;

 private:
  size_t index_of(std::string_view key, std::string_view source) const;
  void set_text(size_t index, std::string_view text, std::string_view source);

  std::span<const clothlab_param_spec> specs_;
  std::string prefix_;
  std::vector<clothlab_param_value> values_;
  std::span<const clothlab_text_param_spec> text_specs_;
  std::vector<std::string> texts_;
};

}  // namespace clothlab::host
