// observer.cpp — GeographicLib-backed observer geometry; see observer.hpp.
#include "atmosh/atmo/observer.hpp"

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "atmosh/error.hpp"
#include "atmosh/format.hpp"

namespace atmosh::atmo {
namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
std::string num(double v) { return atmosh::format_double(v); }
}  // namespace

void validate_observer(const Observer& o) {
  if (!std::isfinite(o.latitude_deg) || o.latitude_deg < -90.0 || o.latitude_deg > 90.0)
    throw InputError("latitude " + num(o.latitude_deg) + " deg is outside -90..90");
  if (!std::isfinite(o.longitude_deg) || o.longitude_deg < -180.0 || o.longitude_deg > 180.0)
    throw InputError("longitude " + num(o.longitude_deg) + " deg is outside -180..180");
  if (!std::isfinite(o.height_m) || o.height_m < kObserverMinHeightM || o.height_m > kObserverMaxHeightM)
    throw InputError("height " + num(o.height_m) + " m is outside " + num(kObserverMinHeightM) + ".." +
                     num(kObserverMaxHeightM));
}

glm::dvec3 observer_ecef_m(const Observer& o) {
  validate_observer(o);
  double x, y, z;
  GeographicLib::Geocentric::WGS84().Forward(o.latitude_deg, o.longitude_deg, o.height_m, x, y, z);
  return {x, y, z};
}

glm::dvec3 ecef_to_enu_m(const Observer& origin, const glm::dvec3& p) {
  validate_observer(origin);
  GeographicLib::LocalCartesian lc(origin.latitude_deg, origin.longitude_deg, origin.height_m,
                                   GeographicLib::Geocentric::WGS84());
  // LocalCartesian works from geodetic input; convert the ECEF point first.
  double lat, lon, h;
  GeographicLib::Geocentric::WGS84().Reverse(p.x, p.y, p.z, lat, lon, h);
  double e, n, u;
  lc.Forward(lat, lon, h, e, n, u);
  return {e, n, u};
}

void enu_axes_ecef(const Observer& o, glm::dvec3& east, glm::dvec3& north, glm::dvec3& up) {
  validate_observer(o);
  double x, y, z;
  std::vector<double> M(9);
  GeographicLib::Geocentric::WGS84().Forward(o.latitude_deg, o.longitude_deg, o.height_m, x, y, z, M);
  // M (row-major) maps ENU components at the point to ECEF components (v0 = M v1):
  // its columns are the ENU axes expressed in ECEF.
  east = {M[0], M[3], M[6]};
  north = {M[1], M[4], M[7]};
  up = {M[2], M[5], M[8]};
}

glm::dvec3 enu_direction(double elevation_deg, double azimuth_deg) {
  if (!std::isfinite(elevation_deg) || !std::isfinite(azimuth_deg)) throw InputError("direction angles must be finite");
  constexpr double kPi = 3.14159265358979323846;
  const double e = elevation_deg * kPi / 180.0, a = azimuth_deg * kPi / 180.0;  // not kDeg: the same bits as before
  return {std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
}

glm::dvec3 enu_direction_from_zenith(double zenith_deg, double azimuth_deg) {
  const double z = zenith_deg * kDeg, a = azimuth_deg * kDeg;
  return {std::sin(z) * std::sin(a), std::sin(z) * std::cos(a), std::cos(z)};
}

double geocentric_radius_m(const Observer& o) {
  const glm::dvec3 p = observer_ecef_m(o);
  return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
}

double observer_radius_in_atmosphere_m(const Observer& o, double planet_radius_m) {
  validate_observer(o);
  if (!std::isfinite(planet_radius_m) || planet_radius_m <= 0.0)
    throw InputError("planet radius " + num(planet_radius_m) + " m must be positive");
  const double r = planet_radius_m + o.height_m;
  if (r <= 0.0) throw InputError("height " + num(o.height_m) + " m puts the observer below the planet's centre");
  return r;
}

}  // namespace atmosh::atmo
