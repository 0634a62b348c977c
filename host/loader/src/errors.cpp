#include "clothlab/host/errors.hpp"

namespace clothlab::host {

PluginLoadError cannot_load(const std::filesystem::path& path, const std::string& why,
                            std::string_view searched) {
  std::string message = "cannot load plugin " + path.string() + ": " + why;
  if (!searched.empty()) message += " (plugin search path: " + std::string(searched) + ")";
  return PluginLoadError(message);
}

const char* status_name(clothlab_status status) {
  switch (status) {
    case CLOTHLAB_OK:
      return "ok";
    case CLOTHLAB_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case CLOTHLAB_ERROR_UNSUPPORTED:
      return "unsupported";
    case CLOTHLAB_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case CLOTHLAB_ERROR_NUMERICAL:
      return "numerical failure";
    case CLOTHLAB_ERROR_INTERNAL:
      return "internal error";
    default:
      return "unknown status";
  }
}

std::string one_line(std::string_view text) {
  static constexpr char digits[] = "0123456789abcdef";
  std::string line;
  line.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\n') {
      line += "\\n";
    } else if (c == '\r') {
      line += "\\r";
    } else if (byte < 0x20 || byte == 0x7f) {
      line += "\\x";
      line += digits[byte >> 4];
      line += digits[byte & 15];
    } else {
      line += c;
    }
  }
  return line;
}

}  // namespace clothlab::host
