#include "clothlab/host/plugin_call_marker.hpp"

#include <algorithm>
#include <cstring>

namespace clothlab::host {

namespace {

PluginCallRecord* placed = nullptr;

// Copies text, cut to the field and NUL-terminated: the reader may be another process.
template <size_t N>
void copy_text(char (&field)[N], std::string_view text) {
  const size_t length = std::min(text.size(), N - 1);
  std::memcpy(field, text.data(), length);
  field[length] = '\0';
}

}  // namespace

void mark_plugin_calls_in(PluginCallRecord* record) { placed = record; }

PluginCallMark::PluginCallMark(const PluginCallSite& site, const char* phase,
                               uint64_t step) noexcept {
  if (placed == nullptr) return;
  placed->active = 0;
  copy_text(placed->library, site.library.native());
  copy_text(placed->component, site.component);
  copy_text(placed->phase, phase);
  placed->step = step;
  placed->active = 1;
}

PluginCallMark::~PluginCallMark() {
  if (placed != nullptr) placed->active = 0;
}

std::string describe_active_call(const PluginCallRecord& record) {
  if (record.active != 1) return "";
  // The record came from another process: read each field only up to its own end.
  const auto field = [](const auto& text) { return std::string(text, strnlen(text, sizeof text)); };
  std::string where = " in " + field(record.component) + "." + field(record.phase) + " (" +
                      field(record.library) + ")";
  if (record.step > 0) where += " at step " + std::to_string(record.step);
  return where;
}

}  // namespace clothlab::host
