// atmosh/studies/studies_rt.hpp — the Monte-Carlo radiative-transfer references as
// drivers with plain inputs: a plane-parallel slab's reflection and transmission, and
// one view of a scene's sky with every scattering order (atmo::MonteCarloSky with the
// scene's solar spectrum). Angles in degrees as named; heights in metres.
#pragma once

#include "atmosh/atmo/radiative_transfer.hpp"
#include "atmosh/atmo/spec.hpp"

#include <string>

namespace atmosh::studies {

// R = pi I_up / (mu0 F0) and T = pi I_down / (mu0 F0) (diffuse) of the slab, with
// standard errors; phi_deg: azimuth of the viewed light's propagation relative to the
// beam's (0 = same azimuth).
atmo::SlabResult rt_slab(const atmo::SlabSpec& slab, double mu0, double mu, double phi_deg,
                         const atmo::RtOptions& options);

// One view of the sky: sun and view directions by elevation and azimuth (from north
// towards east), observer height above the ground.
struct RtSkyView {
  double sun_elevation_deg = 30.0, sun_azimuth_deg = 180.0;
  double view_elevation_deg = 90.0, view_azimuth_deg = 180.0;
  double observer_height_m = 0.0;
};
// Spectral radiance [W m^-2 sr^-1 nm^-1], luminance [cd/m^2] and XYZ with standard
// errors, at the atmosphere's wavelengths, lit by the spectrum's solar irradiance
// (atmo::solar_spectrum_for_bins).
atmo::RtSkyResult rt_sky_view(const atmo::AtmosphereSpec& atmosphere, const RtSkyView& view,
                              const atmo::RtSkyOptions& options);

// The requests of `atmosh rt slab` and `atmosh rt sky` as their options give them; the
// runs below check them first, InputError naming the option as typed (--tau, --phase,
// --paths, --sun-depth, ...), then run the drivers above.
struct RtSlabRequest {
  double tau = 1, omega = 1, g = 0, ground_albedo = 0, mu0 = 1, mu = 1, phi_deg = 0;
  std::string phase = "isotropic";  // isotropic | hg | rayleigh
  atmo::RtOptions run;              // paths, seed, threads (0 = the CPUs this process may use)
  int orders = 0;                   // 0 = all
};
atmo::SlabResult rt_slab(const RtSlabRequest& request);
struct RtSkyRequest {
  RtSkyView view;
  double ground_albedo = -1;  // < 0: the scene's
  std::string sun_depth = "table", line_estimate = "auto";  // table | exact; auto | on | off
  std::string guide = "auto";  // auto (below RtSkyOptions::guide_below_deg) | on | off
  atmo::RtOptions run;
  int orders = 0;
};
atmo::RtSkyResult rt_sky_view(const atmo::AtmosphereSpec& atmosphere, const RtSkyRequest& request);
// "auto" | "on" | "off" -> DeepTwilight | On | Off (the line estimate's and the guide's
// switch); anything else: InputError "<what>: '<word>' is not auto, on or off".
atmo::RtLineEstimate rt_switch(const std::string& word, const std::string& what);

}  // namespace atmosh::studies
