#include "atmosh/atmo/sun_disc.hpp"

#include <algorithm>
#include <cmath>

#include "atmosh/atmo/colour.hpp"
#include "atmosh/error.hpp"

namespace atmosh::atmo {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Gauss-Legendre nodes and weights on [-1, 1] (Newton's method on P_n, n <= 64).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(static_cast<std::size_t>(n), 0.0);
  w.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::fabs(dz) < 1e-16) break;
    }
    // Recompute the derivative at the converged node.
    double p0 = 1.0, p1 = z;
    for (int k = 2; k <= n; ++k) {
      const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    dp = n * (z * p1 - p0) / (z * z - 1.0);
    const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(n - 1 - i);
    x[a] = -z;
    x[b] = z;
    w[a] = w[b] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

// A unit vector perpendicular to the sun direction, in the vertical plane through it,
// pointing up (towards the zenith); north for a sun at the zenith or nadir.
glm::dvec3 up_across(const glm::dvec3& s) {
  const glm::dvec3 z(0.0, 0.0, 1.0);
  glm::dvec3 v = z - s.z * s;
  const double n = glm::length(v);
  if (n < 1e-12) return glm::dvec3(0.0, 1.0, 0.0);
  return v / n;
}

void check_unit(const glm::dvec3& sun) {
  if (!std::isfinite(sun.x) || !std::isfinite(sun.y) || !std::isfinite(sun.z) ||
      std::fabs(glm::length(sun) - 1.0) > 1e-9)
    throw InputError("sun direction must be a finite unit vector");
}

}  // namespace

SunModel parse_sun_model(const std::string& name) {
  if (name == "disc") return SunModel::Disc;
  if (name == "point") return SunModel::Point;
  throw InputError("sun model '" + name + "' is not one of disc, point");
}

const char* sun_model_name(SunModel model) { return model == SunModel::Disc ? "disc" : "point"; }

double sun_angular_radius_rad(double distance_au) {
  const double d = distance_au * kAstronomicalUnitM;
  if (!(d > kSolarRadiusM) || !std::isfinite(d))
    throw InputError("Earth-Sun distance " + std::to_string(distance_au) + " AU is not outside the sun");
  return std::asin(kSolarRadiusM / d);
}

double limb_darkening_exponent(double wavelength_nm) { return -0.023 + 0.292 / (wavelength_nm * 1e-3); }

double limb_darkening(double mu, double wavelength_nm) {
  return std::pow(std::clamp(mu, 0.0, 1.0), limb_darkening_exponent(wavelength_nm));
}

double limb_darkening_disc_mean(double wavelength_nm) { return 2.0 / (limb_darkening_exponent(wavelength_nm) + 2.0); }

double sun_disc_radiance_per_irradiance(double rho_rad, double angular_radius_rad, double wavelength_nm) {
  if (!(rho_rad >= 0.0) || rho_rad >= angular_radius_rad) return 0.0;
  const double sa = std::sin(angular_radius_rad), u = std::sin(rho_rad) / sa;
  const double mu = std::sqrt(std::max(0.0, 1.0 - u * u));
  return limb_darkening(mu, wavelength_nm) / (kPi * sa * sa * limb_darkening_disc_mean(wavelength_nm));
}

std::vector<double> sun_disc_transmittance(const SkyIntegrator& sky, double altitude_m, const glm::dvec3& sun,
                                           int nodes) {
  if (nodes < 1 || nodes > 64) throw InputError("disc quadrature nodes must be in 1..64");
  check_unit(sun);
  const auto& wl = sky.atmosphere().wavelengths_nm();
  const std::size_t nw = wl.size();
  const double alpha_s = sun_angular_radius_rad(sky.options().sun_distance_au);
  const double sa = std::sin(alpha_s);
  // Elevation of the disc centre and of the horizon (straight rays meeting the ground).
  const double e_sun = std::asin(std::clamp(sun.z, -1.0, 1.0));
  const double R = sky.atmosphere().ground_radius(), r = R + std::max(altitude_m, 0.0);
  const double e_horizon = -std::acos(std::clamp(R / r, -1.0, 1.0));
  // theta_h: where the vertical diameter meets the horizon (y = sin theta, the height in
  // disc radii; the direction at height y is rotated by beta = asin(y sin alpha_s)).
  const double y_h = std::sin(e_horizon - e_sun) / sa;
  const double theta_h = y_h <= -1.0 ? -kPi / 2 : y_h >= 1.0 ? kPi / 2 : std::asin(y_h);
  std::vector<double> gx, gw;
  gauss_legendre(nodes, gx, gw);
  const glm::dvec3 v = up_across(sun);
  std::vector<double> alpha(nw);
  for (std::size_t i = 0; i < nw; ++i) alpha[i] = limb_darkening_exponent(wl[i]);
  std::vector<double> num(nw, 0.0), vis(nw, 0.0), hid(nw, 0.0);
  // Hidden part [-pi/2, theta_h]: weights only. Visible part [theta_h, pi/2]: T too.
  auto part = [&](double a, double b, bool visible) {
    if (!(b > a)) return;
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    for (int k = 0; k < nodes; ++k) {
      const double th = mid + half * gx[static_cast<std::size_t>(k)];
      const double c = std::cos(th), wk = half * gw[static_cast<std::size_t>(k)];
      std::vector<double> t;
      if (visible) {
        const double beta = std::asin(std::clamp(std::sin(th) * sa, -1.0, 1.0));
        const glm::dvec3 d = glm::normalize(std::cos(beta) * sun + std::sin(beta) * v);
        t = sky.sun_transmittance(altitude_m, d);
      }
      for (std::size_t i = 0; i < nw; ++i) {
        const double w = wk * std::pow(c, alpha[i] + 2.0);
        if (visible) {
          vis[i] += w;
          num[i] += w * t[i];
        } else {
          hid[i] += w;
        }
      }
    }
  };
  part(-kPi / 2, theta_h, false);
  part(theta_h, kPi / 2, true);
  std::vector<double> out(nw, 0.0);
  for (std::size_t i = 0; i < nw; ++i) out[i] = vis[i] + hid[i] > 0.0 ? num[i] / (vis[i] + hid[i]) : 0.0;
  return out;
}

std::vector<double> direct_sun_transmittance(const SkyIntegrator& sky, double altitude_m, const glm::dvec3& sun) {
  if (sky.options().sun_model == SunModel::Point) return sky.sun_transmittance(altitude_m, sun);
  return sun_disc_transmittance(sky, altitude_m, sun);
}

int add_sun_disc(SkyImage& img, const SkyIntegrator& sky, SkyProjection projection, double altitude_m,
                 const glm::dvec3& sun) {
  if (sky.options().sun_model == SunModel::Point) return 0;
  check_unit(sun);
  const double d = sky.options().sun_distance_au;
  const double alpha_s = sun_angular_radius_rad(d);
  const auto& wl = img.wavelengths_nm;
  const std::size_t nw = wl.size();
  if (nw != sky.solar().size()) throw InputError("sky image and sky have different wavelengths");
  const SpectralToXyz cmf(wl);
  std::vector<double> L(nw);
  int changed = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      glm::dvec3 dir;
      if (!sky_pixel_direction(projection, img.width, img.height, x, y, dir)) continue;
      const double rho = std::atan2(glm::length(glm::cross(dir, sun)), glm::dot(dir, sun));
      if (!(rho < alpha_s)) continue;
      const std::vector<double> t = sky.sun_transmittance(altitude_m, glm::normalize(dir));
      bool any = false;
      for (std::size_t i = 0; i < nw; ++i) {
        L[i] = sky.solar()[i] / (d * d) * sun_disc_radiance_per_irradiance(rho, alpha_s, wl[i]) * t[i];
        any = any || L[i] > 0.0;
      }
      if (!any) continue;
      const std::size_t p = static_cast<std::size_t>(y) * img.width + x;
      store_sky_pixel(img, p, cmf, L, true);
      ++changed;
    }
  return changed;
}

}  // namespace atmosh::atmo
