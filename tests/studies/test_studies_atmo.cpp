// atmosh::studies, atmosphere: the LUT study's rays, the LUT convergence study and the
// zenith sweep, checked against closed forms for an exponential Rayleigh-only
// atmosphere and against the lower-level library calls they summarise.
//
// Closed forms (exponential profile of scale height H, ground extinction beta):
// - vertical column from altitude h to the top z_t: beta H (exp(-h/H) - exp(-z_t/H));
// - horizontal ray from radius r = R + h: beta H exp(-h/H) Ch(x, 90 deg), x = r/H, with
//   the grazing Chapman function Ch(x, 90 deg) = sqrt(pi x / 2) (1 + 3/(8x) + O(x^-2))
//   (its asymptotic series for large x = r/H, ~795 here: the O(x^-2) term is ~2e-7;
//   cross-checked with a 400 000-point midpoint sum of the integral, 3.38439354 at
//   h = 1 km); truncating the ray at the top changes it by < 4e-6 (exp(-z_t/H));
// - a ray from radius r meets the ground iff mu < -sqrt(1 - (R/r)^2).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <utility>

#include <gtest/gtest.h>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/error.hpp"
#include "atmosh/studies/studies_atmo.hpp"

namespace {

using namespace atmosh;

constexpr double kBeta = 13.558e-6, kH = 8000.0, kR = 6360e3, kTop = 100e3;

// Rayleigh only, given by its coefficients (lambda^-4 about 550 nm), exponential.
atmo::AtmosphereSpec exponential_rayleigh() {
  atmo::AtmosphereSpec s;
  s.name = "exponential-rayleigh";
  s.planet.radius_m = kR;
  s.planet.atmosphere_top_m = kTop;
  atmo::RayleighSpec r;
  r.model = atmo::RayleighSpec::Model::Coefficients;
  r.scattering_per_m = kBeta;
  r.reference_nm = 550.0;
  r.profile = atmo::DensityProfileSpec::exponential(kH);
  s.rayleigh = r;
  s.mie.reset();
  s.ozone.reset();
  return s;
}

std::string entry(const io::Provenance& p, const std::string& key) {
  for (const auto& [k, v] : p.entries)
    if (k == key) return v;
  return "(absent)";
}

double vertical_tau(double h) { return kBeta * kH * (std::exp(-h / kH) - std::exp(-kTop / kH)); }

double horizontal_tau(double h) {
  const double x = (kR + h) / kH;
  return kBeta * kH * std::exp(-h / kH) * std::sqrt(std::numbers::pi * x / 2) * (1 + 3 / (8 * x));
}

TEST(StudiesAtmo, StudyRaysStayInsideTheAtmosphereAndIncludeTheKinkProbes) {
  const atmo::Atmosphere atm(atmo::preset("earth-physical"));
  const auto rays = studies::lut_study_rays(atm);
  const double R = atm.ground_radius(), top = atm.top_altitude();
  std::set<std::pair<double, double>> set;
  for (const auto& r : rays) {
    EXPECT_GE(r.r, R);
    EXPECT_LE(r.r, R + top);
    EXPECT_GE(r.mu, -1.0);
    EXPECT_LE(r.mu, 1.0);
    set.insert({r.r, r.mu});
  }
  const auto probes = atmo::kink_probe_rays(atm);
  ASSERT_FALSE(probes.empty());  // earth-physical's U.S. 1976 layers have kinks
  for (const auto& p : probes) EXPECT_TRUE(set.count({p.r, p.mu})) << p.r << " " << p.mu;
  EXPECT_GE(rays.size(), 1000u + probes.size());
  // Deterministic: the same rays every call.
  const auto again = studies::lut_study_rays(atm);
  ASSERT_EQ(again.size(), rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_EQ(again[i].mu, rays[i].mu);
}

TEST(StudiesAtmo, ZenithSweepMatchesTheClosedForms) {
  const double h = 1000.0;
  const auto sweep = studies::zenith_sweep(exponential_rayleigh(), h);
  ASSERT_EQ(sweep.rows.size(), 361u);
  const auto& up = sweep.rows[0];
  EXPECT_EQ(up.zenith_deg, 0.0);
  EXPECT_NEAR(up.tau_reference, vertical_tau(h), 1e-9 * vertical_tau(h));
  EXPECT_NEAR(up.tau_lut, vertical_tau(h), 1e-3 * vertical_tau(h));
  const auto& horizontal = sweep.rows[180];
  EXPECT_EQ(horizontal.zenith_deg, 90.0);
  EXPECT_NEAR(horizontal.tau_reference, horizontal_tau(h), 1e-5 * horizontal_tau(h));
  const double mu_ground = -std::sqrt(1.0 - std::pow(kR / (kR + h), 2.0));
  for (const auto& w : sweep.rows) {
    const double mu = std::cos(w.zenith_deg * std::numbers::pi / 180.0);
    if (std::abs(mu - mu_ground) > 1e-9) {
      EXPECT_EQ(w.hits_ground, mu < mu_ground) << w.zenith_deg;
    }
    if (w.tau_reference > 0.0) {
      EXPECT_NEAR(w.relative_error, std::abs(w.tau_lut - w.tau_reference) / w.tau_reference, 1e-15);
    }
    EXPECT_TRUE(std::isfinite(w.tau_reference) && std::isfinite(w.tau_lut));
  }
  // Optical depth grows with the zenith angle while the ray looks up.
  for (int i = 1; i <= 180; ++i) EXPECT_GT(sweep.rows[i].tau_reference, sweep.rows[i - 1].tau_reference) << i;
  EXPECT_EQ(entry(sweep.provenance, "altitude_m"), "1000");
}

TEST(StudiesAtmo, LutConvergenceRowsBoundTheClosedFormErrorAndShrinkWithFinerTables) {
  const auto spec = exponential_rayleigh();
  studies::LutConvergenceOptions o;
  o.quick = true;
  const auto t = studies::lut_convergence(spec, o);
  ASSERT_EQ(t.rows.size(), 3u);  // reference, 16x32, 40x64 (an exponential profile has no kinks)
  const atmo::Atmosphere atm(spec);
  const auto rays = studies::lut_study_rays(atm);
  const auto col = [&](const std::string& c) {
    for (std::size_t i = 0; i < t.spec.extra_columns.size(); ++i)
      if (t.spec.extra_columns[i] == c) return i;
    ADD_FAILURE() << c;
    return std::size_t{0};
  };
  EXPECT_EQ(t.rows[0].method, "reference");
  EXPECT_LT(t.rows[0].error_max, 1e-9);
  for (std::size_t i = 1; i < 3; ++i) {
    const auto& row = t.rows[i];
    EXPECT_EQ(row.method, "lut");
    EXPECT_EQ(row.extras[col("rays")], double(rays.size()));
    atmo::LutOptions lo;
    lo.shells = int(row.extras[col("shells")]);
    lo.view_directions = lo.sun_directions = int(row.extras[col("directions")]);
    const atmo::OpticalDepthLut lut(atm, lo);
    // The row's maximum error is at least the error on every vertical ray of the set,
    // measured against the closed form (the reference is exact to ~1e-13 there).
    const auto k = atm.coefficients_at(550.0);
    for (const auto& ray : rays) {
      if (ray.mu != 1.0) continue;
      const double exact = vertical_tau(ray.r - kR);
      if (exact <= 0.0) continue;
      const double e = std::abs(atmo::optical_depth(k, lut.view(ray.r, ray.mu).column) - exact) / exact;
      EXPECT_GE(row.error_max * (1 + 1e-6) + 1e-12, e) << row.setting << " at r = " << ray.r;
    }
    EXPECT_LE(row.error_rms, row.error_max);
    EXPECT_DOUBLE_EQ(row.extras[col("error_estimate_rel")], lut.estimate_max_rel_error(550.0));
    EXPECT_EQ(row.extras[col("table_bytes")], double(lut.table_bytes()));
    EXPECT_GT(row.time_s, 0.0);
  }
  EXPECT_EQ(t.rows[1].setting, "16x32");
  EXPECT_EQ(t.rows[2].setting, "40x64");
  EXPECT_LT(t.rows[2].error_max, t.rows[1].error_max);
  EXPECT_LT(t.rows[2].error_max, 1e-3);
  EXPECT_EQ(entry(t.provenance, "device"), "cpu");
}

TEST(StudiesAtmo, OpticalDepthQueryMatchesTheVerticalClosedForm) {
  auto spec = exponential_rayleigh();
  spec.spectrum.wavelengths_nm = {550.0};
  const atmo::Atmosphere atm(spec);
  const double h = 2500.0;
  const auto exact = studies::optical_depth_query(atm, {h, 0.0, false, 40, 64});
  EXPECT_NEAR(exact.rayleigh, vertical_tau(h), 1e-10 * vertical_tau(h));
  EXPECT_EQ(exact.mie, 0.0);
  EXPECT_EQ(exact.total, exact.rayleigh);
  EXPECT_LT(exact.error_estimate, 1e-9 * exact.total);
  EXPECT_FALSE(exact.hits_ground);
  const auto lut = studies::optical_depth_query(atm, {h, 0.0, true, 40, 64});
  // The tables' error stays within their own a-posteriori estimate's order.
  EXPECT_NEAR(lut.total, vertical_tau(h), std::max(3 * lut.error_estimate, 1e-6 * vertical_tau(h)));
  EXPECT_GT(lut.error_estimate, 0.0);
  EXPECT_TRUE(studies::optical_depth_query(atm, {h, 180.0, false, 40, 64}).hits_ground);
  EXPECT_THROW(studies::optical_depth_query(atm, {-1.0, 0.0, false, 40, 64}), InputError);
}

TEST(StudiesAtmo, LutConvergenceRejectsAnUnknownDevice) {
  studies::LutConvergenceOptions o;
  o.quick = true;
  o.device = "tpu";
  EXPECT_THROW(studies::lut_convergence(exponential_rayleigh(), o), InputError);
}

}  // namespace
