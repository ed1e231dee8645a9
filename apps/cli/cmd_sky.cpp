// atmosh sky, atmosh study sun-elevation|day, atmosh sweep [merge], atmosh converge sky.
#include <iostream>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <utility>

#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/netcdf.hpp"
#include "atmosh/scene/sweep.hpp"
#include "atmosh/studies/sky.hpp"
#include "atmosh/studies/sky_studies.hpp"
#include "atmosh/studies/summaries.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {

namespace fs = std::filesystem;

struct SkyCmd {
  std::string scene_file, projection = "equirect", size = "512x256", output, png, device = "cpu", format = "exr";
  studies::SunRequest sun;
  bool spectral = false, json = false;
  studies::SkySettings q;
};

// A notice that prints each distinct message once (a sweep builds a sky per point, on
// several threads: one line per decision, not per point).
studies::Notice notice_once() {
  auto seen = std::make_shared<std::pair<std::mutex, std::set<std::string>>>();
  return [seen](const std::string& m) {
    const std::lock_guard<std::mutex> lock(seen->first);
    if (seen->second.insert(m).second) notice(m);
  };
}

void run_sky(const SkyCmd& c) {
  const studies::SkySettings q = checked_quality(c.q);
  if (c.output.empty()) throw InputError("-o is required (the EXR file to write)");
  if (c.format != "exr" && c.format != "netcdf") throw InputError("--format: '" + c.format + "' is not exr or netcdf");
  const bool netcdf = c.format == "netcdf" || fs::path(c.output).extension() == ".nc";
  check_output_file(c.output, {netcdf ? ".nc" : ".exr"}, "-o");
  if (netcdf && c.projection != "equirect")
    throw InputError("--projection " + c.projection + ": netCDF sky images are equirect (elevation x azimuth)");
  if (netcdf && !c.png.empty()) throw InputError("--png: only with an EXR output");
  if (!c.png.empty()) check_output_file(c.png, {".png"}, "--png");
  check_device(c.device);  // every option before the work: make_sky_model builds the tables (seconds)
  const auto proj = atmo::parse_sky_projection(c.projection);
  const auto size = parse_size(c.size, "--size");
  auto s = q.scene_for(scene_or_default(c.scene_file));
  const studies::SunPlacement sun = studies::place_sun(s, c.sun);
  check_memory(studies::sky_output_bytes(size[0], size[1], atmo::spectrum_wavelengths(s.atmosphere.spectrum).size(),
                                         c.spectral),
               "--size " + c.size + (c.spectral ? " --spectral" : ""));
  if (c.device == "cpu")  // the estimate is of the CPU's loop
    check_time(studies::sky_rays_work(s, q, mul_units(size[0], size[1])), q.threads, "--size " + c.size);
  // Orders tables built on the GPU stay there (the image binds them); the summary and
  // the irradiance read back the part their lookups at the observer need, below.
  const std::string orders_device = studies::use_orders_tables_device(s, c.device, notice, true);
  const auto model = studies::make_sky_model(s, q.sky(s), sun.distance_au);
  model->orders_tables_device = orders_device;  // in its provenance (sky_provenance)
  const double h = std::max(sun.observer_height_m, 0.0);
  std::string used;
  const atmo::SkyImage img = studies::render_sky_on(c.device, *model->sky, proj, size[0], size[1], h, sun.direction(),
                                                    c.spectral, q.threads, used, notice);
  // The summary (and with --json the irradiance) look up the orders tables at the
  // observer on the CPU: only that part of a table kept on the GPU comes back.
  if (const auto rb = studies::read_back_orders_at(*model, h, sun.direction()); rb.bytes > 0) {
    const auto* o = model->sky->orders_tables();
    notice("orders tables: " + std::to_string(rb.bytes) + " of " +
           std::to_string(o->texels() * o->wavelengths() * sizeof(float)) +
           " bytes read back (what the lookups at the observer need; the rest kept on the GPU) in " +
           io::format_double(rb.seconds) + " s, for the summary" + (c.json ? " and the irradiance" : ""));
  }
  auto prov = studies::sky_provenance(*model, sun);
  prov.add("device", used);
  double exposure = std::numeric_limits<double>::quiet_NaN();  // JSON null: no tone mapping in netCDF
  if (netcdf)
    studies::write_sky_netcdf_image(img, c.output, prov, c.projection, sun);
  else
    exposure = studies::write_sky_image(img, c.output, c.png, prov, c.projection, sun);
  if (c.json)
    return print_json(studies::sky_json(*model, sun, img, exposure, used,
                                        {netcdf ? "" : c.output, c.png, netcdf ? c.output : ""}));
  std::cout << "sky: " << c.output << (c.png.empty() ? "" : " and " + c.png) << " (" << img.rays << " rays in "
            << img.seconds << " s; sun " << sun.describe() << "; zenith "
            << atmo::summarize_sky(*model->sky, h, sun.direction()).zenith.xyz.Y << " cd/m^2)\n";
}

struct ElevationCmd {
  std::string scene_file, output;
  bool netcdf = false;
  studies::ElevationStudyOptions e;
};

std::vector<fs::path> run_elevation_study(const ElevationCmd& o, const ProgressCallback& progress) {
  studies::ElevationStudyOptions e = o.e;
  e.sky = checked_quality(o.e.sky);
  e.sky.notice = notice_once();
  if (o.output.empty()) throw InputError("-o is required (output folder)");
  require_range(e.from_deg, -90, 90, "--from");
  require_range(e.to_deg, -90, 90, "--to");
  if (!(e.step_deg > 0)) throw InputError("--step " + io::format_double(e.step_deg) + " must be > 0");
  if (e.to_deg < e.from_deg) throw InputError("--to " + io::format_double(e.to_deg) + " is below --from");
  check_memory(studies::elevation_study_bytes(e), "--from " + io::format_double(e.from_deg) + " --to " +
                                                      io::format_double(e.to_deg) + " --step " +
                                                      io::format_double(e.step_deg));
  check_output_dir(o.output, "-o");
  const auto s = scene_or_default(o.scene_file);
  check_time(studies::elevation_study_work(s, e), e.sky.threads, "--step " + io::format_double(e.step_deg));
  return studies::write_elevation_study(studies::sun_elevation_study(s, e, progress), o.output, o.netcdf);
}

struct DayCmd {
  std::string scene_file, step = "10min", output, frame_size = "128x64";
  studies::DayStudyOptions d;
  bool netcdf = false;
};

std::vector<fs::path> run_day_study(const DayCmd& o, const ProgressCallback& progress) {
  studies::DayStudyOptions d = o.d;
  d.sky = checked_quality(o.d.sky);
  d.sky.notice = notice_once();
  if (o.output.empty()) throw InputError("-o is required (output folder)");
  if (d.date.size() != 10) throw InputError("--date '" + d.date + "' is not YYYY-MM-DD");
  atmo::parse_iso8601(d.date + "T00:00:00Z");  // InputError for a date that is not one
  d.step_s = atmo::parse_duration_s(o.step);
  d.step_text = o.step;
  const auto fsize = parse_size(o.frame_size, "--frame-size");
  check_output_dir(o.output, "-o");
  if (d.frames)  // one frame at a time: the largest holding is one sky image
    check_memory(studies::sky_output_bytes(fsize[0], fsize[1], 0, false), "--frame-size " + o.frame_size);
  require_range(d.latitude_deg, -90, 90, "--lat");
  require_range(d.longitude_deg, -180, 180, "--lon");
  require_range(d.height_m, -500, 1e8, "--height");
  d.frame_width = fsize[0];
  d.frame_height = fsize[1];
  const fs::path dir = o.output;
  const auto s = scene_or_default(o.scene_file);
  check_time(studies::day_study_work(s, d), d.sky.threads,
             "--step " + o.step + (d.frames ? " --frame-size " + o.frame_size : ""));
  std::vector<fs::path> frames;
  const auto st = studies::day_study(
      s, d,
      [&](studies::DayFrame&& f) { frames.push_back(studies::write_day_frame(f, dir)); }, progress);
  const auto files = studies::write_day_study(st, dir, o.netcdf);  // day.csv, then the plots
  std::vector<fs::path> written = {files.front()};
  written.insert(written.end(), frames.begin(), frames.end());
  written.insert(written.end(), files.begin() + 1, files.end());
  return written;
}

}  // namespace

void register_sky_commands(CLI::App& app) {
  {
    static SkyCmd c;
    auto* s = app.add_subcommand("sky",
                                 "Render the sky: single scattering, successive orders or the all-orders "
                                 "approximation (EXR, tone-mapped PNG, JSON summary)");
    add_scene_option(s, c.scene_file);
    s->add_option("--lat", c.sun.lat_deg, "Observer latitude [deg]");
    s->add_option("--lon", c.sun.lon_deg, "Observer longitude [deg, east positive]");
    s->add_option("--height", c.sun.height_m, "Observer height [m]")->capture_default_str();
    s->add_option("--time", c.sun.time_utc, "UTC time, ISO 8601 (sun from NREL SPA)");
    s->add_option("--sun-elevation", c.sun.elevation_deg, "Sun elevation [deg] instead of place and time");
    s->add_option("--sun-azimuth", c.sun.azimuth_deg, "Sun azimuth [deg from north towards east]")->capture_default_str();
    s->add_option("--projection", c.projection, "equirect or fisheye")->capture_default_str();
    s->add_option("--size", c.size, "Image size WxH")->capture_default_str();
    s->add_option("-o,--output", c.output, "EXR file to write (a name ending in .nc: netCDF-CF)")->required();
    s->add_option("--format", c.format, "exr | netcdf (netCDF-CF: X, Y, Z and the spectral cube on elevation x "
                                        "azimuth; equirect only)")
        ->capture_default_str();
    s->add_option("--png", c.png, "Tone-mapped PNG to write");
    s->add_flag("--spectral", c.spectral, "Add one channel per wavelength (L_<nm>nm)");
    add_json_flag(s, c.json);
    add_device_option(s, c.device, "where the image is rendered");
    add_quality_options(s, c.q);
    s->callback([] { run_sky(c); });
  }
  auto* study = app.add_subcommand("study", "Sky colour against sun elevation or time of day")->require_subcommand(1);
  {
    static ElevationCmd o;
    auto* s = study->add_subcommand("sun-elevation", "Zenith and horizon colour and luminance against sun elevation");
    add_scene_option(s, o.scene_file);
    s->add_option("--from", o.e.from_deg, "First sun elevation [deg]")->capture_default_str();
    s->add_option("--to", o.e.to_deg, "Last sun elevation [deg]")->capture_default_str();
    s->add_option("--step", o.e.step_deg, "Step [deg]")->capture_default_str();
    s->add_option("--azimuth", o.e.azimuth_deg, "Sun azimuth [deg]")->capture_default_str();
    s->add_option("-o,--output", o.output, "Output folder")->required();
    add_format_option(s, o.netcdf);
    add_quality_options(s, o.e.sky);
    add_device_option(s, o.e.sky.device, "where the orders tables are built (--scattering orders)");
    s->callback([] { run_step("study sun-elevation", [](auto& p) { print_files(run_elevation_study(o, p)); }); });
  }
  {
    static DayCmd o;
    auto* s = study->add_subcommand("day", "Sky colour through a day at a place (sun from NREL SPA), with EXR frames");
    add_scene_option(s, o.scene_file);
    s->add_option("--lat", o.d.latitude_deg, "Latitude [deg]")->required();
    s->add_option("--lon", o.d.longitude_deg, "Longitude [deg, east positive]")->required();
    s->add_option("--height", o.d.height_m, "Height [m]")->capture_default_str();
    s->add_option("--date", o.d.date, "UTC date YYYY-MM-DD")->required();
    s->add_option("--step", o.step, "Time step (e.g. 10min, 1h)")->capture_default_str();
    s->add_option("--frame-size", o.frame_size, "Size of the EXR frames WxH")->capture_default_str();
    s->add_flag("!--no-frames", o.d.frames, "Skip the EXR frames");
    s->add_option("-o,--output", o.output, "Output folder")->required();
    add_format_option(s, o.netcdf);
    add_quality_options(s, o.d.sky);
    add_device_option(s, o.d.sky.device, "where the orders tables are built (--scattering orders)");
    s->callback([] { run_step("study day", [](auto& p) { print_files(run_day_study(o, p)); }); });
  }
  {
    auto* sw = app.add_subcommand("sweep", "Evaluate the sky over a grid or list of scene parameters (resumable, shardable)");
    static std::string file, out, shard = "1/1";
    static bool resume = false, netcdf = false;
    static studies::SkySettings q;
    sw->add_option("sweep", file, "Sweep file (TOML)");
    sw->add_option("-o,--output", out, "Output folder");
    sw->add_flag("--resume", resume, "Skip points already in the journal of an interrupted run");
    sw->add_option("--shard", shard, "Run shard k of N (k/N), merge later with `atmosh sweep merge`")->capture_default_str();
    add_quality_options(sw, q);
    add_device_option(sw, q.device, "where each point's orders tables are built (--scattering orders)");
    add_format_option(sw, netcdf);
    static std::vector<std::string> merge_in;
    static std::string merge_out;
    auto* merge = sw->add_subcommand("merge", "Join shard CSVs of one sweep (checks every point appears once)");
    merge->add_option("inputs", merge_in, "Shard CSV files")->required();
    merge->add_option("-o,--output", merge_out, "Merged CSV")->required();
    merge->callback([] {
      scene::merge_sweep(std::vector<fs::path>(merge_in.begin(), merge_in.end()), merge_out);
      std::cout << "merged " << merge_in.size() << " file(s) into " << merge_out << "\n";
    });
    sw->callback([sw] {
      if (sw->got_subcommand("merge")) return;
      if (file.empty()) throw InputError("a sweep file is required");
      if (out.empty()) throw InputError("-o is required (output folder)");
      scene::SweepOptions o;
      o.out_dir = out;
      o.resume = resume;
      o.set_shard(shard);
      studies::SkySettings k = checked_quality(q);
      k.notice = notice_once();
      o.threads = k.threads;
      o.settings = k.sweep_settings();
      const auto spec = scene::load_sweep(file);
      ProgressStep step("sweep " + file);
      o.progress = step.callback();
      const auto r = scene::run_sweep(spec, [k](const scene::Scene& s) { return studies::sweep_point(s, k); }, o);
      std::cout << "sweep: " << r.points_in_shard << " point(s) of " << r.points_total << " in " << r.csv.string()
                << " (" << r.points_resumed << " resumed, " << r.points_computed << " computed)\n";
      if (netcdf) io::write_sweep_csv_as_netcdf(r.csv, fs::path(r.csv).replace_extension(".nc"), spec.keys);
    });
  }
  {
    static std::string scene_file, output = "sky_convergence";
    static studies::ConvergeSkyOptions o;
    auto* c = app.get_subcommand("converge")->add_subcommand(
        "sky", "Error of the fast sky integrator against the exact reference, against run time");
    add_scene_option(c, scene_file);
    c->add_option("-o,--output", output, "Output stem (writes STEM.csv and STEM.png)")->capture_default_str();
    add_format_option(c, output);
    c->add_flag("--quick", o.quick, "Few rays and settings");
    add_threads_option(c, o.threads);
    c->callback([] {
      studies::ConvergeSkyOptions x = o;
      x.threads = threads_option(o.threads);
      check_study_stem(output, "-o");
      ProgressStep step("converge sky");
      print_files(studies::write_converge_sky(studies::converge_sky(scene_or_default(scene_file), x), output));
    });
  }
}

}  // namespace atmosh::cli
