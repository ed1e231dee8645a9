// The named stiff/extreme-case suite: every case finite and within its bound.
// References inside each case are independent: the exact Chapman function (integral
// and Bessel forms), H (1 - e^{-h/H}), normalisation to 1 and the exact CDF by
// adaptive quadrature, closed-form moments, Bodhaine et al. (1999) eq. (30), and the
// exact optical depth for the LUT — see stiff_cases.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "atmosh/atmo/stiff_cases.hpp"

using namespace atmosh::atmo;

TEST(StiffCases, AllFiniteAndWithinTheirBounds) {
  auto cases = run_stiff_cases(24, 48);
  ASSERT_GE(cases.size(), 20u);
  for (const auto& c : cases) {
    EXPECT_TRUE(std::isfinite(c.value)) << c.name;
    EXPECT_TRUE(c.pass) << c.name << ": value " << c.value << " reference " << c.reference << " error " << c.error
                        << " bound " << c.bound;
  }
}
