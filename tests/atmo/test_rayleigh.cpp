// Rayleigh scattering against Bodhaine et al. (1999) and Bruneton's constants.
#include <gtest/gtest.h>

#include <cmath>

#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/rayleigh.hpp"

using namespace atmosh::atmo;

// Bodhaine et al. (1999) compute tau = sigma * P A / (m_a g) (their eq. 27) with
// P = 1013.25 hPa, A = 6.0221367e23, m_a = 15.0556 C + 28.9595 g/mol (eq. 17,
// C = 360e-6) and g the gravity at the mass-weighted column height (eqs. 10-11:
// z_c = 0.73737 z + 5517.56 m at z = 0, latitude 45 deg: g = 978.9158 cm/s^2, not
// the sea-level 980.616); their eq. (30) fits that result to better than 0.01 %
// over 250-850 nm. So our cross-section times that column must match eq. (30) to
// 1e-4 at every wavelength of the grid's range.
TEST(Rayleigh, CrossSectionMatchesBodhaineEq30) {
  const double z = 5517.56;  // m
  const double g = (980.6160 - 3.085462e-4 * z + 7.254e-11 * z * z - 1.517e-17 * z * z * z) * 1e-2;  // m/s^2
  EXPECT_NEAR(g, 9.789158, 1e-6);
  const double A = 6.0221367e23, ma = (15.0556 * 360e-6 + 28.9595) * 1e-3;
  const double column = 101325.0 * A / (ma * g);  // molecules per m^2
  for (double nm : {360.0, 400.0, 450.0, 500.0, 550.0, 600.0, 700.0, 830.0}) {
    double ratio = rayleigh_cross_section(nm, 360.0) * column / bodhaine_eq30_optical_depth(nm);
    EXPECT_NEAR(ratio, 1.0, 1e-4) << nm;
  }
  // Spot value of eq. (30) itself at 550 nm (hand-evaluated: 0.09706).
  EXPECT_NEAR(bodhaine_eq30_optical_depth(550.0), 0.09706, 5e-5);
}

// The earth-physical preset integrates the U.S. Standard Atmosphere 1976 density
// (gravity falling with height: ~0.3 % more column than P/(m g0)) sampled every
// 0.5 km and interpolated linearly (~0.05 % more): its sea-level optical depth
// must agree with Bodhaine's eq. (30) within 0.6 %.
TEST(Rayleigh, PhysicalPresetOpticalDepthMatchesBodhaine) {
  Atmosphere atm(preset("earth-physical"));
  OpticalDepthReference ref(atm);
  double col = ref.column(atm.ground_radius(), 1.0).column[kRayleigh];
  for (double nm : {400.0, 550.0, 700.0}) {
    double tau = atm.coefficients_at(nm).extinction[kRayleigh] * col;
    EXPECT_NEAR(tau / bodhaine_eq30_optical_depth(nm), 1.0, 6e-3) << nm;
  }
}

// Bruneton & Neyret (2008), sec. 2: beta_R = (5.8, 13.5, 33.1) e-6 /m at
// (680, 550, 440) nm; Bruneton's 2017 demo: 1.24062e-6 lambda_um^-4.
TEST(Rayleigh, GraphicsPresetCoefficients) {
  Atmosphere atm(preset("earth-graphics"));
  EXPECT_NEAR(atm.coefficients_at(680.0).scattering[kRayleigh], 5.802e-6, 0.002e-6);
  EXPECT_NEAR(atm.coefficients_at(550.0).scattering[kRayleigh], 13.558e-6, 0.002e-6);
  EXPECT_NEAR(atm.coefficients_at(440.0).scattering[kRayleigh], 33.1e-6, 0.05e-6);
}

// King factor of air at 550 nm is ~1.048-1.049 (Bodhaine et al. 1999, Table 2
// trend; Bates 1984), giving a depolarisation ratio ~0.028 (Young 1980: 0.0279).
TEST(Rayleigh, KingFactorAndDepolarisation) {
  double f = king_factor_air(550.0, 360.0);
  EXPECT_NEAR(f, 1.0485, 0.002);
  EXPECT_NEAR(depolarization_from_king(f), 0.0279, 0.001);
}
