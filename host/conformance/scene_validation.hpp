// The rules a scenario's clothlab_scene must satisfy for the core to simulate it.
#pragma once

#include <clothlab/plugin.h>

namespace clothlab::conformance {

// Fails the running check, naming the field and its value, when the core's one scene
// validation (scene_from_abi) rejects `scene`.
void require_valid_scene(const clothlab_scene& scene);

}  // namespace clothlab::conformance
