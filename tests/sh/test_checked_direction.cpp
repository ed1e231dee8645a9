// Directions given at any scale: checked_direction normalises without overflow or
// underflow (components near the largest double, or subnormal), so every function
// that takes a direction "need not be unit length" takes these too.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "atmosh/error.hpp"
#include "atmosh/sh/basis.hpp"

using atmosh::sh::checked_direction;

TEST(CheckedDirection, NormalisesHugeAndTinyComponents) {
  const double big = std::numeric_limits<double>::max(), h = 1.0 / std::sqrt(2.0);
  struct Case {
    glm::dvec3 in, out;
  };
  const Case cases[] = {
      {{1e308, 1e308, 0.0}, {h, h, 0.0}},
      {{big, 0.0, -big}, {h, 0.0, -h}},
      {{big, big, big}, glm::dvec3(1.0) / std::sqrt(3.0)},
      {{1e-310, -1e-310, 0.0}, {h, -h, 0.0}},  // subnormal: squares underflow to 0
      {{3e-200, 4e-200, 0.0}, {0.6, 0.8, 0.0}},
      {{3.0, 4.0, 12.0}, {3.0 / 13.0, 4.0 / 13.0, 12.0 / 13.0}},
  };
  for (const auto& c : cases) {
    const glm::dvec3 u = checked_direction(c.in, "test");
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(u[k], c.out[k], 2e-16) << c.in.x << " " << c.in.y << " " << c.in.z;
  }
  EXPECT_THROW(checked_direction({0.0, 0.0, 0.0}, "test"), atmosh::InputError);
  EXPECT_THROW(checked_direction({big, std::numeric_limits<double>::infinity(), 0.0}, "test"), atmosh::InputError);
}
