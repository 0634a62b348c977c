#include "clothlab/sweep/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace clothlab::sweep {

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

Progress::Progress(std::size_t total, std::size_t already_done, std::ostream& out, bool enabled)
    : total_(total),
      done_(already_done),
      done_at_start_(already_done),
      out_(out),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()) {}

std::string Progress::format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const auto whole = static_cast<long long>(std::llround(seconds));
  char text[32];
  if (whole >= 3600) {
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", whole / 3600, whole / 60 % 60,
                  whole % 60);
  } else {
    std::snprintf(text, sizeof text, "%lld:%02lld", whole / 60, whole % 60);
  }
  return text;
}

std::string Progress::format_line(std::size_t done, std::size_t total, double elapsed_s,
                                  std::size_t done_this_session, const std::string& label) {
  const double percent = total > 0 ? 100.0 * static_cast<double>(done) / total : 100.0;
  const double eta = done_this_session > 0 ? elapsed_s / static_cast<double>(done_this_session) *
                                                 static_cast<double>(total - done)
                                           : -1.0;
  char head[96];
  std::snprintf(head, sizeof head, "[%zu/%zu] %5.1f%%  elapsed %s  ETA %s", done, total, percent,
                format_duration(elapsed_s).c_str(), format_duration(eta).c_str());
  return label.empty() ? std::string(head) : std::string(head) + "  " + label;
}

void Progress::case_finished(const std::string& label) {
  ++done_;
  if (!enabled_) return;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string line = format_line(done_, total_, elapsed, done_ - done_at_start_, label);
  out_ << '\r' << line;
  if (line.size() < last_width_) out_ << std::string(last_width_ - line.size(), ' ');
  out_.flush();
  last_width_ = line.size();
}

void Progress::finish() {
  if (enabled_ && last_width_ > 0) out_ << '\n';
  last_width_ = 0;
}

}  // namespace clothlab::sweep
