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
#include "mc_sky_reference.hpp"
#include "sanitizer_build.hpp"

using namespace atmosh::atmo;
using atmosh::test::kMcSkyReference;
using atmosh::test::McRow;

// Orders N = 4 at the default table sizes (MultipleScatteringOptions) against every
// stored row. Per row e = L / L_mc - 1 of the luminance, s = the row's relative standard
// error. Measured (docs/radiative-transfer.md, "Orders at the default tables"): sun >= 0
// within 0.36 %, -2 and -3 deg within 0.93 %; -4 deg -1.06 ... +2.89 % and -6 deg
// -0.93 ... +1.12 % (rows' s 0.3-4.5 %); -9 deg -6.2 ... +3.1 %, -12 deg -10.9 ... +3.3 %
// (s up to 3.3 %). Bounds:
//   sun >= 0: |e| <= min(1 %, 0.5 % + 3 s); -2 and -3 deg: |e| <= 1 % (the issue's
//   target, met);
//   -4 and -6 deg: |e| <= 1 % + 3 s (the 1 %, not resolved by these rows);
//   -9 and -12 deg: |e| <= 5 % + 3 s (the 5 % is missed by three rows, at 1.4-3.3 %
//   s: not shown within it).
// The default tables take ~8 s of CPU to build: Release only (a sanitizer build takes
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
  for (const McRow& r : kMcSkyReference) {
    sky.radiance(0.0, enu_direction(r.view_el_deg, 180.0 + r.view_rel_az_deg), enu_direction(r.sun_deg, 180.0),
                 L.data());
    const double lum = xyz(L).Y, e = lum / r.luminance - 1, s = r.stderr_ / r.luminance;
    ASSERT_TRUE(std::isfinite(lum) && lum > 0);
    double bound;
    if (r.sun_deg >= 0) {
      bound = std::min(0.01, 0.005 + 3 * s);
    } else if (r.sun_deg >= -3) {
      bound = 0.01;
    } else if (r.sun_deg >= -6) {
      bound = 0.01 + 3 * s;
    } else {
      bound = 0.05 + 3 * s;
    }
    EXPECT_LE(std::fabs(e), bound) << "sun " << r.sun_deg << " view " << r.view_el_deg << "/" << r.view_rel_az_deg
                                   << (r.guided ? " (guided)" : "") << ": L " << lum << " L_mc " << r.luminance
                                   << " +- " << 100 * s << " %";
  }
}
