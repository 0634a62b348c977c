#include "clothlab/host/param_set.hpp"

#include <filesystem>
#include <regex>

#include "clothlab/host/errors.hpp"
#include "clothlab/host/identifiers.hpp"
#include "clothlab/host/param_text.hpp"

namespace clothlab::host {

namespace {

// The folder relative paths given at `source` are relative to: the folder of the
// configuration file a "file:line:column" source names, else the working directory.
std::filesystem::path base_folder(std::string_view source) {
  static const std::regex file_location(R"((.+):[0-9]+:[0-9]+)");
  std::match_results<std::string_view::const_iterator> match;
  if (std::regex_match(source.begin(), source.end(), match, file_location))
    return std::filesystem::absolute(std::filesystem::path(match[1].str())).parent_path();
  return std::filesystem::current_path();
}

// The text as an error message shows it: on one line, at most 80 bytes of it.
std::string shown(std::string_view text) {
  std::string out;
  for (const char c : text.substr(0, 80))
    out += c == '\n' ? "\\n" : c == '\r' ? "\\r" : c == '\0' ? "\\0" : std::string(1, c);
  return text.size() > 80 ? out + "..." : out;
}

}  // namespace

ParamSet::ParamSet(std::span<const clothlab_param_spec> specs, std::string prefix,
                   std::span<const clothlab_text_param_spec> text_specs)
    : specs_(specs), prefix_(std::move(prefix)), text_specs_(text_specs) {
  values_.reserve(specs.size());
  for (const clothlab_param_spec& spec : specs) {
    clothlab_param_value value{};
    for (int k = 0; k < 3; ++k) value.v[k] = spec.default_value[k];
    values_.push_back(value);
  }
  for (const clothlab_text_param_spec& spec : text_specs) texts_.emplace_back(spec.default_text);
}

// Numeric specs first, then the text specs at specs_.size() + their index.
size_t ParamSet::index_of(std::string_view key, std::string_view source) const {
  for (size_t i = 0; i < specs_.size(); ++i)
    if (key == specs_[i].name) return i;
  for (size_t i = 0; i < text_specs_.size(); ++i)
    if (key == text_specs_[i].name) return specs_.size() + i;
  std::vector<std::string> names;
  std::string valid;
  for (const clothlab_param_spec& spec : specs_) {
    names.push_back(prefix_ + "." + spec.name);
    valid += (valid.empty() ? "" : ", ") + names.back();
  }
  for (const clothlab_text_param_spec& spec : text_specs_) {
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
  if (index >= specs_.size()) return set_text(index - specs_.size(), text, source);
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

void ParamSet::set_text(size_t index, std::string_view text, std::string_view source) {
  const clothlab_text_param_spec& spec = text_specs_[index];
  const bool has_break = text.find_first_of(std::string_view("\r\n\0", 3)) != text.npos;
  if (text.size() > spec.max_length || has_break)
    throw InputError(
        std::string(source) + ": " + prefix_ + "." + spec.name + " = " + shown(text) + ": " +
        (has_break ? "a line break or NUL" : std::to_string(text.size()) + " bytes") +
        "; allowed: text of at most " + std::to_string(spec.max_length) + " bytes on one line");
  std::string value(text);
  if ((spec.flags & CLOTHLAB_TEXT_PATH) != 0 && !value.empty() &&
      std::filesystem::path(value).is_relative())
    value = (base_folder(source) / value).lexically_normal().string();
  texts_[index] = std::move(value);
}

const clothlab_param_value& ParamSet::value(std::string_view key) const {
  const size_t index = index_of(key, "parameter lookup");
  if (index >= specs_.size())
    throw InputError("parameter lookup: " + prefix_ + "." + std::string(key) + " is text");
  return values_[index];
}

const std::string& ParamSet::text(std::string_view key) const {
  const size_t index = index_of(key, "parameter lookup");
  if (index < specs_.size())
    throw InputError("parameter lookup: " + prefix_ + "." + std::string(key) + " is a number");
  return texts_[index - specs_.size()];
}

}  // namespace clothlab::host
