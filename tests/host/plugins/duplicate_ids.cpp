// A plugin whose two integrators share one id.
#include <clothlab/sdk.hpp>

namespace {

template <int Variant>
struct Twin {
  static constexpr const char* id = "twin";
  static constexpr const char* name = "Twin";
  static constexpr const char* version = "0.1.0";
  static constexpr const char* description = "an integrator with a duplicated id";
  static constexpr uint32_t order = 1, evals_per_step = 0, flags = 0;
  static constexpr std::array<clothlab_param_spec, 0> params{};
  explicit Twin(const clothlab::sdk::Params&) {}
  template <class Real>
  void prepare(clothlab::sdk::System<Real>&) {}
  template <class Real>
  void step(clothlab::sdk::System<Real>&, double, double) {}
};

using TwinIntegrators = clothlab::sdk::integrators<Twin<1>, Twin<2>>;

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("clothlab-test-duplicates", "0.1.0", TwinIntegrators,
                      clothlab::sdk::scenarios<>)
