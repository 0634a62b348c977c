// Iterations of projective_dynamics (local/global) or xpbd (Gauss-Seidel sweeps of one
// substep) with and without Chebyshev acceleration (parameter chebyshev_rho; Wang 2015) to the
// same error, on the first step of the cotton flag (lab/real-cloth.md, "Chebyshev
// acceleration"): the plugin itself, stepped once (xpbd: one substep) from the flag's initial
// state with N iterations, against the converged step. The plain iteration's asymptotic
// spectral radius is the ratio of its last two changes at the most iterations (of the ladder)
// where they are still above 1e-7 of the step; without --rho that estimate is used. The
// converged step is the plugin's most iterations (its `iterations` parameter's maximum)
// accelerated with the first rho that does not diverge there (else plain), its own error
// estimated by how far it moved over the ladder's last rung (errors below 10x that are not
// reported). The error is the largest particle distance to the converged step relative to the
// largest distance a particle moves in the step. A rho whose step fails (xpbd reports
// divergence as an error) is "diverged" from that rung on.
//
//   build/bin/clothlab_pd_iterations [config] [--integrator projective_dynamics|xpbd]
//       [--side N] [--rate R] [--delay S] [--rho r ...]
//
// config default configs/choose-cotton-flag-200.yaml (material, scenario), integrator
// projective_dynamics, side 50, rate 60 (h = 1/R s), delay the plugin's default.
#include <algorithm>
#include <clothlab/config/yaml_settings.hpp>
#include <clothlab/core/cloth.hpp>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_setup.hpp"
#include "material_scene.hpp"
#include "run_config.hpp"

namespace clothlab::bench {
namespace {

const std::vector<long> kLadder = {1,  2,  3,  4,   6,   8,   11,  16,  23,  32,
                                   45, 64, 91, 128, 181, 256, 362, 512, 724, 1000};
const std::vector<double> kErrors = {1e-2, 1e-3, 1e-4, 1e-5, 1e-6};

using Positions = std::vector<double>;  // 3 per particle

// The flag's positions after one step of the integrator with these parameters.
Positions step_once(const Scene& scene, const std::string& integrator_id, double h,
                    const ParamTexts& params) {
  const Cloth cloth(scene, Precision::Float64, PipelineOptions{true, 1});
  BoundIntegrator integrator(integrator_id, cloth, params);
  integrator.step(0.0, h);
  const sdk::System<double> system(cloth.system());
  Positions out;
  for (uint32_t i = 0; i < system.particle_count(); ++i)
    for (std::size_t k = 0; k < 3; ++k) out.push_back(system.x()[k * system.stride() + i]);
  return out;
}

double largest_distance(const Positions& a, const Positions& b) {
  double largest = 0.0;
  for (std::size_t i = 0; i < a.size(); i += 3)
    largest = std::max(largest, std::hypot(a[i] - b[i], a[i + 1] - b[i + 1], a[i + 2] - b[i + 2]));
  return largest;
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

int run(int argc, char** argv) {
  std::string config_path = "configs/choose-cotton-flag-200.yaml";
  std::string integrator_id = "projective_dynamics";
  int side = 50, rate = 60;
  long delay = 0;
  std::vector<double> rhos;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    const bool has_value = k + 1 < argc;
    if (arg == "--integrator" && has_value) {
      integrator_id = argv[++k];
    } else if (arg == "--side" && has_value) {
      side = static_cast<int>(number_of(arg, argv[++k]));
    } else if (arg == "--rate" && has_value) {
      rate = static_cast<int>(number_of(arg, argv[++k]));
    } else if (arg == "--delay" && has_value) {
      delay = static_cast<long>(number_of(arg, argv[++k]));
    } else if (arg == "--rho" && has_value) {
      rhos.push_back(number_of(arg, argv[++k]));  // its range: the plugin's schema
    } else if (arg.rfind("--", 0) == 0) {
      std::fprintf(stderr, "clothlab_pd_iterations: unknown option '%s'\n", arg.c_str());
      return 2;
    } else {
      config_path = arg;
    }
  }
  if (integrator_id != "projective_dynamics" && integrator_id != "xpbd") {
    std::fprintf(stderr, "clothlab_pd_iterations: --integrator '%s': projective_dynamics or xpbd\n",
                 integrator_id.c_str());
    return 2;
  }
  if (side < 3 || rate <= 0) {
    std::fprintf(stderr, "clothlab_pd_iterations: --side must be >= 3 and --rate > 0\n");
    return 2;
  }
  const cli::RunConfig config = cli::resolve_run_config(config::read_config_file(config_path));
  if (!config.material) {
    std::fprintf(stderr, "%s: no material.* (the table is for a material's cloth)\n",
                 config_path.c_str());
    return 2;
  }
  const Scene scene = make_material_scene(config, side);
  const double h = 1.0 / rate;
  const auto with = [&](long iterations, double rho) {
    ParamTexts params = {{"iterations", std::to_string(iterations)},
                         {"chebyshev_rho", number(rho)}};
    if (delay > 0) params.emplace_back("chebyshev_delay", std::to_string(delay));
    if (integrator_id == "xpbd") params.emplace_back("inner_substeps", "1");  // h is one substep
    return params;
  };
  // The ladder up to the plugin's most iterations.
  const auto most = static_cast<long>(integrator_param_maximum(integrator_id, "iterations"));
  std::vector<long> ladder;
  for (const long n : kLadder)
    if (n < most) ladder.push_back(n);
  ladder.push_back(most);
  const Positions start = step_once(scene, integrator_id, 0.0, with(1, 0.0));
  // The plain iteration's asymptotic radius: the ratio of its last two changes (power
  // iteration on the error; needs no converged step), at the most iterations whose changes
  // are still well above rounding.
  double estimate = 0.0;
  for (auto count = ladder.rbegin(); count != ladder.rend() && estimate == 0.0; ++count) {
    const Positions last[3] = {step_once(scene, integrator_id, h, with(*count - 2, 0.0)),
                               step_once(scene, integrator_id, h, with(*count - 1, 0.0)),
                               step_once(scene, integrator_id, h, with(*count, 0.0))};
    const double change = largest_distance(last[1], last[0]);
    if (change > 1e-7 * largest_distance(last[2], start))
      estimate = largest_distance(last[2], last[1]) / change;
  }
  if (rhos.empty()) rhos.push_back(std::min(estimate, 0.9999));
  // The converged step: the plugin's most iterations, accelerated with the first rho that does
  // not diverge there (else plain); its error estimated by its change over the ladder's last
  // rung.
  double reference_rho = 0.0;
  Positions converged;
  for (const double rho : rhos) {
    try {
      converged = step_once(scene, integrator_id, h, with(most, rho));
      reference_rho = rho;
      break;
    } catch (const std::exception&) {
    }
  }
  if (converged.empty()) converged = step_once(scene, integrator_id, h, with(most, 0.0));
  const double moved = largest_distance(converged, start);
  const double reference_error =
      largest_distance(converged, step_once(scene, integrator_id, h,
                                            with(ladder[ladder.size() - 2], reference_rho))) /
      moved;
  // NaN where the step failed (diverged).
  const auto errors_of = [&](double rho) {
    std::vector<double> errors;
    for (const long n : ladder) {
      try {
        errors.push_back(
            largest_distance(step_once(scene, integrator_id, h, with(n, rho)), converged) / moved);
      } catch (const std::exception& error) {
        std::fprintf(stderr, "rho %s, %ld iterations: %s\n", number(rho).c_str(), n, error.what());
        errors.push_back(std::nan(""));
      }
    }
    return errors;
  };
  std::vector<std::vector<double>> errors = {errors_of(0.0)};
  for (const double rho : rhos) errors.push_back(errors_of(rho));

  std::printf(
      "%s, %s, %s scenario, %dx%d, h = 1/%d s, float64: first step; the converged step is %ld "
      "iterations with rho %s (they changed it by %.1e of the step's motion, %.3g m, after "
      "%ld)\nplain iteration's estimated spectral radius: %.6f\n\n",
      integrator_id.c_str(), config.material->name.c_str(), config.scenario.c_str(), side, side,
      rate, most, number(reference_rho).c_str(), reference_error, moved, ladder[ladder.size() - 2],
      estimate);
  std::printf("| iterations | plain |");
  for (const double rho : rhos) std::printf(" rho %s |", number(rho).c_str());
  std::printf("\n|---|---|");
  for (std::size_t m = 0; m < rhos.size(); ++m) std::printf("---|");
  std::printf("\n");
  for (std::size_t r = 0; r < ladder.size(); ++r) {
    std::printf("| %ld |", ladder[r]);
    for (const std::vector<double>& method : errors)
      std::isnan(method[r]) ? std::printf(" diverged |") : std::printf(" %.2e |", method[r]);
    std::printf("\n");
  }
  std::printf("\n| error | plain |");
  for (const double rho : rhos) std::printf(" rho %s |", number(rho).c_str());
  std::printf("\n|---|---|");
  for (std::size_t m = 0; m < rhos.size(); ++m) std::printf("---|");
  std::printf("\n");
  for (const double target : kErrors) {
    if (target < 10 * reference_error) continue;  // below what the reference resolves
    std::printf("| %.0e |", target);
    for (const std::vector<double>& method : errors) {
      const auto reached = std::find_if(method.begin(), method.end(),
                                        [&](double e) { return e <= target || std::isnan(e); });
      if (reached == method.end())
        std::printf(" > %ld |", ladder.back());
      else if (std::isnan(*reached))
        std::printf(" diverged |");
      else
        std::printf(" %ld |", ladder[static_cast<std::size_t>(reached - method.begin())]);
    }
    std::printf("\n");
  }
  return 0;
}

}  // namespace
}  // namespace clothlab::bench

int main(int argc, char** argv) {
  try {
    return clothlab::bench::run(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "clothlab_pd_iterations: %s\n", error.what());
    return 1;
  }
}
