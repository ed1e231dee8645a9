// atmosh sky, atmosh study sun-elevation|day, atmosh sweep [merge], atmosh converge sky.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
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
#include "atmosh/studies/sky.hpp"
#include "atmosh/studies/sky_studies.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {

namespace fs = std::filesystem;
using namespace atmosh::atmo;
using studies::SunPlacement;
using studies::sun_from_place;
using studies::sun_of_scene;
using studies::make_sky_model;
using studies::sky_provenance;
using studies::write_sky_image;
using studies::sky_output_bytes;

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
  // The options as the studies take them (InputError naming the option for a bad name).
  studies::SkySettings settings_for_studies() const {
    studies::SkySettings k;
    k.shells = shells;
    k.segments = segments;
    k.samples = samples;
    k.max_piece_tau = max_piece_tau;
    if (!sun_model.empty()) k.sun_model = parse_sun_model(sun_model);
    if (!scattering.empty()) k.scattering = parse_scattering_method(scattering, "--scattering");
    if (orders) {
      if (*orders < 1 || *orders > 64) throw InputError("--orders " + std::to_string(*orders) + " is outside [1, 64]");
      k.orders = *orders;
    }
    k.threads = threads;
    return k;
  }
  SkyOptions sky(const scene::Scene& s) const { return settings_for_studies().sky(s); }
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
  std::string scene_file, time, projection = "equirect", size = "512x256", output, png, device = "cpu", format = "exr";
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
  return studies::render_sky_on(device, sky, proj, width, height, altitude_m, sun, spectral, threads, used,
                                [](const std::string& m) { std::cerr << "atmosh: " << m << "\n"; });
}

namespace {

void run_sky(const SkyCmd& cmd) {
  SkyCmd c = cmd;
  c.q = cmd.q.checked();
  if (c.output.empty()) throw InputError("-o is required (the EXR file to write)");
  if (c.format != "exr" && c.format != "netcdf") throw InputError("--format: '" + c.format + "' is not exr or netcdf");
  const bool netcdf = c.format == "netcdf" || fs::path(c.output).extension() == ".nc";
  check_output_file(c.output, {netcdf ? ".nc" : ".exr"}, "-o");
  if (netcdf && c.projection != "equirect")
    throw InputError("--projection " + c.projection + ": netCDF sky images are equirect (elevation x azimuth)");
  if (netcdf && !c.png.empty()) throw InputError("--png: only with an EXR output");
  if (!c.png.empty()) check_output_file(c.png, {".png"}, "--png");
  const auto s = c.q.scene_for(load_or_default(c.scene_file));
  const SunPlacement sun = resolve_sun(c, s);
  const auto proj = parse_sky_projection(c.projection);
  const auto size = parse_size(c.size, "--size");
  check_memory(sky_output_bytes(size[0], size[1], spectrum_wavelengths(s.atmosphere.spectrum).size(), c.spectral),
               "--size " + c.size + (c.spectral ? " --spectral" : ""));
  if (c.device == "cpu")  // the estimate is of the CPU's loop
    check_time(studies::sky_rays_work(s, c.q.settings_for_studies(), mul_units(size[0], size[1])), c.q.threads, "--size " + c.size);
  const auto model = make_sky_model(s, c.q.sky(s), sun.distance_au);
  const double h = std::max(sun.observer_height_m, 0.0);
  std::string used;
  const SkyImage img = render_sky_on(c.device, *model->sky, proj, size[0], size[1], h, sun.direction(), c.spectral,
                                     c.q.threads, used);
  auto prov = sky_provenance(*model, sun);
  prov.add("device", used);
  double exposure = std::numeric_limits<double>::quiet_NaN();  // JSON null: no tone mapping in netCDF
  if (netcdf)
    studies::write_sky_netcdf_image(img, c.output, prov, c.projection, sun);
  else
    exposure = write_sky_image(img, c.output, c.png, prov, c.projection, sun);
  const SkySummary sm = summarize_sky(*model->sky, h, sun.direction());
  if (c.json) {
    nlohmann::json j = {{"exr", netcdf ? nlohmann::json(nullptr) : nlohmann::json(c.output)},
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
    if (netcdf) j["netcdf"] = c.output;
    print_json(j);
  } else {
    std::cout << "sky: " << c.output << (c.png.empty() ? "" : " and " + c.png) << " (" << img.rays << " rays in "
              << img.seconds << " s; sun " << sun.describe() << "; zenith " << sm.zenith.xyz.Y << " cd/m^2)\n";
  }
}

// ----------------------------------------------------- study sun-elevation
struct ElevationStudy {
  std::string scene_file, output;
  double from = -18, to = 90, step = 1, azimuth = 180;
  QualityOptions q;
  bool netcdf = false;
};

std::vector<fs::path> run_elevation_study(const ElevationStudy& given_options, const ProgressCallback& progress) {
  ElevationStudy o = given_options;
  o.q = given_options.q.checked();
  if (o.output.empty()) throw InputError("-o is required (output folder)");
  require_range(o.from, -90, 90, "--from");
  require_range(o.to, -90, 90, "--to");
  if (!(o.step > 0)) throw InputError("--step " + io::format_double(o.step) + " must be > 0");
  if (o.to < o.from) throw InputError("--to " + io::format_double(o.to) + " is below --from");
  studies::ElevationStudyOptions e;
  e.from_deg = o.from;
  e.to_deg = o.to;
  e.step_deg = o.step;
  e.azimuth_deg = o.azimuth;
  check_memory(studies::elevation_study_bytes(e), "--from " + io::format_double(o.from) + " --to " +
                                                      io::format_double(o.to) + " --step " + io::format_double(o.step));
  check_output_dir(o.output, "-o");
  const auto s = load_or_default(o.scene_file);
  e.sky = o.q.settings_for_studies();
  check_time(studies::elevation_study_work(s, e), o.q.threads, "--step " + io::format_double(o.step));
  return studies::write_elevation_study(studies::sun_elevation_study(s, e, progress), o.output, o.netcdf);
}

// ------------------------------------------------------------- study day
struct DayStudy {
  std::string scene_file, date, step = "10min", output, frame_size = "128x64";
  std::optional<double> lat, lon;
  double height = 0;
  bool frames = true, netcdf = false;
  QualityOptions q;
};

std::vector<fs::path> run_day_study(const DayStudy& given_options, const ProgressCallback& progress) {
  DayStudy o = given_options;
  o.q = given_options.q.checked();
  if (o.output.empty()) throw InputError("-o is required (output folder)");
  if (!o.lat || !o.lon) throw InputError("--lat and --lon are required");
  if (o.date.size() != 10) throw InputError("--date '" + o.date + "' is not YYYY-MM-DD");
  parse_iso8601(o.date + "T00:00:00Z");  // InputError for a date that is not one
  studies::DayStudyOptions d;
  d.date = o.date;
  d.step_s = parse_duration_s(o.step);
  d.step_text = o.step;
  const auto fsize = parse_size(o.frame_size, "--frame-size");
  check_output_dir(o.output, "-o");
  if (o.frames)  // one frame at a time: the largest holding is one sky image
    check_memory(sky_output_bytes(fsize[0], fsize[1], 0, false), "--frame-size " + o.frame_size);
  d.latitude_deg = require_range(*o.lat, -90, 90, "--lat");
  d.longitude_deg = require_range(*o.lon, -180, 180, "--lon");
  d.height_m = require_range(o.height, -500, 1e8, "--height");
  d.frames = o.frames;
  d.frame_width = fsize[0];
  d.frame_height = fsize[1];
  const auto s = load_or_default(o.scene_file);
  d.sky = o.q.settings_for_studies();
  check_time(studies::day_study_work(s, d), o.q.threads, "--step " + o.step + (o.frames ? " --frame-size " + o.frame_size : ""));
  const fs::path dir = o.output;
  std::vector<fs::path> frames;
  const auto st = studies::day_study(
      s, d, [&](studies::DayFrame&& f) { frames.push_back(studies::write_day_frame(f, dir)); }, progress);
  const auto files = studies::write_day_study(st, dir, o.netcdf);  // day.csv, then the plots
  std::vector<fs::path> written = {files.front()};
  written.insert(written.end(), frames.begin(), frames.end());
  written.insert(written.end(), files.begin() + 1, files.end());
  return written;
}

// --------------------------------------------------------- converge sky
struct ConvergeSky {
  std::string scene_file, output = "sky_convergence";
  bool quick = false;
  int threads = 0;
};

std::vector<fs::path> run_converge_sky(const ConvergeSky& o) {
  check_study_stem(o.output, "-o");
  const auto s = load_or_default(o.scene_file);
  studies::ConvergeSkyOptions c;
  c.quick = o.quick;
  c.threads = o.threads;
  return studies::write_converge_sky(studies::converge_sky(s, c), fs::path(o.output));
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
    s->add_option("-o,--output", c.output, "EXR file to write (a name ending in .nc: netCDF-CF)")->required();
    s->add_option("--format", c.format, "exr | netcdf (netCDF-CF: X, Y, Z and the spectral cube on elevation x "
                                        "azimuth; equirect only)")
        ->capture_default_str();
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
    add_format_option(s, o.netcdf);
    s->callback([] {
      ProgressStep step("study sun-elevation");
      for (const auto& f : run_elevation_study(o, step.callback())) std::cout << f.string() << "\n";
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
    add_format_option(s, o.netcdf);
    s->callback([] {
      ProgressStep step("study day");
      for (const auto& f : run_day_study(o, step.callback())) std::cout << f.string() << "\n";
    });
  }
  {
    auto* sw = app.add_subcommand("sweep", "Evaluate the sky over a grid or list of scene parameters (resumable, shardable)");
    static std::string file, out, shard = "1/1";
    static bool resume = false, netcdf = false;
    static QualityOptions q;
    sw->add_option("sweep", file, "Sweep file (TOML)");
    sw->add_option("-o,--output", out, "Output folder");
    sw->add_flag("--resume", resume, "Skip points already in the journal of an interrupted run");
    sw->add_option("--shard", shard, "Run shard k of N (k/N), merge later with `atmosh sweep merge`")->capture_default_str();
    add_quality_options(sw, q);
    add_format_option(sw, netcdf);
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
      const studies::SkySettings k = qq.settings_for_studies();
      const auto r = scene::run_sweep(spec, [k](const scene::Scene& s) { return studies::sweep_point(s, k); }, o);
      if (netcdf) io::write_sweep_csv_as_netcdf(r.csv, fs::path(r.csv).replace_extension(".nc"), spec.keys);
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
    add_format_option(c, o.output);
    c->callback([] {
      ConvergeSky x = o;
      x.threads = threads_option(o.threads);
      ProgressStep step("converge sky");
      for (const auto& f : run_converge_sky(x)) std::cout << f.string() << "\n";
    });
  }
}

void demo_sky(DemoContext& ctx) {
  ProgressStep step("demo: sky error against run time");
  for (const auto& f : studies::demo_sky(ctx.out_dir, ctx.quick)) ctx.written.push_back(f);
}

}  // namespace atmosh::cli
