// One rule for the chromaticity of black: none (NaN), where xy_chromaticity keeps
// its D65 fallback for callers that need a colour.
#include <gtest/gtest.h>

#include <cmath>

#include "atmosh/atmo/colour.hpp"

using namespace atmosh::atmo;

TEST(ChromaticityRule, BlackHasNoneAndColoursKeepTheirs) {
  const Chromaticity z = xy_chromaticity_or_nan({0.0, 0.0, 0.0});
  EXPECT_TRUE(std::isnan(z.x) && std::isnan(z.y));
  const Chromaticity n = xy_chromaticity_or_nan({NAN, 1.0, 1.0});
  EXPECT_TRUE(std::isnan(n.x) && std::isnan(n.y));
  // x = X / (X + Y + Z), y = Y / (X + Y + Z) (CIE 15:2004, eq. 7.3).
  const Chromaticity c = xy_chromaticity_or_nan({1.0, 2.0, 5.0});
  EXPECT_DOUBLE_EQ(c.x, 0.125);
  EXPECT_DOUBLE_EQ(c.y, 0.25);
}
