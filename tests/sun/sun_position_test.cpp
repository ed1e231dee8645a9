// Sun position: extreme places, polar day/night, twilight, refraction, the fast
// algorithm and the observer geometry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <glm/geometric.hpp>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/sun_fast.hpp"
#include "atmosh/atmo/sun_position.hpp"
#include "atmosh/atmo/sun_refraction.hpp"
#include "atmosh/atmo/sun_series.hpp"
#include "atmosh/atmo/sun_spa.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"

using namespace atmosh::atmo;

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;

SunQuery at(const char* iso, double lat, double lon) {
  SunQuery q;
  const ParsedTime t = parse_iso8601(iso);
  q.jd_utc = t.jd_utc;
  q.day_offset_minutes = t.offset_minutes;
  q.latitude_deg = lat;
  q.longitude_deg = lon;
  return q;
}

bool all_finite(const SunPosition& s) {
  for (double v : {s.zenith_deg, s.azimuth_deg, s.elevation_deg, s.apparent_zenith_deg, s.apparent_elevation_deg,
                   s.declination_deg, s.hour_angle_deg, s.equation_of_time_min, s.earth_sun_distance_au})
    if (!std::isfinite(v)) return false;
  return true;
}
}  // namespace

TEST(SunPosition, WorkedExampleThroughPublicApi) {
  // Reda & Andreas 2008, Table A5.1 (see spa_worked_example_test.cpp): apparent
  // zenith 50.11162°, azimuth 194.34024°; geometric elevation e0 = 39.872046°
  // (pvlib test_spa.py).
  SunQuery q = at("2003-10-17T12:30:30-07:00", 39.742476, -105.1786);
  q.height_m = 1830.14;
  q.pressure_hpa = 820;
  q.temperature_c = 11;
  q.delta_t_s = 67.0;
  const SunPosition s = sun_position(q);
  EXPECT_NEAR(s.apparent_zenith_deg, 50.11162, 5e-6);
  EXPECT_NEAR(s.azimuth_deg, 194.34024, 5e-6);
  EXPECT_NEAR(s.elevation_deg, 39.872046, 5e-7);
  EXPECT_NEAR(s.declination_deg, -9.31434, 5e-6);
  EXPECT_NEAR(s.earth_sun_distance_au, 0.9965422974, 5e-11);
  // Rise and set of the local day (NREL spa_tester.c: 06:12:43 and 17:20:19 at -7 h).
  ASSERT_TRUE(s.sunrise_jd_utc && s.sunset_jd_utc && s.transit_jd_utc);
  EXPECT_EQ(format_iso8601_utc(*s.sunrise_jd_utc), "2003-10-17T13:12:43Z");
  EXPECT_EQ(format_iso8601_utc(*s.sunset_jd_utc), "2003-10-18T00:20:19Z");
  EXPECT_EQ(s.polar, Polar::None);
}

TEST(SunPosition, PolarDayAndNight) {
  // Closed form: with declination δ the sun never drops below h0' = -0.8333° at
  // latitude φ when φ > 90° - δ + h0' ... i.e. Longyearbyen (78.22°N) at the June
  // solstice (δ ≈ +23.44°) has polar day and at the December solstice polar night
  // (the sun stays below -0.83° when φ > 90° + δ − h0'... δ ≈ -23.44°).
  const SunPosition day = sun_position(at("2024-06-21T12:00:00Z", 78.2232, 15.6267));
  EXPECT_EQ(day.polar, Polar::Day);
  EXPECT_FALSE(day.sunrise_jd_utc.has_value());
  EXPECT_FALSE(day.sunset_jd_utc.has_value());
  EXPECT_TRUE(day.transit_jd_utc.has_value());
  EXPECT_GT(day.elevation_deg, 0.0);
  const SunPosition night = sun_position(at("2024-12-21T12:00:00Z", 78.2232, 15.6267));
  EXPECT_EQ(night.polar, Polar::Night);
  EXPECT_FALSE(night.sunrise_jd_utc.has_value());
  EXPECT_LT(night.elevation_deg, 0.0);
  EXPECT_EQ(polar_name(Polar::Day), "day");
  EXPECT_EQ(polar_name(Polar::Night), "night");
  // The same place at an equinox rises and sets.
  EXPECT_EQ(sun_position(at("2024-03-20T12:00:00Z", 78.2232, 15.6267)).polar, Polar::None);
}

TEST(SunPosition, LongitudesPlusMinus180Agree) {
  for (const char* t : {"2024-01-01T00:00:00Z", "2024-06-21T07:13:00Z", "1850-03-03T12:00:00Z"}) {
    for (double lat : {-60.0, 0.0, 45.0}) {
      const SunPosition a = sun_position(at(t, lat, -180.0));
      const SunPosition b = sun_position(at(t, lat, 180.0));
      EXPECT_NEAR(a.zenith_deg, b.zenith_deg, 1e-9);
      EXPECT_NEAR(std::remainder(a.azimuth_deg - b.azimuth_deg, 360.0), 0.0, 1e-9);
      EXPECT_NEAR(std::remainder(a.hour_angle_deg - b.hour_angle_deg, 360.0), 0.0, 1e-9);
    }
  }
}

TEST(SunPosition, Poles) {
  // At a pole the elevation equals the declination (closed form; the topocentric
  // parallax, ≤ 8.8 arcsec = 0.0025°, is the only difference).
  for (double lat : {90.0, -90.0}) {
    for (const char* t : {"2024-06-21T00:00:00Z", "2024-12-21T12:00:00Z", "2024-03-01T06:00:00Z"}) {
      const SunPosition s = sun_position(at(t, lat, 0.0));
      ASSERT_TRUE(all_finite(s));
      EXPECT_NEAR(s.elevation_deg, lat > 0 ? s.declination_deg : -s.declination_deg, 0.0026) << t << " " << lat;
    }
  }
}

TEST(SunPosition, TwilightIsFiniteAndContinuous) {
  // An evening in Paris from before sunset until after astronomical twilight
  // (elevation below -18°) at 30 s steps: the sun moves < 0.25°/min, so both
  // geometric and apparent elevation must change by < 0.15° per step.
  SunQuery q = at("2024-03-20T17:00:00Z", 48.8566, 2.3522);
  const double from = q.jd_utc, to = parse_iso8601("2024-03-20T21:30:00Z").jd_utc;
  const auto s = sun_series(q, from, to, 30.0);
  ASSERT_GT(s.size(), 500u);
  double min_el = 90.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const SunPosition& p = s[i].position;
    ASSERT_TRUE(all_finite(p));
    min_el = std::fmin(min_el, p.elevation_deg);
    EXPECT_GE(p.apparent_elevation_deg, p.elevation_deg - 1e-12);  // refraction lifts, never lowers
    if (i > 0) {
      EXPECT_LT(std::fabs(p.elevation_deg - s[i - 1].position.elevation_deg), 0.15);
      EXPECT_LT(std::fabs(p.apparent_elevation_deg - s[i - 1].position.apparent_elevation_deg), 0.15);
    }
  }
  EXPECT_LT(min_el, -18.0);  // astronomical twilight ends about 19:50 UT at the equinox
}

TEST(SunRefraction, FiniteContinuousMonotoneEverywhere) {
  // -90..90° in 1e-3° steps, standard and extreme air. The slope bound 0.35°/° (max 0.305 at -2.8° in standard air) is
  // far below the pole of Saemundsson's formula near -5.11° and the 0.57° jump
  // SPA's cut-off makes at -0.83°.
  for (auto [p, t] : {std::pair{1010.0, 10.0}, std::pair{1050.0, -40.0}, std::pair{300.0, 30.0}}) {
    double prev = refraction_deg(-90.0, p, t);
    for (int i = 1; i <= 180000; ++i) {
      const double h = -90.0 + i * 1e-3;
      const double r = refraction_deg(h, p, t);
      ASSERT_TRUE(std::isfinite(r)) << h;
      ASSERT_GE(r, -1e-4) << h;
      ASSERT_LT(r, 1.0) << h;
      ASSERT_LT(std::fabs(r - prev), 0.35 * 1e-3 * (p / 1010.0) * (283.0 / (273.0 + t)) + 1e-12) << h;
      // apparent elevation strictly increasing (no two geometric elevations map
      // to the same apparent one)
      ASSERT_GT(h + r, (h - 1e-3) + prev) << h;
      prev = r;
    }
  }
  EXPECT_EQ(refraction_deg(10.0, 0.0, 10.0), 0.0);  // vacuum
  EXPECT_THROW(refraction_deg(10.0, 1010.0, -280.0), atmosh::InputError);
}

TEST(SunRefraction, AgreesWithBennett) {
  // Bennett (1982), J. Navigation 35, 255; Meeus, Astronomical Algorithms (1998)
  // eq. 16.4: refraction from the APPARENT altitude h0, R = 1/tan(h0 + 7.31/(h0 +
  // 4.4)) arcmin at 1010 hPa, 10 °C. Meeus states Saemundsson's inverse form
  // agrees with it to about 0.1 arcmin; check above the horizon.
  for (double h = 0.0; h <= 89.0; h += 0.5) {
    const double r = refraction_deg(h, 1010.0, 10.0);
    const double ha = h + r;
    const double bennett_arcmin = 1.0 / std::tan((ha + 7.31 / (ha + 4.4)) * kDeg);
    EXPECT_NEAR(r * 60.0, bennett_arcmin, 0.15) << h;
  }
}

TEST(SunFast, WithinStatedAccuracyOverItsRange) {
  // Grena (2012), Table 2: algorithm 5 max error 0.0027° against SPA over
  // 2010–2110 (algorithm 3: 0.0093°, algorithm 1: 0.19°). Sampled at the range's
  // start, middle and end, five latitudes, 400 instants each. Measured here: the
  // year 2110 reaches 0.00283° (5% above the stated value; see docs/sun.md), so
  // the last year is held to the 0.003° of the target instead.
  for (int year : {2010, 2060, 2100, 2110}) {
    const auto rows = sun_accuracy_study(year, {-70.0, -30.0, 0.0, 40.0, 75.0}, 400);
    for (const auto& r : rows) {
      if (r.setting != "all") continue;
      if (r.method == "fast") {
        EXPECT_LE(r.error_max_deg, year < 2110 ? 0.0027 : 0.003) << year;
      }
      if (r.method == "grena3") {
        EXPECT_LE(r.error_max_deg, 0.0093) << year;
      }
      if (r.method == "grena1") {
        EXPECT_LE(r.error_max_deg, 0.19) << year;
      }
      if (r.method == "spa") {
        EXPECT_EQ(r.error_max_deg, 0.0);
      }
    }
  }
}

// Grena (2012), algorithm 5, written out as printed in the paper (section 3.5) with
// libm sines, arctangents and arcsines, in the paper's order: the reference for
// the inlined, rearranged evaluation of grena_position(5, ...) (fast sines, the
// angle-difference form of H, Taylor terms for the small angles, a polynomial
// arctangent), which must agree with it to rounding, far below the algorithm's
// own 0.0027°.
GrenaResult grena5_as_printed(double jd_ut, double delta_t_s, double lat_deg, double lon_deg) {
  const double pi = 3.14159265358979323846;
  const double t = jd_ut - 2473459.5, te = t + 1.1574e-5 * delta_t_s;
  const double w = 0.0172019715 * te;
  const double L = 1.7527901 + 1.7202792159e-2 * te + 3.33024e-2 * std::sin(w) - 2.0582e-3 * std::cos(w) +
                   3.512e-4 * std::sin(2 * w) - 4.07e-5 * std::cos(2 * w) + 5.2e-6 * std::sin(3 * w) -
                   9e-7 * std::cos(3 * w) - 8.23e-5 * std::sin(w) * std::sin(2.92e-5 * te) +
                   1.27e-5 * std::sin(1.49e-3 * te - 2.337) + 1.21e-5 * std::sin(4.31e-3 * te + 3.065) +
                   2.33e-5 * std::sin(1.076e-2 * te - 1.533) + 3.49e-5 * std::sin(1.575e-2 * te - 2.358) +
                   2.67e-5 * std::sin(2.152e-2 * te + 0.074) + 1.28e-5 * std::sin(3.152e-2 * te + 1.547) +
                   3.14e-5 * std::sin(2.1277e-1 * te - 0.488);
  const double nu = 9.282e-4 * te - 0.8;
  const double dlam = 8.34e-5 * std::sin(nu);
  const double lambda = L + pi + dlam;
  const double eps = 4.089567e-1 - 6.19e-9 * te + 4.46e-5 * std::cos(nu);
  double alpha = std::atan2(std::sin(lambda) * std::cos(eps), std::cos(lambda));
  if (alpha < 0) alpha += 2 * pi;
  const double delta = std::asin(std::sin(lambda) * std::sin(eps));
  const double H = std::remainder(1.7528311 + 6.300388099 * t + lon_deg * kDeg - alpha + 0.92 * dlam, 2 * pi);
  const double phi = lat_deg * kDeg;
  const double e0 = std::asin(std::sin(phi) * std::sin(delta) + std::cos(phi) * std::cos(delta) * std::cos(H));
  const double ep = e0 - 4.26e-5 * std::cos(e0);
  const double gamma =
      std::atan2(std::sin(H), std::cos(H) * std::sin(phi) - std::tan(delta) * std::cos(phi));  // from south
  GrenaResult r;
  r.zenith_deg = 90.0 - ep / kDeg;
  r.azimuth_deg = std::fmod(gamma / kDeg + 180.0, 360.0);
  r.declination_deg = delta / kDeg;
  r.hour_angle_deg = H / kDeg;
  r.right_ascension_deg = alpha / kDeg;
  return r;
}

double angle_diff_deg(double a, double b) { return std::fabs(std::remainder(a - b, 360.0)); }

TEST(SunFast, InlinedAlgorithm5MatchesThePrintedFormulas) {
  // 2010..2110 every 37.1 days x 7 latitudes x 5 longitudes (hours cycle with the
  // fraction of the day). Bound 5e-9 degrees (9e-11 rad): the inlined sines are
  // good to 6e-12 rad each (20 of them), the arctangent to 1e-12 rad.
  constexpr double kTol = 5e-9;
  const double jd0 = parse_iso8601("2010-01-01T00:00:00Z").jd_utc;
  const double jd1 = parse_iso8601("2110-12-31T00:00:00Z").jd_utc;
  double worst = 0.0;
  int n = 0;
  for (double jd = jd0; jd < jd1; jd += 37.1234)
    for (double lat : {-89.9, -60.0, -23.0, 0.0, 35.0, 66.6, 89.9})
      for (double lon : {-180.0, -75.5, 0.0, 100.25, 180.0}) {
        const GrenaResult a = grena_position(5, jd, 69.0, lat, lon);
        const GrenaResult b = grena5_as_printed(jd, 69.0, lat, lon);
        ASSERT_TRUE(std::isfinite(a.zenith_deg) && std::isfinite(a.azimuth_deg));
        // Near the zenith, the elevation from its sine (both evaluations) amplifies the
        // sine's error by 1 / sin(zenith): weight by it (as the azimuth below).
        const double sz = std::max(std::sin(b.zenith_deg * kDeg), 1e-3);
        EXPECT_LE(std::fabs(a.zenith_deg - b.zenith_deg) * sz, kTol) << jd << " " << lat << " " << lon;
        EXPECT_NEAR(a.declination_deg, b.declination_deg, kTol);
        EXPECT_LE(angle_diff_deg(a.hour_angle_deg, b.hour_angle_deg), kTol);
        EXPECT_LE(angle_diff_deg(a.right_ascension_deg, b.right_ascension_deg), kTol);
        // The azimuth is ill-conditioned at the zenith; weight it the same way.
        EXPECT_LE(angle_diff_deg(a.azimuth_deg, b.azimuth_deg) * sz, kTol)
            << jd << " " << lat << " " << lon;
        EXPECT_GE(a.azimuth_deg, 0.0);
        EXPECT_LT(a.azimuth_deg, 360.0);
        EXPECT_GE(a.right_ascension_deg, 0.0);
        EXPECT_LT(a.right_ascension_deg, 360.0);
        worst = std::max(worst, std::fabs(a.zenith_deg - b.zenith_deg) * sz);
        ++n;
      }
  EXPECT_GT(n, 30000);
  RecordProperty("max_zenith_difference_deg", std::to_string(worst));
  std::printf("algorithm 5, inlined vs printed formulas: max zenith difference x sin(zenith) %.3g deg over %d points\n", worst, n);
}

TEST(SunFast, RangeEnforced) {
  SunQuery q = at("2009-12-31T23:59:59Z", 10.0, 10.0);
  q.algorithm = SunAlgorithm::Fast;
  EXPECT_THROW(sun_position(q), atmosh::InputError);
  q.jd_utc = parse_iso8601("2111-01-01T00:00:00Z").jd_utc;
  EXPECT_THROW(sun_position(q), atmosh::InputError);
  q.jd_utc = parse_iso8601("2110-12-31T23:00:00Z").jd_utc;
  EXPECT_NO_THROW(sun_position(q));
  EXPECT_EQ(parse_sun_algorithm("fast"), SunAlgorithm::Fast);
  EXPECT_THROW(parse_sun_algorithm("psa"), atmosh::InputError);
}

TEST(SunPosition, RejectsBadInput) {
  EXPECT_THROW(sun_position(at("2024-01-01T00:00Z", 91.0, 0.0)), atmosh::InputError);
  EXPECT_THROW(sun_position(at("2024-01-01T00:00Z", 0.0, 180.5)), atmosh::InputError);
  SunQuery q = at("2024-01-01T00:00Z", 0.0, 0.0);
  q.delta_ut1_s = 1.5;
  EXPECT_THROW(sun_position(q), atmosh::InputError);
  q.delta_ut1_s = 0.0;
  q.pressure_hpa = std::nan("");
  EXPECT_THROW(sun_position(q), atmosh::InputError);
  // Range ends of SPA are accepted and finite.
  EXPECT_TRUE(all_finite(sun_position(at("-2000-01-01T00:00:00Z", 30.0, 30.0))));
  EXPECT_TRUE(all_finite(sun_position(at("6000-12-31T23:00:00Z", -30.0, -30.0))));
}

TEST(SunPosition, DefaultDeltaTIsTheModel) {
  const SunPosition s = sun_position(at("2017-06-15T00:00:00Z", 0.0, 0.0));
  EXPECT_NEAR(s.delta_t_s, delta_t_espenak_meeus(decimal_year(parse_iso8601("2017-06-15T00:00:00Z").jd_utc)), 1e-12);
  // One second of ΔT moves the sun by at most 15 arcsec (Earth rotation rate).
  SunQuery a = at("2017-06-15T09:00:00Z", 40.0, 0.0), b = a;
  a.delta_t_s = 69.0;
  b.delta_t_s = 70.0;
  const double d = std::fabs(sun_position(a).azimuth_deg - sun_position(b).azimuth_deg) +
                   std::fabs(sun_position(a).zenith_deg - sun_position(b).zenith_deg);
  EXPECT_LT(d, 2.0 * 15.0 / 3600.0);
}

TEST(Observer, Wgs84Geometry) {
  // WGS84 defining constants (NIMA TR8350.2): a = 6378137 m, b = 6356752.314245 m.
  const glm::dvec3 p0 = observer_ecef_m({0.0, 0.0, 0.0});
  EXPECT_NEAR(p0.x, 6378137.0, 1e-6);
  EXPECT_NEAR(p0.y, 0.0, 1e-6);
  const glm::dvec3 pn = observer_ecef_m({90.0, 0.0, 100.0});
  EXPECT_NEAR(pn.z, 6356752.314245 + 100.0, 1e-5);
  EXPECT_NEAR(geocentric_radius_m({90.0, 33.0, 0.0}), 6356752.314245, 1e-5);
  // Up is the geodetic normal (cos φ cos λ, cos φ sin λ, sin φ); a point 100 m
  // straight up is at ENU (0, 0, 100).
  const Observer o{48.8566, 2.3522, 35.0};
  glm::dvec3 e, n, u;
  enu_axes_ecef(o, e, n, u);
  const double phi = o.latitude_deg * kDeg, lam = o.longitude_deg * kDeg;
  EXPECT_NEAR(u.x, std::cos(phi) * std::cos(lam), 1e-14);
  EXPECT_NEAR(u.y, std::cos(phi) * std::sin(lam), 1e-14);
  EXPECT_NEAR(u.z, std::sin(phi), 1e-14);
  EXPECT_NEAR(e.x * n.x + e.y * n.y + e.z * n.z, 0.0, 1e-15);
  const glm::dvec3 above = ecef_to_enu_m(o, observer_ecef_m({o.latitude_deg, o.longitude_deg, 135.0}));
  EXPECT_NEAR(above.x, 0.0, 1e-6);
  EXPECT_NEAR(above.y, 0.0, 1e-6);
  EXPECT_NEAR(above.z, 100.0, 1e-6);
  // Directions: zenith is +z, azimuth 90° on the horizon is east.
  const glm::dvec3 z = enu_direction_from_zenith(0.0, 123.0), east = enu_direction_from_zenith(90.0, 90.0);
  EXPECT_NEAR(z.z, 1.0, 1e-15);
  EXPECT_NEAR(east.x, 1.0, 1e-15);
  EXPECT_NEAR(east.y, 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(observer_radius_in_atmosphere_m(o, 6360e3), 6360e3 + 35.0);
  EXPECT_THROW(observer_ecef_m({95.0, 0.0, 0.0}), atmosh::InputError);
}

// One place type, one validation (observer.hpp): the Dead Sea shore, about 430 m below
// sea level (the lowest dry land), is a valid place; -12 km (below the deepest ocean
// floor, formerly accepted by the library) is not, for the observer and for the sun's
// query alike; the ends of the range are inclusive.
TEST(Observer, OneHeightRangeForEveryEntryPoint) {
  EXPECT_NO_THROW(validate_observer({31.5, 35.5, -430.0}));
  EXPECT_NO_THROW(validate_observer({0.0, 0.0, kObserverMinHeightM}));
  EXPECT_NO_THROW(validate_observer({0.0, 0.0, kObserverMaxHeightM}));
  EXPECT_EQ(kObserverMinHeightM, -500.0);
  for (double h : {-500.5, -12000.0, 1.0e8 * 1.0001}) {
    try {
      validate_observer({0.0, 0.0, h});
      ADD_FAILURE() << "accepted height " << h;
    } catch (const atmosh::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("height"), std::string::npos) << e.what();
    }
    SunQuery q = at("2020-06-21T12:00:00Z", 0.0, 0.0);
    q.height_m = h;
    EXPECT_THROW(sun_position(q), atmosh::InputError) << h;
  }
  SunQuery dead_sea = at("2020-06-21T12:00:00Z", 31.5, 35.5);
  dead_sea.height_m = -430.0;
  EXPECT_NO_THROW(sun_position(dead_sea));
}

// enu_direction (elevation) and enu_direction_from_zenith (zenith) are the same vector.
TEST(Observer, EnuDirectionFromElevationOrZenith) {
  for (double el : {-90.0, -12.5, 0.0, 7.0, 45.0, 89.0, 90.0})
    for (double az : {0.0, 33.0, 180.0, 271.5}) {
      const glm::dvec3 a = enu_direction(el, az), b = enu_direction_from_zenith(90.0 - el, az);
      EXPECT_NEAR(a.x, b.x, 1e-15);
      EXPECT_NEAR(a.y, b.y, 1e-15);
      EXPECT_NEAR(a.z, b.z, 1e-15);
      EXPECT_NEAR(glm::length(a), 1.0, 1e-15);
    }
  EXPECT_THROW(enu_direction(std::nan(""), 0.0), atmosh::InputError);
}

TEST(Observer, SunDirectionMatchesEquatorialRotation) {
  // Independent route to the worked example's direction: build the topocentric
  // equatorial unit vector from α', δ' and the Greenwich hour angle in ECEF,
  // project on GeographicLib's ENU axes, and compare with SPA's e0 and Φ.
  SpaInput in;
  in.jd_utc = parse_iso8601("2003-10-17T12:30:30-07:00").jd_utc;
  in.delta_t_s = 67.0;
  in.latitude_deg = 39.742476;
  in.longitude_deg = -105.1786;
  in.elevation_m = 1830.14;
  const SpaResult r = spa_compute(in);
  const double gha = (r.h_prime_deg - in.longitude_deg) * kDeg, dec = r.delta_prime_deg * kDeg;
  const glm::dvec3 d{std::cos(dec) * std::cos(gha), -std::cos(dec) * std::sin(gha), std::sin(dec)};
  glm::dvec3 e, n, u;
  enu_axes_ecef({in.latitude_deg, in.longitude_deg, in.elevation_m}, e, n, u);
  const glm::dvec3 enu{glm::dot(d, e), glm::dot(d, n), glm::dot(d, u)};
  const glm::dvec3 spa = enu_direction_from_zenith(90.0 - r.e0_deg, r.azimuth_deg);
  EXPECT_NEAR(enu.x, spa.x, 1e-12);
  EXPECT_NEAR(enu.y, spa.y, 1e-12);
  EXPECT_NEAR(enu.z, spa.z, 1e-12);
}
