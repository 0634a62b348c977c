// The rules a scenario's clothlab_scene must satisfy for the core to simulate it.
#pragma once

#include <clothlab/plugin.h>

namespace clothlab::conformance {

// Fails the running check, naming the field and its value, when `scene` breaks a rule:
// non-empty grid, pins inside it, positive mass, positive spacing (hence rest lengths)
// where there are two or more particles, unit axes, non-negative springs, finite values.
void require_valid_scene(const clothlab_scene& scene);

}  // namespace clothlab::conformance
