#include "clothlab/host/identifiers.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace clothlab::host {
namespace {

bool lower_or_digit(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); }

// Levenshtein distance (insertions, deletions, substitutions), one row at a time.
size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), size_t{0});
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string quoted(const char* text) {
  if (text == nullptr) return "null";
  std::string result(1, '"');
  result += text;
  result += '"';
  return result;
}

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

std::string nearest_name(std::string_view typed, std::span<const std::string> candidates) {
  // A 30 000-character key is no typo of a short name: skip the quadratic comparison.
  constexpr size_t max_edits = 2;
  std::string nearest;
  size_t nearest_distance = max_edits + 1;
  for (const std::string& candidate : candidates) {
    const size_t length_gap = candidate.size() > typed.size() ? candidate.size() - typed.size()
                                                              : typed.size() - candidate.size();
    if (length_gap > max_edits) continue;
    const size_t distance = edit_distance(typed, candidate);
    if (distance < nearest_distance && 2 * distance < candidate.size()) {
      nearest = candidate;
      nearest_distance = distance;
    }
  }
  return nearest;
}

}  // namespace clothlab::host
