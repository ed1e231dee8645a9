#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/sh/quadrature.hpp"
#include "atmosh/error.hpp"

#include <algorithm>
#include <cstdint>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/sun_disc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/format.hpp"
#include "atmosh/parallel.hpp"

namespace atmosh::atmo {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

SkyProjection parse_sky_projection(const std::string& name) {
  if (name == "equirect") return SkyProjection::Equirect;
  if (name == "fisheye") return SkyProjection::Fisheye;
  throw InputError("projection '" + name + "' is not one of equirect, fisheye");
}

bool sky_pixel_direction(SkyProjection p, int w, int h, int x, int y, glm::dvec3& dir) {
  if (p == SkyProjection::Equirect) {
    const double az = (x + 0.5) / w * 360.0;
    const double el = 90.0 - (y + 0.5) / h * 180.0;
    dir = enu_direction_from_zenith(90.0 - el, az);
    return true;
  }
  // Fisheye: u to the right, v up, in [-1, 1] over the inscribed disc.
  const double size = std::min(w, h);
  const double u = (x + 0.5 - 0.5 * w) / (0.5 * size), v = (0.5 * h - (y + 0.5)) / (0.5 * size);
  const double rr = std::sqrt(u * u + v * v);
  if (rr > 1.0) return false;
  const double zenith = rr * 90.0;
  // North up, east to the left (looking up from below).
  const double az = std::atan2(-u, v) * 180.0 / kPi;
  dir = enu_direction_from_zenith(zenith, az < 0 ? az + 360.0 : az);
  return true;
}

SolarSpectrum solar_spectrum_for_bins(const SpectrumSpec& s) {
  const std::vector<double> w = spectrum_wavelengths(s);
  SolarSpectrum e(w.size());
  for (std::size_t i = 0; i < w.size(); ++i) {
    double lo, hi;
    if (s.wavelengths_nm.empty()) {
      const double bin = (s.to_nm - s.from_nm) / s.count;
      lo = w[i] - 0.5 * bin;
      hi = w[i] + 0.5 * bin;
    } else {
      lo = i > 0 ? 0.5 * (w[i - 1] + w[i]) : w[i] - (w.size() > 1 ? 0.5 * (w[1] - w[0]) : 0.5);
      hi = i + 1 < w.size() ? 0.5 * (w[i] + w[i + 1]) : w[i] + (w.size() > 1 ? 0.5 * (w[i] - w[i - 1]) : 0.5);
    }
    lo = std::clamp(lo, kSolarSpectrumFirstNm, kSolarSpectrumLastNm);
    hi = std::clamp(hi, kSolarSpectrumFirstNm, kSolarSpectrumLastNm);
    e[i] = hi > lo ? solar_irradiance_toa_mean(lo, hi) : solar_irradiance_toa(std::clamp(w[i], kSolarSpectrumFirstNm, kSolarSpectrumLastNm));
  }
  return e;
}

std::size_t sky_image_bytes(int width, int height, std::size_t wavelengths, bool keep_spectral) {
  if (width < 1 || height < 1) return 0;
  const long double n = static_cast<long double>(width) * height;
  const long double per_pixel = 6 * sizeof(float) + sizeof(std::uint8_t) + (keep_spectral ? wavelengths * sizeof(float) : 0);
  const long double b = n * per_pixel;
  return b >= static_cast<long double>(SIZE_MAX) ? SIZE_MAX : static_cast<std::size_t>(b);
}

// One view-ray node of render_sky's equirect loop on one core: a + b x wavelengths [s],
// by method (bench_work BM_WorkSkyImage, fitted; docs/hostile-input.md, "Work estimates").
namespace {
struct NodeCost {
  double a, b;
};
constexpr NodeCost kSingle{134e-9, 0.84e-9};       // 8, 16, 47 wavelengths at 32 nodes; 16 to 64 nodes
constexpr NodeCost kApproximate{139e-9, 9.7e-9};   // 16 and 47 wavelengths at 32 nodes
constexpr NodeCost kOrders{134e-9, 0.84e-9};       // as single: 1.02 x at 16 wavelengths
}  // namespace

WorkEstimate sky_rays_work(double rays, std::size_t wavelengths, const SkyOptions& o) {
  const double nodes = mul_units(std::max(o.segments, 1), std::max(o.samples_per_segment, 1));
  const NodeCost c = o.scattering.method == ScatteringMethod::Approximate ? kApproximate
                     : o.scattering.method == ScatteringMethod::Orders && o.scattering.orders >= 2 ? kOrders
                                                                                                   : kSingle;
  return {mul_units(rays, nodes), c.a + c.b * static_cast<double>(wavelengths), "view-ray nodes"};
}

WorkEstimate sky_image_work(int width, int height, std::size_t wavelengths, const SkyOptions& options) {
  return sky_rays_work(mul_units(std::max(width, 0), std::max(height, 0)), wavelengths, options);
}

void store_sky_pixel(SkyImage& img, std::size_t p, const SpectralToXyz& cmf, std::span<const double> L, bool add) {
  const Xyz c = cmf(L);
  const Rgb rgb = linear_srgb_from_xyz(c);
  const float v[6] = {static_cast<float>(c.X), static_cast<float>(c.Y),   static_cast<float>(c.Z),
                      static_cast<float>(rgb.r), static_cast<float>(rgb.g), static_cast<float>(rgb.b)};
  std::vector<float>* const channel[6] = {&img.X, &img.Y, &img.Z, &img.R, &img.G, &img.B};
  for (int k = 0; k < 6; ++k) (*channel[k])[p] = add ? (*channel[k])[p] + v[k] : v[k];
  if (!img.spectral.empty()) {
    float* s = &img.spectral[p * L.size()];
    for (std::size_t i = 0; i < L.size(); ++i) s[i] = add ? s[i] + static_cast<float>(L[i]) : static_cast<float>(L[i]);
  }
  if (!add) img.valid[p] = 1;
}

SkyImage render_sky(const SkyIntegrator& sky, SkyProjection projection, int width, int height, double altitude_m,
                    const glm::dvec3& sun, bool keep_spectral, int threads) {
  if (width < 1 || height < 1 || width > 65536 || height > 65536)
    throw InputError("image size " + std::to_string(width) + "x" + std::to_string(height) + " is out of range");
  const auto t0 = std::chrono::steady_clock::now();
  SkyImage img;
  img.width = width;
  img.height = height;
  img.wavelengths_nm = sky.atmosphere().wavelengths_nm();
  const std::size_t n = static_cast<std::size_t>(width) * height, nw = img.wavelengths_nm.size();
  for (auto* c : {&img.X, &img.Y, &img.Z, &img.R, &img.G, &img.B}) c->assign(n, 0.0f);
  img.valid.assign(n, 0);
  if (keep_spectral) img.spectral.assign(n * nw, 0.0f);
  const SpectralToXyz cmf(img.wavelengths_nm);
  // Validate the inputs once, on this thread, so errors are not thrown from workers.
  {
    glm::dvec3 d;
    sky_pixel_direction(projection, width, height, width / 2, height / 2, d);
    (void)sky.radiance(altitude_m, glm::dvec3(0, 0, 1), sun);
  }
  std::atomic<long> rays{0};
  parallel_for_ranges(static_cast<std::size_t>(height), 1, threads, [&](std::size_t y0, std::size_t y1) {
    std::vector<double> L(nw), row_L;
    std::vector<glm::dvec3> row_dir;
    long local_rays = 0;
    for (int y = static_cast<int>(y0); y < static_cast<int>(y1); ++y) {
      if (projection == SkyProjection::Equirect) {
        // A row shares its zenith angle: its view-ray nodes are computed once.
        row_dir.resize(static_cast<std::size_t>(width));
        for (int x = 0; x < width; ++x) sky_pixel_direction(projection, width, height, x, y, row_dir[x]);
        row_L.resize(static_cast<std::size_t>(width) * nw);
        sky.radiance_same_zenith(altitude_m, row_dir.data(), row_dir.size(), sun, row_L.data());
      }
      for (int x = 0; x < width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * width + x;
        if (projection == SkyProjection::Equirect) {
          std::copy_n(row_L.begin() + static_cast<std::ptrdiff_t>(x * nw), nw, L.begin());
        } else {
          glm::dvec3 dir;
          if (!sky_pixel_direction(projection, width, height, x, y, dir)) continue;
          sky.radiance(altitude_m, dir, sun, L.data());
        }
        ++local_rays;
        store_sky_pixel(img, p, cmf, L);
      }
    }
    rays += local_rays;
  });
  img.rays = rays.load();
  img.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return img;
}

SkyColour sky_colour(const SkyIntegrator& sky, const SpectralToXyz& cmf, double altitude_m, const glm::dvec3& view,
                     const glm::dvec3& sun) {
  const auto L = sky.radiance(altitude_m, view, sun);
  SkyColour c;
  c.xyz = cmf(L);
  c.srgb = linear_srgb_from_xyz(c.xyz);
  return c;
}

SkySummary summarize_sky(const SkyIntegrator& sky, double altitude_m, const glm::dvec3& sun,
                         double horizon_elevation_deg, double sun_distance_au) {
  if (!(sun_distance_au >= 0) || !std::isfinite(sun_distance_au))
    throw InputError("sun distance " + format_double(sun_distance_au) + " AU must be > 0 (or 0: the integrator's)");
  const SpectralToXyz cmf(sky.atmosphere().wavelengths_nm());
  SkySummary s;
  const double sun_az = std::atan2(sun.x, sun.y) * 180.0 / kPi;
  s.zenith = sky_colour(sky, cmf, altitude_m, glm::dvec3(0, 0, 1), sun);
  s.horizon_toward_sun =
      sky_colour(sky, cmf, altitude_m, enu_direction_from_zenith(90.0 - horizon_elevation_deg, sun_az), sun);
  s.horizon_away = sky_colour(sky, cmf, altitude_m, enu_direction_from_zenith(90.0 - horizon_elevation_deg, sun_az + 180.0), sun);
  // The direct beam of the sky's sun model: averaged over the disc, or the centre's.
  const auto t = direct_sun_transmittance(sky, altitude_m, sun);
  std::vector<double> e(t.size());
  const double d2 = sky.options().sun_distance_au * sky.options().sun_distance_au;
  for (std::size_t i = 0; i < t.size(); ++i) e[i] = sky.solar()[i] / d2 * t[i];
  s.sun_transmitted = cmf(e);
  if (sun_distance_au > 0) {  // the one place a summary is rescaled to another distance
    const double f = d2 / (sun_distance_au * sun_distance_au);
    for (SkyColour* c : {&s.zenith, &s.horizon_toward_sun, &s.horizon_away}) {
      c->xyz = {c->xyz.X * f, c->xyz.Y * f, c->xyz.Z * f};
      c->srgb = {c->srgb.r * f, c->srgb.g * f, c->srgb.b * f};
    }
    s.sun_transmitted = {s.sun_transmitted.X * f, s.sun_transmitted.Y * f, s.sun_transmitted.Z * f};
  }
  s.sun_chromaticity = xy_chromaticity_or_nan(s.sun_transmitted);
  const auto& wl = sky.atmosphere().wavelengths_nm();
  std::size_t best = 0;
  for (std::size_t i = 1; i < wl.size(); ++i)
    if (std::fabs(wl[i] - 550.0) < std::fabs(wl[best] - 550.0)) best = i;
  s.sun_transmittance_550 = t.empty() ? 0.0 : t[best];
  return s;
}

SkyIrradiance sky_irradiance(const SkyIntegrator& sky, double altitude_m, const glm::dvec3& sun, int zenith,
                             int azimuth) {
  if (zenith < 2 || azimuth < 4)
    throw InputError("irradiance quadrature " + std::to_string(zenith) + " x " + std::to_string(azimuth) +
                     " needs >= 2 zenith and >= 4 azimuth points");
  const std::size_t nw = sky.solar().size();
  SkyIrradiance out;
  out.direct.assign(nw, 0.0);
  out.diffuse.assign(nw, 0.0);
  const glm::dvec3 l = glm::normalize(sun);
  if (l.z > 0) {
    const auto t = sky.sun_transmittance(altitude_m, l);
    const double d = sky.options().sun_distance_au;
    for (std::size_t i = 0; i < nw; ++i) out.direct[i] = l.z * sky.solar()[i] / (d * d) * t[i];
  }
  const auto gl = sh::gauss_legendre(zenith);
  const double two_pi = 2.0 * 3.14159265358979323846;
  std::vector<glm::dvec3> views(static_cast<std::size_t>(azimuth));
  std::vector<double> L(static_cast<std::size_t>(azimuth) * nw);
  for (int z = 0; z < zenith; ++z) {
    const double u = 0.5 * (gl.nodes[static_cast<std::size_t>(z)] + 1.0);
    const double mu = u * u, w_mu = 2.0 * u * 0.5 * gl.weights[static_cast<std::size_t>(z)];  // d(mu) = 2u du
    const double sn = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    for (int a = 0; a < azimuth; ++a) {
      const double phi = two_pi * (a + 0.5) / azimuth;
      views[static_cast<std::size_t>(a)] = glm::dvec3(sn * std::cos(phi), sn * std::sin(phi), mu);
    }
    sky.radiance_same_zenith(altitude_m, views.data(), views.size(), l, L.data());
    const double w = w_mu * mu * two_pi / azimuth;
    for (int a = 0; a < azimuth; ++a)
      for (std::size_t i = 0; i < nw; ++i) out.diffuse[i] += w * L[static_cast<std::size_t>(a) * nw + i];
  }
  const SpectralToXyz cmf(sky.atmosphere().wavelengths_nm());
  out.direct_lux = cmf(out.direct).Y;
  out.diffuse_lux = cmf(out.diffuse).Y;
  return out;
}

}  // namespace atmosh::atmo
