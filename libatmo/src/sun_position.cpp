// sun_position.cpp — dispatch over SPA / Grena, refraction and rise-set.
#include "atmosh/atmo/sun_position.hpp"

#include <cmath>
#include <string>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/sun_fast.hpp"
#include "atmosh/atmo/sun_refraction.hpp"
#include "atmosh/atmo/sun_spa.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/format.hpp"

namespace atmosh::atmo {
namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

double wrap180(double x) {
  x = std::remainder(x, 360.0);
  return x <= -180.0 ? x + 360.0 : x;
}

std::string num(double v) { return atmosh::format_double(v); }

void validate(const SunQuery& q) {
  auto finite = [](double v, const std::string& what) {
    if (!std::isfinite(v)) throw InputError(what + " is not finite");
  };
  finite(q.latitude_deg, "latitude");
  finite(q.longitude_deg, "longitude");
  finite(q.height_m, "height");
  finite(q.pressure_hpa, "pressure");
  finite(q.temperature_c, "temperature");
  finite(q.delta_ut1_s, "UT1-UTC");
  validate_observer(Observer{q.latitude_deg, q.longitude_deg, q.height_m});  // the one rule for a place
  if (q.pressure_hpa < 0.0 || q.pressure_hpa > 5000.0)
    throw InputError("pressure " + num(q.pressure_hpa) + " hPa is outside 0..5000");
  if (q.temperature_c <= -273.0 || q.temperature_c > 6000.0)
    throw InputError("temperature " + num(q.temperature_c) + " C is outside -273..6000");
  if (std::fabs(q.delta_ut1_s) > 1.0)
    throw InputError("UT1-UTC " + num(q.delta_ut1_s) + " s is outside -1..1 (|UT1-UTC| < 0.9 s by definition)");
  if (q.delta_t_s && (!std::isfinite(*q.delta_t_s) || std::fabs(*q.delta_t_s) > 1.0e6))
    throw InputError("delta T " + num(*q.delta_t_s) + " s is outside -1e6..1e6");
  if (std::abs(q.day_offset_minutes) > 18 * 60)
    throw InputError("zone offset " + std::to_string(q.day_offset_minutes) + " min is beyond 18 h");
  if (!sun_year_in_range(q.jd_utc)) require_sun_year_range(q.jd_utc, "time");
}
}  // namespace

SunAlgorithm parse_sun_algorithm(const std::string& name) {
  if (name == "spa") return SunAlgorithm::Spa;
  if (name == "fast" || name == "grena5") return SunAlgorithm::Fast;
  if (name == "grena3") return SunAlgorithm::Grena3;
  if (name == "grena1") return SunAlgorithm::Grena1;
  throw InputError("algorithm '" + name + "' is unknown (use spa, fast, grena3 or grena1)");
}

std::string sun_algorithm_name(SunAlgorithm a) {
  switch (a) {
    case SunAlgorithm::Spa: return "spa";
    case SunAlgorithm::Fast: return "fast";
    case SunAlgorithm::Grena3: return "grena3";
    case SunAlgorithm::Grena1: return "grena1";
  }
  return "spa";
}

std::string polar_name(Polar p) {
  switch (p) {
    case Polar::Day: return "day";
    case Polar::Night: return "night";
    default: return "";
  }
}

SunPosition sun_position(const SunQuery& q) {
  validate(q);
  SunPosition out;
  out.algorithm = q.algorithm;
  out.delta_t_s = q.delta_t_s ? *q.delta_t_s : delta_t_espenak_meeus(decimal_year(q.jd_utc));

  if (q.algorithm == SunAlgorithm::Spa) {
    SpaInput in;
    in.jd_utc = q.jd_utc;
    in.delta_ut1_s = q.delta_ut1_s;
    in.delta_t_s = out.delta_t_s;
    in.latitude_deg = q.latitude_deg;
    in.longitude_deg = q.longitude_deg;
    in.elevation_m = q.height_m;
    in.pressure_hpa = q.pressure_hpa;
    in.temperature_c = q.temperature_c;
    const SpaResult r = spa_compute(in);
    out.zenith_deg = 90.0 - r.e0_deg;
    out.azimuth_deg = r.azimuth_deg;
    out.declination_deg = r.geo.delta_deg;
    out.hour_angle_deg = wrap180(r.h_deg);
    out.equation_of_time_min = r.eot_min;
    out.earth_sun_distance_au = r.geo.r_au;
  } else {
    const int variant = q.algorithm == SunAlgorithm::Fast ? 5 : q.algorithm == SunAlgorithm::Grena3 ? 3 : 1;
    const double jd_ut = q.jd_utc + q.delta_ut1_s / 86400.0;
    const GrenaResult g = grena_position(variant, jd_ut, out.delta_t_s, q.latitude_deg, q.longitude_deg);
    out.zenith_deg = g.zenith_deg;
    out.azimuth_deg = g.azimuth_deg;
    out.declination_deg = g.declination_deg;
    out.hour_angle_deg = wrap180(g.hour_angle_deg);
    // Equation of time = apparent solar hour angle − mean solar hour angle, where
    // the mean sun's hour angle is 15°/h·(UT − 12 h) + longitude.
    const double ut_h = (jd_ut - 0.5 - std::floor(jd_ut - 0.5)) * 24.0;
    out.equation_of_time_min = 4.0 * wrap180(g.hour_angle_deg - (15.0 * (ut_h - 12.0) + q.longitude_deg));
    // Earth–Sun distance from the sun's mean anomaly g (Astronomical Almanac,
    // low-precision formulae, section C: R = 1.00014 − 0.01671 cos g − 0.00014
    // cos 2g AU, error ~1e-5 AU over 1950–2050).
    const double n = jd_ut - 2451545.0;
    const double gm = (357.528 + 0.9856003 * n) * kDeg;
    out.earth_sun_distance_au = 1.00014 - 0.01671 * std::cos(gm) - 0.00014 * std::cos(2.0 * gm);
  }
  out.elevation_deg = 90.0 - out.zenith_deg;
  out.apparent_elevation_deg = apparent_elevation_deg(out.elevation_deg, q.pressure_hpa, q.temperature_c);
  out.apparent_zenith_deg = 90.0 - out.apparent_elevation_deg;

  if (q.rise_transit_set) {
    const double jd_local = q.jd_utc + q.day_offset_minutes / 1440.0;
    const CalendarTime day = calendar_from_julian_day(jd_local);
    const double offset_h = q.day_offset_minutes / 60.0;
    const SpaRiseTransitSet rts = spa_rise_transit_set(day.year, day.month, day.day, offset_h, q.latitude_deg,
                                                       q.longitude_deg, out.delta_t_s, q.delta_ut1_s);
    // Local midnight of that day, as a UTC Julian day.
    const double midnight_utc = julian_day(CalendarTime{day.year, day.month, day.day, 0, 0, 0.0}) - offset_h / 24.0;
    out.transit_jd_utc = midnight_utc + rts.transit_day_fraction;
    if (rts.polar == 0) {
      out.sunrise_jd_utc = midnight_utc + rts.rise_day_fraction;
      out.sunset_jd_utc = midnight_utc + rts.set_day_fraction;
    } else {
      out.polar = rts.polar > 0 ? Polar::Day : Polar::Night;
    }
  }
  return out;
}

}  // namespace atmosh::atmo
