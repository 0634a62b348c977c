// Parameter value arrays for driving a plugin's create through the C ABI.
#pragma once

#include <clothlab/plugin.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace clothlab::test {

// One value per spec, each its default.
inline std::vector<clothlab_param_value> default_values(const clothlab_param_spec* specs,
                                                        uint32_t count) {
  std::vector<clothlab_param_value> values(count);
  for (uint32_t i = 0; i < count; ++i)
    for (int k = 0; k < 3; ++k) values[i].v[k] = specs[i].default_value[k];
  return values;
}

// Sets the value of the parameter called `name`; throws if there is none.
inline void set_value(std::vector<clothlab_param_value>& values, const clothlab_param_spec* specs,
                      std::string_view name, clothlab_param_value value) {
  for (size_t i = 0; i < values.size(); ++i)
    if (name == specs[i].name) {
      values[i] = value;
      return;
    }
  throw std::runtime_error("no parameter " + std::string(name));
}

}  // namespace clothlab::test
