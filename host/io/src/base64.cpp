#include "clothlab/io/base64.hpp"

#include <array>
#include <stdexcept>

namespace clothlab::io {

namespace {

constexpr char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

constexpr std::array<int8_t, 256> decoding_table() {
  std::array<int8_t, 256> table{};
  table.fill(-1);
  for (int i = 0; i < 64; ++i) table[static_cast<uint8_t>(alphabet[i])] = static_cast<int8_t>(i);
  return table;
}

}  // namespace

void append_base64(std::string& out, const void* data, size_t bytes) {
  const auto* in = static_cast<const uint8_t*>(data);
  out.reserve(out.size() + (bytes + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 3 <= bytes; i += 3) {
    const uint32_t word = uint32_t{in[i]} << 16 | uint32_t{in[i + 1]} << 8 | in[i + 2];
    out += alphabet[word >> 18];
    out += alphabet[(word >> 12) & 63];
    out += alphabet[(word >> 6) & 63];
    out += alphabet[word & 63];
  }
  if (i < bytes) {
    const bool two = i + 1 < bytes;
    const uint32_t word = uint32_t{in[i]} << 16 | (two ? uint32_t{in[i + 1]} << 8 : 0u);
    out += alphabet[word >> 18];
    out += alphabet[(word >> 12) & 63];
    out += two ? alphabet[(word >> 6) & 63] : '=';
    out += '=';
  }
}

std::vector<uint8_t> decode_base64(std::string_view text) {
  static constexpr std::array<int8_t, 256> table = decoding_table();
  std::vector<uint8_t> out;
  out.reserve(text.size() / 4 * 3);
  uint32_t word = 0;
  int bits = 0;
  for (const char c : text) {
    if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    if (c == '=') break;
    const int8_t value = table[static_cast<uint8_t>(c)];
    if (value < 0) throw std::invalid_argument(std::string("not base64: '") + c + "'");
    word = word << 6 | static_cast<uint32_t>(value);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<uint8_t>(word >> bits));
    }
  }
  return out;
}

}  // namespace clothlab::io
