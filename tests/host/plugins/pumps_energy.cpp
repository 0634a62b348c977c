// Semi-implicit Euler that moves attachments and resolves contacts like the built-ins, then
// multiplies every free velocity by (1 + gain) each step: a method that injects energy, for the
// stability monitor's tests on a dragged cape. The default gain is large enough to be caught
// within 2 s whatever the build's rounding: at 0.002 the injected energy stayed within the
// attachments' work bound on one build's trajectory and not on another's (the cape's contacts
// make the trajectory depend on every rounding). With `relative`, only the velocity relative to
// the pins' mean velocity grows: energy pumped in at the attachments, whose momentum looks like
// the attachments' pull (the monitor still has to tell the two apart).
#include <array>
#include <clothlab/sdk.hpp>
#include <cstddef>

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
      clothlab::sdk::bool_param("relative", false,
                                "scale the velocity relative to the pins' mean velocity"),
  };
  explicit PumpsEnergy(const clothlab::sdk::Params& values)
      : gain_(values.real("gain")), relative_(values.flag("relative")) {}

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    system.reserve_rkn(1);
  }
  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    system.step_rkn(t, dt, euler);
    if (!relative_) system.axpy(system.v(), gain_, system.v());
    system.move_attachments(t + dt);
    if (relative_) pump_relative_to_pins(system);
    system.resolve_contacts(t + dt);
  }

 private:
  template <class Real>
  void pump_relative_to_pins(clothlab::sdk::System<Real>& system) const {
    const std::size_t n = system.particle_count(), stride = system.stride();
    const Real* inverse_mass = system.inverse_mass();
    Real* v = system.v();
    std::array<double, 3> pins{0, 0, 0};
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (inverse_mass[i] == 0) {
        ++count;
        for (std::size_t axis = 0; axis < 3; ++axis) pins[axis] += v[axis * stride + i];
      }
    if (count == 0) return;
    for (std::size_t i = 0; i < n; ++i)
      if (inverse_mass[i] != 0)
        for (std::size_t axis = 0; axis < 3; ++axis) {
          Real& velocity = v[axis * stride + i];
          velocity += static_cast<Real>(gain_ * (velocity - pins[axis] / count));
        }
  }

  double gain_;
  bool relative_;
};

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("clothlab-test-pumps-energy", "0.1.0",
                      clothlab::sdk::integrators<PumpsEnergy>, clothlab::sdk::scenarios<>)
