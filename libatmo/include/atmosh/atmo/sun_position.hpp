// atmosh/atmo/sun_position.hpp — the sun seen from a place at a UTC instant:
// one entry point over SPA and the fast algorithm, with refraction, rise/transit/
// set and polar day/night.
//
// Inputs: UTC instant (Julian day; see time_utc.hpp for ISO 8601), geodetic
// latitude/longitude (degrees, WGS84, east positive), height above the WGS84
// ellipsoid (m), air pressure (hPa) and temperature (°C) for refraction, ΔT =
// TT − UT1 (s; default: Espenak & Meeus model for the instant's year) and
// UT1 − UTC (s; default 0).
//
// Accuracy (zenith/azimuth, geometric):
//   SPA  ±0.0003° (Reda & Andreas 2008) when ΔT and UT1−UTC are supplied from
//        IERS data; with the defaults the ΔT model error dominates (≈ 0.004° per
//        second of ΔT error; UT1−UTC = 0 costs up to 0.9 s ≈ 0.004°).
//   Fast Grena (2012) algorithm 5: stated max 0.0027° against SPA, 2010..2110
//        only (InputError outside).
// Note on height: SPA's parallax term uses the height above sea level; the
// ellipsoidal height given here is used instead (the geoid undulation, < 110 m,
// changes the parallax by < 2e-9°).
//
// Outputs (SunPosition): geometric (no refraction) topocentric zenith and
// elevation drive the sky; apparent ones add refraction_deg() (continuous and
// finite for all elevations); azimuth from north towards east in [0, 360);
// geocentric declination and local hour angle in (-180, 180]; equation of time in
// minutes; Earth–Sun distance in AU. Rise/transit/set: SPA Appendix A.2 for the
// calendar date of the instant in the zone offset `day_offset_minutes` (so a time
// written with -07:00 gets the rise and set of that local day), as UTC Julian
// days; both rise and set are absent during polar day or night, which `polar`
// reports. Rise/transit/set always use SPA (independent of `algorithm`).
#pragma once

#include <optional>
#include <string>

namespace atmosh::atmo {

enum class SunAlgorithm { Spa, Fast, Grena3, Grena1 };  // Fast = Grena 2012 algorithm 5

// "spa", "fast" (also "grena5"), "grena3", "grena1"; InputError otherwise.
SunAlgorithm parse_sun_algorithm(const std::string& name);
std::string sun_algorithm_name(SunAlgorithm a);  // "spa", "fast", "grena3", "grena1"

enum class Polar { None, Day, Night };
// "day", "night" or "" for Polar::None.
std::string polar_name(Polar p);

struct SunQuery {
  double jd_utc = 2451545.0;
  // The place: validated as an atmo::Observer (observer.hpp: validate_observer).
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double height_m = 0.0;
  double pressure_hpa = 1013.25;
  double temperature_c = 15.0;
  std::optional<double> delta_t_s;  // default: delta_t_espenak_meeus(decimal year)
  double delta_ut1_s = 0.0;         // |x| <= 1
  SunAlgorithm algorithm = SunAlgorithm::Spa;
  bool rise_transit_set = true;     // skip for time series (3 extra SPA evaluations)
  int day_offset_minutes = 0;       // zone whose calendar day rise/transit/set refer to
};

// All fields of the `atmosh sun --json` contract (degrees, minutes, AU, UTC JD).
struct SunPosition {
  double zenith_deg = 0;             // geometric topocentric zenith
  double azimuth_deg = 0;            // from north towards east
  double elevation_deg = 0;          // 90 - zenith_deg
  double apparent_zenith_deg = 0;    // with refraction
  double apparent_elevation_deg = 0;
  double declination_deg = 0;        // geocentric apparent declination
  double hour_angle_deg = 0;         // geocentric local hour angle, (-180, 180]
  double equation_of_time_min = 0;
  double earth_sun_distance_au = 0;
  std::optional<double> sunrise_jd_utc, transit_jd_utc, sunset_jd_utc;
  Polar polar = Polar::None;
  double delta_t_s = 0;              // the ΔT actually used
  SunAlgorithm algorithm = SunAlgorithm::Spa;
};

// Validates every input (InputError naming the value) and computes the position.
SunPosition sun_position(const SunQuery& q);

}  // namespace atmosh::atmo
