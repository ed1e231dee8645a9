// atmosh/atmo/observer.hpp — observer geometry on the WGS84 ellipsoid
// (GeographicLib::Geocentric and GeographicLib::LocalCartesian underneath).
//
// Frames: ECEF (Earth-centred, Earth-fixed, metres, WGS84) and the observer's
// local East-North-Up frame (x east, y north, z up along the ellipsoid normal;
// metres for points, unit vectors for directions). Azimuth is measured from
// north towards east, zenith from the up axis.
//
// Accuracy: GeographicLib's conversions are exact to ~5 nm (Karney 2011).
//
// Atmosphere radius: the atmosphere model (spec.hpp) is a sphere of radius
// PlanetSpec::radius_m. An observer at ellipsoidal height h is placed at radius
// planet_radius + h — the spherical-planet approximation: the ellipsoid's
// flattening (21 km between equator and pole) is NOT carried into the sky; only
// the height above the local surface is. geocentric_radius_m() gives the true
// distance from the Earth's centre for reference.
#pragma once

#include <glm/vec3.hpp>

namespace atmosh::atmo {

struct Observer {
  double latitude_deg = 0.0;   // geodetic, -90..90
  double longitude_deg = 0.0;  // east positive, -180..180
  double height_m = 0.0;       // above the WGS84 ellipsoid
};

// Throws InputError naming the bad value (non-finite, |lat| > 90, |lon| > 180,
// height below -12 km or above 1e8 m).
void validate_observer(const Observer& o);

// Geodetic -> ECEF (m).
glm::dvec3 observer_ecef_m(const Observer& o);

// ECEF point (m) -> ENU coordinates (m) relative to the observer.
glm::dvec3 ecef_to_enu_m(const Observer& origin, const glm::dvec3& ecef_m);

// Unit vectors of the local East, North and Up axes expressed in ECEF.
void enu_axes_ecef(const Observer& o, glm::dvec3& east, glm::dvec3& north, glm::dvec3& up);

// Unit direction towards a body at (zenith, azimuth) in the ENU frame:
// (sin z sin A, sin z cos A, cos z). Finite for every finite input.
glm::dvec3 sun_direction_enu(double zenith_deg, double azimuth_deg);

// Distance of the observer from the Earth's centre (m), WGS84.
double geocentric_radius_m(const Observer& o);

// Observer's radius in a spherical atmosphere of ground radius planet_radius_m:
// planet_radius_m + height_m (see above). Throws InputError if below the centre.
double observer_radius_in_atmosphere_m(const Observer& o, double planet_radius_m);

}  // namespace atmosh::atmo
