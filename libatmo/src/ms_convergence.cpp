// Error against run time of the sky's scattering methods against the Monte-Carlo
// reference (ms_convergence.hpp).
#include "atmosh/atmo/ms_convergence.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/colour.hpp"
#include "atmosh/error.hpp"

namespace atmosh::atmo {

std::vector<MsStudySetting> ms_study_default_settings(bool quick) {
  std::vector<MsStudySetting> out;
  MultipleScatteringOptions single;
  single.method = ScatteringMethod::Single;
  out.push_back({"single", "-", single});
  auto approx = [&](int alt, int sun, int zen, int az, int steps) {
    MultipleScatteringOptions o;
    o.method = ScatteringMethod::Approximate;
    o.ms_altitudes = alt;
    o.ms_sun_directions = sun;
    o.ms_zenith_directions = zen;
    o.ms_azimuth_directions = az;
    o.ms_ray_steps = steps;
    out.push_back({"approximate", "altitudes=" + std::to_string(alt) + " sun=" + std::to_string(sun) +
                                      " zenith=" + std::to_string(zen) + " azimuth=" + std::to_string(az) +
                                      " steps=" + std::to_string(steps),
                   o});
  };
  const MultipleScatteringOptions d;
  if (quick) {
    approx(8, 16, 8, 4, 16);
    approx(16, 32, d.ms_zenith_directions, d.ms_azimuth_directions, d.ms_ray_steps);
    return out;
  }
  approx(8, 16, 8, 4, 16);
  approx(16, 32, d.ms_zenith_directions, d.ms_azimuth_directions, d.ms_ray_steps);
  approx(d.ms_altitudes, d.ms_sun_directions, d.ms_zenith_directions, d.ms_azimuth_directions, d.ms_ray_steps);
  approx(64, 128, d.ms_zenith_directions, d.ms_azimuth_directions, d.ms_ray_steps);
  approx(d.ms_altitudes, d.ms_sun_directions, 2 * d.ms_zenith_directions, 2 * d.ms_azimuth_directions,
         2 * d.ms_ray_steps);
  auto orders = [&](int n, int radii, int view, int sun, int az, int steps = 0) {
    MultipleScatteringOptions o;
    o.method = ScatteringMethod::Orders;
    o.orders = n;
    o.orders_radii = radii;
    o.orders_view_directions = view;
    o.orders_sun_directions = sun;
    o.orders_azimuths = az;
    if (steps > 0) o.orders_ray_steps = steps;
    out.push_back({"orders", "N=" + std::to_string(n) + " radii=" + std::to_string(radii) + " view=" +
                                 std::to_string(view) + " sun=" + std::to_string(sun) + " azimuths=" +
                                 std::to_string(az) + (steps > 0 ? " steps=" + std::to_string(steps) : ""),
                   o});
  };
  for (int n : {2, 3, 4, 5, 6, 8})
    orders(n, d.orders_radii, d.orders_view_directions, d.orders_sun_directions, d.orders_azimuths);
  orders(d.orders, d.orders_radii / 2, d.orders_view_directions / 2, d.orders_sun_directions / 2,
         d.orders_azimuths / 2);  // half the default in every dimension
  // Each table dimension doubled alone (the twilight diagnosis of docs/sky.md, "Multiple
  // scattering": which axis moves the error at sun -9 and -12 deg).
  orders(d.orders, 2 * d.orders_radii, d.orders_view_directions, d.orders_sun_directions, d.orders_azimuths);
  orders(d.orders, d.orders_radii, 2 * d.orders_view_directions, d.orders_sun_directions, d.orders_azimuths);
  orders(d.orders, d.orders_radii, d.orders_view_directions, 2 * d.orders_sun_directions, d.orders_azimuths);
  orders(d.orders, d.orders_radii, d.orders_view_directions, d.orders_sun_directions, d.orders_azimuths,
         2 * d.orders_ray_steps);
  return out;
}

const char* ms_study_band(double sun_elevation_deg) {
  if (sun_elevation_deg >= 0) return "day";
  if (sun_elevation_deg >= -6) return "civil";
  return "night";
}

MsStudyResult ms_convergence_study(const Atmosphere& atmosphere, const SolarSpectrum& solar,
                                   const MsStudyOptions& o) {
  if (o.views.empty()) throw InputError("converge ms: no view directions");
  if (o.sun_elevations_deg.empty()) throw InputError("converge ms: no sun elevations");
  if (o.settings.empty()) throw InputError("converge ms: no settings");
  if (o.timing_repetitions < 1)
    throw InputError("converge ms: timing repetitions " + std::to_string(o.timing_repetitions) + " < 1");
  if (o.reference_run.paths < 1)
    throw InputError("converge ms: paths " + std::to_string(o.reference_run.paths) + " < 1");
  for (const auto& s : o.settings) validate(s.scattering);
  for (double e : o.sun_elevations_deg)
    if (!std::isfinite(e) || e < -90 || e > 90) throw InputError("converge ms: sun elevation out of [-90, 90]");

  using clock = std::chrono::steady_clock;
  MsStudyResult res;
  // Reference.
  RtSkyOptions ro = o.reference;
  ro.run = o.reference_run;
  const MonteCarloSky mc(atmosphere, solar, ro);
  const auto t0 = clock::now();
  const auto ref = rt_reference_views(mc, o.views, o.sun_elevations_deg, o.altitude_m, o.reference_run);
  res.reference_time_s = std::chrono::duration<double>(clock::now() - t0).count();
  res.reference_paths_per_row = o.reference_run.paths;
  for (const auto& r : ref) {
    MsStudyPoint p;
    p.sun_elevation_deg = r.sun_elevation_deg;
    p.view_elevation_deg = r.view_elevation_deg;
    p.view_relative_azimuth_deg = r.view_relative_azimuth_deg;
    p.reference_luminance = r.result.luminance;
    p.reference_luminance_stderr = r.result.luminance_stderr;
    res.points.push_back(p);
  }

  // The same directions as the reference (rt_reference_views: sun at azimuth 180 deg).
  std::vector<glm::dvec3> views, suns;
  for (const auto& p : res.points) {
    views.push_back(enu_direction(p.view_elevation_deg, 180.0 + p.view_relative_azimuth_deg));
    suns.push_back(enu_direction(p.sun_elevation_deg, 180.0));
  }
  const SpectralToXyz to_xyz(atmosphere.wavelengths_nm());
  const std::size_t nw = atmosphere.wavelengths_nm().size();

  for (const auto& st : o.settings) {
    SkyOptions so = o.sky;
    so.scattering = st.scattering;
    double best_total = std::numeric_limits<double>::infinity(), best_build = 0, best_eval = 0;
    std::vector<double> lum(res.points.size(), 0.0);
    std::vector<double> L(nw);
    for (int rep = 0; rep < o.timing_repetitions; ++rep) {
      const auto b0 = clock::now();
      const SkyIntegrator sky(atmosphere, solar, so);
      const auto b1 = clock::now();
      for (std::size_t i = 0; i < res.points.size(); ++i) {
        sky.radiance(o.altitude_m, views[i], suns[i], L.data());
        lum[i] = to_xyz(L).Y;
      }
      const auto b2 = clock::now();
      const double build = std::chrono::duration<double>(b1 - b0).count();
      const double eval = std::chrono::duration<double>(b2 - b1).count();
      if (build + eval < best_total) {
        best_total = build + eval;
        best_build = build;
        best_eval = eval;
      }
      if (build + eval > 2.0) break;  // long builds: one run (the clock's noise is small against them)
    }
    for (std::size_t i = 0; i < res.points.size(); ++i) res.points[i].luminance.push_back(lum[i]);

    for (const char* band : {"all", "day", "civil", "night"}) {
      MsStudyRow row;
      row.method = st.method;
      row.setting = st.setting;
      row.band = band;
      row.time_s = best_total;
      row.build_time_s = best_build;
      row.eval_time_s = best_eval;
      double sum2 = 0;
      int n_band = 0;
      for (std::size_t i = 0; i < res.points.size(); ++i) {
        const auto& p = res.points[i];
        if (row.band != "all" && row.band != ms_study_band(p.sun_elevation_deg)) continue;
        ++n_band;
        if (!(p.reference_luminance > 0)) {
          ++row.rows_skipped;
          continue;
        }
        const double e = std::fabs(lum[i] - p.reference_luminance) / p.reference_luminance;
        const double s = p.reference_luminance_stderr / p.reference_luminance;
        row.error_max_rel = std::max(row.error_max_rel, e);
        row.reference_rel_stderr_max = std::max(row.reference_rel_stderr_max, s);
        if (s > 0) row.error_max_sigma = std::max(row.error_max_sigma, e / s);
        row.error_max_rel_minus_3sigma = std::max(row.error_max_rel_minus_3sigma, e - 3 * s);
        sum2 += e * e;
        ++row.rows;
      }
      if (n_band == 0) continue;
      row.error_rms_rel = row.rows ? std::sqrt(sum2 / row.rows) : 0.0;
      res.rows.push_back(row);
    }
  }
  return res;
}

}  // namespace atmosh::atmo
