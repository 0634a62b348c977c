// params.*: schemas are enforced by the plugin itself; fuzzed valid values behave.
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "check.hpp"
#include "fixtures.hpp"

namespace clothlab::conformance {
namespace {

constexpr int fuzz_rounds = 8;

int components_of(const clothlab_param_spec& spec) {
  return spec.type == CLOTHLAB_PARAM_VEC3 ? 3 : 1;
}

std::string value_text(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// Expects create to refuse `values` with an error status and a message.
void require_rejected(const ParameterSubject& subject, const Values& values,
                      const std::string& what) {
  clothlab_message message{};
  const clothlab_status status = subject.try_create(values, message);
  require(status != CLOTHLAB_OK, what + " was accepted");
  require(message.text[0] != '\0', what + " was rejected without a message");
}

Verdict defaults_work(const ParameterSubject& subject) {
  subject.exercise(default_values(subject.component, subject.specs, subject.count));
  return {true, std::to_string(subject.count) + " defaults"};
}

Verdict out_of_range_rejected(const ParameterSubject& subject) {
  const Values defaults = default_values(subject.component, subject.specs, subject.count);
  int tried = 0;
  for (uint32_t i = 0; i < subject.count; ++i) {
    const clothlab_param_spec& spec = subject.specs[i];
    const double span = std::max(1.0, spec.max_value - spec.min_value);
    const double outside[] = {spec.min_value - 1e-3 * span, spec.max_value + 1e-3 * span,
                              std::numeric_limits<double>::quiet_NaN(),
                              std::numeric_limits<double>::infinity()};
    for (int k = 0; k < components_of(spec); ++k) {
      for (double bad : outside) {
        Values values = defaults;
        values[i].v[k] = bad;
        require_rejected(
            subject, values,
            std::string(spec.name) + "[" + std::to_string(k) + "] = " + value_text(bad));
        ++tried;
      }
    }
  }
  return {true, std::to_string(tried) + " invalid values rejected"};
}

Verdict non_integers_rejected(const ParameterSubject& subject) {
  const Values defaults = default_values(subject.component, subject.specs, subject.count);
  int tried = 0;
  for (uint32_t i = 0; i < subject.count; ++i) {
    const clothlab_param_spec& spec = subject.specs[i];
    if (spec.type != CLOTHLAB_PARAM_INT && spec.type != CLOTHLAB_PARAM_BOOL) continue;
    if (spec.max_value - spec.min_value < 0.5) continue;  // no non-integer inside the range
    Values values = defaults;
    values[i].v[0] = spec.min_value + 0.5;
    require_rejected(
        subject, values,
        std::string(spec.name) + " = " + value_text(values[i].v[0]) + " (not an integer)");
    ++tried;
  }
  Values too_many = defaults;
  too_many.push_back({});
  require_rejected(subject, too_many,
                   std::to_string(too_many.size()) + " values for " +
                       std::to_string(subject.count) + " parameters");
  return {true, std::to_string(tried) + " non-integers and a wrong value count rejected"};
}

// Round 0 uses every minimum, round 1 every maximum, the rest uniform draws.
Values fuzzed_values(const ParameterSubject& subject, int round, std::mt19937_64& random) {
  Values values(subject.count);
  for (uint32_t i = 0; i < subject.count; ++i) {
    const clothlab_param_spec& spec = subject.specs[i];
    std::uniform_real_distribution<double> draw(spec.min_value, spec.max_value);
    for (int k = 0; k < components_of(spec); ++k) {
      double value = round == 0 ? spec.min_value : round == 1 ? spec.max_value : draw(random);
      if (spec.type == CLOTHLAB_PARAM_INT || spec.type == CLOTHLAB_PARAM_BOOL)
        value =
            std::clamp(std::round(value), std::ceil(spec.min_value), std::floor(spec.max_value));
      values[i].v[k] = value;
    }
  }
  return values;
}

std::string values_text(const ParameterSubject& subject, const Values& values) {
  std::string text;
  for (uint32_t i = 0; i < subject.count; ++i) {
    text += (i ? ", " : "") + std::string(subject.specs[i].name) + "=" + value_text(values[i].v[0]);
    if (components_of(subject.specs[i]) == 3)
      text += "," + value_text(values[i].v[1]) + "," + value_text(values[i].v[2]);
  }
  return text;
}

Verdict fuzzed_values_work(const ParameterSubject& subject, uint64_t seed) {
  std::mt19937_64 random(seed);
  for (int round = 0; round < fuzz_rounds; ++round) {
    const Values values = fuzzed_values(subject, round, random);
    try {
      subject.exercise(values);
    } catch (const CheckFailure& failure) {
      throw CheckFailure(std::string(failure.what()) + " with " + values_text(subject, values) +
                         " (seed " + std::to_string(seed) + ")");
    }
  }
  return {true, std::to_string(fuzz_rounds) + " value sets (bounds and seed " +
                    std::to_string(seed) + ")"};
}

}  // namespace

std::vector<Check> parameter_checks(const ParameterSubject& subject, const Settings& settings) {
  const uint64_t seed = settings.seed;
  return {
      {subject.component, "params.defaults", [subject] { return defaults_work(subject); }},
      {subject.component, "params.out-of-range",
       [subject] { return out_of_range_rejected(subject); }},
      {subject.component, "params.wrong-type",
       [subject] { return non_integers_rejected(subject); }},
      {subject.component, "params.fuzz",
       [subject, seed] { return fuzzed_values_work(subject, seed); }},
  };
}

}  // namespace clothlab::conformance
