#include "scene_validation.hpp"

#include <clothlab/core/cloth.hpp>
#include <stdexcept>

#include "verdict.hpp"

namespace clothlab::conformance {

void require_valid_scene(const clothlab_scene& scene) {
  try {
    scene_from_abi(scene);
  } catch (const std::invalid_argument& rejection) {
    // The scenario broke the contract: a failed check naming the field, not "exception escaped".
    throw CheckFailure(std::string("the core rejects the scene: ") + rejection.what());
  }
}

}  // namespace clothlab::conformance
