#include "clothlab/analysis/bracket_search.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace clothlab::analysis {
namespace {

void validate(const BracketOptions& options) {
  auto fail = [](const char* key, double value, const char* allowed) {
    throw std::invalid_argument(std::string("bracket search: ") + key + " = " +
                                std::to_string(value) + ", allowed " + allowed);
  };
  if (!(options.lower_limit > 0.0)) fail("lower_limit", options.lower_limit, "> 0");
  if (!(options.upper_limit >= options.lower_limit))
    fail("upper_limit", options.upper_limit, ">= lower_limit");
  if (!(options.start >= options.lower_limit && options.start <= options.upper_limit))
    fail("start", options.start, "in [lower_limit, upper_limit]");
  if (!(options.growth > 1.0)) fail("growth", options.growth, "> 1");
  if (!(options.relative_tolerance > 0.0 && options.relative_tolerance < 1.0))
    fail("relative_tolerance", options.relative_tolerance, "in (0, 1)");
  if (!(options.resolution >= 0.0)) fail("resolution", options.resolution, ">= 0");
  if (options.max_evaluations < 1) fail("max_evaluations", options.max_evaluations, ">= 1");
}

}  // namespace

BracketResult bracket_search(const BracketProbe& probe, const BracketOptions& options) {
  validate(options);
  BracketResult result;
  const auto probe_at = [&](double value) {
    ++result.evaluations;
    const Side side = probe(value, result.low);
    (side == Side::below   ? result.low
     : side == Side::above ? result.high
                           : result.stopped_at) = value;
    return side;
  };
  const auto ended = [&](BracketOutcome outcome) {
    result.outcome = outcome;
    return result;
  };
  const auto out_of_evaluations = [&] { return result.evaluations >= options.max_evaluations; };
  const auto keep_bracketing = [&] {
    return !options.keep_bracketing || options.keep_bracketing();
  };

  // Bracket: walk up from a value below the threshold, or down from one above it.
  double value = options.start;
  const Side first = probe_at(value);
  if (first == Side::stop) return ended(BracketOutcome::Stopped);
  const bool up = first == Side::below;
  while (up ? result.high == 0.0 : result.low == 0.0) {
    if (up ? value >= options.upper_limit : value <= options.lower_limit)
      return ended(up ? BracketOutcome::AllBelow : BracketOutcome::AllAbove);
    if (!keep_bracketing()) return ended(BracketOutcome::Stopped);
    if (out_of_evaluations()) return ended(BracketOutcome::OutOfEvaluations);
    value = up ? std::min(value * options.growth, options.upper_limit)
               : std::max(value / options.growth, options.lower_limit);
    if (probe_at(value) == Side::stop) return ended(BracketOutcome::Stopped);
  }

  // Bisect between the largest value below and the smallest above.
  while (result.high - result.low > options.resolution &&
         result.high - result.low > options.relative_tolerance * result.low) {
    if (out_of_evaluations()) return ended(BracketOutcome::OutOfEvaluations);
    const std::optional<double> next = options.bisect_at
                                           ? options.bisect_at(result.low, result.high)
                                           : std::sqrt(result.low * result.high);
    if (!next || probe_at(*next) == Side::stop) return ended(BracketOutcome::Stopped);
  }
  return ended(BracketOutcome::Bracketed);
}

}  // namespace clothlab::analysis
