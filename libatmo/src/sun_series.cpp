// sun_series.cpp — time series and the accuracy study; see sun_series.hpp.
#include "atmosh/atmo/sun_series.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/sun_fast.hpp"
#include "atmosh/atmo/sun_spa.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"

namespace atmosh::atmo {

std::vector<SunSample> sun_series(const SunQuery& base, double jd_from, double jd_to, double step_s,
                                  std::size_t max_samples) {
  if (!std::isfinite(jd_from) || !std::isfinite(jd_to)) throw InputError("time range: non-finite time");
  if (jd_to < jd_from)
    throw InputError("time range: --to " + format_iso8601_utc(jd_to) + " is before --from " + format_iso8601_utc(jd_from));
  if (!std::isfinite(step_s) || step_s <= 0.0) throw InputError("time range: step must be positive");
  const double span_s = (jd_to - jd_from) * 86400.0;
  // A Julian day near 2.46e6 carries ~40 microseconds of rounding, so a span that is
  // a whole number of steps may come out a hair short (2 s / 0.5 s = 3.9998...):
  // allow 0.2 ms before dropping the `to` endpoint.
  const double tol_steps = std::min(0.5, 2e-4 / step_s + 1e-6);
  const double count = std::floor(span_s / step_s + tol_steps) + 1.0;
  if (count > static_cast<double>(max_samples)) {
    char b[160];
    std::snprintf(b, sizeof b, "time range: %.0f samples exceed the limit of %zu; use a larger --step", count,
                  max_samples);
    throw InputError(b);
  }
  require_sun_year_range(jd_from, "--from");
  require_sun_year_range(jd_to, "--to");
  std::vector<SunSample> out;
  out.reserve(static_cast<std::size_t>(count));
  SunQuery q = base;
  q.rise_transit_set = false;
  for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i) {
    SunSample s;
    s.jd_utc = jd_from + static_cast<double>(i) * step_s / 86400.0;
    if (i + 1 == static_cast<std::size_t>(count) && std::fabs(s.jd_utc - jd_to) * 86400.0 < 2e-4)
      s.jd_utc = jd_to;  // the endpoint exactly, not 40 microseconds off
    q.jd_utc = s.jd_utc;
    s.position = sun_position(q);
    const glm::dvec3 d = enu_direction_from_zenith(s.position.zenith_deg, s.position.azimuth_deg);
    s.east = d.x;
    s.north = d.y;
    s.up = d.z;
    out.push_back(s);
  }
  return out;
}

namespace {
double separation_deg(double z1, double a1, double z2, double a2) {
  const glm::dvec3 u = enu_direction_from_zenith(z1, a1), v = enu_direction_from_zenith(z2, a2);
  const glm::dvec3 c{u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
  const double s = std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
  const double d = u.x * v.x + u.y * v.y + u.z * v.z;
  return std::atan2(s, d) * 180.0 / 3.14159265358979323846;
}
}  // namespace

std::vector<SunAccuracyRow> sun_accuracy_study(int year, const std::vector<double>& latitudes_deg,
                                               std::size_t samples_per_latitude) {
  if (samples_per_latitude < 1 || samples_per_latitude > 10000000)
    throw InputError("accuracy study: samples per latitude " + std::to_string(samples_per_latitude) +
                     " is outside 1..1e7");
  if (latitudes_deg.empty()) throw InputError("accuracy study: no latitudes");
  const bool grena_ok = year >= 2010 && year <= 2110;
  if (year < kMinSunYear || year > kMaxSunYear)
    throw InputError("accuracy study: year " + std::to_string(year) + " is outside -2000..6000");
  const double jd0 = julian_day(CalendarTime{year, 1, 1, 0, 0, 0.0});
  const double days = julian_day(CalendarTime{year + 1, 1, 1, 0, 0, 0.0}) - jd0;
  const double dt = delta_t_espenak_meeus(year + 0.5);
  const std::size_t n = samples_per_latitude;

  std::vector<SunAlgorithm> methods = {SunAlgorithm::Spa};
  if (grena_ok) methods.insert(methods.end(), {SunAlgorithm::Fast, SunAlgorithm::Grena3, SunAlgorithm::Grena1});

  // Inputs and SPA reference, per latitude.
  struct Point {
    double jd, lon, z_ref, a_ref;
  };
  std::vector<std::vector<Point>> pts(latitudes_deg.size());
  for (std::size_t li = 0; li < latitudes_deg.size(); ++li) {
    pts[li].resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      Point& p = pts[li][i];
      p.jd = jd0 + (static_cast<double>(i) + 0.5) * days / static_cast<double>(n) + 0.1234567 * (i % 13) / 13.0;
      if (p.jd >= jd0 + days) p.jd -= days;
      p.lon = std::fmod(static_cast<double>(i) * 137.50776405003785, 360.0) - 180.0;
    }
  }
  std::vector<SunAccuracyRow> rows;
  std::vector<std::vector<std::pair<double, double>>> ref(latitudes_deg.size());
  for (SunAlgorithm m : methods) {
    double all_max = 0.0, all_sq = 0.0, all_time = 0.0;
    std::size_t all_n = 0;
    for (std::size_t li = 0; li < latitudes_deg.size(); ++li) {
      std::vector<std::pair<double, double>> za(n);
      const double lat = latitudes_deg[li];
      const int variant = m == SunAlgorithm::Fast ? 5 : m == SunAlgorithm::Grena3 ? 3 : 1;
      SpaInput in;
      in.delta_t_s = dt;
      in.latitude_deg = lat;
      in.pressure_hpa = 0.0;  // geometric directions only
      const auto t0 = std::chrono::steady_clock::now();
      for (std::size_t i = 0; i < n; ++i) {
        if (m == SunAlgorithm::Spa) {
          in.jd_utc = pts[li][i].jd;
          in.longitude_deg = pts[li][i].lon;
          const SpaResult r = spa_compute(in);
          za[i] = {90.0 - r.e0_deg, r.azimuth_deg};
        } else {
          const GrenaResult g = grena_position(variant, pts[li][i].jd, dt, lat, pts[li][i].lon);
          za[i] = {g.zenith_deg, g.azimuth_deg};
        }
      }
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (m == SunAlgorithm::Spa) ref[li] = za;
      double mx = 0.0, sq = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const double e = separation_deg(za[i].first, za[i].second, ref[li][i].first, ref[li][i].second);
        mx = std::fmax(mx, e);
        sq += e * e;
      }
      SunAccuracyRow r;
      r.method = sun_algorithm_name(m);
      char b[32];
      std::snprintf(b, sizeof b, "lat=%g", latitudes_deg[li]);
      r.setting = b;
      r.error_max_deg = mx;
      r.error_rms_deg = std::sqrt(sq / static_cast<double>(n));
      r.time_s = secs / static_cast<double>(n);
      r.samples = n;
      rows.push_back(r);
      all_max = std::fmax(all_max, mx);
      all_sq += sq;
      all_time += secs;
      all_n += n;
    }
    SunAccuracyRow r;
    r.method = sun_algorithm_name(m);
    r.setting = "all";
    r.error_max_deg = all_max;
    r.error_rms_deg = std::sqrt(all_sq / static_cast<double>(all_n));
    r.time_s = all_time / static_cast<double>(all_n);
    r.samples = all_n;
    rows.push_back(r);
  }
  return rows;
}

}  // namespace atmosh::atmo
