// The sky's studies (see atmosh/studies/sky_studies.hpp).
#include "atmosh/studies/sky_studies.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "atmosh/atmo/multiple_scattering.hpp"
#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sun_disc.hpp"
#include "atmosh/atmo/sun_series.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/sh/convolution.hpp"
#include "atmosh/sh/transform.hpp"

namespace atmosh::studies {

namespace fs = std::filesystem;
using namespace atmosh::atmo;

namespace {

// Chromaticity of a colour, NaN (not the white point) when it is black: the sky in
// the Earth's shadow has no colour to report (JSON: null).
Chromaticity chromaticity_or_nan(const Xyz& c) { return xy_chromaticity_or_nan(c); }

// The transmitted sun's chromaticity, as the CSV and the chromaticity plot report it.
Chromaticity sun_chromaticity_or_nan(const SkySummary& m) {
  return m.sun_transmitted.Y > 0 ? m.sun_chromaticity : Chromaticity{std::nan(""), std::nan("")};
}

void study_plots(const fs::path& dir, const std::string& xname, const std::string& xlabel, const std::vector<double>& x,
                 const std::vector<SkySummary>& rows, const std::vector<std::string>& labels, std::vector<fs::path>& written) {
  std::vector<io::Swatch> hz, zn;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    hz.push_back({display_colour(rows[i].horizon_toward_sun.srgb), labels[i]});
    zn.push_back({display_colour(rows[i].zenith.srgb), labels[i]});
  }
  io::write_swatch_png(dir / "horizon_colour.png", "horizon toward the sun (1 deg up): colour against " + xname, hz);
  io::write_swatch_png(dir / "zenith_colour.png", "zenith: colour against " + xname, zn);
  io::PlotSpec p;
  p.title = "Sky luminance against " + xname;
  p.x_label = xlabel;
  p.y_label = "luminance [cd/m^2]";
  p.log_y = true;
  io::Series a{"zenith", x, {}}, b{"horizon toward sun", x, {}}, c{"horizon away from sun", x, {}};
  for (const auto& r : rows) {
    a.y.push_back(r.zenith.xyz.Y);
    b.y.push_back(r.horizon_toward_sun.xyz.Y);
    c.y.push_back(r.horizon_away.xyz.Y);
  }
  p.series = {a, b, c};
  io::write_plot_png(dir / "luminance.png", p);
  io::PlotSpec q;
  q.title = "Chromaticity x against " + xname + " (larger = redder)";
  q.x_label = xlabel;
  q.y_label = "CIE 1931 x";
  io::Series qa{"zenith", x, {}}, qb{"horizon toward sun", x, {}}, qc{"direct sunlight", x, {}};
  for (const auto& r : rows) {
    qa.y.push_back(chromaticity_or_nan(r.zenith.xyz).x);
    qb.y.push_back(chromaticity_or_nan(r.horizon_toward_sun.xyz).x);
    qc.y.push_back(sun_chromaticity_or_nan(r).x);
  }
  q.series = {qa, qb, qc};
  io::write_plot_png(dir / "chromaticity.png", q);
  for (const char* f : {"horizon_colour.png", "zenith_colour.png", "luminance.png", "chromaticity.png"})
    written.push_back(dir / f);
}

}  // namespace

const std::vector<std::string>& sky_summary_columns() {
  static const std::vector<std::string> cols = {
      "zenith_luminance_cd_m2", "zenith_x", "zenith_y", "zenith_r", "zenith_g", "zenith_b",
      "horizon_sun_luminance_cd_m2", "horizon_sun_x", "horizon_sun_y", "horizon_sun_r", "horizon_sun_g", "horizon_sun_b",
      "horizon_away_luminance_cd_m2", "horizon_away_x", "horizon_away_y", "sun_x", "sun_y",
      "sun_direct_normal_illuminance_lux", "sun_transmittance_550nm"};
  return cols;
}

std::vector<double> sky_summary_values(const SkySummary& m) {
  const auto z = chromaticity_or_nan(m.zenith.xyz), hs = chromaticity_or_nan(m.horizon_toward_sun.xyz),
             ha = chromaticity_or_nan(m.horizon_away.xyz);
  return {m.zenith.xyz.Y, z.x, z.y, m.zenith.srgb.r, m.zenith.srgb.g, m.zenith.srgb.b,
          m.horizon_toward_sun.xyz.Y, hs.x, hs.y, m.horizon_toward_sun.srgb.r, m.horizon_toward_sun.srgb.g,
          m.horizon_toward_sun.srgb.b, m.horizon_away.xyz.Y, ha.x, ha.y, sun_chromaticity_or_nan(m).x, sun_chromaticity_or_nan(m).y,
          m.sun_transmitted.Y, m.sun_transmittance_550};
}

// ----------------------------------------------------- study sun-elevation
std::size_t elevation_study_bytes(const ElevationStudyOptions& o) {
  // Its elevations, sky summaries, CSV rows (~24 cells) and plot series, per row.
  const double rows = std::floor((o.to_deg - o.from_deg) / o.step_deg + 1e-9) + 1;
  constexpr double kPerRow = sizeof(double) + sizeof(SkySummary) + 24 * 48 + 16 * sizeof(double);
  return rows * kPerRow >= static_cast<double>(SIZE_MAX) ? SIZE_MAX : static_cast<std::size_t>(rows * kPerRow);
}

WorkEstimate elevation_study_work(const scene::Scene& s, const ElevationStudyOptions& o) {
  const double rows = std::floor((o.to_deg - o.from_deg) / o.step_deg + 1e-9) + 1;
  return sky_rays_work(s, o.sky, mul_units(rows, kSummaryRays));
}

WorkEstimate day_study_work(const scene::Scene& s, const DayStudyOptions& o) {
  const double rows = o.step_s > 0 ? std::min(std::ceil(86400.0 / o.step_s), 100000.0) : 0.0;  // day_study's cap
  const double frame = o.frames ? mul_units(std::max(o.frame_width, 0), std::max(o.frame_height, 0)) : 0.0;
  return sky_rays_work(s, o.sky, mul_units(rows, kSummaryRays + frame));
}

ElevationStudy sun_elevation_study(const scene::Scene& s, const ElevationStudyOptions& o, const ProgressCallback& progress) {
  for (double v : {o.from_deg, o.to_deg})
    if (!(v >= -90 && v <= 90)) throw InputError("sun-elevation study: elevation " + io::format_double(v) + " is outside [-90, 90]");
  if (!(o.step_deg > 0)) throw InputError("sun-elevation study: step " + io::format_double(o.step_deg) + " must be > 0");
  if (o.to_deg < o.from_deg) throw InputError("sun-elevation study: to " + io::format_double(o.to_deg) + " is below from");
  const auto model = make_sky_model(s, o.sky, 1.0);
  const double h = s.observer ? std::max(s.observer->height_m, 0.0) : 0.0;
  ElevationStudy st;
  st.azimuth_deg = o.azimuth_deg;
  auto& elev = st.elevations_deg;
  for (double e = o.from_deg; e <= o.to_deg + 1e-9; e += o.step_deg) elev.push_back(e);
  st.rows.resize(elev.size());
  auto body = [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      st.rows[i] = summarize_sky(*model->sky, h, enu_direction_from_zenith(90.0 - elev[i], o.azimuth_deg));
  };
  if (progress) parallel_for_ranges(elev.size(), 1, o.sky.threads, body, progress);
  else parallel_for_ranges(elev.size(), 1, o.sky.threads, body);
  SunPlacement sun;
  sun.azimuth_deg = o.azimuth_deg;
  sun.elevation_deg = std::nan("");  // varied: the column sun_elevation_deg
  sun.observer_height_m = h;         // the scene's observer (0 for a scene with [sun] only)
  st.provenance = sky_provenance(*model, sun);
  st.provenance.add("study", "sun elevation from " + io::format_double(o.from_deg) + " to " + io::format_double(o.to_deg) +
                                 " step " + io::format_double(o.step_deg) + " deg");
  st.provenance.add("horizon", "view elevation 1 deg, at the sun's azimuth (toward) and opposite (away)");
  st.provenance.add("rgb_units", "linear sRGB (D65), scaled so that Y is luminance in cd/m^2");
  return st;
}

io::CsvTable elevation_study_table(const ElevationStudy& st) {
  std::vector<std::string> cols = {"sun_elevation_deg"};
  cols.insert(cols.end(), sky_summary_columns().begin(), sky_summary_columns().end());
  io::CsvTable t(cols);
  for (std::size_t i = 0; i < st.elevations_deg.size(); ++i) {
    std::vector<io::CsvCell> r = {st.elevations_deg[i]};
    for (double v : sky_summary_values(st.rows[i])) r.emplace_back(v);
    t.add_row(std::move(r));
  }
  return t;
}

io::NetcdfTableOptions elevation_study_netcdf_options(const ElevationStudy& st) {
  io::NetcdfTableOptions o;
  o.title = "atmosh sun-elevation study: sky colour and luminance against sun elevation";
  o.coordinate_column = "sun_elevation_deg";
  o.scalars["solar_azimuth_angle"] = {st.azimuth_deg, "degree", "solar_azimuth_angle"};
  return o;
}

std::vector<fs::path> write_elevation_study(const ElevationStudy& st, const fs::path& dir, bool netcdf) {
  std::vector<std::string> labels;
  for (double e : st.elevations_deg) {
    std::ostringstream l;
    l << e;
    labels.push_back(l.str());
  }
  std::vector<fs::path> written =
      io::write_table_files(dir / "sun_elevation.csv", elevation_study_table(st), st.provenance, netcdf,
                            elevation_study_netcdf_options(st));
  study_plots(dir, "sun elevation", "sun elevation [deg]", st.elevations_deg, st.rows, labels, written);
  return written;
}

// ------------------------------------------------------------- study day
DayStudy day_study(const scene::Scene& s, const DayStudyOptions& o, const std::function<void(DayFrame&&)>& on_frame,
                   const ProgressCallback& progress) {
  if (o.date.size() != 10) throw InputError("day study: date '" + o.date + "' is not YYYY-MM-DD");
  const double jd0 = parse_iso8601(o.date + "T00:00:00Z").jd_utc;
  SunQuery base;
  base.latitude_deg = o.latitude_deg;
  base.longitude_deg = o.longitude_deg;
  base.height_m = o.height_m;
  // Times in [00:00, 24:00) of the date: the end is half a step (at most 0.5 s) before
  // the next midnight, far above the Julian day's rounding (~40 us at JD 2.46e6), so a
  // step that divides the day never yields the next day's 00:00 (whose frame would
  // overwrite this day's sky_0000Z.exr).
  const double margin_d = std::min(0.5 * o.step_s, 0.5) / 86400.0;
  const auto series = sun_series(base, jd0, jd0 + 1.0 - margin_d, o.step_s, 100000);
  const auto model = make_sky_model(s, o.sky, 1.0);
  const double h = std::max(o.height_m, 0.0);
  DayStudy st;
  st.date = o.date;
  st.latitude_deg = o.latitude_deg, st.longitude_deg = o.longitude_deg, st.height_m = o.height_m;
  for (const auto& smp : series) {
    if (progress) progress(static_cast<double>(st.rows.size()) / static_cast<double>(series.size()));
    const glm::dvec3 sun(smp.east, smp.north, smp.up);
    const double d2 = smp.position.earth_sun_distance_au;
    // The tables are built once, for 1 AU; the summary is scaled to this day's distance
    // in one place (summarize_sky), the sun's XYZ and the sky alike.
    DayRow row;
    row.time_utc = format_iso8601_utc(smp.jd_utc);
    row.hours = (smp.jd_utc - jd0) * 24.0;
    row.sun = smp.position;
    row.summary = summarize_sky(*model->sky, h, sun, 1.0, d2);
    if (o.frames) {
      DayFrame f;
      f.time_utc = row.time_utc;
      f.sun.elevation_deg = smp.position.elevation_deg;
      f.sun.azimuth_deg = smp.position.azimuth_deg;
      f.sun.distance_au = d2;
      f.sun.observer_height_m = h;
      f.image = render_sky(*model->sky, SkyProjection::Equirect, o.frame_width, o.frame_height, h, sun, false, o.sky.threads);
      add_sun_disc(f.image, *model->sky, SkyProjection::Equirect, h, sun);
      const float k = static_cast<float>(1.0 / (d2 * d2));
      for (auto* c : {&f.image.R, &f.image.G, &f.image.B, &f.image.X, &f.image.Y, &f.image.Z})
        for (auto& v : *c) v *= k;
      f.provenance = sky_provenance(*model, f.sun);
      f.provenance.add("time_utc", row.time_utc);
      if (on_frame) on_frame(std::move(f));
    }
    st.rows.push_back(std::move(row));
  }
  SunPlacement sp;
  sp.elevation_deg = std::nan("");  // varied with the time: columns of the file
  sp.azimuth_deg = std::nan("");
  sp.distance_au = std::nan("");
  sp.observer_height_m = h;
  st.provenance = sky_provenance(*model, sp);
  st.provenance.add("latitude_deg", base.latitude_deg).add("longitude_deg", base.longitude_deg).add("height_m", base.height_m);
  st.provenance.add("date_utc", o.date).add("step", o.step_text.empty() ? io::format_double(o.step_s) + " s" : o.step_text);
  st.provenance.add("sun", "NREL SPA, geometric elevation drives the sky; apparent elevation reported");
  return st;
}

fs::path write_day_frame(const DayFrame& f, const fs::path& dir) {
  std::string stamp = f.time_utc.substr(11, 5);
  stamp.erase(std::remove(stamp.begin(), stamp.end(), ':'), stamp.end());
  const fs::path exr = dir / "frames" / ("sky_" + stamp + "Z.exr");
  write_sky_image(f.image, exr, {}, f.provenance, "equirect", f.sun);
  return exr;
}

io::CsvTable day_study_table(const DayStudy& st) {
  std::vector<std::string> cols = {"time_utc", "sun_elevation_deg", "sun_azimuth_deg", "apparent_sun_elevation_deg"};
  cols.insert(cols.end(), sky_summary_columns().begin(), sky_summary_columns().end());
  io::CsvTable t(cols);
  for (const auto& r : st.rows) {
    std::vector<io::CsvCell> c = {r.time_utc, r.sun.elevation_deg, r.sun.azimuth_deg, r.sun.apparent_elevation_deg};
    for (double v : sky_summary_values(r.summary)) c.emplace_back(v);
    t.add_row(std::move(c));
  }
  return t;
}

io::NetcdfTableOptions day_study_netcdf_options(const DayStudy& st) {
  io::NetcdfTableOptions o;
  o.title = "atmosh day study: sky colour and luminance through the UTC day " + st.date;
  for (const auto& r : st.rows) {
    // Julian date 2440587.5 is 1970-01-01T00:00:00 UTC; the ISO times hold whole
    // milliseconds at most, so the Julian day's rounding (~40 us) is rounded away.
    const double s = (parse_iso8601(r.time_utc).jd_utc - 2440587.5) * 86400.0;
    o.time_unix_s.push_back(std::round(s * 1000.0) / 1000.0);
  }
  o.scalars["latitude"] = {st.latitude_deg, "degree_north", "latitude"};
  o.scalars["longitude"] = {st.longitude_deg, "degree_east", "longitude"};
  o.scalars["height"] = {st.height_m, "m", "height_above_reference_ellipsoid"};
  return o;
}

std::vector<fs::path> write_day_study(const DayStudy& st, const fs::path& dir, bool netcdf) {
  std::vector<SkySummary> rows;
  std::vector<double> hours;
  std::vector<std::string> labels;
  for (const auto& r : st.rows) {
    rows.push_back(r.summary);
    hours.push_back(r.hours);
    labels.push_back(r.time_utc.substr(11, 5));
  }
  std::vector<fs::path> written =
      io::write_table_files(dir / "day.csv", day_study_table(st), st.provenance, netcdf, day_study_netcdf_options(st));
  study_plots(dir, "UTC time on " + st.date, "hours since " + st.date + " 00:00 UTC", hours, rows, labels, written);
  return written;
}

// ------------------------------------------------------------------ sweep
scene::SweepOutputs sweep_point(const scene::Scene& s, const SkySettings& q) {
  const SunPlacement sun = sun_of_scene(s);
  const auto m = make_sky_model(s, q, sun.distance_au);
  const SkySummary sm = summarize_sky(*m->sky, std::max(sun.observer_height_m, 0.0), sun.direction());
  scene::SweepOutputs out = {{"sun_elevation_deg", sun.elevation_deg}, {"sun_azimuth_deg", sun.azimuth_deg}};
  const auto v = sky_summary_values(sm);
  for (std::size_t i = 0; i < v.size(); ++i) out.emplace_back(sky_summary_columns()[i], v[i]);
  out.emplace_back("table_build_time_s", m->build_time_s);
  return out;
}

scene::SweepSettings sweep_settings(const SkySettings& q) {
  return {{"lut_shells", std::to_string(q.shells)},
          {"view_segments", std::to_string(q.segments)},
          {"samples_per_segment", std::to_string(q.samples)},
          {"max_piece_optical_depth", io::format_double(q.max_piece_tau)},
          {"sun_model", q.sun_model ? sun_model_name(*q.sun_model) : "scene"},
          {"scattering", q.scattering ? scattering_method_name(*q.scattering) : "scene"},
          {"orders", q.orders ? std::to_string(*q.orders) : "scene"}};
}

// --------------------------------------------------------- converge sky
ConvergeSky converge_sky(const scene::Scene& s, const ConvergeSkyOptions& o) {
  const Atmosphere atm(s.atmosphere);
  const SolarSpectrum solar = solar_spectrum_for_bins(s.atmosphere.spectrum);
  const SkyReference ref(atm, solar);
  struct Ray {
    double sun_el, view_el, rel_az;
    std::vector<double> L;
  };
  std::vector<Ray> rays;
  // Day (sun >= 0) and twilight (sun below the horizon) rays are reported separately.
  const std::vector<double> suns =
      o.quick ? std::vector<double>{-4, 0, 10} : std::vector<double>{-6, -3, 0, 2, 5, 10, 30, 60};
  const std::vector<double> views = o.quick ? std::vector<double>{1, 30, 90} : std::vector<double>{0.5, 1, 2, 5, 10, 20, 45, 90};
  const std::vector<double> azs = o.quick ? std::vector<double>{0, 180} : std::vector<double>{0, 45, 90, 180};
  for (double se : suns)
    for (double ve : views)
      for (double az : azs) {
        if (ve == 90 && az != azs.front()) continue;
        rays.push_back({se, ve, az, {}});
      }
  // Reference, in parallel.
  const auto t0 = std::chrono::steady_clock::now();
  parallel_for(rays.size(), o.threads, [&](std::size_t i) {
    rays[i].L = ref.radiance(0.0, enu_direction_from_zenith(90 - rays[i].view_el, rays[i].rel_az),
                             enu_direction_from_zenith(90 - rays[i].sun_el, 0.0)).radiance;
  });
  const double ref_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  struct Setting {
    int shells, segments, samples;
    double max_tau = SkyOptions{}.max_piece_optical_depth;
  };
  std::vector<Setting> settings;
  if (o.quick) {
    settings = {{16, 4, 1}, {32, 8, 2}, {32, 16, 2}};
  } else {
    for (int sh : {16, 32, 64})
      for (int seg : {4, 8, 16, 24})
        for (int q : {1, 2, 3, 4})
          if (seg < sh) settings.push_back({sh, seg, q});
    // Longer pieces near the horizon (fewer splits): faster, less accurate.
    for (double tau : {1.0, 2.0})
      for (int seg : {8, 16}) settings.push_back({32, seg, 2, tau});
  }
  ConvergeSky c;
  for (const auto& st : settings) {
    SkyOptions so;
    so.lut.shells = st.shells;
    so.segments = st.segments;
    so.samples_per_segment = st.samples;
    so.max_piece_optical_depth = st.max_tau;
    const auto b0 = std::chrono::steady_clock::now();
    const SkyIntegrator sky(atm, solar, so);
    const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - b0).count();
    std::vector<double> L(solar.size());
    double emax[2] = {0, 0}, esum[2] = {0, 0};  // [day, twilight]
    long n[2] = {0, 0};
    // Time the rays over enough repetitions for a stable per-ray figure.
    const int reps = o.quick ? 3 : 20;
    const auto r0 = std::chrono::steady_clock::now();
    for (int rep = 0; rep < reps; ++rep)
      for (const auto& r : rays) {
        sky.radiance(0.0, enu_direction_from_zenith(90 - r.view_el, r.rel_az), enu_direction_from_zenith(90 - r.sun_el, 0.0), L.data());
        if (rep > 0) continue;
        const double peak = *std::max_element(r.L.begin(), r.L.end());
        const int k = r.sun_el < 0 ? 1 : 0;
        for (std::size_t i = 0; i < L.size(); ++i)
          if (r.L[i] > 1e-6 * peak) {
            const double e = std::fabs(L[i] - r.L[i]) / r.L[i];
            emax[k] = std::max(emax[k], e);
            esum[k] += e * e;
            ++n[k];
          }
      }
    const double per_ray = std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count() / (reps * rays.size());
    std::ostringstream name;
    name << "shells=" << st.shells << " segments=" << st.segments << " samples=" << st.samples
         << " max_tau=" << st.max_tau;
    for (int k = 0; k < 2; ++k)
      c.rows.push_back({std::string(k ? "twilight" : "day") + " q=" + std::to_string(st.samples), name.str(), emax[k],
                        n[k] ? std::sqrt(esum[k] / n[k]) : 0.0, build + per_ray * 1024.0 * 512.0,
                        {double(st.shells), double(st.segments), double(st.samples), st.max_tau, build, per_ray,
                         ref_time / rays.size()}});
  }
  c.spec.title = "Single-scattering sky: error vs run time (1024x512 image, " + std::to_string(solar.size()) + " wavelengths)";
  c.spec.time_axis_label = "run time for a 1024x512 image incl. table build, one core [s]";
  c.spec.error_axis_label = "max relative error of spectral radiance";
  c.spec.extra_columns = {"shells",       "segments",       "samples_per_segment",     "max_piece_optical_depth",
                          "build_time_s", "time_per_ray_s", "reference_time_per_ray_s"};
  c.provenance = io::Provenance::current();
  c.provenance.add("scene", s.source);
  c.provenance.add("rays", static_cast<double>(rays.size()));
  c.provenance.add("directions", "view elevations x azimuths relative to the sun x sun elevations; method 'day' = rays with "
                                 "the sun >= 0 deg, 'twilight' = sun below the horizon; error over wavelengths where the "
                                 "reference exceeds 1e-6 of the ray's maximum");
  c.provenance.add("reference", "adaptive Gauss-Kronrod over the view ray, exact optical depths, rel tol 1e-6");
  c.provenance.add("time_s", "table build + 524288 rays x measured time per ray (single thread)");
  return c;
}

std::vector<fs::path> write_converge_sky(const ConvergeSky& c, const fs::path& stem, bool netcdf) {
  return io::write_study(stem, c.spec, c.rows, c.provenance, netcdf);
}

// ---------------------------------------------------- the sky's SH (sky -> SH)
SkySh project_sky_sh(const SkyModel& model, const SunPlacement& sun, int bands) {
  if (bands < 1) throw InputError("sky SH: bands " + std::to_string(bands) + " must be >= 1");
  // Sample the sky on a Gauss-Legendre grid four times denser than the band limit
  // (the sky is not band-limited: the sun's aureole and the horizon), analyse each
  // linear-sRGB channel. Frame: SH x = east, y = north, z = up (ENU).
  const int nlat = std::max(4 * bands, 64);
  const sh::GaussGrid grid = sh::gauss_grid(bands, nlat, 2 * nlat);
  const SpectralToXyz cmf(model.atmosphere->wavelengths_nm());
  const double h = std::max(sun.observer_height_m, 0.0);
  std::vector<std::vector<double>> ch(3, std::vector<double>(static_cast<std::size_t>(grid.nlat) * grid.nphi));
  parallel_for(static_cast<std::size_t>(grid.nlat), 0, [&](std::size_t i) {
    for (int j = 0; j < grid.nphi; ++j) {
      const double ph = grid.phi(j);
      const glm::dvec3 d(grid.sin_t[i] * std::cos(ph), grid.sin_t[i] * std::sin(ph), grid.cos_t[i]);
      const SkyColour c = sky_colour(*model.sky, cmf, h, glm::normalize(d), sun.direction());
      const std::size_t k = i * static_cast<std::size_t>(grid.nphi) + static_cast<std::size_t>(j);
      ch[0][k] = c.srgb.r;
      ch[1][k] = c.srgb.g;
      ch[2][k] = c.srgb.b;
    }
  });
  SkySh out;
  out.bands = bands;
  out.nlat = grid.nlat;
  out.nphi = grid.nphi;
  for (std::size_t c = 0; c < 3; ++c) out.coeffs[c] = sh::analyse(grid, ch[c].data());
  auto& prov = out.provenance;
  prov = sky_provenance(model, sun);
  prov.add("sh", "real orthonormal SH with Condon-Shortley phase, index l(l+1)+m, " + std::to_string(bands) + " bands");
  prov.add("sh_frame", "x = east, y = north, z = up (observer's ENU); phi from east towards north");
  prov.add("sh_units", "coefficients of linear sRGB radiance (Y in cd/m^2) times sr");
  prov.add("value_units", "cd/m^2");
  prov.add("sh_projection", "Gauss-Legendre grid " + std::to_string(grid.nlat) + " x " + std::to_string(grid.nphi));
  return out;
}

std::vector<fs::path> write_sky_sh(const SkySh& sh, const fs::path& csv) {
  const int bands = sh.bands;
  const auto& coeffs = sh.coeffs;
  // The one SH coefficient CSV writer (columns l, m, index, r, g, b); the convention
  // is already in the projection's provenance.
  io::write_sh_coefficients(csv, io::ShCoefficients{bands, {"r", "g", "b"}, {coeffs[0], coeffs[1], coeffs[2]}, {}},
                            sh.provenance, false);
  // Band energy (rotation-invariant power per band) of the luminance-like green channel and all three.
  fs::path stem = csv;
  stem.replace_extension();
  const fs::path bcsv = stem.string() + "_bands.csv", bpng = stem.string() + "_bands.png";
  io::CsvTable bt({"l", "energy_r", "energy_g", "energy_b", "cumulative_fraction_g"});
  std::vector<std::vector<double>> e;
  for (const auto& c : coeffs) e.push_back(atmosh::sh::band_energy(c, bands));
  const auto cum = atmosh::sh::cumulative_energy_fraction(e[1]);
  // Coefficients of linear sRGB radiance on the luminance scale (cd/m^2) times sr.
  io::PlotSpec p = io::band_energy_plot_spec("Band energy of the sky's SH (linear sRGB channels)",
                                             {"red", "green", "blue"}, e, "cd/m^2");
  const std::array<double, 3> cols[] = {{0.85, 0.2, 0.2}, {0.2, 0.65, 0.2}, {0.2, 0.3, 0.85}};
  for (int c = 0; c < 3; ++c) p.series[static_cast<std::size_t>(c)].color = cols[c];
  for (int l = 0; l < bands; ++l) {
    const auto L = static_cast<std::size_t>(l);
    bt.add_row({std::int64_t{l}, e[0][L], e[1][L], e[2][L], cum[L]});
  }
  bt.write(bcsv, sh.provenance);
  io::write_plot_png(bpng, p);
  return {csv, bcsv, bpng};
}

// ------------------------------------------------- the demo's sky step
std::vector<fs::path> demo_sky(const fs::path& dir, bool quick) {
  ConvergeSkyOptions o;
  o.quick = quick;
  return write_converge_sky(converge_sky(scene::default_scene(), o), dir / "sky_convergence");
}

}  // namespace atmosh::studies
