// Presets and validation of atmosphere parameters.
#include <gtest/gtest.h>

#include <cmath>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/density.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/error.hpp"

using namespace atmosh::atmo;

namespace {
std::string message_of(const AtmosphereSpec& s) {
  try {
    validate(s);
  } catch (const atmosh::InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Presets, AllBuildAndValidate) {
  for (const auto& n : preset_names()) {
    auto s = preset(n);
    EXPECT_NO_THROW(validate(s)) << n;
    Atmosphere a(s);
    EXPECT_FALSE(a.wavelengths_nm().empty());
  }
  try {
    preset("mars");
    FAIL();
  } catch (const atmosh::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("earth-graphics"), std::string::npos);
  }
}

// Default spectrum: 360-830 nm in 10 nm bins.
TEST(Presets, DefaultSpectrum) {
  auto w = spectrum_wavelengths(SpectrumSpec{});
  ASSERT_EQ(w.size(), 47u);
  EXPECT_DOUBLE_EQ(w.front(), 365.0);
  EXPECT_DOUBLE_EQ(w.back(), 825.0);
}

// U.S. Standard Atmosphere 1976 density ratios (NOAA 1976, Table I): 0.33756 at
// 11 km (0.41351 kg/m^3... ratio rho/rho0 at 10 km = 0.33756), 0.072674 at 20 km.
// Its layer boundaries are nodes: the tropopause at geopotential 11 km' (geometric
// 11019.07 m), rho = 0.36392 kg/m^3, and 20 km' (20063.12 m), 0.088035 kg/m^3
// (NOAA 1976, Table I by geopotential altitude; rho0 = 1.2250 kg/m^3).
TEST(Presets, UsStandard1976) {
  auto p = us_standard_1976_profile(100e3, 500.0);
  auto at = [&](double z) {
    for (std::size_t i = 0; i < p.altitude_m.size(); ++i)
      if (std::abs(p.altitude_m[i] - z) < 0.01) return p.value[i];
    ADD_FAILURE() << "no node at " << z << " m";
    return -1.0;
  };
  EXPECT_DOUBLE_EQ(p.value[0], 1.0);
  EXPECT_NEAR(at(10e3), 0.33756, 2e-4);
  EXPECT_NEAR(at(20e3), 0.072674, 1e-4);
  EXPECT_NEAR(at(11019.07), 0.36392 / 1.2250, 2e-5);
  EXPECT_NEAR(at(20063.12), 0.088035 / 1.2250, 2e-5);
  // Every 500 m otherwise (grid nodes within 50 m of a boundary move onto it).
  for (std::size_t i = 1; i < p.altitude_m.size(); ++i) {
    EXPECT_GT(p.altitude_m[i] - p.altitude_m[i - 1], 50.0) << i;
    EXPECT_LE(p.altitude_m[i] - p.altitude_m[i - 1], 550.0) << i;
  }
  EXPECT_EQ(p.altitude_m.back(), 100e3);
  // The kinks that stand out of the table's sampled curvature are exactly the seven
  // layer boundaries (geopotential 11, 20, 32, 47, 51, 71, 84.852 km'), and the excess
  // at the tropopause is the standard's jump of d rho/dh there, -rho (dT/dH jump) / T
  // = -(0.36392 / 1.2250) (6.5e-3 / 216.65) dH/dz per metre (dH/dz = (r0 / (r0 + z))^2).
  const DensityProfile prof(p);
  const auto ks = prof.strongest_kink_jumps(16, 0.0, 100e3, 0.3);
  const double r0 = 6356766.0;
  ASSERT_EQ(ks.size(), 7u);
  const double boundary[7] = {11e3, 20e3, 32e3, 47e3, 51e3, 71e3, 84852.0};
  for (int i = 0; i < 7; ++i) EXPECT_NEAR(ks[i].altitude_m, r0 * boundary[i] / (r0 - boundary[i]), 0.01) << i;
  const double z = ks[0].altitude_m, dHdz = (r0 / (r0 + z)) * (r0 / (r0 + z));
  EXPECT_NEAR(ks[0].excess_jump, -(0.36392 / 1.2250) * (6.5e-3 / 216.65) * dHdz, 0.03 * 8.9e-6);
  // The jump of d2rho/dz2 there, from the standard's laws: with G = g0 M0 / R* and
  // lapse rate L below (0 above), d ln rho / dH = -(G + L) / T, so
  // d2rho/dH2 = rho ((G + L)^2 + (G + L) L) / T^2 below and rho G^2 / T^2 above; in
  // geometric z: rho_zz = rho_HH (dH/dz)^2 + rho_H d2H/dz2, rho_H jumping by rho L / T.
  const double G = 9.80665 * 28.9644 / 8314.32, L = -6.5e-3, T = 216.65, rho = 0.36392 / 1.2250;
  const double jump_HH = rho * (G * G - (G + L) * (G + L) - (G + L) * L) / (T * T);
  const double d2Hdz2 = -2.0 * dHdz / (r0 + z);
  const double want = jump_HH * dHdz * dHdz + rho * L / T * d2Hdz2;  // 3.659e-9 / m^2
  EXPECT_NEAR(ks[0].curvature_jump, want, 0.02 * want);
}

TEST(Presets, ValidationNamesTheKey) {
  auto s = preset("earth-graphics");
  s.mie->scattering_per_m = -1.0;
  EXPECT_NE(message_of(s).find("mie.scattering_per_m"), std::string::npos);
  s = preset("earth-graphics");
  s.planet.atmosphere_top_m = -5.0;
  EXPECT_NE(message_of(s).find("planet.atmosphere_top_m"), std::string::npos);
  s = preset("earth-graphics");
  s.mie->profile.scale_height_m = std::nan("");
  EXPECT_NE(message_of(s).find("mie.profile.scale_height_m"), std::string::npos);
  s = preset("earth-graphics");
  s.rayleigh->profile.scale_height_m = -5.0;
  EXPECT_NE(message_of(s).find("rayleigh.profile.scale_height_m = -5"), std::string::npos);
  s = preset("earth-graphics");
  s.spectrum.wavelengths_nm = {300.0};
  EXPECT_NE(message_of(s).find("spectrum.wavelengths_nm[0]"), std::string::npos);
  s = preset("earth-graphics");
  s.ozone->profile.peak_m = 50e3;
  EXPECT_NE(message_of(s).find("ozone.profile"), std::string::npos);
  // The physical Rayleigh model holds 240-1690 nm (the measurements behind Peck &
  // Reeder's refractivity fit): outside a spectrum is bad input even without ozone;
  // coefficients are unbounded. A generated grid is named by the key that was written.
  s = preset("earth-physical");
  s.ozone.reset();
  s.spectrum.wavelengths_nm = {1800.0};
  EXPECT_NE(message_of(s).find("spectrum.wavelengths_nm[0] = 1800"), std::string::npos);
  s.spectrum.wavelengths_nm = {239.0};
  EXPECT_NE(message_of(s).find("physical Rayleigh"), std::string::npos);
  s.spectrum.wavelengths_nm = {240.0, 1064.0, 1690.0};
  EXPECT_NO_THROW(Atmosphere{s});
  auto grid = [](AtmosphereSpec a, double from, double to, int count) {
    a.spectrum.wavelengths_nm.clear();
    a.spectrum.from_nm = from;
    a.spectrum.to_nm = to;
    a.spectrum.count = count;
    return a;
  };
  EXPECT_NE(message_of(grid(s, 380.0, 2000.0, 16)).find("spectrum.to_nm = 2000"), std::string::npos);
  EXPECT_NE(message_of(grid(preset("earth-graphics"), 300.0, 700.0, 8)).find("spectrum.from_nm = 300"),
            std::string::npos);
  s = preset("test-planet");
  s.ozone.reset();
  s.spectrum.wavelengths_nm = {1800.0};
  EXPECT_NO_THROW(Atmosphere{s});
  // Extreme values that broke the columns (found by a stress sweep): scale heights
  // below 1 mm (exp(-h/H) overflows for altitudes rounded just below 0), profile nodes
  // below the planet's centre, atmospheres thinner than 1 m, coefficients and ozone
  // columns whose products overflow.
  s = preset("earth-graphics");
  s.mie->profile.scale_height_m = 1e-100;
  EXPECT_NE(message_of(s).find("mie.profile.scale_height_m"), std::string::npos);
  s = preset("earth-graphics");
  s.ozone->profile.bottom_m = -2e7;
  s.ozone->profile.peak_m = -1e7;
  EXPECT_NE(message_of(s).find("ozone.profile.bottom_m"), std::string::npos);
  s = preset("earth-graphics");
  s.planet.atmosphere_top_m = 1e-9;
  EXPECT_NE(message_of(s).find("planet.atmosphere_top_m"), std::string::npos);
  s = preset("earth-graphics");
  s.mie->scattering_per_m = 1.7e308;
  EXPECT_NE(message_of(s).find("mie.scattering_per_m"), std::string::npos);
  s = preset("earth-graphics");
  s.ozone->column_du = 1e300;
  EXPECT_NE(message_of(s).find("ozone.column_du"), std::string::npos);
  s = preset("earth-graphics");
  s.ozone->profile.bottom_m = 0.0;
  s.ozone->profile.peak_m = 1e-300;
  s.ozone->profile.top_m = 2e-300;
  EXPECT_NE(message_of(s).find("ozone.profile"), std::string::npos);
  s = preset("earth-graphics");
  s.ozone->profile.bottom_m = -1e300;
  s.ozone->profile.peak_m = 0.0;
  s.ozone->profile.top_m = 1e300;
  EXPECT_NE(message_of(s).find("ozone.profile"), std::string::npos);
  // Coefficient x density x (reference / lambda)^angstrom must stay finite.
  s = preset("earth-graphics");
  s.mie->reference_nm = 1e90;
  s.mie->angstrom = 10.0;
  EXPECT_NE(message_of(s).find("mie.reference_nm"), std::string::npos);
  s = preset("earth-graphics");
  s.mie->profile = DensityProfileSpec{};
  s.mie->profile.kind = DensityProfileSpec::Kind::Tabulated;
  s.mie->profile.altitude_m = {0.0, 1000.0, 2000.0};
  s.mie->profile.value = {1e306, 1e306, 0.0};
  EXPECT_NE(message_of(s).find("mie.profile.value[0]"), std::string::npos);
  // Values that would overflow the number density p / (k T).
  s = preset("earth-physical");
  s.rayleigh->pressure_pa = 1e300;
  EXPECT_NE(message_of(s).find("rayleigh.pressure_pa"), std::string::npos);
  s = preset("earth-physical");
  s.rayleigh->temperature_k = 1e-300;
  EXPECT_NE(message_of(s).find("rayleigh.temperature_k"), std::string::npos);
}

// Leaving a constituent out removes it: zero coefficients.
TEST(Presets, AbsentConstituentsAreZero) {
  auto s = preset("earth-graphics");
  s.mie.reset();
  s.ozone.reset();
  Atmosphere a(s);
  EXPECT_FALSE(a.has(kMie));
  auto k = a.coefficients_at(500.0);
  EXPECT_EQ(k.extinction[kMie], 0.0);
  EXPECT_EQ(k.extinction[kOzone], 0.0);
}
