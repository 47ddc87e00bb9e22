#include <gtest/gtest.h>

#include "sim/render/scene.h"

TEST(Scene, Builds) {
  vid::sim::SceneConfig c;
  vid::sim::Scene s(c);
  EXPECT_EQ(s.surfaces().size(), 6 + 6 * s.boxes().size());
}
