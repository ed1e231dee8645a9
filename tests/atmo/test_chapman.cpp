// Chapman function and erfcx against closed forms and asymptotic series.
#include <gtest/gtest.h>

#include <cmath>

#include "atmosh/atmo/chapman.hpp"
#include "atmosh/error.hpp"

using namespace atmosh::atmo;

namespace {
constexpr double kPi = 3.14159265358979323846;
}

// Ch(x, 90 deg) = x e^x K1(x) against its asymptotic series (Abramowitz & Stegun
// 9.7.2): sqrt(pi x/2)(1 + 3/(8x) - 15/(128x^2) + 105/(1024x^3)); the truncation
// error is below the next term, 4725/(32768 x^4) relative.
TEST(Chapman, HorizontalMatchesBesselAsymptotics) {
  for (double x : {795.0, 5300.0, 200.0}) {
    double exact = chapman_horizontal_exact(x);
    double s = std::sqrt(kPi * x / 2.0) * (1 + 3 / (8 * x) - 15 / (128 * x * x) + 105 / (1024 * x * x * x));
    EXPECT_NEAR(exact / s - 1.0, 0.0, 4725.0 / (32768.0 * x * x * x * x) + 2e-15) << x;
  }
}

// The stiff horizontal values quoted for Earth: x = 6360 km / 8 km = 795 gives
// ~35.35, x = 6360 km / 1.2 km = 5300 gives ~91.25 (leading term sqrt(pi x / 2)).
TEST(Chapman, EarthHorizontalValues) {
  EXPECT_NEAR(chapman_horizontal_exact(795.0), std::sqrt(kPi * 795.0 / 2.0) * (1 + 3 / (8 * 795.0)), 1e-5);
  EXPECT_NEAR(chapman_horizontal_exact(795.0), 35.35, 0.01);
  EXPECT_NEAR(chapman_horizontal_exact(5300.0), 91.25, 0.01);
}

// Independent routes: the Huestis integral at mu -> 0 must meet x e^x K1(x)
// (computed from std::cyl_bessel_k below x = 50).
TEST(Chapman, IntegralFormMeetsBesselForm) {
  for (double x : {10.0, 40.0, 795.0}) {
    EXPECT_NEAR(chapman_exact(x, 0.0) / chapman_horizontal_exact(x), 1.0, 1e-12) << x;
    EXPECT_NEAR(chapman_exact(x, 1e-12) / chapman_horizontal_exact(x), 1.0, 1e-9) << x;
  }
  EXPECT_NEAR(chapman_horizontal_exact(10.0), 10.0 * std::exp(10.0) * std::cyl_bessel_k(1.0, 10.0), 1e-12);
}

// Overhead sun: Ch = 1; near-vertical: Ch ~ 1/mu (plane-parallel limit) as x -> inf.
TEST(Chapman, PlaneParallelLimit) {
  EXPECT_DOUBLE_EQ(chapman_exact(795.0, 1.0), 1.0);
  for (double mu : {0.9, 0.5, 0.3}) {
    double ch = chapman_exact(1e7, mu);
    EXPECT_NEAR(ch * mu, 1.0, 1e-5) << mu;
  }
}

// erfcx: erfcx(0) = 1; exp(y^2) erfc(y) at moderate y; asymptotic 1/(y sqrt(pi))
// (1 - 1/(2y^2) + 3/(4y^4)) at large y; reflection for negative y.
TEST(Chapman, Erfcx) {
  EXPECT_DOUBLE_EQ(erfcx(0.0), 1.0);
  for (double y : {0.1, 1.0, 3.0, 8.0})
    EXPECT_NEAR(erfcx(y) / (std::exp(y * y) * std::erfc(y)), 1.0, 1e-13) << y;
  for (double y : {30.0, 100.0, 1e4}) {
    double a = 1.0 / (y * std::sqrt(kPi)) * (1 - 1 / (2 * y * y) + 3 / (4 * y * y * y * y));
    EXPECT_NEAR(erfcx(y) / a, 1.0, 20.0 / std::pow(y, 6)) << y;
  }
  EXPECT_NEAR(erfcx(-1.0), 2.0 * std::exp(1.0) - erfcx(1.0), 1e-13);
  EXPECT_THROW(erfcx(std::nan("")), atmosh::InputError);
}

// The erfcx closed form is accurate to O(1/x): within 1/x of the exact value.
TEST(Chapman, ErfcxClosedFormWithinItsBound) {
  for (double x : {795.0, 5300.0})
    for (double mu : {1.0, 0.7, 0.2, 0.01, 0.0, -0.01, -0.05}) {
      double e = chapman_exact(x, mu), a = chapman_erfcx(x, mu);
      EXPECT_TRUE(std::isfinite(a));
      EXPECT_LT(std::abs(a / e - 1.0), 1.0 / x) << x << " " << mu;
    }
}
