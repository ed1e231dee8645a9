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

// Where an observer stands: the one place type of atmosh (scene files hold it plus a
// time, scene::Observer; the sun's queries take its fields).
struct Observer {
  double latitude_deg = 0.0;   // geodetic, -90..90
  double longitude_deg = 0.0;  // east positive, -180..180
  double height_m = 0.0;       // above the WGS84 ellipsoid, kObserverMinHeightM..kObserverMaxHeightM
};

// The valid heights [m] of an observer, for every entry point (scene files, the sun's
// queries, the sky). Lower end: an observer stands under the open sky, and the lowest
// dry land is the Dead Sea shore, about 430 m below sea level (the geoid there lies
// within a few tens of metres of the ellipsoid); -500 m leaves a margin for that and
// for open-pit mines (the deepest reach about 300 m below sea level), while rejecting
// sign and unit slips (-5 km, -12 km). Underground or undersea points see no sky, and
// the atmosphere model's ground is at height 0 anyway: the sky takes max(height, 0).
// Upper end: 1e8 m, far beyond the top of any atmosphere (the sky handles observers in
// space) and beyond geostationary orbit.
inline constexpr double kObserverMinHeightM = -500.0;
inline constexpr double kObserverMaxHeightM = 1.0e8;

// Throws InputError naming the bad value (non-finite, |lat| > 90, |lon| > 180,
// height outside kObserverMinHeightM..kObserverMaxHeightM, i.e. -500..1e8 m).
void validate_observer(const Observer& o);

// Geodetic -> ECEF (m).
glm::dvec3 observer_ecef_m(const Observer& o);

// ECEF point (m) -> ENU coordinates (m) relative to the observer.
glm::dvec3 ecef_to_enu_m(const Observer& origin, const glm::dvec3& ecef_m);

// Unit vectors of the local East, North and Up axes expressed in ECEF.
void enu_axes_ecef(const Observer& o, glm::dvec3& east, glm::dvec3& north, glm::dvec3& up);

// Unit vectors of the ENU frame from angles in degrees, azimuth A from north towards
// east: any direction (the sun's, a view ray's, a pixel's). Two parameterisations, each
// kept with its own arithmetic so that results stay bit for bit what they were:
//   enu_direction(elevation e, A) = (cos e sin A, cos e cos A, sin e);
//     InputError for non-finite angles.
//   enu_direction_from_zenith(zenith z, A) = (sin z sin A, sin z cos A, cos z);
//     finite for every finite input (no check: inner loops).
glm::dvec3 enu_direction(double elevation_deg, double azimuth_deg);
glm::dvec3 enu_direction_from_zenith(double zenith_deg, double azimuth_deg);

// Distance of the observer from the Earth's centre (m), WGS84.
double geocentric_radius_m(const Observer& o);

// Observer's radius in a spherical atmosphere of ground radius planet_radius_m:
// planet_radius_m + height_m (see above). Throws InputError if below the centre.
double observer_radius_in_atmosphere_m(const Observer& o, double planet_radius_m);

}  // namespace atmosh::atmo
