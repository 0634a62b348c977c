// Faulty: right on a grid, but on any other cloth its step (a general path written apart from
// the grid's) nudges the pinned particles. Only the irregular mesh of the sheet checks catches
// it (numerics.pinned-* there): a runner with grids alone passes it.
#include <optional>

#include "symplectic_euler.hpp"

struct MovesPinsOffTheGrid : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "moves-pins-off-the-grid";
  static constexpr const char* name = "Symplectic Euler that moves pins on meshes";
  static constexpr const char* description =
      "faulty: on a cloth that is no grid, pinned particles drift by 1e-6 m per step";

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    SymplecticEulerBase::prepare(system);
    on_grid_ = system.grid().has_value();
  }

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, dt);
    if (on_grid_) return;
    for (uint32_t i = 0; i < system.particle_count(); ++i)
      if (system.inverse_mass()[i] == Real(0)) system.x()[i] += Real(1e-6);
  }

  bool on_grid_ = false;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-moves-pins-off-the-grid", "0.0.1",
                      clothlab::sdk::integrators<MovesPinsOffTheGrid>, clothlab::sdk::scenarios<>)
