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
#include "atmosh/atmo/ms_convergence.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/error.hpp"
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
// reference (every order, an independent solver), views of the study's fixed set, the
// sun above the horizon (below it the reference needs minutes per row for a useful
// standard error: docs/radiative-transfer.md). Per row |L - L_mc| / L_mc <= bound +
// 3 relative standard errors of the reference. The target for `orders`: <= 1 %
// for views above the horizon and sun >= -6 deg; what the methods meet is stated with
// the bounds (measured with `atmosh converge ms`, docs/radiative-transfer.md).
TEST(MsConvergence, MultipleScatteringMethodsAgainstTheMonteCarloReference) {
  const AtmosphereSpec spec = preset("earth-graphics");
  const Atmosphere atm(spec);
  MsStudyOptions o;
  o.views = rt_reference_view_set();
  o.sun_elevations_deg = {30, 0};
  o.reference_run.paths = paths(48000);
  o.reference_run.seed = 11;
  o.timing_repetitions = 1;
  MultipleScatteringOptions approx;
  approx.method = ScatteringMethod::Approximate;
  MultipleScatteringOptions orders;  // N = 4, half the default tables (the default's build takes ~15 s CPU)
  orders.method = ScatteringMethod::Orders;
  orders.orders = 4;
  orders.orders_radii = 8;
  orders.orders_view_directions = 32;
  orders.orders_sun_directions = 24;
  orders.orders_azimuths = 4;
  o.settings = {{"approximate", "default", approx}, {"orders", "N=4 half tables", orders}};
  const MsStudyResult r = ms_convergence_study(atm, solar_spectrum_for_bins(spec.spectrum), o);
  ASSERT_EQ(r.points.size(), 12u);
  // Measured at these rows (48 000 paths, seed 11): the approximation within 3.8 %
  // except the horizon away from the sun at sun 0 deg, -6.2 % (stderr 0.84 %; a
  // 128 000-path run found -3.0 % there: the reference's spread near the horizon exceeds
  // its stated standard error, rare high-weight paths); orders N = 4 on these half
  // tables within 3.2 % except that row, -4.3 % (before the tables' interpolation was
  // corrected for the geometric mean's low bias, scattering_orders.cpp: within 6.0 %
  // and -7.7 % there, with 16 sun directions). Bounds: 4.5 % for both (+ 3 sigma).
  // The target (orders <= 1 %) is for the default tables, too slow to build in
  // a unit test: measured within 0.64 % for sun >= 0 against a 1 280 000-path
  // reference (stderr <= 0.15 %; docs/radiative-transfer.md).
  const double bound[2] = {0.045, 0.045};
  for (const auto& p : r.points) {
    const double s_rel = p.reference_luminance_stderr / p.reference_luminance;
    EXPECT_LT(s_rel, 0.03) << p.sun_elevation_deg << " " << p.view_elevation_deg;
    for (int k = 0; k < 2; ++k) {
      const double e = std::fabs(p.luminance[k] - p.reference_luminance) / p.reference_luminance;
      EXPECT_LE(e, bound[k] + 3 * s_rel) << o.settings[k].method << " sun " << p.sun_elevation_deg << " view "
                                         << p.view_elevation_deg << "/" << p.view_relative_azimuth_deg;
    }
  }
}
