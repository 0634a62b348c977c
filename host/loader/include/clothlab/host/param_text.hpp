// Reading, writing and describing parameter values by their spec's type.
#pragma once

#include <clothlab/plugin.h>

#include <optional>
#include <string>
#include <string_view>

namespace clothlab::host {

// "real", "int", "bool", "vec3" (or "unknown").
const char* param_type_name(uint32_t type);

// The one number parser of the host: a finite double, optionally signed, surrounded by
// spaces or not ("1e-3", "+2", " 0.5 "); nothing else (no "0x10", "inf", "1,5").
std::optional<double> parse_real(std::string_view text);

// Numbers in their shortest form ("1e1" and "10.0" give "10"), other text unchanged: the
// spelling-independent form sweeps key cases by.
std::string canonical_value(std::string_view text);

// Shortest text that reads back to the same double.
std::string format_number(double value);

// The value as a user writes it: 0.5, 300, true, [0, -9.81, 0].
std::string format_param_value(const clothlab_param_spec& spec, const clothlab_param_value& value);

// What the spec allows, e.g. "real in [0, 1e+06] N/m", "bool (true/false/1/0)".
std::string describe_allowed(const clothlab_param_spec& spec);

// Parses text by the spec's type: real, int (whole number), bool (true/false/1/0),
// vec3 ("[x, y, z]" or "x,y,z"). Returns the reason on failure; does not check the range.
struct ParsedParam {
  std::optional<clothlab_param_value> value;
  std::string problem;
};
ParsedParam parse_param_text(const clothlab_param_spec& spec, std::string_view text);

// Whether the value lies in the spec's range (every component for vec3).
bool in_range(const clothlab_param_spec& spec, const clothlab_param_value& value);

}  // namespace clothlab::host
