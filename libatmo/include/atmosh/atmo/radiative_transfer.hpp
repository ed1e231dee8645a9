// atmosh/atmo/radiative_transfer.hpp — Monte-Carlo radiative transfer: the exact
// (unbiased, statistical) reference for multiply scattered skylight, and its
// plane-parallel mode for the published slab benchmarks.
//
// Method (docs/radiative-transfer.md). Backward path tracing from the observer, one
// wavelength per path, every order of scattering:
//   * free paths by delta tracking against a majorant of the extinction (unbiased for
//     any majorant >= the extinction): in the spherical atmosphere the majorant of a
//     flight is sum_c k_c sup_{h >= h_min} rho_c(h), with h_min the lowest altitude
//     the rest of the ray reaches (its own altitude going up, the tangent point or
//     the ground going down), renewed at every tentative collision; in the slab the
//     medium is homogeneous and the flight is sampled exactly;
//   * at a collision the weight is multiplied by the single-scattering albedo
//     sigma_s / sigma_t of the point (absorption by weight: Mie absorption, ozone),
//     the scatterer is chosen among the constituents with probability
//     sigma_s,c / sigma_s, the new direction is sampled from its phase function
//     (PhaseFunction::sample: exact inverse CDF), or, with probability
//     sun_cone_share, uniformly inside a cone about the sun (in twilight the lit
//     atmosphere lies toward the sun, at directions phase sampling rarely takes):
//     one-sample multiple importance sampling, weight x f / ((1 - b) f + b p_cone);
//   * next-event estimation (the local estimate) toward the sun at every scattering
//     and ground vertex: weight x E x p_c(cos theta) x T_sun (x albedo/pi x mu_sun on
//     the ground), T_sun = 0 where the ground blocks the sun (Earth's shadow);
//   * a Lambertian ground: cosine-weighted reflection, weight x albedo;
//   * line estimate (RtSkyOptions::line_estimate): from every vertex, the expected
//     value of the next vertex's next-event estimate is added instead of that estimate
//     itself: the single-scattering integral of sunlight along the new direction (and
//     the lit ground it may end on), one uniformly placed point per piece of <= 1 km
//     altitude / 20 km length (stratified sampling: unbiased), the transmittance to it
//     exact (piece columns by 8-point Gauss-Legendre). ~20x the cost of a vertex; in
//     twilight it turns the rare flights that end in the lit atmosphere into every
//     flight that crosses it;
//   * the first collision on the view ray is importance-sampled from its exact optical
//     depth (the ray cut every <= 250 m of altitude and <= 5 km of length and at
//     profile kinks, each piece's column by 8-point Gauss-Legendre, < 1e-13): a piece
//     by its share of the collision probability, the point uniformly in it, weight
//     sigma_s(s) e^{-tau(s)} / q(s) with the exact tau(s); a ray that meets the ground
//     ends there with probability e^{-tau}; rays toward space never escape unscattered
//     (a forced collision: their escape carries no light). In the slab: the truncated
//     exponential, weight 1 - e^{-tau/mu};
//   * Russian roulette once the weight falls below `roulette_weight` (survival
//     probability weight / roulette_weight, the survivor's weight reset to it).
// Each vertex (scattering or ground reflection) is one order; max_orders = 1 is single
// scattering (plus the directly lit ground), the quantity SkyReference integrates.
// The sun disc (unscattered sunlight) is not part of the radiance, as in sky.hpp.
//
// Sun transmittance. RtSunDepth::Exact uses OpticalDepthReference per vertex
// (relative error 1e-12). RtSunDepth::Table (default) uses the multi-shell sun table
// (OpticalDepthLut, view tables left out) at RtSkyOptions::table_shells x
// table_directions; its estimated maximum relative error of the optical depth
// (OpticalDepthLut::estimate_max_rel_error at the middle wavelength, reported in
// RtSkyResult::sun_depth_rel_error) bounds the relative bias of a sun transmittance
// by that times the sun's slant optical depth at the vertex, below the statistical
// error of any feasible run (values and build times per table size:
// docs/radiative-transfer.md; the checks: docs/validation.md, "Monte-Carlo radiative
// transfer").
//
// Statistics. Paths are split evenly over the wavelengths (stratified); each
// wavelength's paths run in `batches` fixed batches, each with its own
// xoshiro256++ stream seeded by SplitMix64 from (seed, wavelength, batch). Results
// are sums per batch added in batch order: bit-identical for a given seed on any
// thread count. Standard errors are per-path sample standard deviations / sqrt(n)
// per wavelength; the luminance and XYZ combine the wavelengths as independent
// estimates. Nothing prints; InputError for bad input.
//
// Frames and units: as sky.hpp (ENU at the observer, unit directions pointing away
// from the observer, altitudes in metres, radiance in W m^-2 sr^-1 nm^-1, luminance
// in cd m^-2).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/colour.hpp"
#include "atmosh/atmo/observer.hpp"  // enu_direction
#include "atmosh/atmo/sky.hpp"

namespace atmosh::atmo {

// ---------------------------------------------------------------------------
// Plane-parallel mode: a flat homogeneous slab of optical thickness tau over a
// Lambertian ground (albedo 0: a black lower boundary), lit by a parallel beam of
// flux F0 per unit area normal to it from the direction with cosine mu0 of its zenith
// angle. Outputs: the reflection and transmission functions
//   R(mu0, mu, phi) = pi I_up(top, mu, phi) / (mu0 F0),
//   T(mu0, mu, phi) = pi I_down(bottom, mu, phi) / (mu0 F0)   (diffuse light only),
// mu the cosine of the viewed light's zenith angle (mu > 0 upward at the top, the
// light going down at the bottom), phi the azimuth of the viewed light's direction of
// propagation relative to the beam's (phi = 0: both propagate toward the same
// azimuth, as DISORT's PHI - PHI0).

enum class SlabPhase { Isotropic, HenyeyGreenstein, Rayleigh };

struct SlabSpec {
  double tau = 1.0;            // optical thickness (> 0, finite)
  double omega = 1.0;          // single-scattering albedo [0, 1]
  SlabPhase phase = SlabPhase::Isotropic;
  double g = 0.0;              // Henyey-Greenstein asymmetry (|g| < 1)
  double ground_albedo = 0.0;  // Lambertian [0, 1]
};

struct RtOptions {
  std::int64_t paths = 100000;  // per quantity (>= 1)
  std::uint64_t seed = 1;
  int max_orders = 0;           // 0: every order (paths end by escape or roulette)
  int threads = 0;              // 0: the CPUs this process may use (atmosh::resolve_threads)
  int batches = 64;             // fixed work units (determinism); >= 1
  double roulette_weight = 0.1; // (0, 1]
};

struct SlabResult {
  double reflection = 0, reflection_stderr = 0;
  double transmission = 0, transmission_stderr = 0;
  std::int64_t paths = 0;  // per function
  double time_s = 0;
};

// R and T at one geometry. InputError for mu0, mu outside (0, 1], non-finite phi or
// an invalid slab/options.
SlabResult slab_reflection_transmission(const SlabSpec& slab, double mu0, double mu, double phi_rad,
                                        const RtOptions& options = {});

// Fluxes: the plane albedo (upward flux at the top / mu0 F0) and the diffuse
// transmittance (diffuse downward flux at the bottom / mu0 F0), estimated by the same
// backward paths started in cosine-weighted random directions (E[R] over them is the
// flux ratio).
struct SlabFluxResult {
  double albedo = 0, albedo_stderr = 0;
  double transmittance = 0, transmittance_stderr = 0;  // diffuse
  std::int64_t paths = 0;
  double time_s = 0;
};
SlabFluxResult slab_fluxes(const SlabSpec& slab, double mu0, const RtOptions& options = {});

// ---------------------------------------------------------------------------
// Spherical atmosphere.

enum class RtSunDepth { Table, Exact };
// Line estimate of the next vertex's sunlight (see the header comment): always, never,
// or in deep twilight, sun below -7 deg at the observer, where it pays (its measured
// efficiency by sun elevation: docs/radiative-transfer.md).
enum class RtLineEstimate { Off, On, DeepTwilight };
inline constexpr double kRtDeepTwilightDeg = -7.0;

struct RtSkyOptions {
  RtOptions run{.paths = 64000};   // paths in total, over all wavelengths
  double sun_distance_au = 1.0;
  double ground_albedo = -1.0;     // < 0: the atmosphere's planet.ground_albedo
  RtSunDepth sun_depth = RtSunDepth::Table;
  int table_shells = 64;           // RtSunDepth::Table sizes
  int table_directions = 256;
  // Scattering directions: this share is drawn uniformly inside a cone about the sun
  // (one-sample MIS with the phase function; 0: phase sampling only).
  double sun_cone_share = 0.2;        // [0, 1)
  double sun_cone_half_angle_deg = 15.0;
  RtLineEstimate line_estimate = RtLineEstimate::DeepTwilight;
  // Guided scattering (twilight): before the paths, a pilot per wavelength evaluates,
  // at `guide_points` points of the view ray, the light a first vertex there would
  // send toward the observer: its next-event estimate plus, over a grid of
  // guide_zenith x guide_azimuth cells of outgoing directions (local frame: zenith
  // cosine in cells finer near the horizon, azimuth from the sun's vertical plane), the
  // phase function times the line estimate along each. The first collision is then
  // drawn with the view ray's collision density times that value (mixed with the plain
  // density, share guide_defensive), and every scattering direction, with share
  // guide_share, from the cell distribution of a pilot point (the nearest one along the
  // view ray for the first vertex, the nearest in altitude for later ones): one-sample
  // MIS with the phase function and the sun cone. Every density is evaluated exactly,
  // so the estimate is unbiased whatever the pilot found; the line estimate is used
  // wherever the guide is (the guide aims at it). On by default below guide_below_deg
  // (sun elevation at the observer), where the light comes from the sunlit atmosphere
  // far from the view ray and plain paths are heavy-tailed; measured gains:
  // docs/radiative-transfer.md. The pilot costs ~guide_points x cells line estimates
  // per wavelength (~0.3 s per wavelength on one core with the defaults).
  RtLineEstimate guide = RtLineEstimate::DeepTwilight;  // Off, On, DeepTwilight (below guide_below_deg)
  double guide_below_deg = -5.0;
  int guide_points = 16;       // [2, 256]
  int guide_zenith = 16;       // [2, 256]
  int guide_azimuth = 12;      // [1, 256]
  double guide_share = 0.6;    // [0, 1)
  double guide_defensive = 0.2;  // (0, 1]
};

struct RtSkyResult {
  std::vector<double> wavelengths_nm;
  std::vector<double> radiance;         // W m^-2 sr^-1 nm^-1
  std::vector<double> radiance_stderr;
  Xyz xyz;                              // Y = luminance [cd m^-2]
  Xyz xyz_stderr;
  double luminance = 0, luminance_stderr = 0;  // cd m^-2
  std::int64_t paths = 0;               // in total
  std::int64_t paths_per_wavelength = 0;
  double mean_orders = 0;               // vertices per path (scattering + ground)
  double time_s = 0;
  double sun_depth_rel_error = 0;       // estimated max relative error of the sun's optical depth
};

class MonteCarloSky {
 public:
  // `solar`: E(lambda) at 1 AU per wavelength of the atmosphere [W m^-2 nm^-1] (as
  // SkyIntegrator). Builds the sun table for RtSunDepth::Table. InputError for bad
  // options or a spectrum of the wrong size. Refers to `atmosphere` (no copy): it
  // must outlive this object.
  MonteCarloSky(const Atmosphere& atmosphere, SolarSpectrum solar, RtSkyOptions options = {});
  ~MonteCarloSky();
  MonteCarloSky(const MonteCarloSky&) = delete;
  MonteCarloSky& operator=(const MonteCarloSky&) = delete;

  // Spectral radiance and luminance toward `view` seen from altitude_m (above the top
  // is fine), sun in direction `sun` (unit vectors, ENU). Uses options().run.
  RtSkyResult radiance(double altitude_m, const glm::dvec3& view, const glm::dvec3& sun) const;
  // The same with another run configuration (paths, seed, orders, threads).
  RtSkyResult radiance(double altitude_m, const glm::dvec3& view, const glm::dvec3& sun, const RtOptions& run) const;

  const Atmosphere& atmosphere() const { return atm_; }
  const RtSkyOptions& options() const { return opt_; }
  double sun_depth_rel_error() const { return sun_depth_rel_error_; }

  struct Impl;

 private:
  const Atmosphere& atm_;
  SolarSpectrum solar_;
  RtSkyOptions opt_;
  double sun_depth_rel_error_ = 0;
  std::unique_ptr<Impl> impl_;
};

// Time to reach a relative standard error of the zenith luminance: runs of doubling
// path counts (from `first_paths`) until luminance_stderr / luminance <= target or
// the next run would exceed max_seconds (estimated from the last one). Observer at
// the ground, sun at azimuth 180 deg.
struct RtConvergence {
  double target_rel_stderr = 0, reached_rel_stderr = 0;
  bool reached = false;
  std::int64_t paths = 0;  // of the last run
  double time_s = 0;       // of the last run (wall clock)
  double luminance = 0;
  double paths_per_second = 0;
  // time_s (reached / target)^2: the time the target needs at the last run's rate (the
  // standard error falls as 1/sqrt(paths)); equals time_s when reached.
  double extrapolated_time_s = 0;
  int threads = 0;
};
RtConvergence rt_time_to_rel_stderr(const MonteCarloSky& sky, double sun_elevation_deg, double target_rel_stderr,
                                    double max_seconds, std::int64_t first_paths = 4000, const RtOptions& run = {});

// Reference views for convergence studies: every view of `views` (elevation,
// azimuth relative to the sun's, degrees) at every sun elevation of
// `sun_elevations_deg`, observer at altitude_m; one row each.
struct RtViewDirection {
  double elevation_deg = 90, relative_azimuth_deg = 0;
};
struct RtReferenceRow {
  double sun_elevation_deg = 0, view_elevation_deg = 0, view_relative_azimuth_deg = 0;
  RtSkyResult result;
};
// The fixed set used by the studies: zenith; horizon-ish 5 deg toward, across and
// away from the sun; 30 and 60 deg away from the sun.
std::vector<RtViewDirection> rt_reference_view_set();
// Sun elevations 60, 30, 10, 0, -3, -6, -9, -12, -15 degrees.
std::vector<double> rt_reference_sun_elevations();
std::vector<RtReferenceRow> rt_reference_views(const MonteCarloSky& sky, const std::vector<RtViewDirection>& views,
                                               const std::vector<double>& sun_elevations_deg, double altitude_m,
                                               const RtOptions& run);

}  // namespace atmosh::atmo
