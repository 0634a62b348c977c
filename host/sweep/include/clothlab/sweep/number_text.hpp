// Numbers as text: the shortest form that reads back to the same double, so case keys do not
// depend on how a value was written (1e-3, 0.001 and 0.0010 give one key).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace clothlab::sweep {

std::string format_number(double value);
// The whole text as a finite double, or nothing.
std::optional<double> parse_number(std::string_view text);
// Numbers in canonical form; any other text unchanged.
std::string canonical_value(std::string_view text);

}  // namespace clothlab::sweep
