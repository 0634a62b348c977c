#include "clothlab/host/param_set.hpp"

#include "clothlab/host/errors.hpp"
#include "clothlab/host/identifiers.hpp"
#include "clothlab/host/param_text.hpp"

namespace clothlab::host {

ParamSet::ParamSet(std::span<const clothlab_param_spec> specs, std::string prefix)
    : specs_(specs), prefix_(std::move(prefix)) {
  values_.reserve(specs.size());
  for (const clothlab_param_spec& spec : specs) {
    clothlab_param_value value{};
    for (int k = 0; k < 3; ++k) value.v[k] = spec.default_value[k];
    values_.push_back(value);
  }
}

size_t ParamSet::index_of(std::string_view key, std::string_view source) const {
  for (size_t i = 0; i < specs_.size(); ++i)
    if (key == specs_[i].name) return i;
  std::vector<std::string> names;
  std::string valid;
  for (const clothlab_param_spec& spec : specs_) {
    names.push_back(prefix_ + "." + spec.name);
    valid += (valid.empty() ? "" : ", ") + names.back();
  }
  const std::string typed = prefix_ + "." + std::string(key);
  const std::string nearest = nearest_name(typed, names);
  throw InputError(
      std::string(source) + ": unknown parameter " + typed +
      (nearest.empty() ? "" : " (did you mean " + nearest + "?)") +
      (valid.empty() ? "; the " + prefix_ + " takes no parameters" : "; valid: " + valid));
}

void ParamSet::set(std::string_view key, std::string_view text, std::string_view source) {
  const size_t index = index_of(key, source);
  const clothlab_param_spec& spec = specs_[index];
  const ParsedParam parsed = parse_param_text(spec, text);
  const std::string problem = !parsed.value                    ? parsed.problem
                              : !in_range(spec, *parsed.value) ? "out of range"
                                                               : std::string();
  if (!problem.empty())
    throw InputError(std::string(source) + ": " + prefix_ + "." + std::string(key) + " = " +
                     std::string(text) + ": " + problem + "; allowed: " + describe_allowed(spec));
  values_[index] = *parsed.value;
}

const clothlab_param_value& ParamSet::value(std::string_view key) const {
  return values_[index_of(key, "parameter lookup")];
}

}  // namespace clothlab::host
