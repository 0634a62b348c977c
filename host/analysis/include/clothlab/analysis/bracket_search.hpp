// Bracket, then bisect: where a property that is monotone in a value changes, probing as few
// values as it can (each probe may be a whole simulation run).
#pragma once

#include <functional>
#include <limits>
#include <optional>

namespace clothlab::analysis {

// Where a probed value lies: below the threshold or above it; or stop: the search ends there
// (a probe that found its answer not worth having, e.g. over a cost budget).
enum class Side { below, above, stop };

// probe(value, low): the side of value; low is the largest value known to lie below (0: none),
// the bottom of the bracket that value tops.
using BracketProbe = std::function<Side(double value, double low)>;

struct BracketOptions {
  double start = 0.0;        // the first probe, in [lower_limit, upper_limit]
  double lower_limit = 0.0;  // > 0: the walk down ends here
  double upper_limit = 0.0;  // >= lower_limit: the walk up ends here
  double growth = 2.0;       // > 1: the walk's factor per probe
  // The bisection ends once high - low is at most relative_tolerance x low (in (0, 1)) or at
  // most resolution (1 for a whole-number value: nothing lies between).
  double relative_tolerance = 0.02;
  double resolution = 0.0;
  int max_evaluations = std::numeric_limits<int>::max();  // >= 1
  // Asked after each probe of the walk (up or down) that did not bracket yet; false ends the
  // search (Stopped). None: the walk goes on to its limit.
  std::function<bool()> keep_bracketing = nullptr;
  // The value in (low, high) to probe next; none ends the search (Stopped). None given: the
  // geometric mean, so that the tolerance is relative at every scale.
  std::function<std::optional<double>(double low, double high)> bisect_at = nullptr;
};

enum class BracketOutcome {
  Bracketed,         // low < threshold <= high, to the tolerance
  AllBelow,          // below up to upper_limit
  AllAbove,          // above down to lower_limit
  Stopped,           // a probe said stop, or keep_bracketing / bisect_at ended the search
  OutOfEvaluations,  // max_evaluations probes, not yet to the tolerance
};

struct BracketResult {
  BracketOutcome outcome = BracketOutcome::AllAbove;
  double low = 0.0;         // the last value probed below: the largest (0: none)
  double high = 0.0;        // the last value probed above: the smallest (0: none)
  double stopped_at = 0.0;  // the value whose probe said stop (0: none)
  int evaluations = 0;
};

// Probes start, then walks up (from below) or down (from above) by growth until a value lies
// on the other side or a limit is reached, then bisects the bracket [low, high]. Assumes the
// side is monotone in the value. Throws std::invalid_argument on options out of range.
BracketResult bracket_search(const BracketProbe& probe, const BracketOptions& options);

}  // namespace clothlab::analysis
