// The sun as a limb-darkened disc (sun_disc.hpp), against references computed here:
//  * its angular radius from the IAU 2015 nominal solar radius and the IAU 2012 au;
//  * the disc's radiance integrated over its solid angle (cos(rho) dOmega, fine
//    quadrature here) gives back the irradiance: the law's normalisation 2/(alpha+2)
//    (Hestroffer & Magnan 1998: I/I(1) = mu^alpha) integrated analytically;
//  * with no atmosphere the disc's direct beam equals the point sun's; with the centre
//    on the horizon exactly half the disc's flux arrives (the chord weights
//    (1 - y^2)^((alpha+1)/2) are even in y); for other heights of the horizon the
//    visible share matches a polar integral of mu^alpha over the visible region;
//  * through a real atmosphere near the horizon (differential extinction, partial
//    occultation) the disc average matches a 2-D quadrature over the disc that takes the
//    transmittance along every direction of the disc;
//  * in images the disc's centre has radiance E / (pi sin^2(alpha_s) 2/(alpha+2)) times
//    the transmittance, and pixels outside the disc are unchanged;
//  * the point sun keeps the centre's transmittance and no disc.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/error.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/atmo/sun_disc.hpp"

using namespace atmosh::atmo;

namespace {

constexpr double kPi = 3.14159265358979323846;
// IAU 2015 Resolution B3 nominal solar radius, IAU 2012 Resolution B2 au [km].
constexpr double kRsunKm = 695700.0, kAuKm = 149597870.7;

glm::dvec3 dir(double elevation_deg, double azimuth_deg) { return enu_direction_from_zenith(90.0 - elevation_deg, azimuth_deg); }

// test-planet, 5 wavelengths; `thin`: Rayleigh only, 1e-20 /m (transmittance 1 - 1e-15).
AtmosphereSpec spec_for(bool thin, const char* name = "test-planet") {
  AtmosphereSpec s = preset(name);
  s.spectrum.wavelengths_nm = {380.0, 450.0, 550.0, 650.0, 780.0};
  if (thin) {
    s.mie.reset();
    s.ozone.reset();
    s.rayleigh->scattering_per_m = 1e-20;
  }
  return s;
}

// Gauss-Legendre on [a, b] with n nodes (independent of the library's; nodes cached).
struct GaussRule {
  std::vector<double> x, w;
};
const GaussRule& gauss_rule(int n) {
  static std::map<int, GaussRule> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  GaussRule r;
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), pp = 1;
    for (int iter = 0; iter < 100; ++iter) {
      double p1 = 1, p2 = 0;
      for (int k = 1; k <= n; ++k) {
        const double p3 = p2;
        p2 = p1;
        p1 = ((2.0 * k - 1) * z * p2 - (k - 1.0) * p3) / k;
      }
      pp = n * (z * p1 - p2) / (z * z - 1);
      const double dz = p1 / pp;
      z -= dz;
      if (std::fabs(dz) < 1e-15) break;
    }
    r.x.push_back(z);
    r.w.push_back(2 / ((1 - z * z) * pp * pp));
  }
  return cache.emplace(n, std::move(r)).first->second;
}
template <class F>
double gauss(F&& f, double a, double b, int n) {
  const GaussRule& r = gauss_rule(n);
  double s = 0;
  for (int i = 0; i < n; ++i)
    s += r.w[static_cast<std::size_t>(i)] * f(0.5 * (a + b) + 0.5 * (b - a) * r.x[static_cast<std::size_t>(i)]);
  return 0.5 * (b - a) * s;
}

}  // namespace

TEST(SunDisc, AngularRadiusFromTheEarthSunDistance) {
  for (double d : {0.98329, 1.0, 1.01671}) {
    const double expected = std::asin(kRsunKm / (d * kAuKm));
    EXPECT_NEAR(sun_angular_radius_rad(d), expected, 1e-15) << d;
  }
  // 959.23 arcsec at 1 au (R_sun / au = 4.6505e-3 rad), 0.26645 deg.
  EXPECT_NEAR(sun_angular_radius_rad(1.0) * 180.0 / kPi * 3600.0, 959.23, 0.005);
}

// Hestroffer & Magnan (1998): alpha = -0.023 + 0.292 / lambda[um].
TEST(SunDisc, LimbDarkeningLaw) {
  EXPECT_NEAR(limb_darkening_exponent(500.0), 0.561, 1e-12);
  EXPECT_NEAR(limb_darkening_exponent(1000.0), 0.269, 1e-12);
  EXPECT_DOUBLE_EQ(limb_darkening(1.0, 450.0), 1.0);
  EXPECT_DOUBLE_EQ(limb_darkening(0.0, 450.0), 0.0);
  EXPECT_NEAR(limb_darkening(0.5, 500.0), std::pow(0.5, 0.561), 1e-15);
  // Blue darkens more towards the limb than red.
  EXPECT_LT(limb_darkening(0.3, 400.0), limb_darkening(0.3, 700.0));
}

// int_disc L cos(rho) dOmega = E: integrated here in rho (via u = sin t) with 400
// Gauss-Legendre nodes, against the closed-form normalisation in the library.
TEST(SunDisc, RadianceIntegratesToTheIrradiance) {
  for (double d : {0.98329, 1.0167})
    for (double nm : {380.0, 550.0, 780.0}) {
      const double a = sun_angular_radius_rad(d), sa = std::sin(a);
      // rho = asin(sa sin t): cos(rho) sin(rho) drho = sa^2 sin t cos t dt.
      const double e = 2 * kPi * gauss([&](double t) {
        const double rho = std::asin(sa * std::sin(t));
        return sun_disc_radiance_per_irradiance(rho, a, nm) * sa * sa * std::sin(t) * std::cos(t);
      }, 0.0, kPi / 2, 400);
      EXPECT_NEAR(e, 1.0, 1e-9) << d << " AU, " << nm << " nm";
      // Closed form at the centre: E / (pi sin^2 a * 2 / (alpha + 2)).
      const double alpha = -0.023 + 0.292 / (nm / 1000.0);
      EXPECT_NEAR(sun_disc_radiance_per_irradiance(0.0, a, nm), (alpha + 2) / (2 * kPi * sa * sa),
                  1e-12 * (alpha + 2) / (2 * kPi * sa * sa));
      EXPECT_EQ(sun_disc_radiance_per_irradiance(a * 1.0000001, a, nm), 0.0);
    }
}

// No atmosphere: the disc's direct beam is the point sun's (both 1 above the horizon);
// with the disc centre on the horizon, exactly half arrives.
TEST(SunDisc, NoAtmosphereWholeAndHalfDisc) {
  const AtmosphereSpec s = spec_for(true);
  const Atmosphere atm(s);
  const SkyIntegrator sky(atm, SolarSpectrum(5, 1.0));
  const SkyIntegrator point(atm, SolarSpectrum(5, 1.0), [] {
    SkyOptions o;
    o.sun_model = SunModel::Point;
    return o;
  }());
  for (double el : {0.5, 10.0, 60.0, 90.0}) {
    const auto t = direct_sun_transmittance(sky, 0.0, dir(el, 123.0));
    const auto p = direct_sun_transmittance(point, 0.0, dir(el, 123.0));
    for (std::size_t i = 0; i < t.size(); ++i) {
      EXPECT_NEAR(t[i], 1.0, 1e-13) << el;
      EXPECT_NEAR(t[i], p[i], 1e-13) << el;
    }
  }
  // The horizon at 0 m is elevation 0; at 1 km it dips by acos(R / (R + h)).
  const double R = atm.ground_radius();
  for (double h : {0.0, 1000.0}) {
    const double dip = std::acos(R / (R + h)) * 180.0 / kPi;
    for (double t : sun_disc_transmittance(sky, h, dir(-dip, 40.0))) EXPECT_NEAR(t, 0.5, 1e-12) << h;
    for (double t : sun_disc_transmittance(sky, h, dir(-dip - 0.3, 40.0))) EXPECT_EQ(t, 0.0) << h;
  }
}

// Partial occultation: the visible share against the polar integral of mu^alpha over
// the part of the disc above the horizon line y > y_h (y in disc radii):
// share = int_0^1 mu^alpha u (pi - 2 asin(clamp(y_h / u))) du / (pi int_0^1 mu^alpha 2u du ... ).
TEST(SunDisc, PartialOcclusionMatchesAPolarIntegral) {
  const Atmosphere atm(spec_for(true));
  const SkyIntegrator sky(atm, SolarSpectrum(5, 1.0));
  const double a = sun_angular_radius_rad(1.0);
  const auto& wl = atm.wavelengths_nm();
  for (double el_deg : {-0.2, -0.1, 0.05, 0.15, 0.25}) {
    const auto t = sun_disc_transmittance(sky, 0.0, dir(el_deg, 200.0));
    const double y_h = std::sin(-el_deg * kPi / 180.0) / std::sin(a);
    for (std::size_t i = 0; i < wl.size(); ++i) {
      const double alpha = limb_darkening_exponent(wl[i]);
      // u = sin s, mu = cos s: mu^alpha u du = cos^(alpha+1) s sin s ds.
      auto share_of = [&](double s) {
        const double u = std::sin(s), q = u > 0 ? std::clamp(y_h / u, -1.0, 1.0) : (y_h < 0 ? -1.0 : 1.0);
        return (kPi - 2.0 * std::asin(q)) / (2.0 * kPi);
      };
      const double num = gauss([&](double s) { return std::pow(std::cos(s), alpha + 1) * std::sin(s) * share_of(s); },
                               0.0, kPi / 2, 600);
      const double den = gauss([&](double s) { return std::pow(std::cos(s), alpha + 1) * std::sin(s); }, 0.0, kPi / 2, 600);
      EXPECT_NEAR(t[i], num / den, 2e-5) << el_deg << " deg, " << wl[i] << " nm";
    }
  }
}

// Through test-planet's atmosphere near the horizon (transmittance steep across the
// disc, part of it hidden): the library's chord rule against a 2-D Gauss-Legendre
// quadrature over the disc's projected plane (x, y) that evaluates the transmittance
// along each direction (x, y) of the disc.
TEST(SunDisc, DifferentialExtinctionMatchesA2DQuadrature) {
  const Atmosphere atm(spec_for(false));
  const SkyIntegrator sky(atm, SolarSpectrum(5, 1.0));
  const double a = sun_angular_radius_rad(1.0), sa = std::sin(a);
  const auto& wl = atm.wavelengths_nm();
  for (double h : {0.0, 2000.0})
    for (double el_deg : {0.1, 0.6, 3.0, 30.0}) {
      const glm::dvec3 s = dir(el_deg, 75.0);
      const auto t = sun_disc_transmittance(sky, h, s);
      const glm::dvec3 e(std::cos(75.0 * kPi / 180.0), -std::sin(75.0 * kPi / 180.0), 0.0);  // horizontal, across
      const glm::dvec3 v = glm::normalize(glm::cross(e, s));                                    // up across
      std::vector<double> num(wl.size(), 0.0);
      // y = sin(p), x = cos(p) sin(q) over the unit disc: dx dy = cos^2(p) cos(q) dp dq;
      // p from the horizon line (straight rays meeting the ground below it) to the top.
      const double R = atm.ground_radius(), e_h = -std::acos(R / (R + h));
      const double y_h = std::sin(e_h - el_deg * kPi / 180.0) / sa;
      const double p_lo = y_h <= -1.0 ? -kPi / 2 : std::asin(std::min(y_h, 1.0));
      const GaussRule& gp = gauss_rule(64);
      const GaussRule& gq = gauss_rule(40);
      for (std::size_t a_i = 0; a_i < gp.x.size(); ++a_i)
        for (std::size_t b_i = 0; b_i < gq.x.size(); ++b_i) {
          const double p = 0.5 * (p_lo + kPi / 2) + 0.5 * (kPi / 2 - p_lo) * gp.x[a_i], q = 0.5 * kPi * gq.x[b_i];
          const double wpq = 0.5 * (kPi / 2 - p_lo) * gp.w[a_i] * 0.5 * kPi * gq.w[b_i];
          const double y = std::sin(p), x = std::cos(p) * std::sin(q), u2 = x * x + y * y;
          const double mu = std::sqrt(std::max(0.0, 1.0 - u2)), rho = std::asin(std::sqrt(u2) * sa);
          const glm::dvec3 off = u2 > 0 ? (x * e + y * v) / std::sqrt(u2) : glm::dvec3(0.0);
          const glm::dvec3 d = glm::normalize(std::cos(rho) * s + std::sin(rho) * off);
          const auto tt = sky.sun_transmittance(h, d);
          const double jac = std::cos(p) * std::cos(p) * std::cos(q);
          for (std::size_t i = 0; i < wl.size(); ++i)
            num[i] += std::pow(mu, limb_darkening_exponent(wl[i])) * jac * tt[i] * wpq;
        }
      for (std::size_t i = 0; i < wl.size(); ++i) {
        // The whole disc's weight in closed form: int mu^alpha dA = 2 pi / (alpha + 2).
        const double den = 2 * kPi / (limb_darkening_exponent(wl[i]) + 2);
        EXPECT_NEAR(t[i], num[i] / den, 2e-5 * t[i] + 1e-12) << "h " << h << " el " << el_deg << " nm " << wl[i];
      }
    }
}

// In an image the pixel centred on the sun shows the disc centre's radiance,
// E / d^2 / (pi sin^2 a * 2 / (alpha + 2)) times the transmittance; pixels whose
// centres miss the disc are unchanged; the point sun adds nothing.
TEST(SunDisc, ImagePixelOnTheDiscCentre) {
  const Atmosphere atm(spec_for(true));
  SolarSpectrum solar = {1.2, 1.9, 1.85, 1.6, 1.2};
  SkyOptions o;
  o.sun_distance_au = 0.99;
  const SkyIntegrator sky(atm, solar, o);
  const int W = 64, H = 32;
  glm::dvec3 sun;  // the centre of pixel (20, 10)
  sky_pixel_direction(SkyProjection::Equirect, W, H, 20, 10, sun);
  SkyImage img = render_sky(sky, SkyProjection::Equirect, W, H, 0.0, sun, true, 1);
  const SkyImage before = img;
  EXPECT_EQ(add_sun_disc(img, sky, SkyProjection::Equirect, 0.0, sun), 1);
  const double a = std::asin(kRsunKm / (0.99 * kAuKm)), sa = std::sin(a);
  const std::size_t p = 10 * W + 20;
  for (std::size_t i = 0; i < 5; ++i) {
    const double alpha = -0.023 + 0.292 / (atm.wavelengths_nm()[i] / 1000.0);
    const double expected = solar[i] / (0.99 * 0.99) * (alpha + 2) / (2 * kPi * sa * sa);
    EXPECT_NEAR(img.spectral[p * 5 + i] - before.spectral[p * 5 + i], expected, 1e-6 * expected) << i;
  }
  EXPECT_GT(img.Y[p], 1e8f);  // ~1e9 cd/m^2
  for (std::size_t q = 0; q < img.Y.size(); ++q)
    if (q != p) {
      EXPECT_EQ(img.Y[q], before.Y[q]) << q;
    }
  SkyOptions po = o;
  po.sun_model = SunModel::Point;
  const SkyIntegrator point(atm, solar, po);
  SkyImage img2 = before;
  EXPECT_EQ(add_sun_disc(img2, point, SkyProjection::Equirect, 0.0, sun), 0);
  EXPECT_EQ(img2.Y, before.Y);
}

// The point sun stays available: its direct beam is the centre's transmittance.
TEST(SunDisc, PointSunKeepsTheCentresTransmittance) {
  const Atmosphere atm(spec_for(false));
  SkyOptions o;
  o.sun_model = SunModel::Point;
  const SkyIntegrator sky(atm, SolarSpectrum(5, 1.0), o);
  for (double el : {0.2, 5.0, 45.0}) EXPECT_EQ(direct_sun_transmittance(sky, 0.0, dir(el, 10.0)), sky.sun_transmittance(0.0, dir(el, 10.0)));
  EXPECT_EQ(parse_sun_model("point"), SunModel::Point);
  EXPECT_EQ(parse_sun_model("disc"), SunModel::Disc);
  EXPECT_THROW(parse_sun_model("square"), atmosh::InputError);
}
