// Monte-Carlo radiative-transfer drivers (atmosh/studies/studies_rt.hpp).
#include "atmosh/studies/studies_rt.hpp"

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/sky_image.hpp"

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

}  // namespace atmosh::studies
