// Base64 (RFC 4648, with padding): how the viewer bundle embeds float arrays in runs.js.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace clothlab::io {

void append_base64(std::string& out, const void* data, size_t bytes);
// Skips whitespace; throws std::invalid_argument on any other character outside the alphabet.
std::vector<uint8_t> decode_base64(std::string_view text);

}  // namespace clothlab::io
