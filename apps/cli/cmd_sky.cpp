// atmosh sky, atmosh study sun-elevation|day, atmosh sweep [merge], atmosh converge sky.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/sun_disc.hpp"
#include "atmosh/atmo/shared/view_ray.glsl.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sun_series.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/scene/outputs.hpp"
#include "atmosh/scene/sweep.hpp"
#include "atmosh/sh/convolution.hpp"
#include "atmosh/sh/transform.hpp"
#include "cli_common.hpp"
#include "progress.hpp"
#include "sky_common.hpp"
#ifdef ATMOSH_HAVE_GPU
#include "atmosh/gpu/sky.hpp"
#endif

namespace atmosh::cli {

namespace {

namespace fs = std::filesystem;
using namespace atmosh::atmo;

struct QualityOptions {
  int shells = 32, segments = 16, samples = 2, threads = 0;
  double max_piece_tau = SkyOptions{}.max_piece_optical_depth;
  std::string scattering;  // --scattering: overrides the scene's [scattering] method ("" = the scene's)
  std::optional<int> orders;  // --orders: overrides the scene's orders
  // The scene with the command line's scattering overrides (InputError naming the
  // option for a bad value, before any long work).
  scene::Scene scene_for(scene::Scene s) const {
    if (!scattering.empty()) s.scattering.method = parse_scattering_method(scattering, "--scattering");
    if (orders) {
      if (*orders < 1 || *orders > 64) throw InputError("--orders " + std::to_string(*orders) + " is outside [1, 64]");
      s.scattering.orders = *orders;
    }
    return s;
  }
  std::string sun_model;  // --sun-model: disc | point; empty: the scene's sun_model
  // Validated, naming the options as typed, with threads resolved (0 = the CPUs this
  // process may use). Every command that takes these options calls it first.
  QualityOptions checked() const {
    QualityOptions q = *this;
    if (shells < 4 || shells > 4096)
      throw InputError("--shells " + std::to_string(shells) + " is outside [4, 4096]");
    const int max_segments = std::min(shells - 1, atmo::shared::kMaxCutSpheres);
    if (segments < 1 || segments > max_segments)
      throw InputError("--segments " + std::to_string(segments) + " is outside [1, " + std::to_string(max_segments) +
                       "] (at most --shells - 1 and " + std::to_string(atmo::shared::kMaxCutSpheres) + ")");
    if (samples < 1 || samples > 8) throw InputError("--samples " + std::to_string(samples) + " is outside [1, 8]");
    if (!std::isfinite(max_piece_tau) || !(max_piece_tau > 0))
      throw InputError("--max-piece-tau " + io::format_double(max_piece_tau) + " must be finite and > 0");
    q.threads = threads_option(threads);
    return q;
  }
  // The settings that change results, as recorded in CSVs and hashed into a sweep's identity.
  scene::SweepSettings settings() const {
    return {{"lut_shells", std::to_string(shells)},
            {"view_segments", std::to_string(segments)},
            {"samples_per_segment", std::to_string(samples)},
            {"max_piece_optical_depth", io::format_double(max_piece_tau)},
            {"sun_model", sun_model.empty() ? "scene" : sun_model},
            {"scattering", scattering.empty() ? "scene" : scattering},
            {"orders", orders ? std::to_string(*orders) : "scene"}};
  }
  SkyOptions sky(const scene::Scene& s) const {
    SkyOptions o;
    o.lut.shells = shells;
    o.segments = segments;
    o.samples_per_segment = samples;
    o.max_piece_optical_depth = max_piece_tau;
    o.sun_model = parse_sun_model(sun_model.empty() ? s.sun_model : sun_model);
    return o;
  }
};

void add_quality_options(CLI::App* c, QualityOptions& q) {
  c->add_option("--shells", q.shells, "Shells of the optical-depth tables")->capture_default_str();
  c->add_option("--segments", q.segments, "Shells that cut each view ray")->capture_default_str();
  c->add_option("--samples", q.samples, "Gauss-Legendre points per view-ray piece")->capture_default_str();
  c->add_option("--max-piece-tau", q.max_piece_tau,
                "Largest extinction optical depth of one view-ray piece before it is split (accuracy vs speed: "
                "see atmosh converge sky)")
      ->capture_default_str();
  c->add_option("--threads", q.threads, "Worker threads (0 = the CPUs this process may use)")->capture_default_str();
  c->add_option("--sun-model", q.sun_model,
                "disc (limb-darkened solar disc: direct beam, sun colour, the sun in images) or point; "
                "default: the scene's sun_model (disc)");
  c->add_option("--scattering", q.scattering,
                "Scattering method: single | orders | approximate (default: the scene's [scattering] method)");
  c->add_option("--orders", q.orders, "Highest order of scattering for --scattering orders (default: the scene's)");
}

scene::Scene load_or_default(const std::string& file) {
  return file.empty() ? scene::default_scene() : scene::load_scene(file);
}

nlohmann::json rgb_json(const Rgb& c) { return nlohmann::json::array({c.r, c.g, c.b}); }

// A chromaticity for JSON: [x, y], or null when the colour has none.
nlohmann::json xy_json(const Xyz& c) {
  const Chromaticity q = xy_chromaticity_or_nan(c);
  if (std::isnan(q.x)) return nlohmann::json(nullptr);
  return nlohmann::json::array({q.x, q.y});
}

// ---------------------------------------------------------------- atmosh sky
struct SkyCmd {
  std::string scene_file, time, projection = "equirect", size = "512x256", output, png, device = "cpu";
  std::optional<double> lat, lon, sun_elevation;
  double height = 0.0, sun_azimuth = 180.0;
  bool spectral = false, json = false;
  QualityOptions q;
};

SunPlacement resolve_sun(const SkyCmd& c, const scene::Scene& s) {
  const bool place = c.lat || c.lon || !c.time.empty();
  if (place && c.sun_elevation) throw InputError("give either --lat/--lon/--time or --sun-elevation, not both");
  if (place) {
    if (!c.lat || !c.lon || c.time.empty()) throw InputError("--lat, --lon and --time go together");
    return sun_from_place(require_range(*c.lat, -90, 90, "--lat"), require_range(*c.lon, -180, 180, "--lon"),
                          require_range(c.height, -500, 1e8, "--height"), c.time);
  }
  if (c.sun_elevation) {
    SunPlacement p;
    p.elevation_deg = require_range(*c.sun_elevation, -90, 90, "--sun-elevation");
    p.azimuth_deg = require_range(c.sun_azimuth, -360, 360, "--sun-azimuth");
    p.observer_height_m = require_range(c.height, -500, 1e8, "--height");
    return p;
  }
  return sun_of_scene(s);
}

}  // namespace

SkyImage render_sky_on(const std::string& device, const SkyIntegrator& sky, SkyProjection proj, int width, int height,
                       double altitude_m, const glm::dvec3& sun, bool spectral, int threads, std::string& used) {
  check_device(device);
  // gpu: the GPU pass or an error; auto: the GPU pass, else the CPU with a one-line notice.
  used = "cpu";
  if (device != "cpu" && sky.method() != ScatteringMethod::Single) {
    // The GPU pass computes single scattering only.
    const std::string what = std::string("scattering method '") + scattering_method_name(sky.method()) + "'";
    if (device == "gpu") throw std::runtime_error("--device gpu: " + what + " is not supported on the GPU (use --scattering single or --device cpu)");
    std::cerr << "atmosh: " << what << " is not supported on the GPU; rendering on the CPU\n";
    return render_sky(sky, proj, width, height, altitude_m, sun, spectral, threads);
  }
  if (device != "cpu") {
#ifdef ATMOSH_HAVE_GPU
    try {
      SkyImage img = gpu::render_sky(sky, proj, width, height, altitude_m, sun, spectral);
      used = "gpu";
      add_sun_disc(img, sky, proj, altitude_m, sun);  // the visible disc (CPU; a few pixels)
      return img;
    } catch (const gpu::Unavailable& e) {
      if (device == "gpu") throw std::runtime_error(std::string("--device gpu: ") + e.what());
      std::cerr << "atmosh: no GPU (" << e.what() << "); rendering on the CPU\n";
    } catch (const gpu::Unsupported& e) {
      if (device == "gpu") throw std::runtime_error(std::string("--device gpu: ") + e.what());
      std::cerr << "atmosh: " << e.what() << " is not supported on the GPU; rendering on the CPU\n";
    }
#else
    if (device == "gpu") throw std::runtime_error("--device gpu: atmosh was built without ATMOSH_WITH_GPU");
    std::cerr << "atmosh: built without GPU support; rendering on the CPU\n";
#endif
  }
  SkyImage img = render_sky(sky, proj, width, height, altitude_m, sun, spectral, threads);
  add_sun_disc(img, sky, proj, altitude_m, sun);  // the visible disc (SkyOptions::sun_model)
  return img;
}

namespace {

void run_sky(const SkyCmd& cmd) {
  SkyCmd c = cmd;
  c.q = cmd.q.checked();
  if (c.output.empty()) throw InputError("-o is required (the EXR file to write)");
  check_output_file(c.output, {".exr"}, "-o");
  if (!c.png.empty()) check_output_file(c.png, {".png"}, "--png");
  const auto s = c.q.scene_for(load_or_default(c.scene_file));
  const SunPlacement sun = resolve_sun(c, s);
  const auto proj = parse_sky_projection(c.projection);
  const auto size = parse_size(c.size, "--size");
  check_memory(sky_output_bytes(size[0], size[1], spectrum_wavelengths(s.atmosphere.spectrum).size(), c.spectral),
               "--size " + c.size + (c.spectral ? " --spectral" : ""));
  const auto model = make_sky_model(s, c.q.sky(s), sun.distance_au);
  const double h = std::max(sun.observer_height_m, 0.0);
  std::string used;
  const SkyImage img = render_sky_on(c.device, *model->sky, proj, size[0], size[1], h, sun.direction(), c.spectral,
                                     c.q.threads, used);
  auto prov = sky_provenance(*model, sun);
  prov.add("device", used);
  const double exposure = write_sky_image(img, c.output, c.png, prov, c.projection, sun);
  const SkySummary sm = summarize_sky(*model->sky, h, sun.direction());
  if (c.json) {
    nlohmann::json j = {{"exr", c.output},
                        {"png", c.png.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.png)},
                        {"sun_elevation_deg", sun.elevation_deg},
                        {"sun_azimuth_deg", sun.azimuth_deg},
                        {"zenith_luminance_cd_m2", sm.zenith.xyz.Y},
                        {"zenith_srgb", rgb_json(sm.zenith.srgb)},
                        {"zenith_xy", xy_json(sm.zenith.xyz)},
                        {"horizon_srgb", rgb_json(sm.horizon_toward_sun.srgb)},
                        {"horizon_luminance_cd_m2", sm.horizon_toward_sun.xyz.Y},
                        {"horizon_away_srgb", rgb_json(sm.horizon_away.srgb)},
                        {"srgb_units", "linear sRGB (D65), scaled so that Y is luminance in cd/m^2"},
                        {"sun_model", sun_model_name(model->sky->options().sun_model)},
                        {"sun_angular_radius_deg", sun_angular_radius_rad(sun.distance_au) * 57.29577951308232},
                        {"exposure", exposure},
                        {"rays", img.rays},
                        {"device", used},
                        {"render_time_s", img.seconds},
                        {"table_build_time_s", model->build_time_s},
                        {"rays_per_s", img.seconds > 0 ? img.rays / img.seconds : 0.0},
                        {"scattering", scattering_method_name(model->sky->method())}};
    if (model->sky->method() == ScatteringMethod::Orders) j["scattering_orders"] = model->sky->options().scattering.orders;
    const SkyIrradiance irr = sky_irradiance(*model->sky, h, sun.direction());
    j["irradiance_direct_lux"] = irr.direct_lux;
    j["irradiance_diffuse_lux"] = irr.diffuse_lux;
    j["irradiance_direct_w_m2_nm"] = irr.direct;
    j["irradiance_diffuse_w_m2_nm"] = irr.diffuse;
    j["wavelengths_nm"] = model->atmosphere->wavelengths_nm();
    if (sun.spa) j["apparent_sun_elevation_deg"] = sun.spa->apparent_elevation_deg;
    print_json(j);
  } else {
    std::cout << "sky: " << c.output << (c.png.empty() ? "" : " and " + c.png) << " (" << img.rays << " rays in "
              << img.seconds << " s; sun " << sun.describe() << "; zenith " << sm.zenith.xyz.Y << " cd/m^2)\n";
  }
}

// ---------------------------------------------------------- studies (shared)
const std::vector<std::string> kStudyColumns = {
    "zenith_luminance_cd_m2", "zenith_x", "zenith_y", "zenith_r", "zenith_g", "zenith_b",
    "horizon_sun_luminance_cd_m2", "horizon_sun_x", "horizon_sun_y", "horizon_sun_r", "horizon_sun_g", "horizon_sun_b",
    "horizon_away_luminance_cd_m2", "horizon_away_x", "horizon_away_y", "sun_x", "sun_y",
    "sun_direct_normal_illuminance_lux", "sun_transmittance_550nm"};

// Chromaticity of a colour, NaN (not the white point) when it is black: the sky in
// the Earth's shadow has no colour to report (JSON: null).
Chromaticity chromaticity_or_nan(const Xyz& c) { return xy_chromaticity_or_nan(c); }

// The transmitted sun's chromaticity, as the CSV and the chromaticity plot report it.
Chromaticity sun_chromaticity_or_nan(const SkySummary& m) {
  return m.sun_transmitted.Y > 0 ? m.sun_chromaticity : Chromaticity{std::nan(""), std::nan("")};
}

std::vector<double> study_values(const SkySummary& m) {
  const auto z = chromaticity_or_nan(m.zenith.xyz), hs = chromaticity_or_nan(m.horizon_toward_sun.xyz),
             ha = chromaticity_or_nan(m.horizon_away.xyz);
  return {m.zenith.xyz.Y, z.x, z.y, m.zenith.srgb.r, m.zenith.srgb.g, m.zenith.srgb.b,
          m.horizon_toward_sun.xyz.Y, hs.x, hs.y, m.horizon_toward_sun.srgb.r, m.horizon_toward_sun.srgb.g,
          m.horizon_toward_sun.srgb.b, m.horizon_away.xyz.Y, ha.x, ha.y, sun_chromaticity_or_nan(m).x, sun_chromaticity_or_nan(m).y,
          m.sun_transmitted.Y, m.sun_transmittance_550};
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

// ----------------------------------------------------- study sun-elevation
struct ElevationStudy {
  std::string scene_file, output;
  double from = -18, to = 90, step = 1, azimuth = 180;
  QualityOptions q;
};

// Memory of the study: its elevations, sky summaries, CSV rows (~24 cells) and plot
// series, per row. Saturates for a hostile step (1e-9 deg: 1.8e11 rows).
std::size_t elevation_study_bytes(const ElevationStudy& o) {
  const double rows = std::floor((o.to - o.from) / o.step + 1e-9) + 1;
  constexpr double kPerRow = sizeof(double) + sizeof(SkySummary) + 24 * 48 + 16 * sizeof(double);
  return rows * kPerRow >= static_cast<double>(SIZE_MAX) ? SIZE_MAX : static_cast<std::size_t>(rows * kPerRow);
}

std::vector<fs::path> run_elevation_study(const ElevationStudy& given_options, const scene::Scene* given = nullptr,
                                          const ProgressCallback& progress = {}) {
  ElevationStudy o = given_options;
  o.q = given_options.q.checked();
  if (o.output.empty()) throw InputError("-o is required (output folder)");
  require_range(o.from, -90, 90, "--from");
  require_range(o.to, -90, 90, "--to");
  if (!(o.step > 0)) throw InputError("--step " + io::format_double(o.step) + " must be > 0");
  if (o.to < o.from) throw InputError("--to " + io::format_double(o.to) + " is below --from");
  check_memory(elevation_study_bytes(o), "--from " + io::format_double(o.from) + " --to " + io::format_double(o.to) +
                                             " --step " + io::format_double(o.step));
  if (!given) check_output_dir(o.output, "-o");
  const auto s = given ? *given : load_or_default(o.scene_file);
  const auto model = make_sky_model(o.q.scene_for(s), o.q.sky(s), 1.0);
  const double h = s.observer ? std::max(s.observer->height_m, 0.0) : 0.0;
  std::vector<double> elev;
  for (double e = o.from; e <= o.to + 1e-9; e += o.step) elev.push_back(e);
  std::vector<SkySummary> rows(elev.size());
  auto body = [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) rows[i] = summarize_sky(*model->sky, h, enu_direction_from_zenith(90.0 - elev[i], o.azimuth));
  };
  if (progress) parallel_for_ranges(elev.size(), 1, o.q.threads, body, progress);
  else parallel_for_ranges(elev.size(), 1, o.q.threads, body);
  std::vector<std::string> cols = {"sun_elevation_deg"};
  cols.insert(cols.end(), kStudyColumns.begin(), kStudyColumns.end());
  io::CsvTable t(cols);
  std::vector<std::string> labels;
  for (std::size_t i = 0; i < elev.size(); ++i) {
    std::vector<io::CsvCell> r = {elev[i]};
    for (double v : study_values(rows[i])) r.emplace_back(v);
    t.add_row(std::move(r));
    std::ostringstream l;
    l << elev[i];
    labels.push_back(l.str());
  }
  SunPlacement sun;
  sun.azimuth_deg = o.azimuth;
  sun.elevation_deg = std::nan("");  // varied: the column sun_elevation_deg
  sun.observer_height_m = h;         // the scene's observer (0 for a scene with [sun] only)
  auto prov = sky_provenance(*model, sun);
  prov.add("study", "sun elevation from " + io::format_double(o.from) + " to " + io::format_double(o.to) + " step " +
                        io::format_double(o.step) + " deg");
  prov.add("horizon", "view elevation 1 deg, at the sun's azimuth (toward) and opposite (away)");
  prov.add("rgb_units", "linear sRGB (D65), scaled so that Y is luminance in cd/m^2");
  const fs::path dir = o.output;
  std::vector<fs::path> written = {dir / "sun_elevation.csv"};
  t.write(written[0], prov);
  study_plots(dir, "sun elevation", "sun elevation [deg]", elev, rows, labels, written);
  return written;
}

// ------------------------------------------------------------- study day
struct DayStudy {
  std::string scene_file, date, step = "10min", output, frame_size = "128x64";
  std::optional<double> lat, lon;
  double height = 0;
  bool frames = true;
  QualityOptions q;
};

std::vector<fs::path> run_day_study(const DayStudy& given_options, const ProgressCallback& progress = {}) {
  DayStudy o = given_options;
  o.q = given_options.q.checked();
  if (o.output.empty()) throw InputError("-o is required (output folder)");
  if (!o.lat || !o.lon) throw InputError("--lat and --lon are required");
  if (o.date.size() != 10) throw InputError("--date '" + o.date + "' is not YYYY-MM-DD");
  const double jd0 = parse_iso8601(o.date + "T00:00:00Z").jd_utc;
  const double step_s = parse_duration_s(o.step);
  const auto fsize = parse_size(o.frame_size, "--frame-size");
  check_output_dir(o.output, "-o");
  if (o.frames)  // one frame at a time: the largest holding is one sky image
    check_memory(sky_output_bytes(fsize[0], fsize[1], 0, false), "--frame-size " + o.frame_size);
  SunQuery base;
  base.latitude_deg = require_range(*o.lat, -90, 90, "--lat");
  base.longitude_deg = require_range(*o.lon, -180, 180, "--lon");
  base.height_m = require_range(o.height, -500, 1e8, "--height");
  const auto series = sun_series(base, jd0, jd0 + 1.0 - 1e-9, step_s, 100000);
  const auto s = load_or_default(o.scene_file);
  const auto model = make_sky_model(o.q.scene_for(s), o.q.sky(s), 1.0);
  const double h = std::max(o.height, 0.0);
  const fs::path dir = o.output;
  std::vector<std::string> cols = {"time_utc", "sun_elevation_deg", "sun_azimuth_deg", "apparent_sun_elevation_deg"};
  cols.insert(cols.end(), kStudyColumns.begin(), kStudyColumns.end());
  io::CsvTable t(cols);
  std::vector<SkySummary> rows;
  std::vector<double> hours;
  std::vector<std::string> labels;
  std::vector<fs::path> written;
  for (const auto& smp : series) {
    if (progress) progress(static_cast<double>(rows.size()) / static_cast<double>(series.size()));
    const glm::dvec3 sun(smp.east, smp.north, smp.up);
    const double d2 = smp.position.earth_sun_distance_au;
    // The tables are built once, for 1 AU; the summary is scaled to this day's distance
    // in one place (summarize_sky), the sun's XYZ and the sky alike.
    const SkySummary m = summarize_sky(*model->sky, h, sun, 1.0, d2);
    const std::string ts = format_iso8601_utc(smp.jd_utc);
    std::vector<io::CsvCell> r = {ts, smp.position.elevation_deg, smp.position.azimuth_deg,
                                  smp.position.apparent_elevation_deg};
    for (double v : study_values(m)) r.emplace_back(v);
    t.add_row(std::move(r));
    rows.push_back(m);
    hours.push_back((smp.jd_utc - jd0) * 24.0);
    labels.push_back(ts.substr(11, 5));
    if (o.frames) {
      SunPlacement sp;
      sp.elevation_deg = smp.position.elevation_deg;
      sp.azimuth_deg = smp.position.azimuth_deg;
      sp.distance_au = d2;
      sp.observer_height_m = h;
      SkyImage img = render_sky(*model->sky, SkyProjection::Equirect, fsize[0], fsize[1], h, sun, false, o.q.threads);
      add_sun_disc(img, *model->sky, SkyProjection::Equirect, h, sun);
      SkyImage scaled = img;
      const float f = static_cast<float>(1.0 / (d2 * d2));
      for (auto* c : {&scaled.R, &scaled.G, &scaled.B, &scaled.X, &scaled.Y, &scaled.Z})
        for (auto& v : *c) v *= f;
      std::string stamp = ts.substr(11, 5);
      stamp.erase(std::remove(stamp.begin(), stamp.end(), ':'), stamp.end());
      const fs::path exr = dir / "frames" / ("sky_" + stamp + "Z.exr");
      auto prov = sky_provenance(*model, sp);
      prov.add("time_utc", ts);
      write_sky_image(scaled, exr, {}, prov, "equirect", sp);
      written.push_back(exr);
    }
  }
  SunPlacement sp;
  sp.elevation_deg = std::nan("");  // varied with the time: columns of the file
  sp.azimuth_deg = std::nan("");
  sp.distance_au = std::nan("");
  sp.observer_height_m = h;
  auto prov = sky_provenance(*model, sp);
  prov.add("latitude_deg", base.latitude_deg).add("longitude_deg", base.longitude_deg).add("height_m", base.height_m);
  prov.add("date_utc", o.date).add("step", o.step);
  prov.add("sun", "NREL SPA, geometric elevation drives the sky; apparent elevation reported");
  written.insert(written.begin(), dir / "day.csv");
  t.write(dir / "day.csv", prov);
  study_plots(dir, "UTC time on " + o.date, "hours since " + o.date + " 00:00 UTC", hours, rows, labels, written);
  return written;
}

// ------------------------------------------------------------------ sweep
scene::SweepOutputs sweep_point(const scene::Scene& s, const QualityOptions& q) {
  const SunPlacement sun = sun_of_scene(s);
  const auto m = make_sky_model(q.scene_for(s), q.sky(s), sun.distance_au);
  const SkySummary sm = summarize_sky(*m->sky, std::max(sun.observer_height_m, 0.0), sun.direction());
  scene::SweepOutputs out = {{"sun_elevation_deg", sun.elevation_deg}, {"sun_azimuth_deg", sun.azimuth_deg}};
  const auto v = study_values(sm);
  for (std::size_t i = 0; i < v.size(); ++i) out.emplace_back(kStudyColumns[i], v[i]);
  out.emplace_back("table_build_time_s", m->build_time_s);
  return out;
}

// --------------------------------------------------------- converge sky
struct ConvergeSky {
  std::string scene_file, output = "sky_convergence";
  bool quick = false;
  int threads = 0;
};

std::vector<fs::path> run_converge_sky(const ConvergeSky& o) {
  auto s = load_or_default(o.scene_file);
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
  std::vector<io::StudyRow> out;
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
      out.push_back({std::string(k ? "twilight" : "day") + " q=" + std::to_string(st.samples), name.str(), emax[k],
                     n[k] ? std::sqrt(esum[k] / n[k]) : 0.0, build + per_ray * 1024.0 * 512.0,
                     {double(st.shells), double(st.segments), double(st.samples), st.max_tau, build, per_ray,
                      ref_time / rays.size()}});
  }
  io::StudySpec spec;
  spec.title = "Single-scattering sky: error vs run time (1024x512 image, " + std::to_string(solar.size()) + " wavelengths)";
  spec.time_axis_label = "run time for a 1024x512 image incl. table build, one core [s]";
  spec.error_axis_label = "max relative error of spectral radiance";
  spec.extra_columns = {"shells",       "segments",       "samples_per_segment",     "max_piece_optical_depth",
                        "build_time_s", "time_per_ray_s", "reference_time_per_ray_s"};
  auto prov = io::Provenance::current();
  prov.add("scene", s.source);
  prov.add("rays", static_cast<double>(rays.size()));
  prov.add("directions", "view elevations x azimuths relative to the sun x sun elevations; method 'day' = rays with "
                         "the sun >= 0 deg, 'twilight' = sun below the horizon; error over wavelengths where the "
                         "reference exceeds 1e-6 of the ray's maximum");
  prov.add("reference", "adaptive Gauss-Kronrod over the view ray, exact optical depths, rel tol 1e-6");
  prov.add("time_s", "table build + 524288 rays x measured time per ray (single thread)");
  return io::write_study(fs::path(o.output), spec, out, prov);
}

}  // namespace

void register_sky_commands(CLI::App& app) {
  {
    static SkyCmd c;
    auto* s = app.add_subcommand("sky", "Render the single-scattering sky (EXR, tone-mapped PNG, JSON summary)");
    s->add_option("--scene", c.scene_file, "Scene file (default: built-in scene)");
    s->add_option("--lat", c.lat, "Observer latitude [deg]");
    s->add_option("--lon", c.lon, "Observer longitude [deg, east positive]");
    s->add_option("--height", c.height, "Observer height [m]")->capture_default_str();
    s->add_option("--time", c.time, "UTC time, ISO 8601 (sun from NREL SPA)");
    s->add_option("--sun-elevation", c.sun_elevation, "Sun elevation [deg] instead of place and time");
    s->add_option("--sun-azimuth", c.sun_azimuth, "Sun azimuth [deg from north towards east]")->capture_default_str();
    s->add_option("--projection", c.projection, "equirect or fisheye")->capture_default_str();
    s->add_option("--size", c.size, "Image size WxH")->capture_default_str();
    s->add_option("-o,--output", c.output, "EXR file to write")->required();
    s->add_option("--png", c.png, "Tone-mapped PNG to write");
    s->add_flag("--spectral", c.spectral, "Add one channel per wavelength (L_<nm>nm)");
    s->add_flag("--json", c.json, "Print a JSON summary");
    s->add_option("--device", c.device, "cpu, gpu or auto (GPU if a headless EGL device exists, else CPU)")
        ->capture_default_str();
    add_quality_options(s, c.q);
    s->callback([] { run_sky(c); });
  }
  auto* study = app.add_subcommand("study", "Sky colour against sun elevation or time of day")->require_subcommand(1);
  {
    static ElevationStudy o;
    auto* s = study->add_subcommand("sun-elevation", "Zenith and horizon colour and luminance against sun elevation");
    s->add_option("--scene", o.scene_file, "Scene file (default: built-in scene)");
    s->add_option("--from", o.from, "First sun elevation [deg]")->capture_default_str();
    s->add_option("--to", o.to, "Last sun elevation [deg]")->capture_default_str();
    s->add_option("--step", o.step, "Step [deg]")->capture_default_str();
    s->add_option("--azimuth", o.azimuth, "Sun azimuth [deg]")->capture_default_str();
    s->add_option("-o,--output", o.output, "Output folder")->required();
    add_quality_options(s, o.q);
    s->callback([] {
      ProgressStep step("study sun-elevation");
      for (const auto& f : run_elevation_study(o, nullptr, step.callback())) std::cout << f.string() << "\n";
    });
  }
  {
    static DayStudy o;
    auto* s = study->add_subcommand("day", "Sky colour through a day at a place (sun from NREL SPA), with EXR frames");
    s->add_option("--scene", o.scene_file, "Scene file (default: built-in scene)");
    s->add_option("--lat", o.lat, "Latitude [deg]")->required();
    s->add_option("--lon", o.lon, "Longitude [deg, east positive]")->required();
    s->add_option("--height", o.height, "Height [m]")->capture_default_str();
    s->add_option("--date", o.date, "UTC date YYYY-MM-DD")->required();
    s->add_option("--step", o.step, "Time step (e.g. 10min, 1h)")->capture_default_str();
    s->add_option("--frame-size", o.frame_size, "Size of the EXR frames WxH")->capture_default_str();
    s->add_flag("!--no-frames", o.frames, "Skip the EXR frames");
    s->add_option("-o,--output", o.output, "Output folder")->required();
    add_quality_options(s, o.q);
    s->callback([] {
      ProgressStep step("study day");
      for (const auto& f : run_day_study(o, step.callback())) std::cout << f.string() << "\n";
    });
  }
  {
    auto* sw = app.add_subcommand("sweep", "Evaluate the sky over a grid or list of scene parameters (resumable, shardable)");
    static std::string file, out, shard = "1/1";
    static bool resume = false;
    static QualityOptions q;
    sw->add_option("sweep", file, "Sweep file (TOML)");
    sw->add_option("-o,--output", out, "Output folder");
    sw->add_flag("--resume", resume, "Skip points already in the journal of an interrupted run");
    sw->add_option("--shard", shard, "Run shard k of N (k/N), merge later with `atmosh sweep merge`")->capture_default_str();
    add_quality_options(sw, q);
    static std::vector<std::string> merge_in;
    static std::string merge_out;
    auto* merge = sw->add_subcommand("merge", "Join shard CSVs of one sweep (checks every point appears once)");
    merge->add_option("inputs", merge_in, "Shard CSV files")->required();
    merge->add_option("-o,--output", merge_out, "Merged CSV")->required();
    merge->callback([] {
      std::vector<fs::path> in(merge_in.begin(), merge_in.end());
      scene::merge_sweep(in, merge_out);
      std::cout << "merged " << in.size() << " file(s) into " << merge_out << "\n";
    });
    sw->callback([sw] {
      if (sw->got_subcommand("merge")) return;
      if (file.empty()) throw InputError("a sweep file is required");
      if (out.empty()) throw InputError("-o is required (output folder)");
      scene::SweepOptions o;
      o.out_dir = out;
      o.resume = resume;
      const auto slash = shard.find('/');
      try {
        if (slash == std::string::npos) throw std::invalid_argument("");
        o.shard = std::stoi(shard.substr(0, slash));
        o.shards = std::stoi(shard.substr(slash + 1));
      } catch (const std::logic_error&) {
        throw InputError("--shard '" + shard + "' is not k/N");
      }
      const QualityOptions qq = q.checked();
      o.threads = qq.threads;
      o.settings = qq.settings();
      const auto spec = scene::load_sweep(file);
      ProgressStep step("sweep " + file);
      o.progress = step.callback();
      const auto r = scene::run_sweep(spec, [qq](const scene::Scene& s) { return sweep_point(s, qq); }, o);
      std::cout << "sweep: " << r.points_in_shard << " point(s) of " << r.points_total << " in " << r.csv.string()
                << " (" << r.points_resumed << " resumed, " << r.points_computed << " computed)\n";
    });
  }
  {
    static ConvergeSky o;
    auto* c = app.get_subcommand("converge")->add_subcommand(
        "sky", "Error of the fast sky integrator against the exact reference, against run time");
    c->add_option("--scene", o.scene_file, "Scene file (default: built-in scene)");
    c->add_option("-o,--output", o.output, "Output stem (writes STEM.csv and STEM.png)")->capture_default_str();
    c->add_flag("--quick", o.quick, "Few rays and settings");
    c->add_option("--threads", o.threads, "Threads for the reference (0 = the CPUs this process may use)");
    c->callback([] {
      ConvergeSky x = o;
      x.threads = threads_option(o.threads);
      ProgressStep step("converge sky");
      for (const auto& f : run_converge_sky(x)) std::cout << f.string() << "\n";
    });
  }
}

std::vector<fs::path> write_sky_sh(const SkyModel& model, const SunPlacement& sun, int bands, const fs::path& csv) {
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
  std::vector<std::vector<double>> coeffs;
  for (const auto& c : ch) coeffs.push_back(sh::analyse(grid, c.data()));
  io::CsvTable t({"l", "m", "index", "r", "g", "b"});
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m) {
      const int i = l * (l + 1) + m;
      t.add_row({std::int64_t{l}, std::int64_t{m}, std::int64_t{i}, coeffs[0][static_cast<std::size_t>(i)],
                 coeffs[1][static_cast<std::size_t>(i)], coeffs[2][static_cast<std::size_t>(i)]});
    }
  auto prov = sky_provenance(model, sun);
  prov.add("sh", "real orthonormal SH with Condon-Shortley phase, index l(l+1)+m, " + std::to_string(bands) + " bands");
  prov.add("sh_frame", "x = east, y = north, z = up (observer's ENU); phi from east towards north");
  prov.add("sh_units", "coefficients of linear sRGB radiance (Y in cd/m^2) times sr");
  prov.add("value_units", "cd/m^2");
  prov.add("sh_projection", "Gauss-Legendre grid " + std::to_string(grid.nlat) + " x " + std::to_string(grid.nphi));
  t.write(csv, prov);
  // Band energy (rotation-invariant power per band) of the luminance-like green channel and all three.
  fs::path stem = csv;
  stem.replace_extension();
  const fs::path bcsv = stem.string() + "_bands.csv", bpng = stem.string() + "_bands.png";
  io::CsvTable bt({"l", "energy_r", "energy_g", "energy_b", "cumulative_fraction_g"});
  std::vector<std::vector<double>> e;
  for (const auto& c : coeffs) e.push_back(sh::band_energy(c, bands));
  const auto cum = sh::cumulative_energy_fraction(e[1]);
  // Coefficients of linear sRGB radiance on the luminance scale (cd/m^2) times sr.
  io::PlotSpec p = io::band_energy_plot_spec("Band energy of the sky's SH (linear sRGB channels)",
                                             {"red", "green", "blue"}, e, "cd/m^2");
  const std::array<double, 3> cols[] = {{0.85, 0.2, 0.2}, {0.2, 0.65, 0.2}, {0.2, 0.3, 0.85}};
  for (int c = 0; c < 3; ++c) p.series[static_cast<std::size_t>(c)].color = cols[c];
  for (int l = 0; l < bands; ++l) {
    const auto L = static_cast<std::size_t>(l);
    bt.add_row({std::int64_t{l}, e[0][L], e[1][L], e[2][L], cum[L]});
  }
  bt.write(bcsv, prov);
  io::write_plot_png(bpng, p);
  return {csv, bcsv, bpng};
}

void run_scene(const scene::Scene& s, const fs::path& dir, bool quick, std::vector<fs::path>& written,
               const std::string& device) {
  check_device(device);
  scene::check_outputs(s);  // what each kind needs (the scene reader checked it too)
  std::optional<SunPlacement> sun;
  std::unique_ptr<SkyModel> model;
  auto need_sky = [&]() -> const SkyModel& {
    if (!model) {
      sun = sun_of_scene(s);
      model = make_sky_model(s, QualityOptions{}.sky(s), sun->distance_au);
    }
    return *model;
  };
  auto image_size = [&](const scene::Output& out) {
    return std::array<int, 2>{quick ? std::min(64, out.size[0]) : out.size[0], quick ? std::min(32, out.size[1]) : out.size[1]};
  };
  // One runner per kind of scene::output_kinds(); `file` is dir/out.file, `stem` without its extension.
  using Runner = std::function<void(const scene::Output&, const fs::path& file, const fs::path& stem)>;
  const std::map<std::string_view, Runner> runners = {
      {"sky-image",
       [&](const scene::Output& out, const fs::path& file, const fs::path&) {
         const SkyModel& m = need_sky();
         const auto [w, h] = image_size(out);
         std::string used;
         const auto img = render_sky_on(device, *m.sky, parse_sky_projection(out.projection), w, h,
                                        std::max(sun->observer_height_m, 0.0), sun->direction(), out.spectral, 0, used);
         fs::path png = file;
         png.replace_extension(".png");
         auto prov = sky_provenance(m, *sun);
         prov.add("device", used);
         write_sky_image(img, file, png, prov, out.projection, *sun);
         written.push_back(file);
         written.push_back(png);
         fs::path side = png;
         side += ".json";  // the tone mapping (write_sky_image)
         written.push_back(side);
       }},
      {"sh-coefficients",
       [&](const scene::Output& out, const fs::path& file, const fs::path&) {
         const SkyModel& m = need_sky();
         for (const auto& f : write_sky_sh(m, *sun, out.bands > 0 ? out.bands : 3, file)) written.push_back(f);
       }},
      {"sun-track",
       [&](const scene::Output&, const fs::path&, const fs::path& stem) {
         const auto& o = *s.observer;  // check_outputs: a sun-track has an [observer]
         for (const auto& f : write_sun_track(o.latitude_deg, o.longitude_deg, o.height_m, o.time_utc,
                                              quick ? 1800.0 : 600.0, stem))
           written.push_back(f);
       }},
      {"sun-elevation-study",
       [&](const scene::Output&, const fs::path&, const fs::path& stem) {
         ElevationStudy e;
         e.output = stem.string();
         e.step = quick ? 12 : 1;
         for (const auto& f : run_elevation_study(e, &s)) written.push_back(f);
       }},
      {"lut-convergence",
       [&](const scene::Output&, const fs::path&, const fs::path& stem) {
         for (const auto& f : write_lut_convergence(s.atmosphere, stem, quick)) written.push_back(f);
       }},
      {"optical-depth",
       [&](const scene::Output&, const fs::path&, const fs::path& stem) {
         for (const auto& f : write_optical_depth_table(s.atmosphere, stem)) written.push_back(f);
       }},
  };
  // Before any work: a runner for every output, and the memory the largest one holds.
  std::size_t peak = 0;
  std::string peak_what;
  for (const auto& out : s.outputs) {
    if (!runners.count(out.kind)) throw InputError(s.source + ": output kind '" + out.kind + "' has no runner");
    const std::size_t bytes = scene_output_bytes(s, out, image_size(out));
    if (bytes > peak) peak = bytes, peak_what = s.source + ": output '" + out.file + "' (" + out.kind + ")";
  }
  if (peak > 0) check_memory(peak, peak_what);
  for (std::size_t oi = 0; oi < s.outputs.size(); ++oi) {
    const auto& out = s.outputs[oi];
    ProgressStep step("output[" + std::to_string(oi) + "] " + out.kind + " " + out.file);
    const fs::path file = dir / out.file;
    fs::path stem = file;
    stem.replace_extension();
    runners.at(out.kind)(out, file, stem);
  }
}

void demo_sky(DemoContext& ctx) {
  ProgressStep step("demo: sky error against run time");
  ConvergeSky c;
  c.quick = ctx.quick;
  c.output = (ctx.out_dir / "sky_convergence").string();
  for (const auto& f : run_converge_sky(c)) ctx.written.push_back(f);
}

}  // namespace atmosh::cli
