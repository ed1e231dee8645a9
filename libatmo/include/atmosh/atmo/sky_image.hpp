// atmosh/atmo/sky_image.hpp — sky images and summaries from a SkyIntegrator.
//
// Projections (observer's East-North-Up frame):
//   * Equirect: pixel column x -> azimuth (x + 0.5) / W * 360 deg from north
//     towards east (north at the left edge, east a quarter across); row y ->
//     elevation 90 - (y + 0.5) / H * 180 deg (zenith at the top, nadir at the
//     bottom).
//   * Fisheye: the upper hemisphere in an azimuthal equidistant (angular)
//     projection seen from below, as an all-sky camera looking up: zenith at the
//     centre, the horizon on the inscribed circle, north up and east to the
//     LEFT. Pixels outside the circle are masked (0).
// Radiance channels: spectral radiance [W m^-2 sr^-1 nm^-1] per wavelength,
// CIE XYZ with Y = luminance [cd/m^2] (SpectralToXyz, piecewise-linear), and
// linear sRGB (D65) on the same scale.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmosh/atmo/colour.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/work.hpp"

namespace atmosh::atmo {

enum class SkyProjection { Equirect, Fisheye };
SkyProjection parse_sky_projection(const std::string& name);  // InputError if unknown

// Direction through the centre of pixel (x, y); false when outside the fisheye disc.
bool sky_pixel_direction(SkyProjection p, int width, int height, int x, int y, glm::dvec3& dir);

// Solar irradiance at 1 AU averaged over the bin each wavelength of
// spectrum_wavelengths(spectrum) stands for (equal bins, or for explicit lists the
// cells between midpoints, clipped to the solar table): Fraunhofer lines make point
// values noisy.
SolarSpectrum solar_spectrum_for_bins(const SpectrumSpec& spectrum);

struct SkyImage {
  int width = 0, height = 0;
  std::vector<double> wavelengths_nm;
  std::vector<float> spectral;           // [(y * width + x) * n_wavelengths + i], if kept
  std::vector<float> X, Y, Z, R, G, B;   // planar, row 0 at the top
  std::vector<std::uint8_t> valid;       // 0 outside the fisheye disc
  double seconds = 0;                    // wall time of the render
  long rays = 0;
};

// Bytes a SkyImage of width x height holds (X, Y, Z, R, G, B as float32, the validity
// mask, and with keep_spectral one float32 per wavelength per pixel): what render_sky
// allocates, for callers that check a memory budget before rendering. Saturates at
// SIZE_MAX instead of wrapping.
std::size_t sky_image_bytes(int width, int height, std::size_t wavelengths, bool keep_spectral);

// The work of `rays` view rays through the sky (atmosh/work.hpp), before tracing them:
// rays x view-ray nodes (segments x samples_per_segment), a node costing on one core
// a + b x wavelengths, a and b measured for render_sky's loop with options.scattering's
// method (bench/bench_work.cpp; docs/hostile-input.md, "Work estimates": within -35 %
// to +20 % of 4 to 64 nodes and 8 to 47 wavelengths). Not counted: the tables built
// first (optical depths, the approximate and orders methods' tables).
WorkEstimate sky_rays_work(double rays, std::size_t wavelengths, const SkyOptions& options);
// sky_rays_work of a width x height image (every pixel a ray; a fisheye traces pi/4 of them).
WorkEstimate sky_image_work(int width, int height, std::size_t wavelengths, const SkyOptions& options);

// The one spectrum -> colour step of every sky image (render_sky, gpu::render_sky,
// add_sun_disc): pixel p of img from its spectral radiance L [W m^-2 sr^-1 nm^-1, one
// value per wavelength of the image]: X, Y, Z through cmf (the image's wavelengths; Y
// in cd/m^2), linear sRGB through linear_srgb_from_xyz, and L itself where the image
// keeps the spectrum (img.spectral not empty), all as float; the pixel becomes valid.
// With add = true the values are added to the pixel's instead (validity unchanged).
void store_sky_pixel(SkyImage& img, std::size_t p, const SpectralToXyz& cmf, std::span<const double> L,
                     bool add = false);

// Renders with `threads` worker threads (0 = the CPUs this process may use, atmosh::resolve_threads).
SkyImage render_sky(const SkyIntegrator& sky, SkyProjection projection, int width, int height, double altitude_m,
                    const glm::dvec3& sun, bool keep_spectral, int threads = 0);

// Colour of the sky in one direction.
struct SkyColour {
  Xyz xyz;       // Y in cd/m^2
  Rgb srgb;      // linear sRGB, same scale
};
SkyColour sky_colour(const SkyIntegrator& sky, const SpectralToXyz& cmf, double altitude_m, const glm::dvec3& view,
                     const glm::dvec3& sun);

// The numbers a study or sweep reports for one sky.
struct SkySummary {
  SkyColour zenith;
  SkyColour horizon_toward_sun;  // view elevation `horizon_elevation_deg`, sun's azimuth
  SkyColour horizon_away;        // same elevation, opposite azimuth
  Xyz sun_transmitted;           // XYZ of the transmitted solar irradiance (W m^-2 weighted; Y in lux),
                                 // the direct beam of SkyOptions::sun_model (disc-averaged by default)
  Chromaticity sun_chromaticity; // of the transmitted direct sunlight (NaN when none arrives)
  double sun_transmittance_550 = 0;  // direct-beam transmittance nearest 550 nm (same sun model)
};
// sun_distance_au > 0: the Earth-Sun distance of this sky when it differs from the
// integrator's (SkyOptions::sun_distance_au; a day study builds its tables once for
// 1 AU): every quantity here is linear in the solar spectrum, so the whole summary —
// sky colours and the transmitted sun's XYZ alike — is scaled once, by
// (integrator's distance / sun_distance_au)^2; chromaticities do not change. 0: the
// integrator's distance.
SkySummary summarize_sky(const SkyIntegrator& sky, double altitude_m, const glm::dvec3& sun,
                         double horizon_elevation_deg = 1.0, double sun_distance_au = 0.0);

// Irradiance on a horizontal surface at the observer: what a solar-energy or
// daylighting user asks for first.
//   direct  = mu_s E T_sun per wavelength (0 with the sun below the horizontal plane
//             or behind the planet) [W m^-2 nm^-1], E the solar spectrum at the
//             sky's Earth-Sun distance, T_sun SkyIntegrator::sun_transmittance;
//   diffuse = int over the upper hemisphere of L(v) cos(theta) dw, with L the sky's
//             radiance (its scattering method; the sun disc is not part of L)
//             [W m^-2 nm^-1]. Quadrature: Gauss-Legendre in u on [0, 1] with
//             cos(theta) = u^2 (`zenith` points; gathers them toward the horizon,
//             where the radiance changes fastest) x `azimuth` uniform azimuths
//             (midpoints). The view rays of one zenith ring share their nodes
//             (SkyIntegrator::radiance_same_zenith).
// Illuminances [lux]: 683 lm/W x the CIE 1931 photopic curve over the spectrum
// (SpectralToXyz, piecewise linear: Y of the irradiance). InputError for zenith < 2 or
// azimuth < 4.
struct SkyIrradiance {
  std::vector<double> direct, diffuse;  // [wavelength] W m^-2 nm^-1
  double direct_lux = 0, diffuse_lux = 0;
};
SkyIrradiance sky_irradiance(const SkyIntegrator& sky, double altitude_m, const glm::dvec3& sun, int zenith = 24,
                             int azimuth = 48);

}  // namespace atmosh::atmo
