// clothlab_speedup CONFIG [REPETITIONS STEPS]: the in-run baseline comparison of issue 4.
//
// Builds the flag of CONFIG's `scenario:` map (configs/bench-300-soft.yaml), then alternates
// blocks of STEPS semi-implicit Euler steps of (a) the seed-style reference force
// evaluation, one thread, and (b) the fast core with the euler plugin, REPETITIONS times
// each, so both see the same machine load. Prints one JSON object: per-step medians of
// both, their ratio, and whether both states stayed finite.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <clothlab/core/cloth.hpp>
#include <cmath>
#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_setup.hpp"
#include "reference_forces.hpp"

namespace clothlab::bench {
namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The `scenario:` map as parameter texts; a sequence becomes "[a, b, c]".
ParamTexts scenario_params(const YAML::Node& config) {
  ParamTexts params;
  for (const auto& entry : config["scenario"]) {
    const auto key = entry.first.as<std::string>();
    if (key == "plugin") continue;
    std::string text;
    if (entry.second.IsSequence()) {
      for (const auto& item : entry.second)
        text += (text.empty() ? "[" : ", ") + item.as<std::string>();
      text += "]";
    } else {
      text = entry.second.as<std::string>();
    }
    params.emplace_back(key, text);
  }
  return params;
}

class ReferenceEuler {
 public:
  explicit ReferenceEuler(const Scene& scene)
      : cloth_(scene), x_(cloth_.initial_positions()), v_(x_.size(), 0.0f), a_(x_.size()) {}

  void step(float dt) {
    cloth_.acceleration(x_.data(), v_.data(), a_.data());
    for (std::size_t i = 0; i < x_.size(); ++i) {
      v_[i] += dt * a_[i];
      x_[i] += dt * v_[i];
    }
  }
  bool finite() const {
    return std::all_of(x_.begin(), x_.end(), [](float value) { return std::isfinite(value); });
  }
  std::size_t springs() const { return cloth_.springs().size(); }

 private:
  reference::ReferenceCloth<float> cloth_;
  std::vector<float> x_, v_, a_;
};

template <class StepFunction>
void time_block(int steps, StepFunction step, std::vector<double>& step_seconds) {
  for (int i = 0; i < steps; ++i) {
    const auto start = Clock::now();
    step();
    step_seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
}

int run(const std::string& config_path, int repetitions, int steps) {
  const YAML::Node config = YAML::LoadFile(config_path);
  const double dt = config["dt"].as<double>();
  const Scene scene = make_scene("flag", scenario_params(config));

  ReferenceEuler baseline(scene);
  Cloth cloth(scene, Precision::Float32, PipelineOptions{true, config["threads"].as<int>(0)});
  BoundIntegrator euler("euler", cloth);
  std::vector<double> baseline_s, fast_s;
  double t = 0.0;
  for (int repetition = 0; repetition < repetitions; ++repetition) {
    time_block(
        steps, [&] { baseline.step(static_cast<float>(dt)); }, baseline_s);
    time_block(
        steps,
        [&] {
          euler.step(t, dt);
          t += dt;
        },
        fast_s);
  }
  const double baseline_ms = 1e3 * median(baseline_s);
  const double fast_ms = 1e3 * median(fast_s);
  const nlohmann::json result = {
      {"scenario", "flag"},
      {"integrator", "euler"},
      {"rows", scene.rows},
      {"cols", scene.cols},
      {"springs", baseline.springs()},
      {"dt", dt},
      {"steps_per_block", steps},
      {"repetitions", repetitions},
      {"baseline_ms_per_step_median", baseline_ms},
      {"fast_ms_per_step_median", fast_ms},
      {"fast_threads", cloth.threads()},
      {"speedup", baseline_ms / fast_ms},
      {"baseline_springs_per_second",
       static_cast<double>(baseline.springs()) / (baseline_ms * 1e-3)},
      {"finite", baseline.finite() && cloth.state_is_finite()},
  };
  std::printf("%s\n", result.dump(2).c_str());
  return result["finite"].get<bool>() ? 0 : 3;
}

}  // namespace
}  // namespace clothlab::bench

int main(int argc, char** argv) {
  if (argc != 2 && argc != 4) {
    std::fprintf(stderr, "usage: clothlab_speedup CONFIG [REPETITIONS STEPS]\n");
    return 1;
  }
  try {
    const int repetitions = argc == 4 ? std::stoi(argv[2]) : 5;
    const int steps = argc == 4 ? std::stoi(argv[3]) : 100;
    if (repetitions < 1 || steps < 1) {
      std::fprintf(stderr, "clothlab_speedup: REPETITIONS and STEPS must be >= 1\n");
      return 1;
    }
    return clothlab::bench::run(argv[1], repetitions, steps);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "clothlab_speedup: error: %s\n", error.what());
    return 1;
  }
}
