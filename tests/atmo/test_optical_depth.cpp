// Exact optical-depth reference and Nishita lookup tables against closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <limits>

#include "atmosh/atmo/chapman.hpp"
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/ozone.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/error.hpp"

using namespace atmosh::atmo;

namespace {
// A single exponential layer (scale height H) on an Earth-sized planet with the
// top 60 scale heights up: truncation e^-60 ~ 1e-26 is far below the tolerance.
AtmosphereSpec exponential_only(double H) {
  AtmosphereSpec s;
  s.planet.radius_m = 6360e3;
  s.planet.atmosphere_top_m = 60.0 * H;
  RayleighSpec r;
  r.model = RayleighSpec::Model::Coefficients;
  r.profile.kind = DensityProfileSpec::Kind::Exponential;
  r.profile.scale_height_m = H;
  s.rayleigh = r;
  s.mie.reset();
  s.ozone.reset();
  return s;
}
}  // namespace

// Vertical column of an exponential layer: H (1 - exp(-T/H)) exactly.
TEST(OpticalDepthReference, VerticalExponentialLayer) {
  auto spec = preset("earth-graphics");
  Atmosphere atm(spec);
  OpticalDepthReference ref(atm);
  auto c = ref.column(atm.ground_radius(), 1.0);
  EXPECT_NEAR(c.column[kRayleigh] / (8000.0 * -std::expm1(-60e3 / 8000.0)), 1.0, 1e-12);
  EXPECT_NEAR(c.column[kMie] / (1200.0 * -std::expm1(-60e3 / 1200.0)), 1.0, 1e-12);
  // Tent 10-25-40 km: area = peak * (40 - 10) km / 2 = 15 km.
  EXPECT_NEAR(c.column[kOzone], 15000.0, 1e-8);
  EXPECT_FALSE(c.hits_ground);
  EXPECT_NEAR(c.length_m, 60e3, 1e-6);
}

// Adaptive reference against the exact Chapman function, H Ch(r/H, mu) e^{-h/H},
// to 1e-10 relative, including the horizontal (Ch ~ 35 and ~ 91) and downward
// rays that pass their tangent point above the ground.
TEST(OpticalDepthReference, MatchesExactChapman) {
  for (double H : {8000.0, 1200.0}) {
    Atmosphere atm(exponential_only(H));
    OpticalDepthReference ref(atm);
    const double R = atm.ground_radius();
    for (double h : {0.0, 1000.0, 5000.0, 20000.0})
      for (double mu : {1.0, 0.8, 0.3, 0.05, 0.01, 0.0, -0.01, -0.03}) {
        double r = R + h;
        if (shared::ray_hits_ground(r, mu, R)) continue;
        auto c = ref.column(r, mu);
        double expect = H * std::exp(-h / H) * chapman_exact(r / H, mu);
        EXPECT_NEAR(c.column[kRayleigh] / expect, 1.0, 1e-10) << H << " " << h << " " << mu;
        EXPECT_LT(c.error[kRayleigh], 1e-10 * expect);
      }
  }
}

// Thin layers (H = 10 m and 1 m; R / H up to 6e6): a point's altitude is rounded to
// ~eps R, i.e. eps R / H of a scale height, so the reference asks for no more than
// that relative accuracy. It converges (it used to bisect rounding noise up to its
// 20000-interval cap, ~6e5 evaluations, converged = false) and matches the exact
// Chapman function to 1e-9 on horizontal, grazing and slant rays from near the ground.
TEST(OpticalDepthReference, ThinLayersConvergeAtTheirRoundingFloor) {
  for (double H : {10.0, 1.0}) {
    Atmosphere atm(exponential_only(H));
    OpticalDepthReference ref(atm);
    const double R = atm.ground_radius();
    for (double h : {0.0, 3.0 * H, 10.0 * H})
      for (double mu : {1.0, 0.5, 0.01, 1e-3, 0.0, -1e-5}) {
        const double r = R + h;
        if (shared::ray_hits_ground(r, mu, R)) continue;
        const auto c = ref.column(r, mu);
        EXPECT_TRUE(c.converged) << H << " " << h << " " << mu;
        EXPECT_LT(c.evaluations, 5000) << H << " " << h << " " << mu;
        const double expect = H * std::exp(-h / H) * chapman_exact(r / H, mu);
        EXPECT_NEAR(c.column[kRayleigh] / expect, 1.0, 1e-9) << H << " " << h << " " << mu;
      }
  }
}

// Splitting a ray into pieces (each evaluated from its own origin) must give the
// same column: the reference does not depend on how the path is cut.
TEST(OpticalDepthReference, InvariantUnderSplitting) {
  Atmosphere atm(preset("earth-graphics"));
  OpticalDepthReference ref(atm);
  const double R = atm.ground_radius();
  for (double mu : {0.3, 0.0, -0.02}) {
    double r0 = R + 2000.0;
    auto whole = ref.column(r0, mu);
    for (int n : {2, 5, 16}) {
      glm::dvec3 sum(0.0);
      double step = whole.length_m / n;
      for (int i = 0; i < n; ++i) {
        double s = i * step;
        double rs = shared::radius_along(r0, mu, s);
        double ms = shared::mu_along(r0, mu, s, rs);
        sum += ref.column(rs, ms, step).column;
      }
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], whole.column[c], 1e-10 * whole.column[c] + 1e-9) << n;
    }
  }
}

// Observer above the atmosphere: the column equals that from the entry point.
TEST(OpticalDepthReference, ObserverAboveTheTopLooksThroughTheLimb) {
  Atmosphere atm(preset("earth-graphics"));
  OpticalDepthReference ref(atm);
  const double R = atm.ground_radius(), T = atm.top_radius();
  double r = T + 300e3, mu = -std::sqrt(1.0 - std::pow((R + 30e3) / r, 2.0));  // tangent at 30 km
  auto c = ref.column(r, mu);
  double s0 = shared::distance_to_top_from_outside(r, mu, T);
  auto c2 = ref.column(T, (r * mu + s0) / T);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c.column[k], c2.column[k], 1e-9 * c2.column[k]);
  EXPECT_GT(c.column[kRayleigh], 0.0);
  // A ray missing the atmosphere has zero column.
  EXPECT_EQ(ref.column(r, 0.5).column[kRayleigh], 0.0);
}

TEST(OpticalDepthReference, RaysThatHitTheGround) {
  Atmosphere atm(preset("earth-graphics"));
  OpticalDepthReference ref(atm);
  const double R = atm.ground_radius();
  auto c = ref.column(R + 1000.0, -1.0);
  EXPECT_TRUE(c.hits_ground);
  EXPECT_NEAR(c.length_m, 1000.0, 1e-9);
  // Straight down from 1 km: H (1 - e^{-1000/H}).
  EXPECT_NEAR(c.column[kRayleigh], 8000.0 * -std::expm1(-1000.0 / 8000.0), 1e-9);
  auto g = ref.column(R, -0.5);  // on the ground looking down: empty path
  EXPECT_TRUE(g.hits_ground);
  EXPECT_EQ(g.column[kRayleigh], 0.0);
}

TEST(OpticalDepthReference, BadInput) {
  Atmosphere atm(preset("test-planet"));
  OpticalDepthReference ref(atm);
  EXPECT_THROW(ref.column(std::nan(""), 0.5), atmosh::InputError);
  EXPECT_THROW(ref.column(atm.ground_radius() + 10.0, 1.5), atmosh::InputError);
  EXPECT_THROW(ref.column(atm.ground_radius() - 100.0, 0.5), atmosh::InputError);
}

// Transmittance underflows to exactly 0, never NaN.
TEST(OpticalDepth, TransmittanceUnderflowIsExactlyZero) {
  EXPECT_EQ(transmittance(1e6), 0.0);
  EXPECT_EQ(transmittance(std::numeric_limits<double>::infinity()), 0.0);
  EXPECT_EQ(transmittance(std::nan("")), 0.0);
  EXPECT_EQ(transmittance(0.0), 1.0);
  EXPECT_GT(transmittance(700.0), 0.0);
}

// Ozone: the vertical optical depth equals column_du * DU * sigma.
TEST(Atmosphere, OzoneColumnMatchesDobsonUnits) {
  Atmosphere atm(preset("earth-graphics"));
  OpticalDepthReference ref(atm);
  auto c = ref.column(atm.ground_radius(), 1.0);
  double tau = atm.coefficients_at(600.0).extinction[kOzone] * c.column[kOzone];
  EXPECT_NEAR(tau / (300.0 * kDobsonUnitPerM2 * ozone_cross_section(600.0)), 1.0, 1e-10);
}

// LUT against the reference on the small test planet, including grazing rays,
// tangent points just above the ground and rays that hit the ground.
TEST(OpticalDepthLut, MatchesReferenceOnTestPlanet) {
  Atmosphere atm(preset("test-planet"));
  OpticalDepthReference ref(atm);
  LutOptions o;
  o.shells = 32;
  o.view_directions = 64;
  o.sun_directions = 64;
  OpticalDepthLut lut(atm, o);
  auto k = atm.coefficients_at(550.0);
  const double R = atm.ground_radius(), T = atm.top_radius();
  double worst = 0.0;
  for (double h : {0.0, 10.0, 300.0, 2000.0, 8000.0, 15000.0, 19999.0}) {
    double r = R + h, muh = shared::mu_horizon(r, R);
    for (double mu : {1.0, 0.5, 0.1, 0.0, -0.3, -1.0, muh + 1e-7, muh - 1e-7, muh + 1e-3, muh - 1e-3}) {
      if (mu < -1.0 || mu > 1.0) continue;
      auto a = ref.column(r, mu);
      auto b = lut.view(r, mu);
      ASSERT_EQ(a.hits_ground, b.hits_ground) << h << " " << mu;
      double ta = optical_depth(k, a.column), tb = optical_depth(k, b.column);
      ASSERT_TRUE(std::isfinite(tb));
      if (ta > 0.0) worst = std::max(worst, std::abs(tb - ta) / ta);
    }
  }
  EXPECT_LT(worst, 2e-3);
  // The sun table reports rays into the ground as blocked.
  EXPECT_TRUE(lut.sun(R + 100.0, -0.5).hits_ground);
  EXPECT_GT(lut.sun(R + 100.0, 0.5).column[kRayleigh], 0.0);
  EXPECT_EQ(lut.view(T + 1e6, 1.0).column[kRayleigh], 0.0);
}

// A sun-only build (LutOptions::view_tables = false, the sky integrator's) has the same
// sun table as a full build, a third of its bytes, no view lookups, and its error
// estimate still checks the sun table against fresh integrals.
TEST(OpticalDepthLut, SunOnlyBuildLeavesTheViewTablesOut) {
  Atmosphere atm(preset("earth-graphics"));
  LutOptions full_o, sun_o;
  sun_o.view_tables = false;
  const OpticalDepthLut full(atm, full_o), sun_only(atm, sun_o);
  const double R = atm.ground_radius();
  for (double h : {0.0, 1500.0, 30e3})
    for (double mu : {1.0, 0.3, 0.0, -0.05, -0.5}) {
      const auto a = full.sun(R + h, mu), b = sun_only.sun(R + h, mu);
      EXPECT_EQ(a.hits_ground, b.hits_ground);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(a.column[c], b.column[c]) << h << " " << mu;
    }
  EXPECT_EQ(3 * sun_only.table_bytes(), full.table_bytes());
  EXPECT_THROW(sun_only.view(R, 1.0), std::logic_error);
  // With as many sun as view directions (the default) the full build reuses the view
  // table's sky branch for the sun table; with another count it builds its own. Both
  // equal a sun-only build of that count.
  LutOptions full48 = full_o, sun48 = sun_o;
  full48.sun_directions = sun48.sun_directions = 48;
  const OpticalDepthLut full_b(atm, full48), sun_only_b(atm, sun48);
  for (double h : {0.0, 1500.0, 30e3, 99e3})
    for (double mu : {1.0, 0.3, 0.0, -0.05, -0.15}) {
      const auto a = full_b.sun(R + h, mu), b = sun_only_b.sun(R + h, mu);
      EXPECT_EQ(a.hits_ground, b.hits_ground);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(a.column[c], b.column[c]) << h << " " << mu;
      // The view lookup of a ray toward the top reads the same entries at 64.
      const auto v = full.view(R + h, mu), s = full.sun(R + h, mu);
      if (!v.hits_ground)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(v.column[c], s.column[c]) << h << " " << mu;
    }
  // The a-posteriori estimate (midpoints between table samples against fresh
  // integrals, the closed-form ozone column included): below the 1e-4 target
  // for earth-graphics at the default 32 x 64 (measured 2.7e-5 for both builds).
  for (const OpticalDepthLut* lut : {&full, &sun_only}) {
    const double e = lut->estimate_max_rel_error();
    EXPECT_GT(e, 0.0);
    EXPECT_LT(e, 1e-4);
    // The default is the middle wavelength of the grid; another wavelength weighs the
    // constituents differently; a negative or NaN one is bad input.
    const auto& wl = atm.wavelengths_nm();
    EXPECT_EQ(lut->estimate_max_rel_error(wl[wl.size() / 2]), e);
    const double e400 = lut->estimate_max_rel_error(400.0);
    EXPECT_GT(e400, 0.0);
    EXPECT_LT(e400, 1e-4);
    EXPECT_NE(e400, e);
    EXPECT_THROW(lut->estimate_max_rel_error(-1.0), atmosh::InputError);
    EXPECT_THROW(lut->estimate_max_rel_error(std::nan("")), atmosh::InputError);
  }
}

namespace {
// Calls f(name, analytic, atmosphere, lut) with the sun table alone (as the sky
// builds it) of each preset, with the ozone tent in closed form (analytic = 16) and
// interpolated across its kinks (analytic = 0).
template <class F>
void for_each_sun_table(F&& f) {
  for (const char* name : {"earth-graphics", "earth-physical", "test-planet"})
    for (int analytic : {16, 0}) {
      const Atmosphere atm(preset(name));
      LutOptions o;
      o.view_tables = false;
      o.analytic_max_nodes = analytic;
      const OpticalDepthLut lut(atm, o);
      f(name, analytic, atm, lut);
    }
}

}  // namespace

// The sun table reduced to one radius (SunAtRadius, the sky's image rows) gives the
// same columns as a full lookup at that radius: the same Lagrange weights summed in
// another order, so equal to rounding (1e-12 relative), and the same blocked rays.
// Exponential and tabulated (log-encoded) profiles, the closed-form ozone tent, and
// the ozone tent interpolated across its kinks (analytic_max_nodes = 0); radii at the
// ground, between and on shells, near profile kinks, at and above the top; directions up, horizontal, at
// the horizon +-1e-9 and down.
TEST(OpticalDepthLut, SunAtRadiusEqualsSunLookup) {
  for_each_sun_table([](const char* name, int analytic, const Atmosphere& atm, const OpticalDepthLut& lut) {
    const double R = atm.ground_radius(), T = atm.top_radius();
    std::vector<double> radii{R, R + 1.0, R + 777.0, T, T - 1e-3, T + 5e3};
    for (double r : lut.shell_radii()) radii.push_back(r);
    for (double f : {0.013, 0.21, 0.5, 0.77}) radii.push_back(R + f * (T - R));
    for (double k : atm.kinks())  // windows that stop at a profile kink
      for (double dh : {-700.0, -90.0, 0.0, 90.0, 700.0}) radii.push_back(std::clamp(R + k + dh, R, T));
    int compared = 0, blocked = 0;
    for (double r : radii) {
      const OpticalDepthLut::SunAtRadius at = lut.sun_at(r);
      const double muh = r > R ? shared::mu_horizon(r, R) : 0.0;
      for (double mu : {1.0, 0.7, 0.2, 0.01, 0.0, -0.01, -0.1, muh + 1e-9, muh - 1e-9, muh + 1e-4, -0.6, -1.0}) {
        if (mu < -1.0 || mu > 1.0) continue;
        const LutColumn a = lut.sun(r, mu), b = at(mu);
        ASSERT_EQ(a.hits_ground, b.hits_ground) << name << " r " << r << " mu " << mu;
        blocked += a.hits_ground;
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(std::isfinite(b.column[c]));
          EXPECT_LE(std::abs(a.column[c] - b.column[c]), 1e-12 * std::abs(a.column[c]) + 1e-300)
              << name << " analytic " << analytic << " r - R " << r - R << " mu " << mu << " c " << c;
        }
        ++compared;
      }
    }
    EXPECT_GT(blocked, 10);
    EXPECT_GT(compared, 200);
  });
}

// sun_at(r, mu_lo, mu_hi, budget) fits the lookups of the sun table over a range of
// mu: lookups equal sun(r, mu) to the fit's 1e-10 of each column's largest value in
// the range, at 101 directions across the range (not the fit's check points) and
// outside it. Ranges: narrow and wide, upward and downward, through the tangent
// directions of the ozone tent's node spheres, from the ground to the top; the three
// presets and their profile kinds; no fit where a ray of the range is blocked or r
// is above the top.
TEST(OpticalDepthLut, SunAtRadiusFitEqualsSunLookup) {
  for_each_sun_table([](const char* name, int analytic, const Atmosphere& atm, const OpticalDepthLut& lut) {
    const double R = atm.ground_radius(), T = atm.top_radius();
    int fitted = 0, eligible = 0, tried = 0;
    for (double h : {0.0, 1500.0, 9e3, 10e3, 17e3, 25e3, 33e3, 40e3, 45e3, (T - R) * 0.99, T - R + 1e3}) {
      const double r = R + h;
      const double muh = h > 0 ? shared::mu_horizon(r, R) : 0.0;
      struct Range {
        double lo, hi;
      };
      for (const Range g : {Range{0.30, 0.31}, Range{0.05, 0.6}, Range{0.2, 1.0}, Range{-0.05, 0.05},
                            Range{muh + 1e-3, muh + 0.05}, Range{-0.3, 0.1}, Range{0.5, 0.5}, Range{muh - 0.01, 0.2}}) {
        if (g.lo < -1.0 || g.hi > 1.0) continue;
        ++tried;
        const OpticalDepthLut::SunAtRadius at = lut.sun_at(r, g.lo, g.hi, 1000);
        const bool has_fit = at.fit().valid();
        fitted += has_fit;
        if (r > T || lut.sun(r, g.lo).hits_ground) {
          EXPECT_FALSE(has_fit) << name << " h " << h << " [" << g.lo << ", " << g.hi << "]";
        } else {
          ++eligible;
          // Narrow ranges (an image row's nodes near the observer) always fit.
          if (g.hi - g.lo <= 0.01) {
            EXPECT_TRUE(has_fit) << name << " h " << h << " [" << g.lo << ", " << g.hi << "]";
          }
        }
        glm::dvec3 scale(0.0);
        std::vector<double> mus;
        for (int i = 0; i <= 100; ++i) mus.push_back(g.lo + (g.hi - g.lo) * i / 100.0);
        for (double mu : mus) scale = glm::max(scale, lut.sun(r, mu).column);
        mus.insert(mus.end(), {g.lo - 0.01, g.hi + 0.01, -1.0, 1.0});
        for (double mu : mus) {
          if (mu < -1.0 || mu > 1.0) continue;
          const LutColumn a = lut.sun(r, mu), b = at(mu);
          ASSERT_EQ(a.hits_ground, b.hits_ground) << name << " h " << h << " mu " << mu;
          for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(b.column[c]));
            EXPECT_LE(std::abs(a.column[c] - b.column[c]), 1e-10 * scale[c] + 1e-12 * std::abs(a.column[c]) + 1e-300)
                << name << " analytic " << analytic << " h " << h << " [" << g.lo << ", " << g.hi << "] mu " << mu
                << " c " << c;
          }
        }
      }
    }
    // Most eligible ranges are fitted (the comparison above is not vacuous); the
    // widest ones reaching mu ~ 0.05, where the columns grow like 1/mu, may need
    // more parts than the budget allows.
    EXPECT_GE(5 * fitted, 4 * eligible) << name << " analytic " << analytic;
    EXPECT_LT(eligible, tried) << name;
  });
}

TEST(OpticalDepthLut, BadOptions) {
  Atmosphere atm(preset("test-planet"));
  LutOptions o;
  o.shells = 2;
  EXPECT_THROW(OpticalDepthLut(atm, o), atmosh::InputError);
  o = LutOptions{};
  o.altitude_share = -1.0;
  EXPECT_THROW(OpticalDepthLut(atm, o), atmosh::InputError);
  o.altitude_share = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(OpticalDepthLut(atm, o), atmosh::InputError);
  o = LutOptions{};
  o.subtracted_kinks = -1;
  EXPECT_THROW(OpticalDepthLut(atm, o), atmosh::InputError);
  o.subtracted_kinks = 16;
  EXPECT_THROW(OpticalDepthLut(atm, o), atmosh::InputError);
  o = LutOptions{};
  o.threads = -1;
  EXPECT_THROW(OpticalDepthLut(atm, o), atmosh::InputError);
  o.threads = 1025;
  EXPECT_THROW(OpticalDepthLut(atm, o), atmosh::InputError);
}

// The build's worker threads take whole shells (each writes its own entries), so the
// tables are the same bit for bit for any thread count: earth-physical (closed-form
// entries of its tabulated Rayleigh, subtracted kinks, exponential Mie by quadrature).
TEST(OpticalDepthLut, TablesDoNotDependOnTheThreadCount) {
  Atmosphere atm(preset("earth-physical"));
  LutOptions o;
  o.shells = 16;
  o.view_directions = o.sun_directions = 24;
  o.threads = 1;
  const OpticalDepthLut one(atm, o);
  const double R = atm.ground_radius(), top = atm.top_altitude();
  for (int threads : {2, 3, 7}) {
    o.threads = threads;
    const OpticalDepthLut many(atm, o);
    ASSERT_EQ(many.shell_radii(), one.shell_radii());
    for (double h : {0.0, 10.0, 5e3, 11019.0, 40e3, 0.999 * top})
      for (double mu : {-1.0, -0.3, -0.12, -0.01, 0.0, 0.02, 0.5, 1.0}) {
        const auto a = one.view(R + h, mu), b = many.view(R + h, mu);
        const auto sa = one.sun(R + h, mu), sb = many.sun(R + h, mu);
        EXPECT_EQ(a.hits_ground, b.hits_ground);
        for (int c = 0; c < 3; ++c) {
          EXPECT_EQ(a.column[c], b.column[c]) << threads << " threads, h " << h << " mu " << mu;
          EXPECT_EQ(sa.column[c], sb.column[c]) << threads << " threads, h " << h << " mu " << mu;
        }
      }
  }
}

// Shell placement for a tabulated profile positive up to the top: equal steps of
// the fraction of e-folds of density below the shell. For samples of exp(-h/H)
// the e-fold count at a node is exactly h/H, so with uniform_share = 0 and the
// targets k/(S-1) falling on nodes the shells are equally spaced in altitude.
TEST(OpticalDepthLut, TabulatedShellsEquallySpacedInEfolds) {
  const double H = 8000.0, top = 60e3;
  AtmosphereSpec s = exponential_only(H);
  s.planet.atmosphere_top_m = top;
  auto& p = s.rayleigh->profile;
  p = DensityProfileSpec{};
  p.kind = DensityProfileSpec::Kind::Tabulated;
  for (int i = 0; i <= 60; ++i) {
    p.altitude_m.push_back(1000.0 * i);
    p.value.push_back(std::exp(-1000.0 * i / H));
  }
  Atmosphere atm(s);
  LutOptions o;
  o.shells = 31;
  o.uniform_share = 0.0;
  o.analytic_max_nodes = 0;
  OpticalDepthLut lut(atm, o);
  const auto& radii = lut.shell_radii();
  ASSERT_EQ(radii.size(), 31u);
  for (int k = 0; k < 31; ++k) EXPECT_NEAR(radii[k] - atm.ground_radius(), 2000.0 * k, 1e-3) << k;
}

// earth-physical (U.S. Standard Atmosphere 1976 Rayleigh, 206 nodes, interpolated
// from the tables) at the default 40 x 64 against the exact reference. The 1e-4
// target is not met for this profile (docs/atmosphere.md: its layer boundaries,
// where the lapse rate jumps, are kinks of ln(density), and its 500 m linear pieces
// are not smooth at the 1e-4 level); this bounds the current accuracy: 4.4e-4 worst
// on these rays with the kinks' slope and curvature jumps subtracted (6.4e-4 with the
// slope jumps alone; 3.9e-3 at 32 x 64 before the kinks were subtracted; 9.1e-3 with
// the shells placed by column fraction, as for exponentials).
TEST(OpticalDepthLut, EarthPhysicalDefaultTables) {
  Atmosphere atm(preset("earth-physical"));
  OpticalDepthReference ref(atm);
  OpticalDepthLut lut(atm);
  auto k = atm.coefficients_at(550.0);
  const double R = atm.ground_radius();
  double worst = 0.0, worst_sun = 0.0;
  for (double h : {0.0, 100.0, 5000.0, 11000.0, 30e3, 50e3, 80e3, 85e3, 90e3, 99e3, 99999.0}) {
    double r = R + h, muh = shared::mu_horizon(r, R);
    for (double mu : {1.0, 0.7, 0.3, 0.1, 0.01, 0.0, -0.01, -0.05, -0.1, -0.3, -1.0, muh + 1e-5, muh - 1e-5, muh + 1e-2,
                      muh - 1e-2}) {
      if (mu < -1.0 || mu > 1.0) continue;
      auto a = ref.column(r, mu);
      auto b = lut.view(r, mu);
      ASSERT_EQ(a.hits_ground, b.hits_ground) << h << " " << mu;
      double ta = optical_depth(k, a.column), tb = optical_depth(k, b.column);
      ASSERT_TRUE(std::isfinite(tb));
      if (ta > 0.0) worst = std::max(worst, std::abs(tb - ta) / ta);
      if (!a.hits_ground && ta > 0.0)
        worst_sun = std::max(worst_sun, std::abs(optical_depth(k, lut.sun(r, mu).column) - ta) / ta);
    }
  }
  std::printf("  earth-physical, default tables: max rel. error %.3g (view), %.3g (sun)\n", worst, worst_sun);
  EXPECT_LT(worst, 6e-4);
  EXPECT_LT(worst_sun, 6e-4);
}

namespace {
struct TableKink {
  double h, J, C = 0.0;  // altitude [m], slope ramp [1/m], curvature ramp [1/m^2]
};
// A tabulated profile on an irregular grid (nodes every ~400-600 m, and at the kinks):
// exp(-h/H) plus ramps J_k (h_k - h)_+ + C_k / 2 (h_k - h)_+^2 below given kink
// altitudes, so its slope jumps by exactly J_k there and its curvature by -C_k, on
// top of the smooth exponential's.
DensityProfileSpec kinked_table(const std::vector<TableKink>& kinks, double top, double step = 500.0) {
  DensityProfileSpec p;
  p.kind = DensityProfileSpec::Kind::Tabulated;
  std::vector<double> h;
  for (int i = 0; step * i < top; ++i)
    h.push_back(step * i + (i % 3 == 1 ? 0.18 * step : i % 3 == 2 ? -0.14 * step : 0.0));
  h.push_back(top);
  for (const auto& k : kinks) h.push_back(k.h);
  std::sort(h.begin(), h.end());
  for (double x : h) {
    double v = std::exp(-x / 8000.0);
    for (const auto& k : kinks) {
      const double d = std::max(0.0, k.h - x);
      v += k.J * d + 0.5 * k.C * d * d;
    }
    p.altitude_m.push_back(x);
    p.value.push_back(v);
  }
  return p;
}
}  // namespace

// The kinks that stand out of a sampled profile, and their own slope jumps: for a
// sampled quadratic none (its excess is exactly 0 on any grid), for exp(-h/H) with two
// ramps added the two ramp altitudes, with excess jumps equal to the ramps' slopes to
// the size of the smooth curvature's variation between neighbours (~Delta^2 / H^3).
TEST(DensityProfile, StrongestKinkJumps) {
  DensityProfileSpec q;
  q.kind = DensityProfileSpec::Kind::Tabulated;
  for (double x : {0.0, 300.0, 1000.0, 1250.0, 2400.0, 2500.0, 4000.0, 4100.0}) {
    q.altitude_m.push_back(x);
    q.value.push_back(3.0 - 1e-3 * x + 2e-7 * x * x);
  }
  for (const auto& k : DensityProfile(q).strongest_kink_jumps(8))
    if (k.altitude_m > 0.0 && k.altitude_m < 4100.0) {
      EXPECT_NEAR(k.excess_jump, 0.0, 1e-15) << k.altitude_m;
      EXPECT_GT(k.smooth_jump, 1e-5) << k.altitude_m;  // 4e-7 / m^2 x half span (>= 50 m)
    }
  EXPECT_TRUE(DensityProfile(q).strongest_kink_jumps(8, 0.0, 4100.0, 0.01).empty());

  const double J1 = -1.5e-6, J2 = 4e-7;  // [1/m]; exp(-h/H) has slope -5.6e-5 at 11 km
  const DensityProfile p(kinked_table({{11019.07, J1}, {31850.0, J2}}, 60e3));
  // The end nodes rank first (their whole jump, from / to 0 outside the table);
  // inside (0, 60 km) the two ramps.
  const auto ends = p.strongest_kink_jumps(2);
  ASSERT_EQ(ends.size(), 2u);
  EXPECT_EQ(ends[0].altitude_m, 0.0);
  EXPECT_EQ(ends[1].altitude_m, 60e3);
  const auto ks = p.strongest_kink_jumps(2, 0.0, 60e3);
  ASSERT_EQ(ks.size(), 2u);
  EXPECT_DOUBLE_EQ(ks[0].altitude_m, 11019.07);
  EXPECT_DOUBLE_EQ(ks[1].altitude_m, 31850.0);
  // smooth part: |d3/dh3 exp(-h/H)| Delta^2 ~ 2e-12 / m at 11 km
  EXPECT_NEAR(ks[0].excess_jump, J1, 2e-2 * std::abs(J1));
  EXPECT_NEAR(ks[1].excess_jump, J2, 2e-2 * std::abs(J2));
}

// Subtracted kinks (LutOptions::subtracted_kinks): on a long table with two strong
// kinks, the tables hold the density less p (smooth), p's column is added back in
// closed form, and the error against the exact reference on the rays beside the kinks
// (kink_probe_rays) falls several-fold; at the table's own samples a lookup is the
// exact column. A kink that would dominate the density (rho - p outside [1/2, 2] of
// rho) is not subtracted.
TEST(OpticalDepthLut, SubtractedKinks) {
  AtmosphereSpec s = exponential_only(8000.0);
  s.planet.atmosphere_top_m = 60e3;
  s.rayleigh->profile = kinked_table({{11019.07, -1.5e-6}, {31850.0, 4e-7}}, 60e3);
  const Atmosphere atm(s);
  const OpticalDepthReference ref(atm);
  const double R = atm.ground_radius();
  auto worst_of = [&](const OpticalDepthLut& lut) {
    double worst = 0.0;
    for (const ProbeRay& p : kink_probe_rays(atm)) {
      const RayColumn a = ref.column(p.r, p.mu);
      const double b = lut.view(p.r, p.mu).column[0];
      EXPECT_TRUE(std::isfinite(b));
      if (a.column[0] > 0.0) worst = std::max(worst, std::abs(b - a.column[0]) / a.column[0]);
    }
    return worst;
  };
  LutOptions plain;
  plain.subtracted_kinks = 0;
  const OpticalDepthLut without(atm, plain), with(atm);
  EXPECT_EQ(without.subtracted(0).nodes(), 0);
  ASSERT_GE(with.subtracted(0).nodes(), 3);  // the ground and the two kinks
  const auto& nr = with.subtracted(0).node_radii();
  EXPECT_TRUE(std::find(nr.begin(), nr.end(), R + 11019.07) != nr.end());
  EXPECT_TRUE(std::find(nr.begin(), nr.end(), R + 31850.0) != nr.end());
  // The tables' density is rho - p: at the kinks its slope jumps by the smooth
  // curvature's share only, rho's jump less the ramp's J_k (to 2 %).
  const double eps = 1.0;
  auto slope_jump = [&](double h, auto density) {
    return (density(h + eps) - density(h)) / eps - (density(h) - density(h - eps)) / eps;
  };
  const auto tab = [&](double h) { return with.tabulated_density(h)[0]; };
  const auto rho = [&](double h) { return atm.profile(0)(h); };
  EXPECT_NEAR(slope_jump(11019.07, rho) - slope_jump(11019.07, tab), -1.5e-6, 3e-8);
  EXPECT_NEAR(slope_jump(31850.0, rho) - slope_jump(31850.0, tab), 4e-7, 8e-9);
  const double e0 = worst_of(without), e1 = worst_of(with);
  std::printf("  two kinks, 40 x 64, rays beside them: max rel. error %.3g plain, %.3g subtracted\n", e0, e1);
  EXPECT_LT(e1, e0 / 5.0);
  // At a table sample (shell 7, direction 10 of the sky branch) the lookup is exact.
  const double r = with.shell_radii()[7], T = atm.top_radius(), rho7 = std::sqrt((r - R) * (r + R));
  const double d = (T - r) + 10.0 / 63.0 * (rho7 + std::sqrt((T - R) * (T + R)) - (T - r));
  const double mu = ((T - r) * (T + r) - d * d) / (2.0 * r * d);
  const double exact = ref.column(r, mu).column[0];
  EXPECT_NEAR(with.view(r, mu).column[0], exact, 1e-7 * exact);

  // rho = exp(-h/H) up to 20 km, then falling linearly to ~0 over 500 m: the kink's
  // ramp would exceed rho near the ground.
  AtmosphereSpec s2 = s;
  auto& t = s2.rayleigh->profile;
  t.altitude_m.clear();
  t.value.clear();
  for (int i = 0; i <= 40; ++i) {
    t.altitude_m.push_back(500.0 * i);
    t.value.push_back(std::exp(-500.0 * i / 8000.0));
  }
  for (double h : {20500.0, 60e3}) {
    t.altitude_m.push_back(h);
    t.value.push_back(1e-6 * std::exp(-20e3 / 8000.0));
  }
  const Atmosphere atm2(s2);
  const OpticalDepthLut lut2(atm2);
  EXPECT_EQ(lut2.subtracted(0).nodes(), 0);
}

// The curvature part of the subtracted kinks (LutOptions::subtract_curvature): a table
// whose curvature jumps at a kink as well (by -C = 4e-9 / m^2 at 11 km, about the
// U.S. 1976 tropopause's 3.7e-9) gets that jump estimated (to 3 %), q holds it, and
// the error on the rays beside the kinks falls against the slope jumps alone. Nodes
// every ~100 m: with 500 m the linear pieces' own ripple ((dz/H)^2/8 ~ 5e-4 of rho
// between nodes, which rays that stay near one node interval see) hides the gain.
TEST(OpticalDepthLut, SubtractedCurvature) {
  AtmosphereSpec s = exponential_only(8000.0);
  s.planet.atmosphere_top_m = 60e3;
  const double C = -4e-9;
  s.rayleigh->profile = kinked_table({{11019.07, -1.5e-6, C}, {31850.0, 4e-7}}, 60e3, 100.0);
  const Atmosphere atm(s);
  const auto ks = atm.profile(0).strongest_kink_jumps(2, 0.0, 60e3);
  ASSERT_EQ(ks.size(), 2u);
  EXPECT_NEAR(ks[0].curvature_jump, -C, 0.03 * std::abs(C));
  EXPECT_LT(std::abs(ks[1].curvature_jump), 0.03 * std::abs(C));  // the exponential's variation only
  const OpticalDepthReference ref(atm);
  LutOptions slope_only;
  slope_only.subtract_curvature = false;
  const OpticalDepthLut without(atm, slope_only), with(atm);
  EXPECT_EQ(without.subtracted_curvature(0).ramps(), 0);
  ASSERT_EQ(with.subtracted_curvature(0).ramps(), 2);
  EXPECT_DOUBLE_EQ(with.subtracted_curvature(0).ramp_radii()[0], atm.ground_radius() + 11019.07);
  // q = -D/2 (h_k - h)_+^2: the tables' density is rho less p and q.
  const double hk = 11019.07, below = hk - 3000.0;
  const double d1 = 31850.0 - below;
  EXPECT_NEAR(with.subtracted_curvature(0).at(below),
              -0.5 * (ks[0].curvature_jump * 3000.0 * 3000.0 + ks[1].curvature_jump * d1 * d1), 1e-13);
  EXPECT_NEAR(with.tabulated_density(below)[0] - without.tabulated_density(below)[0],
              -with.subtracted_curvature(0).at(below), 1e-12);
  double e0 = 0.0, e1 = 0.0;
  for (const ProbeRay& p : kink_probe_rays(atm)) {
    const RayColumn a = ref.column(p.r, p.mu);
    if (!(a.column[0] > 0.0)) continue;
    const double b0 = without.view(p.r, p.mu).column[0], b1 = with.view(p.r, p.mu).column[0];
    ASSERT_TRUE(std::isfinite(b0) && std::isfinite(b1));
    e0 = std::max(e0, std::abs(b0 - a.column[0]) / a.column[0]);
    e1 = std::max(e1, std::abs(b1 - a.column[0]) / a.column[0]);
  }
  std::printf("  curvature jump at 11 km, 40 x 64, rays beside the kinks: max rel. error %.3g slope only, %.3g with curvature\n", e0, e1);
  EXPECT_LT(e1, e0 / 5.0);
}

// QuadraticRampsColumn against composite Gauss-Legendre quadrature of the ramps along
// the ray (20 points on each of 400 pieces between the ray's crossings of the ramp
// spheres, in long double): rays from the ground, inside the ramps, grazing and
// tangent to a ramp sphere, from above the top through the limb, and ending at the
// ground. Relative to the column of |q|.
TEST(QuadraticRampsColumn, MatchesCompositeQuadrature) {
  const double R = 6356766.0;
  const std::vector<double> h{11019.07, 47350.09, 85999.95}, hc{1.8e-9, -2.3e-12, 1.5e-14};
  const QuadraticRampsColumn q(h, hc, R);
  const auto gl = [] {  // 20-point Gauss-Legendre on [-1, 1] by Newton on P_20
    std::vector<long double> x(20), w(20);
    for (int i = 0; i < 20; ++i) {
      long double z = std::cos(3.14159265358979323846L * (i + 0.75L) / 20.5L), dp = 1.0L;
      for (int it = 0; it < 100; ++it) {
        long double p0 = 1.0L, p1 = 0.0L;
        for (int j = 1; j <= 20; ++j) {
          const long double p2 = p1;
          p1 = p0;
          p0 = ((2 * j - 1) * z * p1 - (j - 1) * p2) / j;
        }
        dp = 20.0L * (z * p0 - p1) / (z * z - 1.0L);
        const long double dz = p0 / dp;
        z -= dz;
        if (std::fabs(static_cast<double>(dz)) < 1e-19) break;
      }
      x[i] = z;
      w[i] = 2.0L / ((1.0L - z * z) * dp * dp);
    }
    return std::pair{x, w};
  }();
  // power 2: the column of sum |half_curv| e^2 (the scale), 1: of sum |half_curv| e.
  auto reference = [&](double r, double mu, double len, bool absolute, int power = 2) {
    std::vector<long double> cuts{0.0L, static_cast<long double>(len)};
    const long double t = -static_cast<long double>(r) * mu;
    if (t > 0 && t < len) cuts.push_back(t);
    for (double x : h) {
      const long double D = shared::sphere_discriminant(r, mu, R + x);
      if (D > 0)
        for (long double s : {t - std::sqrt(D), t + std::sqrt(D)})
          if (s > 0 && s < len) cuts.push_back(s);
    }
    std::sort(cuts.begin(), cuts.end());
    long double sum = 0.0L;
    for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
      const long double a = cuts[c], b = cuts[c + 1], step = (b - a) / 400.0L;
      for (int p = 0; p < 400; ++p)
        for (int g = 0; g < 20; ++g) {
          const long double s = a + step * (p + 0.5L * (1.0L + gl.first[g])), u = s - t;
          const long double rs = std::sqrt(u * u + static_cast<long double>(r) * r * (1.0L - static_cast<long double>(mu) * mu));
          long double v = 0.0L;
          for (std::size_t k = 0; k < h.size(); ++k) {
            const long double e = std::max(0.0L, R + h[k] - rs);
            v += (absolute ? std::fabs(hc[k]) : hc[k]) * (power == 2 ? e * e : e);
          }
          sum += 0.5L * step * gl.second[g] * v;
        }
    }
    return static_cast<double>(sum);
  };
  const double T = R + 100e3;
  struct Ray {
    double r, mu, len;
  };
  std::vector<Ray> rays;
  for (double hr : {0.0, 5000.0, 11019.07, 30e3, 99e3})
    for (double mu : {1.0, 0.5, 0.05, 1e-4, 0.0, -0.02, -0.1}) {
      const double r = R + hr;
      if (shared::ray_hits_ground(r, mu, R)) rays.push_back({r, mu, shared::distance_to_ground(r, mu, R)});
      else rays.push_back({r, mu, shared::distance_to_top(r, mu, T)});
    }
  for (double ht : {11019.07 + 1e-3, 11019.07 - 1e-3, 47350.09 + 1.0, 85999.95 - 0.5, 1.0}) {  // tangent points
    const double r = T, rt = R + ht;
    rays.push_back({r, -std::sqrt((r - rt) * (r + rt)) / r, 2.0 * std::sqrt((r - rt) * (r + rt))});
  }
  rays.push_back({R + 400e3, -0.2, 1e6});  // from above the top: only the chord inside counts
  for (const Ray& ray : rays) {
    const double got = q(ray.r, ray.mu, ray.len), want = reference(ray.r, ray.mu, ray.len, false);
    // 1e-13 of the scale, plus the rounding of the ray's radii (~eps R in e, as for
    // every column of a profile along a ray: 4 eps R here), which dominates the tiny
    // columns of rays whose tangent point lies just below a ramp's top.
    const double scale = reference(ray.r, ray.mu, ray.len, true), lin = reference(ray.r, ray.mu, ray.len, true, 1);
    ASSERT_TRUE(std::isfinite(got));
    EXPECT_LE(std::abs(got - want), 1e-13 * scale + 4.0 * 2.2e-16 * R * lin + 1e-300)
        << ray.r - R << " " << ray.mu << " " << ray.len;
  }
  EXPECT_EQ(q(R + 90e3, 0.3, 1e5), 0.0);  // above every ramp
  EXPECT_THROW(QuadraticRampsColumn({2.0, 1.0}, {1.0, 1.0}, R), atmosh::InputError);
  EXPECT_THROW(QuadraticRampsColumn({1.0}, {std::nan("")}, R), atmosh::InputError);
}
