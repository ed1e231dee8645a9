// Monte-Carlo radiative-transfer drivers (atmosh/studies/studies_rt.hpp).
#include "atmosh/studies/studies_rt.hpp"

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/check.hpp"
#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"

namespace atmosh::studies {

namespace {
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
}

atmo::SlabResult rt_slab(const atmo::SlabSpec& slab, double mu0, double mu, double phi_deg,
                         const atmo::RtOptions& options) {
  return atmo::slab_reflection_transmission(slab, mu0, mu, phi_deg * kDegToRad, options);
}

atmo::RtSkyResult rt_sky_view(const atmo::AtmosphereSpec& spec, const RtSkyView& v, const atmo::RtSkyOptions& so) {
  const atmo::Atmosphere atm(spec);
  const atmo::MonteCarloSky mc(atm, atmo::solar_spectrum_for_bins(spec.spectrum), so);
  const glm::dvec3 view = atmo::enu_direction(v.view_elevation_deg, v.view_azimuth_deg);
  const glm::dvec3 sun = atmo::enu_direction(v.sun_elevation_deg, v.sun_azimuth_deg);
  return mc.radiance(v.observer_height_m, view, sun);
}

namespace {
void check_paths(std::int64_t n) {
  if (n < 1 || n > (std::int64_t{1} << 40)) throw InputError("--paths " + std::to_string(n) + ": must be in [1, 2^40]");
}
}  // namespace

atmo::SlabResult rt_slab(const RtSlabRequest& o) {
  atmo::SlabSpec s;
  if (o.phase == "isotropic") s.phase = atmo::SlabPhase::Isotropic;
  else if (o.phase == "hg") s.phase = atmo::SlabPhase::HenyeyGreenstein;
  else if (o.phase == "rayleigh") s.phase = atmo::SlabPhase::Rayleigh;
  else throw InputError("--phase: '" + o.phase + "' is not isotropic, hg or rayleigh");
  s.tau = require_range(o.tau, 1e-300, 1e6, "--tau");
  if (!(s.tau > 0)) throw InputError("--tau: must be > 0");
  s.omega = require_range(o.omega, 0.0, 1.0, "--omega");
  s.g = require_range(o.g, -0.999999, 0.999999, "--g");
  s.ground_albedo = require_range(o.ground_albedo, 0.0, 1.0, "--ground-albedo");
  const double mu0 = require_range(o.mu0, 1e-6, 1.0, "--mu0");
  const double mu = require_range(o.mu, 1e-6, 1.0, "--mu");
  const double phi = require_range(o.phi_deg, -360.0, 360.0, "--phi-deg");
  check_paths(o.run.paths);
  require_range(o.orders, 0, 1 << 30, "--orders");
  resolve_threads(o.run.threads, "--threads");  // the one thread-count policy
  atmo::RtOptions run = o.run;
  run.max_orders = o.orders;
  return rt_slab(s, mu0, mu, phi, run);
}

atmo::RtSkyResult rt_sky_view(const atmo::AtmosphereSpec& spec, const RtSkyRequest& o) {
  require_range(o.view.sun_elevation_deg, -90.0, 90.0, "--sun-elevation");
  require_range(o.view.view_elevation_deg, -90.0, 90.0, "--view-elevation");
  require_range(o.view.sun_azimuth_deg, -360.0, 360.0, "--sun-azimuth");
  require_range(o.view.view_azimuth_deg, -360.0, 360.0, "--view-azimuth");
  require_range(o.view.observer_height_m, 0.0, 1e9, "--height");
  if (o.ground_albedo != -1) require_range(o.ground_albedo, 0.0, 1.0, "--ground-albedo");
  require_range(o.orders, 0, 1 << 30, "--orders");
  resolve_threads(o.run.threads, "--threads");
  check_paths(o.run.paths);
  atmo::RtSkyOptions so;
  if (o.sun_depth == "table") so.sun_depth = atmo::RtSunDepth::Table;
  else if (o.sun_depth == "exact") so.sun_depth = atmo::RtSunDepth::Exact;
  else throw InputError("--sun-depth: '" + o.sun_depth + "' is not table or exact");
  so.line_estimate = rt_switch(o.line_estimate, "--line-estimate");
  so.guide = rt_switch(o.guide, "--guide");
  so.run = o.run;
  so.run.max_orders = o.orders;
  so.ground_albedo = o.ground_albedo;
  return rt_sky_view(spec, o.view, so);
}

atmo::RtLineEstimate rt_switch(const std::string& word, const std::string& what) {
  if (word == "auto") return atmo::RtLineEstimate::DeepTwilight;
  if (word == "on") return atmo::RtLineEstimate::On;
  if (word == "off") return atmo::RtLineEstimate::Off;
  throw InputError(what + ": '" + word + "' is not auto, on or off");
}

}  // namespace atmosh::studies
