// Compiled with GLM_FORCE_DEFAULT_ALIGNED_GENTYPES by package.glm_configuration_is_checked: the
// C++ API must refuse it at compile time with the reason (core/glm_abi.hpp), not fail to link.
#include "marionette/scene/scene.hpp"

int main() {
  marionette::Scene scene;
  return scene.setObject("probe", glm::vec3(0.0f)) ? 0 : 1;
}
