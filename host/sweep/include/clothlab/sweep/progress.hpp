// One self-overwriting progress line: cases done/total, elapsed, ETA.
#pragma once

#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>

namespace clothlab::sweep {

class Progress {
 public:
  // `enabled` is normally stderr_is_terminal(); when false nothing is written.
  Progress(std::size_t total, std::size_t already_done, std::ostream& out, bool enabled);
  void case_finished(const std::string& label);
  void finish();  // ends the line

  // "[ 12/240]  5.0%  elapsed 0:32  ETA 10:40  <label>"; the ETA is from this session's pace.
  static std::string format_line(std::size_t done, std::size_t total, double elapsed_s,
                                 std::size_t done_this_session, const std::string& label);
  static std::string format_duration(double seconds);

 private:
  std::size_t total_, done_, done_at_start_;
  std::ostream& out_;
  bool enabled_;
  std::size_t last_width_ = 0;
  std::chrono::steady_clock::time_point start_;
};

bool stderr_is_terminal();

}  // namespace clothlab::sweep
