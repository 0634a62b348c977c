#include "clothlab/host/param_text.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <vector>

namespace clothlab::host {

namespace {

std::string_view trim(std::string_view text) {
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

// A whole number in any spelling a real has (300, 3e2, 300.0), so a value keyed as "300" by a
// sweep reads the same way whatever its spelling.
std::optional<double> parse_integer(std::string_view text) {
  const std::optional<double> value = parse_real(text);
  if (!value || *value != std::floor(*value) || std::fabs(*value) > 9007199254740992.0)
    return std::nullopt;
  return value;
}

std::optional<double> parse_bool(std::string_view text) {
  text = trim(text);
  if (text == "true" || text == "1") return 1.0;
  if (text == "false" || text == "0") return 0.0;
  return std::nullopt;
}

std::optional<std::array<double, 3>> parse_vec3(std::string_view text) {
  text = trim(text);
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']')
    text = text.substr(1, text.size() - 2);
  std::vector<std::string_view> parts;
  while (true) {
    const size_t comma = text.find(',');
    parts.push_back(text.substr(0, comma));
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  if (parts.size() != 3) return std::nullopt;
  std::array<double, 3> vector{};
  for (size_t k = 0; k < 3; ++k) {
    const std::optional<double> component = parse_real(parts[k]);
    if (!component) return std::nullopt;
    vector[k] = *component;
  }
  return vector;
}

}  // namespace

const char* param_type_name(uint32_t type) {
  switch (type) {
    case CLOTHLAB_PARAM_REAL:
      return "real";
    case CLOTHLAB_PARAM_INT:
      return "int";
    case CLOTHLAB_PARAM_BOOL:
      return "bool";
    case CLOTHLAB_PARAM_VEC3:
      return "vec3";
    default:
      return "unknown";
  }
}

std::optional<double> parse_real(std::string_view text) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() ||
      !std::isfinite(value))
    return std::nullopt;
  return value;
}

std::string canonical_value(std::string_view text) {
  const std::optional<double> number = parse_real(text);
  return number ? format_number(*number) : std::string(text);
}

std::string format_number(double value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

std::string format_param_value(const clothlab_param_spec& spec, const clothlab_param_value& value) {
  switch (spec.type) {
    case CLOTHLAB_PARAM_BOOL:
      return value.v[0] != 0.0 ? "true" : "false";
    case CLOTHLAB_PARAM_VEC3: {
      // Appended piece by piece: GCC 12 warns falsely on "[" + std::string.
      std::string text("[");
      for (int k = 0; k < 3; ++k) {
        if (k > 0) text += ", ";
        text += format_number(value.v[k]);
      }
      return text += "]";
    }
    default:
      return format_number(value.v[0]);
  }
}

std::string describe_allowed(const clothlab_param_spec& spec) {
  if (spec.type == CLOTHLAB_PARAM_BOOL) return "bool (true/false/1/0)";
  std::string text =
      spec.type == CLOTHLAB_PARAM_VEC3 ? "vec3 [x, y, z], each" : param_type_name(spec.type);
  text += " in [" + format_number(spec.min_value) + ", " + format_number(spec.max_value) + "]";
  if (spec.unit != nullptr && *spec.unit != '\0') text += std::string(" ") + spec.unit;
  return text;
}

ParsedParam parse_param_text(const clothlab_param_spec& spec, std::string_view text) {
  clothlab_param_value value{};
  switch (spec.type) {
    case CLOTHLAB_PARAM_REAL:
      if (const auto real = parse_real(text)) {
        value.v[0] = *real;
        return {value, {}};
      }
      return {std::nullopt, "not a finite number"};
    case CLOTHLAB_PARAM_INT:
      if (const auto integer = parse_integer(text)) {
        value.v[0] = *integer;
        return {value, {}};
      }
      return {std::nullopt, "not a whole number"};
    case CLOTHLAB_PARAM_BOOL:
      if (const auto flag = parse_bool(text)) {
        value.v[0] = *flag;
        return {value, {}};
      }
      return {std::nullopt, "not true/false/1/0"};
    case CLOTHLAB_PARAM_VEC3:
      if (const auto vector = parse_vec3(text)) {
        value.v[0] = (*vector)[0];
        value.v[1] = (*vector)[1];
        value.v[2] = (*vector)[2];
        return {value, {}};
      }
      return {std::nullopt, "not three finite numbers"};
    default:
      return {std::nullopt, "parameter has an unknown type"};
  }
}

bool in_range(const clothlab_param_spec& spec, const clothlab_param_value& value) {
  const int components = spec.type == CLOTHLAB_PARAM_VEC3 ? 3 : 1;
  for (int k = 0; k < components; ++k)
    if (!(value.v[k] >= spec.min_value && value.v[k] <= spec.max_value)) return false;
  return true;
}

}  // namespace clothlab::host
