// The GLM configuration the C++ API is compiled with. GLM's types are in the API's
// signatures (glm::vec3, glm::quat, glm::mat4), and GLM_FORCE_DEFAULT_ALIGNED_GENTYPES or a
// GLM_FORCE_PRECISION_* macro changes their qualifier: a program built so would fail to link
// ("undefined reference to ... glm::vec<3, float, (qualifier)3>") or, worse, disagree on
// layout. This stops it at compile time with the reason. The C API (marionette.h) has no GLM
// in it: an engine with another GLM configuration uses that, or builds Marionette with the
// same macros (docs/bridge.md).
#pragma once
#include <type_traits>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

static_assert(std::is_same_v<glm::vec3, glm::vec<3, float, glm::packed_highp>> &&
                  std::is_same_v<glm::mat4, glm::mat<4, 4, float, glm::packed_highp>> &&
                  std::is_same_v<glm::quat, glm::qua<float, glm::packed_highp>>,
              "Marionette's C++ API is built with GLM's default packed highp types; this translation unit "
              "defines GLM_FORCE_DEFAULT_ALIGNED_GENTYPES or a GLM_FORCE_PRECISION_* macro. Use the C API "
              "(marionette.h), or build Marionette with the same GLM configuration (docs/bridge.md).");
