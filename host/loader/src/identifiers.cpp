#include "clothlab/host/identifiers.hpp"

#include <algorithm>

namespace clothlab::host {
namespace {

bool lower_or_digit(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); }

}  // namespace

bool is_plugin_id(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return lower_or_digit(c) || c == '_' || c == '-';
  });
}

bool is_param_name(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return lower_or_digit(c) || c == '_' || c == '.';
  });
}

}  // namespace clothlab::host
