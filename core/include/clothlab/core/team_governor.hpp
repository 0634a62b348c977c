// Whether the next step runs its parallel passes on the whole thread team or on the calling
// thread alone, from what the last steps got of the machine.
//
// A step on a team of T threads should get T x its wall time of CPU: the threads work or spin
// at a barrier (OpenMP's default wait policy). Much less means another process took a core, and
// then every barrier waits for a thread that waits for a core, a scheduler time slice at a
// time. So the steps after such a step run on the calling thread, which has a core to itself,
// and the team is tried again after `hold` steps; the hold doubles while the tries find a core
// still taken, and falls back to its least once a try gets its share. Results do not depend on
// it: every pass gives the same bits on any thread count. docs/performance.md, "The engine on a
// shared machine", has the measurements behind the numbers.
#pragma once

#include <algorithm>
#include <cstdint>

namespace clothlab {

class TeamGovernor {
 public:
  // A team step that gets less than this share of T x wall time of CPU lost a core.
  static constexpr double kLeastShare = 0.8;
  static constexpr uint32_t kLeastHold = 4, kMostHold = 256;

  // `team`: the threads of a full step; a governor of one thread, or a disabled one, always
  // says "team" (the engine then runs exactly as configured).
  TeamGovernor(int team, bool enabled) : team_(team), enabled_(enabled && team > 1) {}

  // Whether the coming step runs on the team.
  bool team_step() const { return !enabled_ || solo_left_ == 0; }

  // The step that team_step() decided took `wall_s` seconds and the process `cpu_s` seconds
  // of CPU time over them.
  void finished(double wall_s, double cpu_s) {
    if (!enabled_) return;
    if (solo_left_ > 0) {
      --solo_left_;
      return;
    }
    if (wall_s > 0 && cpu_s < kLeastShare * team_ * wall_s) {
      solo_left_ = hold_;
      hold_ = std::min(2 * hold_, kMostHold);
    } else {
      hold_ = kLeastHold;
    }
  }

 private:
  int team_;
  bool enabled_;
  uint32_t hold_ = kLeastHold;
  uint32_t solo_left_ = 0;
};

}  // namespace clothlab
