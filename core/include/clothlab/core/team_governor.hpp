// Whether the next step runs its parallel passes on the whole thread team or on the calling
// thread alone, judged by which of the two the machine lets finish a step sooner.
//
// A team step waits at every barrier for its slowest thread; when another process takes a
// core, that thread waits for the core a scheduler time slice at a time, and the team's step
// can take longer than the calling thread's alone. How much of the CPU the team got does not
// tell: a short step's threads sleep between its passes on an idle machine too. So the
// governor measures both: among team steps it runs a few steps alone now and then (a probe) and
// at once after a team step much slower than the recent ones. When the probe's mean beats the
// team's recent mean (or the slow step), the steps after it run alone for a hold, after which a few
// team steps try again; the team comes back only when it is clearly faster, and the hold doubles
// while the tries lose and halves when one wins. The probe interval doubles while the team clearly
// wins and falls back to its least when the two are close, so a noisy machine is probed often where
// the choice is close. Results do not depend on it: every pass gives the same bits on any thread
// count. lab/performance.md, "The engine on a shared machine", has the measurements behind the
// numbers.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

namespace clothlab {

class TeamGovernor {
 public:
  static constexpr uint32_t kLeastProbeInterval = 16, kMostProbeInterval = 256;
  static constexpr uint32_t kLeastHold = 4, kMostHold = 256;
  // A team step this much slower than the recent team steps' mean calls for a probe now.
  static constexpr double kSlowStep = 1.5;
  // The team wins clearly (it comes back after a hold; its probe interval doubles) when its
  // mean is below this fraction of the steps' alone: a team barely faster than one thread is
  // not worth the core it takes from the machine.
  static constexpr double kTeamGain = 0.9;
  static constexpr uint32_t kTrySteps = 4, kProbeSteps = 3;

  // `team`: the threads of a full step; a governor of one thread, or a disabled one, always
  // says "team" (the engine then runs exactly as configured).
  TeamGovernor(int team, bool enabled) : enabled_(enabled && team > 1) {}

  // Whether the coming step runs on the team.
  bool team_step() const { return !enabled_ || mode_ == Mode::team || mode_ == Mode::trying; }

  // The step that team_step() decided took `wall_s` seconds.
  void finished(double wall_s) {
    if (!enabled_) return;
    switch (mode_) {
      case Mode::team:
        return finished_team_step(wall_s);
      case Mode::probing:
        return finished_probe_step(wall_s);
      case Mode::alone:
        return finished_alone(wall_s);
      case Mode::trying:
        return finished_try(wall_s);
    }
  }

 private:
  enum class Mode { team, probing, alone, trying };
  static constexpr uint32_t kRecentSteps = 8;

  void finished_team_step(double wall_s) {
    const bool slow = recent_count_ > 0 && wall_s > kSlowStep * recent_mean();
    remember_team_step(wall_s);
    if (slow || --until_probe_ == 0) {
      mode_ = Mode::probing;
      probe_sum_ = 0;
      probe_left_ = kProbeSteps;
      // A slow step is measured against itself: the mean still holds the steps before it.
      probe_reference_ = slow ? wall_s : recent_mean();
    }
  }

  void finished_probe_step(double wall_s) {
    probe_sum_ += wall_s;
    if (--probe_left_ > 0) return;
    const double alone = probe_sum_ / kProbeSteps, team = probe_reference_;
    if (alone < team) {
      start_hold();
      alone_sum_ = probe_sum_;  // the probe's steps were alone too
      alone_count_ = kProbeSteps;
      return;
    }
    mode_ = Mode::team;
    const bool clear_win = team < kTeamGain * alone;
    probe_interval_ =
        clear_win ? std::min(2 * probe_interval_, kMostProbeInterval) : kLeastProbeInterval;
    until_probe_ = probe_interval_;
  }

  void finished_alone(double wall_s) {
    alone_sum_ += wall_s;
    ++alone_count_;
    if (--alone_left_ == 0) {
      mode_ = Mode::trying;
      try_sum_ = 0;
      try_left_ = kTrySteps;
    }
  }

  void finished_try(double wall_s) {
    try_sum_ += wall_s;
    if (--try_left_ > 0) return;
    if (try_sum_ / kTrySteps < kTeamGain * alone_sum_ / alone_count_) {
      mode_ = Mode::team;
      hold_ = std::max(kLeastHold, hold_ / 2);  // a contention that comes and goes: stay wary
      probe_interval_ = kLeastProbeInterval;
      until_probe_ = probe_interval_;
      recent_count_ = recent_next_ = 0;
      for (uint32_t k = 0; k < kTrySteps; ++k) remember_team_step(try_sum_ / kTrySteps);
    } else {
      hold_ = std::min(2 * hold_, kMostHold);
      start_hold();
    }
  }

  void start_hold() {
    mode_ = Mode::alone;
    alone_left_ = hold_;
    alone_sum_ = 0;
    alone_count_ = 0;
  }

  void remember_team_step(double wall_s) {
    recent_[recent_next_] = wall_s;
    recent_next_ = (recent_next_ + 1) % kRecentSteps;
    recent_count_ = std::min(recent_count_ + 1, kRecentSteps);
  }

  double recent_mean() const {
    double sum = 0;
    for (uint32_t k = 0; k < recent_count_; ++k) sum += recent_[k];
    return recent_count_ > 0 ? sum / recent_count_ : 0.0;
  }

  bool enabled_;
  Mode mode_ = Mode::team;
  std::array<double, kRecentSteps> recent_{};
  uint32_t recent_next_ = 0, recent_count_ = 0;
  uint32_t probe_interval_ = kLeastProbeInterval, until_probe_ = kLeastProbeInterval;
  uint32_t hold_ = kLeastHold, alone_left_ = 0, alone_count_ = 0, try_left_ = 0, probe_left_ = 0;
  double alone_sum_ = 0, try_sum_ = 0, probe_sum_ = 0, probe_reference_ = 0;
};

}  // namespace clothlab
