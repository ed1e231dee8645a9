// The error study of the sky's scattering methods against the Monte-Carlo reference
// (ms_convergence.hpp), and the bounds the methods meet against that reference.
//
// The reference is the Monte-Carlo radiative transfer of radiative_transfer.hpp
// (every order of scattering; its plane-parallel mode is checked against DISORT's
// published test problems in test_radiative_transfer.cpp): an independent solver. Every
// bound below is stated with the reference's own 3 standard errors added.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/colour.hpp"
#include "atmosh/atmo/ms_convergence.hpp"
#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/error.hpp"
#include "mc_sky_reference.hpp"
#include "sanitizer_build.hpp"

using namespace atmosh::atmo;

namespace {

using atmosh::test::kSanitized;

// Sanitizer builds run ~10x slower: fewer paths; every bound carries the reference's
// 3 standard errors, so it widens with them.
std::int64_t paths(std::int64_t release) { return kSanitized ? std::max<std::int64_t>(release / 8, 2000) : release; }

const MsStudyPoint& point(const MsStudyResult& r, double sun, double view_el, double rel_az) {
  for (const auto& p : r.points)
    if (p.sun_elevation_deg == sun && p.view_elevation_deg == view_el && p.view_relative_azimuth_deg == rel_az)
      return p;
  throw std::runtime_error("no such point");
}

}  // namespace

TEST(MsConvergence, RowsAreWellFormedAndSingleScatteringIsFarBelowTheReference) {
  const AtmosphereSpec spec = preset("earth-graphics");
  const Atmosphere atm(spec);
  MsStudyOptions o;
  o.views = {{90, 0}, {5, 180}};
  o.sun_elevations_deg = {10};
  o.reference_run.paths = paths(32000);
  o.settings = ms_study_default_settings(true);
  o.timing_repetitions = 1;
  const MsStudyResult r = ms_convergence_study(atm, solar_spectrum_for_bins(spec.spectrum), o);

  ASSERT_EQ(r.points.size(), 2u);
  ASSERT_EQ(o.settings.size(), 3u);
  EXPECT_EQ(o.settings[0].method, "single");
  EXPECT_EQ(o.settings[1].method, "approximate");
  // Per setting the bands "all" and "day" (sun >= 0 only: no civil / night rows).
  ASSERT_EQ(r.rows.size(), 2 * o.settings.size());
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const auto& row = r.rows[i];
    EXPECT_EQ(row.method, o.settings[i / 2].method);
    EXPECT_EQ(row.band, i % 2 ? "day" : "all");
    EXPECT_EQ(row.rows, 2);
    EXPECT_EQ(row.rows_skipped, 0);
    EXPECT_TRUE(std::isfinite(row.error_max_rel) && row.error_max_rel >= row.error_rms_rel && row.error_rms_rel > 0);
    EXPECT_GT(row.time_s, 0.0);
    EXPECT_NEAR(row.time_s, row.build_time_s + row.eval_time_s, 1e-12 * row.time_s + 1e-15);
    EXPECT_GT(row.reference_rel_stderr_max, 0.0);
    EXPECT_LT(row.reference_rel_stderr_max, 0.05);
  }
  for (const auto& p : r.points) {
    ASSERT_EQ(p.luminance.size(), o.settings.size());
    EXPECT_GT(p.reference_luminance, 0.0);
    EXPECT_GT(p.reference_luminance_stderr, 0.0);
  }
  // Single scattering alone misses a fifth to a third of the zenith's light (an
  // independent property: Bruneton's 2017 reference implementation, 4 orders, albedo
  // 0.1, finds the zenith luminance 22 % low at sun 10 deg; issue 24's table). At least
  // 5 % below the Monte-Carlo mean beyond its 3 standard errors:
  const MsStudyPoint& z = point(r, 10, 90, 0);
  const double s_rel = z.reference_luminance_stderr / z.reference_luminance;
  const double single_deficit = (z.reference_luminance - z.luminance[0]) / z.reference_luminance;
  EXPECT_GT(single_deficit, 0.05 + 3 * s_rel) << "stderr " << s_rel;
  EXPECT_LT(single_deficit, 0.40);
  // The all-orders approximation closes most of that gap.
  for (std::size_t k = 1; k < o.settings.size(); ++k) {
    const double e = std::fabs(z.luminance[k] - z.reference_luminance) / z.reference_luminance;
    EXPECT_LT(e, single_deficit) << o.settings[k].setting;
    EXPECT_LT(r.rows[2 * k].error_max_rel, r.rows[0].error_max_rel) << o.settings[k].setting;
  }
}

TEST(MsConvergence, BadInputIsAnInputError) {
  const AtmosphereSpec spec = preset("earth-graphics");
  const Atmosphere atm(spec);
  const SolarSpectrum solar = solar_spectrum_for_bins(spec.spectrum);
  MsStudyOptions o;
  o.views.clear();
  EXPECT_THROW(ms_convergence_study(atm, solar, o), atmosh::InputError);
  o = {};
  o.sun_elevations_deg = {std::nan("")};
  EXPECT_THROW(ms_convergence_study(atm, solar, o), atmosh::InputError);
  o = {};
  o.reference_run.paths = 0;
  EXPECT_THROW(ms_convergence_study(atm, solar, o), atmosh::InputError);
  o = {};
  o.settings[1].scattering.ms_altitudes = 1;
  EXPECT_THROW(ms_convergence_study(atm, solar, o), atmosh::InputError);
  o = {};
  o.timing_repetitions = 0;
  EXPECT_THROW(ms_convergence_study(atm, solar, o), atmosh::InputError);
}

// Issue 24's assertion: the multiple-scattering methods against the Monte-Carlo
// reference (every order, an independent solver), the stored rows of
// mc_sky_reference.hpp with the sun above the horizon (60, 30, 10 and 0 deg, the study's
// 6 views, 1 280 000 paths per row: relative standard error s 0.07-0.15 %). Per row
// |L / L_mc - 1| <= bound + 3 s. (The rows were computed here with 48 000 paths per run
// before; the stored ones are ~5x more precise and cost nothing: the methods' tables are
// the test's only cost.) Measured: the approximation -3.39 ... +3.18 % (its isotropic
// second and later scattering, docs/radiative-transfer.md), orders N = 4 on half tables
// (8 radii, 32 view, 24 sun, 4 azimuths) -1.21 ... +1.00 %; the default tables meet the
// issue's 1 % (orders_accuracy_test.cpp). Bounds: 3.6 % and 1.5 %.
TEST(MsConvergence, MultipleScatteringMethodsAgainstTheMonteCarloReference) {
  AtmosphereSpec spec;  // the reference rows' atmosphere (mc_sky_reference.hpp)
  spec.spectrum.from_nm = 380;
  spec.spectrum.to_nm = 780;
  spec.spectrum.count = 16;
  ASSERT_EQ(spec.planet.ground_albedo, 0.0);
  const Atmosphere atm(spec);
  MultipleScatteringOptions approx;
  approx.method = ScatteringMethod::Approximate;
  MultipleScatteringOptions orders;  // N = 4, about half the default tables (the default's build takes ~8 s CPU)
  orders.method = ScatteringMethod::Orders;
  orders.orders = 4;
  orders.orders_radii = 8;
  orders.orders_view_directions = 32;
  orders.orders_sun_directions = 24;
  orders.orders_azimuths = 4;
  const MultipleScatteringOptions methods[2] = {approx, orders};
  const double bound[2] = {0.036, 0.015};
  const SpectralToXyz xyz(atm.wavelengths_nm());
  std::vector<double> L(atm.wavelengths_nm().size());
  for (int k = 0; k < 2; ++k) {
    SkyOptions so;
    so.scattering = methods[k];
    const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum), so);
    int rows = 0;
    for (const atmosh::test::McRow& r : atmosh::test::kMcSkyReference) {
      if (r.sun_deg < 0) continue;
      ++rows;
      sky.radiance(0.0, enu_direction(r.view_el_deg, 180.0 + r.view_rel_az_deg), enu_direction(r.sun_deg, 180.0),
                   L.data());
      const double e = std::fabs(xyz(L).Y / r.luminance - 1), s_rel = r.stderr_ / r.luminance;
      ASSERT_LT(s_rel, 0.002);
      EXPECT_LE(e, bound[k] + 3 * s_rel) << (k ? "orders" : "approximate") << " sun " << r.sun_deg << " view "
                                         << r.view_el_deg << "/" << r.view_rel_az_deg;
    }
    EXPECT_EQ(rows, 24);
  }
}
