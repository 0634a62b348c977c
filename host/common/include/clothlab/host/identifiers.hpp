// The spelling of plugin ids ([a-z0-9_-]+) and parameter names ([a-z0-9_.]+), checked by the
// loader, the conformance runner and the sweep reader alike. Plain loops, so a 30 000-character
// string cannot overflow the stack (std::regex recursed once per character).
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace clothlab::host {

bool is_plugin_id(std::string_view text);
bool is_param_name(std::string_view text);

// The candidate a mistyped name most likely meant (at most two edits away, and fewer edits
// than half its length), or "" when none is that close: the "did you mean" of unknown-key
// messages.
std::string nearest_name(std::string_view typed, std::span<const std::string> candidates);

// A plugin's C string as reports quote it: "text", or null.
std::string quoted(const char* text);

}  // namespace clothlab::host
