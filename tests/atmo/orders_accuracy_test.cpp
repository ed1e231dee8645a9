// The successive-orders method at its default table sizes against stored Monte-Carlo
// reference values (issue 24: "orders <= 1 % in luminance for every view above the
// horizon and every sun elevation >= -6 deg; <= 5 % from -6 to -12 deg").
//
// The reference: atmosh's Monte-Carlo radiative transfer, an independent solver (no
// table, no sphere rule); its stored rows, their provenance (function, scene, seed,
// paths) and standard errors: mc_sky_reference.hpp.
//
// The views are the study's fixed set: the zenith, 5 deg up toward / across / away from
// the sun, and 30 and 60 deg up away from it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/colour.hpp"
#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "double_scattering_reference.hpp"
#include "mc_sky_reference.hpp"
#include "sanitizer_build.hpp"

using namespace atmosh::atmo;
using atmosh::test::McPooled;
using atmosh::test::pooled_mc_reference;

namespace {
// Observers above the ground (2 km and 10 km), sun 30, 0 and -3 deg, the study's 6 views:
// rt_reference_views(MonteCarloSky(atmosphere, solar, RtSkyOptions{}), rt_reference_view_set(),
// {30, 0, -3}, height, run) with run.paths = 1 280 000 and run.seed = 7 (the plain
// estimator: RtSkyOptions' guide is off above -5 deg) on the atmosphere of the test below
// (the built-in default scene's, black ground). Luminance and standard error [cd/m^2].
struct McElevatedRow {
  double height_m, sun_deg, view_el_deg, view_rel_az_deg, luminance, stderr_;
};
// clang-format off
constexpr McElevatedRow kMcElevated[] = {
    {2000, 30, 90, 0, 714.850954, 0.682648841},
    {2000, 30, 5, 0, 7520.19718, 5.499281},
    {2000, 30, 5, 90, 4405.58144, 4.36127495},
    {2000, 30, 5, 180, 6655.55934, 5.17393709},
    {2000, 30, 30, 180, 1399.00834, 1.35007915},
    {2000, 30, 60, 180, 690.618568, 0.740352758},
    {2000, 0, 90, 0, 149.668456, 0.178544559},
    {2000, 0, 5, 0, 2417.32283, 1.78983465},
    {2000, 0, 5, 90, 931.864206, 1.11183655},
    {2000, 0, 5, 180, 1198.28981, 1.19509924},
    {2000, 0, 30, 180, 437.801281, 0.442271111},
    {2000, 0, 60, 180, 204.281996, 0.226052793},
    {2000, -3, 90, 0, 23.3284748, 0.0887614012},
    {2000, -3, 5, 0, 465.863062, 1.12515},
    {2000, -3, 5, 90, 105.793608, 0.440092845},
    {2000, -3, 5, 180, 22.2555882, 0.266380365},
    {2000, -3, 30, 180, 53.8693716, 0.214008449},
    {2000, -3, 60, 180, 30.5280926, 0.117016866},
    {10000, 30, 90, 0, 277.125738, 0.357635031},
    {10000, 30, 5, 0, 3372.0088, 3.04003394},
    {10000, 30, 5, 90, 2050.45989, 2.2696918},
    {10000, 30, 5, 180, 3123.71275, 2.90246486},
    {10000, 30, 30, 180, 555.000306, 0.622514982},
    {10000, 30, 60, 180, 267.961404, 0.372613287},
    {10000, 0, 90, 0, 94.6513607, 0.107278679},
    {10000, 0, 5, 0, 1605.29376, 1.03739855},
    {10000, 0, 5, 90, 773.050831, 0.659915198},
    {10000, 0, 5, 180, 1174.49826, 0.982051783},
    {10000, 0, 30, 180, 296.704503, 0.257494917},
    {10000, 0, 60, 180, 131.470727, 0.133499873},
    {10000, -3, 90, 0, 22.3267511, 0.0609914637},
    {10000, -3, 5, 0, 510.99902, 0.850517223},
    {10000, -3, 5, 90, 152.815559, 0.361764896},
    {10000, -3, 5, 180, 72.9764896, 0.164535968},
    {10000, -3, 30, 180, 62.2145464, 0.159859098},
    {10000, -3, 60, 180, 30.6906289, 0.0812546478},
};
// clang-format on
}  // namespace

// Orders N = 5 at the default table sizes (MultipleScatteringOptions) against every
// stored view, its runs pooled (pooled_mc_reference: guided runs only where a view has
// them; the error bar the larger of the formal one and the runs' scatter). Per view
// e = L / L_mc - 1 of the luminance, s = the pooled relative standard error. Measured
// (docs/sky.md, "Multiple scattering"): sun >= 0 -0.22 ... +0.24 % (s 0.07-0.15 %);
// -2 deg -0.05 ... +0.73 % (s 0.14-0.21 %); -3 deg -0.27 ... +0.44 % (s 0.14-0.33 %);
// -4 deg -0.16 ... +0.43 % (s 0.08-0.17 %); -6 deg -0.03 ... +0.24 % (s 0.10-0.41 %);
// -9 deg -0.61 ... +0.91 % (s 0.18-0.67 %); -12 deg -1.09 ... +2.46 % (s 0.14-1.17 %).
// (The previous interpolation, a correction by the corners' variance, with the previous
// defaults: 0.46 / 1.71 / 1.48 / 3.77 / 8.51 % at sun >= 0 / -2..-3 / -4..-6 / -9 / -12
// deg against the same rows.)
// Bounds (what is met):
//   sun >= 0: |e| <= min(0.5 %, 0.2 % + 3 s);
//   -2 to -6 deg: |e| <= 1 % (the 1 %, met by every view);
//   -9 deg: |e| <= 2 %, -12 deg: |e| <= 4 % (the 5 %, met by every view).
// Observers at 2 km and 10 km (kMcElevated; the same table build): sun >= 0
// -0.40 ... +0.25 % (s 0.06-0.14 %), -3 deg -0.35 ... +0.87 % (s 0.17-1.20 %).
// Bounds: sun >= 0: |e| <= min(0.5 %, 0.2 % + 3 s); -3 deg: |e| <= 1 % (the 1 %).
// The default tables take ~10 s of CPU to build: Release only (a sanitizer build takes
// minutes); the reduced tables of multiple_scattering_test.cpp run there.
TEST(ScatteringOrders, DefaultTablesAgainstStoredMonteCarloReference) {
  if (atmosh::test::kSanitized) GTEST_SKIP() << "the default tables take minutes to build under a sanitizer";
  AtmosphereSpec spec;
  spec.spectrum.from_nm = 380;
  spec.spectrum.to_nm = 780;
  spec.spectrum.count = 16;
  ASSERT_EQ(spec.planet.ground_albedo, 0.0);  // the reference's black ground
  const Atmosphere atm(spec);
  SkyOptions so;
  so.scattering.method = ScatteringMethod::Orders;  // every other option at its default
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum), so);
  const SpectralToXyz xyz(atm.wavelengths_nm());
  std::vector<double> L(atm.wavelengths_nm().size());
  const std::vector<McPooled> ref = pooled_mc_reference();
  EXPECT_EQ(ref.size(), 60u);  // 10 sun elevations x the 6 views
  for (const McPooled& r : ref) {
    sky.radiance(0.0, enu_direction(r.view_el_deg, 180.0 + r.view_rel_az_deg), enu_direction(r.sun_deg, 180.0),
                 L.data());
    const double lum = xyz(L).Y, e = lum / r.luminance - 1, s = r.stderr_ / r.luminance;
    ASSERT_TRUE(std::isfinite(lum) && lum > 0);
    double bound;
    if (r.sun_deg >= 0) {
      bound = std::min(0.005, 0.002 + 3 * s);
    } else if (r.sun_deg >= -6) {
      bound = 0.01;
    } else if (r.sun_deg >= -9) {
      bound = 0.02;
    } else {
      bound = 0.04;
    }
    EXPECT_LE(std::fabs(e), bound) << "sun " << r.sun_deg << " view " << r.view_el_deg << "/" << r.view_rel_az_deg
                                   << " (" << r.runs << " runs): L " << lum << " L_mc " << r.luminance << " +- "
                                   << 100 * s << " %";
  }
  for (const McElevatedRow& r : kMcElevated) {
    sky.radiance(r.height_m, enu_direction(r.view_el_deg, 180.0 + r.view_rel_az_deg), enu_direction(r.sun_deg, 180.0),
                 L.data());
    const double lum = xyz(L).Y, e = lum / r.luminance - 1, s = r.stderr_ / r.luminance;
    ASSERT_TRUE(std::isfinite(lum) && lum > 0);
    const double bound = r.sun_deg >= 0 ? std::min(0.005, 0.002 + 3 * s) : 0.01;
    EXPECT_LE(std::fabs(e), bound) << "observer at " << r.height_m << " m, sun " << r.sun_deg << " view "
                                   << r.view_el_deg << "/" << r.view_rel_az_deg << ": L " << lum << " L_mc "
                                   << r.luminance << " +- " << 100 * s << " %";
  }
}

// The second order alone (orders = 2 minus single scattering) at the default table
// sizes against an independent quadrature of double scattering with every
// transmittance (double_scattering_full: nested Gauss-Legendre rules, the shadow's
// boundary resolved on every ray, nothing shared with the tables), for the default
// atmosphere without aerosol (Rayleigh and ozone: the quadrature converges at a cost a
// test affords; Mie's forward peak needs ~4x its rules), black ground, the 530 nm bin
// of 4. The quadrature's settings (6 Gauss points a piece, 12 zenith cosines a side,
// 24 azimuths) agree with (6, 16, 32) to 4e-4 here.
// Measured (docs/sky.md, "Multiple scattering", "Second order against a quadrature"),
// 5 deg up away from the sun: sun 30 deg -0.24 %, 0 deg +0.72 %, -3 deg +0.62 %.
// The interpolation's former correction by the corners' variance put the last at +2.6 %
// (and +3.9 % at -6 deg with 2-4x finer tables, where the curvature correction converges
// to -0.1 %).
// Bounds: 0.5 % by day, 1 % at sunset and at sun -3 deg.
TEST(ScatteringOrders, SecondOrderAgainstFullDoubleScatteringQuadrature) {
  if (atmosh::test::kSanitized) GTEST_SKIP() << "the quadrature takes minutes under a sanitizer";
  AtmosphereSpec spec;
  spec.mie.reset();
  spec.spectrum.from_nm = 380;
  spec.spectrum.to_nm = 780;
  spec.spectrum.count = 4;
  ASSERT_EQ(spec.planet.ground_albedo, 0.0);  // the quadrature's black ground
  const Atmosphere atm(spec);
  const SolarSpectrum solar = solar_spectrum_for_bins(spec.spectrum);
  SkyOptions s1, s2;
  s1.scattering.method = ScatteringMethod::Single;
  s2.scattering.method = ScatteringMethod::Orders;
  s2.scattering.orders = 2;  // every table size at its default
  const SkyIntegrator single(atm, solar, s1), two(atm, solar, s2);
  const std::size_t wl = 1;  // 530 nm
  ASSERT_NEAR(atm.wavelengths_nm()[wl], 530.0, 1e-9);
  struct Case {
    double sun_deg, view_el_deg, view_rel_az_deg, bound;
  };
  for (const Case c : {Case{30, 5, 180, 0.005}, Case{0, 5, 180, 0.01}, Case{-3, 5, 180, 0.01}}) {
    const glm::dvec3 v = enu_direction(c.view_el_deg, 180.0 + c.view_rel_az_deg), l = enu_direction(c.sun_deg, 180.0);
    const double tables = (two.radiance(0.0, v, l)[wl] - single.radiance(0.0, v, l)[wl]) / solar[wl];
    const double ref = test_ms::double_scattering_full(atm, wl, v, l, 6, 12, 24);
    ASSERT_TRUE(std::isfinite(ref) && ref > 0);
    EXPECT_NEAR(tables / ref - 1.0, 0.0, c.bound)
        << "sun " << c.sun_deg << " view " << c.view_el_deg << "/" << c.view_rel_az_deg << ": " << tables << " vs "
        << ref;
  }
}
