#include <gtest/gtest.h>

#include <cmath>

#include "marionette/core/transform.hpp"

using namespace marionette;

TEST(Transform, SafeNormalizeRejectsZeroAndNaN) {
  EXPECT_EQ(safeNormalize(glm::quat(0, 0, 0, 0)), glm::quat(1, 0, 0, 0));
  EXPECT_EQ(safeNormalize(glm::quat(NAN, 0, 0, 0)), glm::quat(1, 0, 0, 0));
  glm::quat q = safeNormalize(glm::quat(2, 0, 0, 0));
  EXPECT_FLOAT_EQ(q.w, 1.0f);
}
