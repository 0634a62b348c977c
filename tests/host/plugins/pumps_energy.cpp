// Semi-implicit Euler that moves attachments and resolves contacts like the built-ins, then
// multiplies every free velocity by (1 + gain) each step: a method that injects energy, for the
// stability monitor's tests on a dragged cape. The default gain is large enough to be caught
// within 2 s whatever the build's rounding: at 0.002 the injected energy stayed within the
// attachments' work bound on one build's trajectory and not on another's (the cape's contacts
// make the trajectory depend on every rounding).
#include <array>
#include <clothlab/sdk.hpp>

namespace {

inline constexpr clothlab::sdk::RknScheme<1> euler{{0.0}, {0.0}, {0.0}, {0.0}, {1.0}, {1.0}};

struct PumpsEnergy {
  static constexpr const char* id = "test-pumps-energy";
  static constexpr const char* name = "Test energy pump";
  static constexpr const char* version = "0.1.0";
  static constexpr const char* description =
      "semi-implicit Euler with every velocity scaled up by 1 + gain per step; for host tests";
  static constexpr uint32_t order = 1, evals_per_step = 1;
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_RESOLVES_CONTACTS | CLOTHLAB_TRAIT_MOVES_ATTACHMENTS, nullptr, nullptr};
  static constexpr std::array params{
      clothlab::sdk::real_param("gain", 0.01, 0.0, 1.0, "", "velocity gain per step"),
  };
  explicit PumpsEnergy(const clothlab::sdk::Params& values) : gain_(values.real("gain")) {}

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    system.reserve_rkn(1);
  }
  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    system.step_rkn(t, dt, euler);
    system.axpy(system.v(), gain_, system.v());
    system.move_attachments(t + dt);
    system.resolve_contacts(t + dt);
  }

 private:
  double gain_;
};

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("clothlab-test-pumps-energy", "0.1.0",
                      clothlab::sdk::integrators<PumpsEnergy>, clothlab::sdk::scenarios<>)
