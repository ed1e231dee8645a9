// Single-scattering sky: closed forms, symmetry, reddening, leaving Mie out, the
// stiff cases, and the fast integrator against the exact reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <vector>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/error.hpp"
#include "sky_impl.hpp"  // private (libatmo/src): the spectral loop

using namespace atmosh::atmo;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Rayleigh-only (coefficients) + Mie, exponential profiles, no ozone: every
// quantity of the closed forms below is elementary.
AtmosphereSpec simple_spec(bool with_mie) {
  AtmosphereSpec s;
  s.name = "closed-form";
  s.planet.radius_m = 6360e3;
  s.planet.atmosphere_top_m = 100e3;
  RayleighSpec r;
  r.model = RayleighSpec::Model::Coefficients;
  r.scattering_per_m = 13.558e-6;
  r.reference_nm = 550.0;
  r.profile = DensityProfileSpec::exponential(8000.0);
  s.rayleigh = r;
  if (with_mie) {
    MieSpec m;
    m.scattering_per_m = 3.996e-6;
    m.single_scattering_albedo = 0.9;
    m.profile = DensityProfileSpec::exponential(1200.0);
    m.phase = PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, 0.76);
    s.mie = m;
  } else {
    s.mie.reset();
  }
  s.ozone.reset();
  s.spectrum.wavelengths_nm.clear();
  s.spectrum.from_nm = 400;
  s.spectrum.to_nm = 700;
  s.spectrum.count = 4;
  return s;
}

// The preset `name` on `count` equal bins from `from_nm` to `to_nm`.
AtmosphereSpec preset_on_bins(const char* name, double from_nm, double to_nm, int count) {
  AtmosphereSpec s = preset(name);
  s.spectrum.wavelengths_nm.clear();
  s.spectrum.from_nm = from_nm;
  s.spectrum.to_nm = to_nm;
  s.spectrum.count = count;
  return s;
}

glm::dvec3 dir(double elevation_deg, double azimuth_deg) { return enu_direction_from_zenith(90.0 - elevation_deg, azimuth_deg); }

double rel(double a, double b) { return std::fabs(a - b) / std::fabs(b); }

}  // namespace

// SkyIntegrator and SkyReference keep their own copy of the atmosphere (sky.hpp): built
// from an Atmosphere destroyed right after construction, and then moved, they give the
// same bits as ones built from a live atmosphere (a dangling reference would read freed
// memory: reported under ASan, garbage otherwise).
TEST(Sky, KeepsItsOwnAtmosphere) {
  const AtmosphereSpec spec = simple_spec(true);
  const Atmosphere live(spec);
  const SolarSpectrum sun(4, 1.5);
  const SkyReferenceOptions ro{.rel_tol = 1e-4};
  auto gone = std::make_unique<Atmosphere>(spec);
  SkyIntegrator built(*gone, sun);
  const SkyReference ref_built(*gone, sun, ro);
  EXPECT_NE(&built.atmosphere(), gone.get());
  gone.reset();
  const SkyIntegrator moved(std::move(built));
  const glm::dvec3 view = dir(20.0, 90.0), s = dir(35.0, 180.0);
  const std::vector<double> got = moved.radiance(100.0, view, s), want = SkyIntegrator(live, sun).radiance(100.0, view, s);
  ASSERT_EQ(got.size(), 4u);
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_GT(want[i], 0.0);
    EXPECT_EQ(got[i], want[i]) << i;
  }
  EXPECT_EQ(moved.atmosphere().wavelengths_nm(), live.wavelengths_nm());
  EXPECT_EQ(ref_built.radiance(100.0, view, s).radiance, SkyReference(live, sun, ro).radiance(100.0, view, s).radiance);
}

// Sun overhead, looking up: every scattering point sees the whole vertical column
// (view part + sun part), so L = E p(1) tau_s exp(-tau) exactly, with tau_s the
// vertical scattering optical depth and tau the extinction one (both closed form
// for exponential layers: beta H (1 - exp(-top/H))).
TEST(Sky, ZenithWithSunOverheadMatchesClosedForm) {
  const AtmosphereSpec spec = simple_spec(true);
  const Atmosphere atm(spec);
  const SolarSpectrum sun(4, 1.5);  // W m^-2 nm^-1
  const SkyReference ref(atm, sun);
  const SkyIntegrator fast(atm, sun);
  const auto Lr = ref.radiance(0.0, {0, 0, 1}, {0, 0, 1});
  const auto Lf = fast.radiance(0.0, {0, 0, 1}, {0, 0, 1});
  const double top = spec.planet.atmosphere_top_m;
  const double col_r = 8000.0 * (1 - std::exp(-top / 8000.0)), col_m = 1200.0 * (1 - std::exp(-top / 1200.0));
  // Rayleigh phase at cos = 1 from PhaseFunction (its closed form is tested in the
  // phase-function suite); HG forward value (1 - g^2) / (4 pi (1 - g)^3) written out here.
  const double p_r = PhaseFunction(spec.rayleigh->phase).value(1.0);
  const double g = 0.76, p_m = (1 - g * g) / (4 * kPi * std::pow(1 + g * g - 2 * g, 1.5));  // HG forward value
  for (std::size_t i = 0; i < 4; ++i) {
    const double lam = atm.wavelengths_nm()[i];
    const double sr = 13.558e-6 * std::pow(550.0 / lam, 4.0), sm = 3.996e-6;
    const double tau_s_r = sr * col_r, tau_s_m = sm * col_m;
    const double tau = tau_s_r + tau_s_m / 0.9;
    const double expect = 1.5 * (p_r * tau_s_r + p_m * tau_s_m) * std::exp(-tau);
    EXPECT_LT(rel(Lr.radiance[i], expect), 1e-6) << lam;
    EXPECT_LT(rel(Lf[i], expect), 2e-4) << lam;
  }
}

// Optically thin layer, sun overhead, looking at zenith angle theta: with tau << 1 the
// radiance tends to E p(cos theta) tau_s / cos(theta) (plane-parallel limit; the
// sphericity correction, about (H/R) tan^2(theta), is 1.3e-3 at 45 deg for H = 8 km).
TEST(Sky, OpticallyThinLimit) {
  AtmosphereSpec spec = simple_spec(false);
  spec.rayleigh->scattering_per_m = 1e-9;  // tau ~ 8e-6
  const Atmosphere atm(spec);
  const SolarSpectrum sun(4, 1.0);
  const SkyIntegrator fast(atm, sun);
  const double col = 8000.0 * (1 - std::exp(-100e3 / 8000.0));
  const PhaseFunction p(spec.rayleigh->phase);
  for (double zen : {0.0, 30.0, 45.0}) {
    const auto L = fast.radiance(0.0, dir(90 - zen, 0), {0, 0, 1});
    for (std::size_t i = 0; i < 4; ++i) {
      const double lam = atm.wavelengths_nm()[i];
      const double tau_s = 1e-9 * std::pow(550.0 / lam, 4.0) * col;
      const double mu = std::cos(zen * kPi / 180);
      EXPECT_LT(rel(L[i], p.value(mu) * tau_s / mu), 2e-3) << "zenith " << zen << " lambda " << lam;
    }
  }
}

TEST(Sky, SymmetricAboutTheSunAzimuth) {
  const Atmosphere atm(simple_spec(true));
  const SkyIntegrator fast(atm, SolarSpectrum(4, 1.0));
  const glm::dvec3 sun = dir(12.0, 140.0);
  for (double d : {10.0, 45.0, 120.0})
    for (double el : {2.0, 20.0, 60.0}) {
      const auto a = fast.radiance(0.0, dir(el, 140.0 + d), sun), b = fast.radiance(0.0, dir(el, 140.0 - d), sun);
      for (std::size_t i = 0; i < a.size(); ++i) EXPECT_LT(rel(a[i], b[i]), 1e-9) << d << " " << el;
    }
}

// As the sun lowers, the horizon toward it reddens (CIE x grows) and the direct
// sunlight too — on the physically based Earth, 16 wavelengths.
TEST(Sky, HorizonReddensMonotonicallyAsTheSunSets) {
  AtmosphereSpec spec = preset_on_bins("earth-physical", 380, 780, 16);
  const Atmosphere atm(spec);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
  double prev_x = 0, prev_sun_x = 0;
  for (double el = 40.0; el >= 0.0; el -= 5.0) {
    const SkySummary s = summarize_sky(sky, 0.0, dir(el, 180.0));
    const double x = xy_chromaticity(s.horizon_toward_sun.xyz).x;
    EXPECT_GT(x, prev_x) << "sun elevation " << el;
    EXPECT_GT(s.sun_chromaticity.x, prev_sun_x) << "sun elevation " << el;
    prev_x = x;
    prev_sun_x = s.sun_chromaticity.x;
  }
  // At sunset the horizon is orange-red: red dominates blue clearly.
  const SkySummary s0 = summarize_sky(sky, 0.0, dir(0.0, 180.0));
  EXPECT_GT(s0.horizon_toward_sun.srgb.r, 2.0 * s0.horizon_toward_sun.srgb.b);
  // The zenith of a high sun is blue.
  const SkySummary s60 = summarize_sky(sky, 0.0, dir(60.0, 180.0));
  EXPECT_GT(s60.zenith.srgb.b, s60.zenith.srgb.r);
}

// Leaving [mie] out computes the same sky as Mie with zero scattering: exactly (to the
// reference's tolerance) for the exact integral; within the fast path's error for
// the tables, whose shells are placed by the constituents present.
TEST(Sky, NoMieEqualsMieSetToZero) {
  AtmosphereSpec zero = simple_spec(true);
  zero.mie->scattering_per_m = 0.0;
  const Atmosphere a(simple_spec(false)), b(zero);
  EXPECT_FALSE(a.has(kMie));
  const SkyReference ra(a, SolarSpectrum(4, 1.0)), rb(b, SolarSpectrum(4, 1.0));
  const SkyIntegrator fa(a, SolarSpectrum(4, 1.0)), fb(b, SolarSpectrum(4, 1.0));
  for (double el : {0.5, 10.0, 90.0}) {
    const auto la = ra.radiance(0.0, dir(el, 30.0), dir(5.0, 0.0)), lb = rb.radiance(0.0, dir(el, 30.0), dir(5.0, 0.0));
    const auto fa_ = fa.radiance(0.0, dir(el, 30.0), dir(5.0, 0.0)), fb_ = fb.radiance(0.0, dir(el, 30.0), dir(5.0, 0.0));
    for (std::size_t i = 0; i < la.radiance.size(); ++i) {
      EXPECT_LT(rel(la.radiance[i], lb.radiance[i]), 1e-8) << el;
      EXPECT_LT(rel(fa_[i], fb_[i]), 1e-3) << el;
    }
  }
}

// Stiff and extreme cases: finite, non-negative, and physically right where known.
TEST(Sky, StiffCasesAreFinite) {
  AtmosphereSpec spec = preset("earth-physical");
  const Atmosphere atm(spec);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
  auto finite = [](const std::vector<double>& L) {
    for (double v : L)
      if (!std::isfinite(v) || v < 0) return false;
    return true;
  };
  // Twilight down to -18 deg, all directions including below the horizon.
  for (double sun_el : {-18.0, -12.0, -6.0, -0.5, 0.0})
    for (double el : {-90.0, -10.0, -0.01, 0.0, 0.01, 5.0, 90.0})
      EXPECT_TRUE(finite(sky.radiance(0.0, dir(el, 0.0), dir(sun_el, 0.0)))) << sun_el << " " << el;
  // The zenith goes dark once the Earth's shadow is above the top of the atmosphere:
  // shadow height R (1/cos(d) - 1) > 100 km for a depression d > 10.1 deg.
  for (double v : sky.radiance(0.0, {0, 0, 1}, dir(-11.0, 0.0))) EXPECT_EQ(v, 0.0);
  // Observer in space: looking through the limb is bright, looking past the planet is black.
  const double h = 1000e3;
  const double R = spec.planet.radius_m, T = R + spec.planet.atmosphere_top_m;
  const double limb = -std::acos((R + 20e3) / (R + h)) * 180.0 / kPi;  // tangent altitude 20 km
  const auto Ll = sky.radiance(h, dir(limb, 0.0), dir(0.0, 90.0));
  EXPECT_TRUE(finite(Ll));
  EXPECT_GT(Ll[10], 0.0);
  const double miss = -std::acos(T / (R + h)) * 180.0 / kPi + 1.0;  // above the top's horizon
  for (double v : sky.radiance(h, dir(miss, 0.0), dir(0.0, 90.0))) EXPECT_EQ(v, 0.0);
  // Grazing rays from just above the ground and at the tangent of the top.
  EXPECT_TRUE(finite(sky.radiance(1e-6, dir(0.0, 0.0), dir(10.0, 0.0))));
  EXPECT_TRUE(finite(sky.radiance(100e3, dir(0.0, 0.0), dir(10.0, 0.0))));
  // Huge optical depth: transmittance underflows to exactly 0, never NaN.
  AtmosphereSpec thick = spec;
  thick.mie->scattering_per_m *= 1e5;
  const Atmosphere atm2(thick);
  const SkyIntegrator sky2(atm2, solar_spectrum_for_bins(thick.spectrum));
  EXPECT_TRUE(finite(sky2.radiance(0.0, dir(0.5, 0.0), dir(0.5, 180.0))));
  for (double t : sky2.sun_transmittance(0.0, dir(5.0, 0.0))) EXPECT_EQ(t, 0.0);
  // Forward-peaked phase functions g = +-0.999.
  for (double g : {0.999, -0.999}) {
    AtmosphereSpec pk = spec;
    pk.mie->phase = PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, g);
    const Atmosphere a3(pk);
    const SkyIntegrator s3(a3, solar_spectrum_for_bins(pk.spectrum));
    EXPECT_TRUE(finite(s3.radiance(0.0, dir(20.0, 0.0), dir(20.0, 0.0))));
    EXPECT_TRUE(finite(s3.radiance(0.0, dir(20.0, 180.0), dir(20.0, 0.0))));
  }
  EXPECT_THROW(sky.radiance(-10.0, {0, 0, 1}, {0, 0, 1}), atmosh::InputError);
  EXPECT_THROW(sky.radiance(0.0, {0, 0, std::nan("")}, {0, 0, 1}), atmosh::InputError);
  EXPECT_THROW(sky.radiance(0.0, {0, 0, 2}, {0, 0, 1}), atmosh::InputError);
}

// The fast integrator with default settings is within 1 % of the exact reference
// for view directions above the horizon and sun elevations down to 0 deg (the
// full sweep is `atmosh converge sky`).
TEST(Sky, FastWithinOnePercentOfReference) {
  AtmosphereSpec spec = preset_on_bins("earth-graphics", 380, 780, 6);  // exponential Rayleigh/Mie + ozone tent
  const Atmosphere atm(spec);
  const SolarSpectrum e = solar_spectrum_for_bins(spec.spectrum);
  const SkyIntegrator fast(atm, e);
  SkyReferenceOptions ro;
  ro.rel_tol = 1e-5;
  const SkyReference ref(atm, e, ro);
  // Hardest corners of the converge-sky sweep: low sun, near-horizon views, both sides.
  for (double sun_el : {0.0, 8.0})
    for (double el : {1.0, 30.0})
      for (double az : {0.0, 180.0}) {
        if (el == 30.0 && az == 0.0) continue;
        const auto r = ref.radiance(0.0, dir(el, az), dir(sun_el, 0.0));
        const auto f = fast.radiance(0.0, dir(el, az), dir(sun_el, 0.0));
        for (std::size_t i = 0; i < f.size(); ++i)
          EXPECT_LT(rel(f[i], r.radiance[i]), 1e-2) << "sun " << sun_el << " view " << el << " az " << az;
      }
}

// Twilight: the view ray is cut at the edge of the Earth's shadow, where the
// integrand jumps. The lit part of a twilight ray lies high up, where the default
// pieces are long: measured worst case 8.5 % here (sun -6 deg, 20 deg up, away from
// the sun; 11 % before the shadow-edge cut), so the bound is 10 %; 64 shells,
// 24 segments, 4 points reach 0.11 % (bound 0.2 %). `converge sky` reports
// twilight rays separately.
TEST(Sky, TwilightCutAtTheShadowEdge) {
  AtmosphereSpec spec = preset_on_bins("earth-graphics", 400, 700, 3);
  const Atmosphere atm(spec);
  const SolarSpectrum e = solar_spectrum_for_bins(spec.spectrum);
  SkyOptions fine;
  fine.lut.shells = 64;
  fine.segments = 24;
  fine.samples_per_segment = 4;
  const SkyIntegrator fast(atm, e), precise(atm, e, fine);
  SkyReferenceOptions ro;
  ro.rel_tol = 1e-6;
  const SkyReference ref(atm, e, ro);
  double worst_fast = 0, worst_precise = 0;
  for (double sun_el : {-3.0, -6.0})
    for (double el : {2.0, 20.0, 60.0})
      for (double az : {0.0, 180.0}) {
        const auto r = ref.radiance(0.0, dir(el, az), dir(sun_el, 0.0));
        const auto f = fast.radiance(0.0, dir(el, az), dir(sun_el, 0.0));
        const auto p = precise.radiance(0.0, dir(el, az), dir(sun_el, 0.0));
        const double peak = *std::max_element(r.radiance.begin(), r.radiance.end());
        for (std::size_t i = 0; i < f.size(); ++i) {
          if (!(r.radiance[i] > 1e-6 * peak)) continue;
          worst_fast = std::max(worst_fast, rel(f[i], r.radiance[i]));
          worst_precise = std::max(worst_precise, rel(p[i], r.radiance[i]));
          EXPECT_LT(rel(f[i], r.radiance[i]), 1e-1) << "sun " << sun_el << " view " << el << " az " << az;
          EXPECT_LT(rel(p[i], r.radiance[i]), 2e-3) << "sun " << sun_el << " view " << el << " az " << az;
        }
      }
  std::printf("  twilight: max rel error %.3g (default), %.3g (64 shells, 24 segments, 4 points)\n", worst_fast,
              worst_precise);
}

// An image row (views of one zenith angle) shares its view-ray nodes and a sun table
// reduced per node radius: radiance_same_zenith equals radiance() view by view up to
// rounding (the spectral terms are formed in float: 1e-6 relative). Rows above,
// at and below the horizon; day, low sun and twilight (rays that cross the shadow
// edge at some azimuths, integrated on their own); an observer on the ground, at
// 30 km and in space looking through the limb; both presets' profile kinds; rows
// short and long enough for the closed-form ozone columns to be fitted per node
// (OpticalDepthLut::sun_at with a range).
TEST(Sky, SameZenithRowEqualsPerRayRadiance) {
  for (const char* name : {"earth-graphics", "earth-physical"}) {
    AtmosphereSpec spec = preset_on_bins(name, 380, 780, 11);
    const Atmosphere atm(spec);
    const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
    const std::size_t nw = 11;
    const double R = spec.planet.radius_m;
    const double h_space = 1000e3;
    const double limb = -std::acos((R + 20e3) / (R + h_space)) * 180.0 / kPi;
    struct Case {
      double h, el;
    };
    for (const Case c : {Case{0.0, 30.0}, Case{0.0, 0.5}, Case{0.0, -0.2}, Case{0.0, -40.0}, Case{30e3, -1.0},
                         Case{30e3, 80.0}, Case{h_space, limb}})
      for (double sun_el : {20.0, 2.0, -4.0, -9.0})
        for (int width : {48, 480}) {  // 480: the row fits the ozone columns of its nodes
          std::vector<glm::dvec3> views;
          const double step = 360.0 / width;
          for (int x = 0; x < width; ++x) views.push_back(dir(c.el, (x + 0.5) * step));
          std::vector<double> row(views.size() * nw);
          const glm::dvec3 sun = dir(sun_el, 33.0);
          sky.radiance_same_zenith(c.h, views.data(), views.size(), sun, row.data());
          double peak = 0.0;
          for (double v : row) peak = std::max(peak, v);
          if (c.el > 0 && sun_el > 0) {
            EXPECT_GT(peak, 0.0) << name;
          }
          for (std::size_t k = 0; k < views.size(); ++k) {
            const auto L = sky.radiance(c.h, views[k], sun);
            for (std::size_t i = 0; i < nw; ++i) {
              ASSERT_TRUE(std::isfinite(row[k * nw + i]));
              EXPECT_LE(std::fabs(row[k * nw + i] - L[i]), 1e-6 * L[i] + 1e-12 * peak)
                  << name << " h " << c.h << " el " << c.el << " az " << (k + 0.5) * step << " sun " << sun_el
                  << " wavelength " << i;
            }
          }
        }
    const glm::dvec3 bad[2] = {dir(10.0, 0.0), dir(10.001, 90.0)};
    double out[2 * 11];
    EXPECT_THROW(sky.radiance_same_zenith(0.0, bad, 2, dir(10.0, 0.0), out), atmosh::InputError);
    const glm::dvec3 nan_view[2] = {dir(10.0, 0.0), {0.0, std::nan(""), dir(10.0, 0.0).z}};
    EXPECT_THROW(sky.radiance_same_zenith(0.0, nan_view, 2, dir(10.0, 0.0), out), atmosh::InputError);
  }
}

// The view-column weights of a part integrate every polynomial of degree <= n + 1
// exactly from -1 to each Gauss-Legendre node and to 1 (closed form: the integral
// of t^k from -1 to u is (u^(k+1) - (-1)^(k+1)) / (k + 1)); nodes of the rule:
// Abramowitz & Stegun 1964, table 25.4 (n = 2: +-1/sqrt(3); n = 3: 0, +-sqrt(3/5)).
TEST(Sky, PartColumnWeightsIntegratePolynomialsExactly) {
  const double n2[2] = {-1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0)};
  const double n3[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
  for (int n = 1; n <= 8; ++n) {
    const std::vector<double> w = sky_part_column_weights(n);
    ASSERT_EQ(w.size(), static_cast<std::size_t>((n + 1) * (n + 2)));
    // The points: -1, the nodes (roots of P_n, found here by bisection on the
    // Legendre recurrence, independent of the library's rule), 1.
    std::vector<double> t{-1.0};
    auto legendre = [&](double x) {
      double p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      return n == 1 ? x : p1;
    };
    const int grid = 20000;
    for (int i = 0; i < grid; ++i) {
      double lo = -1.0 + 2.0 * i / grid, hi = -1.0 + 2.0 * (i + 1) / grid;
      if (legendre(lo) == 0.0) t.push_back(lo);
      if (legendre(lo) * legendre(hi) >= 0) continue;
      for (int it = 0; it < 200; ++it) {
        const double m = 0.5 * (lo + hi);
        (legendre(lo) * legendre(m) <= 0 ? hi : lo) = m;
      }
      t.push_back(0.5 * (lo + hi));
    }
    t.push_back(1.0);
    ASSERT_EQ(t.size(), static_cast<std::size_t>(n + 2)) << n;
    if (n == 2)
      for (int q = 0; q < 2; ++q) EXPECT_NEAR(t[q + 1], n2[q], 1e-15);
    if (n == 3)
      for (int q = 0; q < 3; ++q) EXPECT_NEAR(t[q + 1], n3[q], 1e-15);
    for (int row = 0; row <= n; ++row) {
      const double u = row < n ? t[row + 1] : 1.0;
      for (int k = 0; k <= n + 1; ++k) {
        double sum = 0;
        for (int j = 0; j < n + 2; ++j) sum += w[row * (n + 2) + j] * std::pow(t[j], k);
        const double exact = (std::pow(u, k + 1) - std::pow(-1.0, k + 1)) / (k + 1);
        EXPECT_NEAR(sum, exact, 1e-13) << "n " << n << " row " << row << " degree " << k;
      }
    }
  }
  EXPECT_THROW(sky_part_column_weights(0), atmosh::InputError);
  EXPECT_THROW(sky_part_column_weights(9), atmosh::InputError);
}

// The spectral loop against the same sums in double precision with libm's exp,
// formed from the same (float) inputs: every wavelength count around the vector
// widths (8 on AVX2, 16 on AVX-512; ctest runs this suite on both paths), blocks of
// nodes of any size. Optical depths up to 10 and terms of both signs' magnitudes
// as in the sky. The bound: the float terms' relative error, ~3 ulp of tau
// (6e-8 x 3 x 10) plus exp_neg_f's 2e-7 plus the scattering's rounding, < 3e-6 of
// the sum of the terms' magnitudes. Lanes past n are never written.
TEST(Sky, SpectralLoopMatchesDoublePrecisionSums) {
  std::uint32_t state = 12345u;  // deterministic (LCG)
  auto uniform = [&](double lo, double hi) {
    state = state * 1664525u + 1013904223u;
    return lo + (hi - lo) * (state >> 8) * (1.0 / 16777216.0);
  };
  for (std::size_t n : {1u, 7u, 8u, 9u, 15u, 16u, 17u, 40u, 48u, 70u}) {
    std::vector<float> ext(3 * n), sca(2 * n);
    for (auto& e : ext) e = static_cast<float>(uniform(0.0, 2e-5));    // [1/m]
    for (auto& c : sca) c = static_cast<float>(uniform(0.0, 1.5e-5));
    std::vector<detail::SkyNodeTerms> nodes(45);
    for (auto& t : nodes) {
      for (float& x : t.x) x = static_cast<float>(uniform(0.0, 10.0 / 6e-5));  // tau <= 10 [m]
      t.sr = static_cast<float>(uniform(0.0, 2e3));
      t.sm = static_cast<float>(uniform(0.0, 5e2));
    }
    std::vector<double> want(n, 0.0), scale(n, 0.0);
    for (const auto& t : nodes)
      for (std::size_t i = 0; i < n; ++i) {
        const double tau = double(ext[i]) * t.x[0] + double(ext[n + i]) * t.x[1] + double(ext[2 * n + i]) * t.x[2];
        const double term = std::exp(-tau) * (double(sca[i]) * t.sr + double(sca[n + i]) * t.sm);
        want[i] += term;
        scale[i] += std::fabs(term);
      }
    for (std::size_t block : {1u, 7u, 32u, 45u}) {
      std::vector<double> acc(n + 16, -7.0);  // sentinels past n
      std::fill(acc.begin(), acc.begin() + static_cast<std::ptrdiff_t>(n), 0.0);
      for (std::size_t k = 0; k < nodes.size(); k += block)
        detail::accumulate_sky_nodes(n, ext.data(), sca.data(), nodes.data() + k, std::min(block, nodes.size() - k),
                                     acc.data());
      for (std::size_t i = 0; i < n; ++i)
        EXPECT_LE(std::fabs(acc[i] - want[i]), 3e-6 * scale[i]) << "n " << n << " block " << block << " i " << i;
      for (std::size_t i = n; i < acc.size(); ++i) EXPECT_EQ(acc[i], -7.0) << "n " << n << " lane " << i;
    }
  }
  EXPECT_TRUE(detail::sky_spectral_lanes() == 8 || detail::sky_spectral_lanes() == 16);
}
