// `atmosh gi render` — diffuse global illumination of a scene: the path-traced reference,
// radiance probes, the multi-bounce radiosity approximation and light propagation volumes
// (CPU, atmosh::gi; radiosity and lpv through gi::render_method).
// `atmosh gi converge` — probes (and the path tracer at fewer samples) against the path-traced
// reference at matched lighting: error against run time (io::write_study) and the images.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "atmosh/error.hpp"
#include "atmosh/gi/methods.hpp"
#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/probes.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {
namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

struct GiRenderOptions {
  std::string builtin, mesh, method = "path", light, sun_irradiance = "1,1,1", sky, env, env_sh, size = "256x256", out, png;
  double sun_radius_deg = 0, albedo = 0.8;
  int bounces = -1, samples = 16, threads = 0, resolution = 32;
  // probes
  int bands = 3, grid = 4, cube_size = 8, pixel_samples = 4, iterations = -1;
  bool probe_visibility = false;
  std::string window = "none", device = "cpu";
  std::uint64_t seed = 1;
  bool json = false;
};

sh::Window probe_window(const std::string& w) {
  if (w != "none" && w != "hanning" && w != "lanczos" && w != "nonnegative")
    throw InputError("--window: unknown window '" + w + "' (none, hanning, lanczos, nonnegative)");
  return sh::parse_window(w);
}

void check_probe_options(const GiRenderOptions& o) {
  if (o.bands < 1 || o.bands > 16) throw InputError("--bands: must be in 1..16, got " + std::to_string(o.bands));
  if (o.grid < 1 || o.grid > 64) throw InputError("--grid: must be in 1..64, got " + std::to_string(o.grid));
  if (o.cube_size < 1 || o.cube_size > 512)
    throw InputError("--cube-size: must be in 1..512, got " + std::to_string(o.cube_size));
  if (o.pixel_samples < 1 || o.pixel_samples > 1000000)
    throw InputError("--pixel-samples: must be in 1..1000000, got " + std::to_string(o.pixel_samples));
  probe_window(o.window);
}

gi::MethodOptions method_options(const GiRenderOptions& o) {
  gi::MethodOptions m;
  m.method = o.method;
  m.samples = o.samples;
  m.bounces = o.bounces;
  m.seed = o.seed;
  m.threads = o.threads;
  m.bands = o.bands;
  m.grid = o.grid;
  m.cube_size = o.cube_size;
  m.pixel_samples = o.pixel_samples;
  m.window = probe_window(o.window);
  m.probe_visibility = o.probe_visibility;
  m.iterations = o.iterations;
  m.device = check_device(o.device);
  return m;
}

// Everything checked before any work; returns the scene to render.
gi::Scene prepare(const GiRenderOptions& o, int& w, int& h) {
  if (o.method != "path" && o.method != "probes" && o.method != "radiosity" && o.method != "lpv")
    throw InputError("--method: unknown method '" + o.method + "' (path, probes, radiosity, lpv)");
  if (o.builtin.empty() == o.mesh.empty()) throw InputError("give exactly one of --scene-builtin NAME or --mesh FILE");
  if (o.samples < 2 || o.samples > 10000000)
    throw InputError("--samples: must be in 2..10000000, got " + std::to_string(o.samples));
  if (o.bounces < -1 || o.bounces > 100000)
    throw InputError("--bounces: must be -1 (unlimited) or 0..100000, got " + std::to_string(o.bounces));
  threads_option(o.threads);
  check_probe_options(o);
  gi::check_method_options(method_options(o));
  const auto sz = parse_size(o.size, "--size");
  w = sz[0];
  h = sz[1];
  if (w > 16384 || h > 16384) throw InputError("--size: '" + o.size + "' is larger than 16384 a side");
  check_output_file(o.out, {".exr"}, "-o");
  if (!o.png.empty()) check_output_file(o.png, {".png"}, "--png");
  check_memory(mul_bytes(static_cast<std::size_t>(w), static_cast<std::size_t>(h), 64), "the gi image");
  require_range(o.sun_radius_deg, 0, 28, "--sun-radius (degrees)");
  require_range(o.albedo, 0, 1, "--albedo");
  const auto e = parse_triple(o.sun_irradiance, "--sun-irradiance");
  for (double v : e)
    if (v < 0) throw InputError("--sun-irradiance: '" + o.sun_irradiance + "' has a negative value");

  gi::Scene s;
  if (!o.builtin.empty()) {
    bool known = false;
    for (const auto& n : gi::builtin_scene_names()) known = known || n == o.builtin;
    if (!known) throw InputError("--scene-builtin: unknown scene '" + o.builtin + "' (cornell-box, sphere-on-plane, box-occluder)");
    s = gi::builtin_scene(o.builtin, o.resolution);
  } else {
    s = gi::scene_from_mesh(o.mesh, o.albedo);
  }
  if (!o.light.empty()) {
    if (o.light.rfind("sun:", 0) != 0) throw InputError("--light: '" + o.light + "' is not sun:AZ,EL (degrees)");
    const auto ae = parse_list(o.light.substr(4), "--light");
    if (ae.size() != 2) throw InputError("--light: '" + o.light + "' is not sun:AZ,EL (degrees)");
    if (ae[1] < -90 || ae[1] > 90) throw InputError("--light: elevation in '" + o.light + "' is outside [-90, 90]");
    s.sun = gi::Sun{gi::sun_direction(s, ae[0], ae[1]), glm::dvec3(e[0], e[1], e[2]), o.sun_radius_deg * kPi / 180};
  }
  if (!o.sky.empty()) {
    const auto L = parse_triple(o.sky, "--sky-radiance");
    for (double v : L)
      if (v < 0) throw InputError("--sky-radiance: '" + o.sky + "' has a negative value");
    s.env_bands = 1;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = {L[c] * 2 * std::sqrt(kPi)};  // Y_00 = 1 / (2 sqrt(pi))
  }
  if (!o.env_sh.empty()) {
    if (!o.sky.empty()) throw InputError("give at most one of --sky-radiance and --env-sh");
    const io::ShCoefficients sh = io::read_sh_coefficients(o.env_sh);
    if (sh.channels.empty() || sh.bands < 1 || sh.bands > 64)
      throw InputError("--env-sh: '" + o.env_sh + "' has no channel columns or more than 64 bands");
    s.env_bands = sh.bands;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = sh.channels[std::min<std::size_t>(c, sh.channels.size() - 1)];
  }
  if (!o.env.empty()) s.env_map = gi::read_environment_map(o.env);
  bool emitters = false;
  for (const auto& m : s.materials) emitters = emitters || m.emission.x + m.emission.y + m.emission.z > 0;
  if (!emitters && !s.sun && s.env_bands == 0 && !s.env_map) {  // nothing lights it: a white sky of radiance 1
    s.env_bands = 1;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = {2 * std::sqrt(kPi)};
  }
  gi::validate(s);
  return s;
}

void run_render(const GiRenderOptions& o) {
  int w = 0, h = 0;
  const gi::Scene s = prepare(o, w, h);
  gi::TraceOptions opt;
  opt.samples = o.samples;
  opt.bounces = o.bounces;
  opt.seed = o.seed;
  opt.threads = threads_option(o.threads);
  io::set_threads(opt.threads);
  if (o.method == "path" || o.method == "probes")  // CPU only: gpu is an error, auto a notice
    device_notice(resolve_device(check_device(o.device), GpuUnusable{GpuUnusable::Why::unsupported,
                                                                     "method '" + o.method + "'", ""},
                                 "rendering on the CPU"));
  gi::RadianceImage img;
  double probe_seconds = 0;
  if (o.method == "probes") {
    gi::ProbeOptions po;
    po.bands = o.bands;
    po.cube_size = o.cube_size;
    po.samples = o.samples;
    po.bounces = o.bounces;
    po.seed = o.seed;
    po.window = probe_window(o.window);
    po.threads = opt.threads;
    check_memory(mul_bytes(static_cast<std::size_t>(o.grid) * o.grid * o.grid, 6ull * o.cube_size * o.cube_size, 128),
                 "the probe grid");
    gi::ProbeGrid g;
    {
      ProgressStep step("gi probes");
      g = gi::build_probe_grid(s, o.grid, po);
    }
    probe_seconds = g.seconds;
    gi::ProbeRenderOptions ro;
    ro.samples = o.pixel_samples;
    ro.seed = o.seed;
    ro.threads = opt.threads;
    ro.visibility = o.probe_visibility;
    img = gi::render_probes(s, s.camera, w, h, g, false, ro);
    img.stats.rays += g.stats.rays;
    img.stats.shadow_rays += g.stats.shadow_rays;
  } else if (o.method != "path") {  // radiosity, lpv
    ProgressStep step("gi " + o.method);
    gi::MethodOptions m = method_options(o);
    m.threads = opt.threads;
    const gi::MethodResult r = gi::render_method(s, s.camera, w, h, m);
    device_notice(r.device);
    img = r.image;
    img.stats.seconds = r.shade_seconds;
    probe_seconds = r.build_seconds;
  } else {
    ProgressStep step("gi render");
    opt.progress = step.callback();
    img = gi::render(s, s.camera, w, h, opt);
  }
  io::ExrImage ex(w, h, {"R", "G", "B", "stderr.R", "stderr.G", "stderr.B"});
  for (int c = 0; c < 3; ++c) {
    ex.data[c] = img.mean[c];
    ex.data[3 + c] = img.stderr_[c];
  }
  ex.string_attributes["atmosh:quantity"] =
      o.method == "path"     ? "radiance (R, G, B) and its standard error (stderr.*), path tracer, pinhole camera"
      : o.method == "probes" ? "radiance (R, G, B), radiance probes (SH irradiance of a probe grid; direct sun by shadow "
                               "rays), and the standard error over each pixel's camera rays (stderr.*), pinhole camera"
                             : "radiance (R, G, B), " + o.method + " (docs/gi.md), and the standard error over each "
                               "pixel's camera rays (stderr.*), pinhole camera";
  ex.string_attributes["atmosh:units"] = "units of the lights' radiance (W m^-2 sr^-1 for a sun in W m^-2)";
  auto prov = io::Provenance::current();
  prov.add("scene", s.name).add("method", o.method).add("samples", std::to_string(o.samples))
      .add("bounces", std::to_string(o.bounces)).add("seed", std::to_string(o.seed))
      .add("rays", std::to_string(img.stats.rays)).add("seconds", img.stats.seconds + probe_seconds);
  if (o.method == "probes")
    prov.add("bands", std::to_string(o.bands)).add("grid", std::to_string(o.grid))
        .add("cube_size", std::to_string(o.cube_size)).add("window", o.window)
        .add("pixel_samples", std::to_string(o.pixel_samples)).add("probe_seconds", probe_seconds)
        .add("visibility", o.probe_visibility ? "on" : "off");
  if (o.method == "radiosity" || o.method == "lpv")
    prov.add("grid", std::to_string(o.grid)).add("bands", std::to_string(o.bands))
        .add("cube_size", std::to_string(o.cube_size)).add("iterations", std::to_string(o.iterations))
        .add("pixel_samples", std::to_string(o.pixel_samples)).add("build_seconds", probe_seconds);
  if (s.sun)
    prov.add("sun_direction", io::format_double(s.sun->direction.x) + "," + io::format_double(s.sun->direction.y) + "," +
                                  io::format_double(s.sun->direction.z));
  io::write_exr(o.out, ex, prov);
  if (!o.png.empty()) {
    std::vector<float> lum(img.mean[1]);
    std::sort(lum.begin(), lum.end());
    const double p = lum.empty() ? 1.0 : lum[static_cast<std::size_t>(0.99 * (lum.size() - 1))];
    const double exposure = p > 0 ? 1.0 / p : 1.0;
    io::write_tonemapped_png(o.png, w, h, img.mean[0], img.mean[1], img.mean[2], exposure, "reinhard");
    io::write_tone_map_side_file(o.png, "reinhard v/(1+v) on linear RGB, then the sRGB transfer curve", exposure,
                                 "1 / (99th percentile of G)", std::filesystem::path(o.out).filename().string());
  }
  if (o.json) {
    double se_max = 0;
    for (int c = 0; c < 3; ++c)
      for (float v : img.stderr_[c]) se_max = std::max(se_max, static_cast<double>(v));
    const double secs = img.stats.seconds + probe_seconds;
    nlohmann::json j = {{"scene", s.name}, {"method", o.method}, {"width", w}, {"height", h}, {"samples", o.samples},
                {"bounces", o.bounces}, {"seed", o.seed}, {"rays", img.stats.rays},
                {"shadow_rays", img.stats.shadow_rays}, {"seconds", secs},
                {"rays_per_second", secs > 0 ? img.stats.rays / secs : 0.0},
                {"stderr_max", se_max}, {"output", o.out}};
    if (o.method == "probes") {
      j["bands"] = o.bands;
      j["grid"] = o.grid;
      j["cube_size"] = o.cube_size;
      j["window"] = o.window;
      j["probe_seconds"] = probe_seconds;
      j["visibility"] = o.probe_visibility;
      j["shade_seconds"] = img.stats.seconds;
    }
    if (o.method == "radiosity" || o.method == "lpv") {
      j["grid"] = o.grid;
      j["bands"] = o.bands;
      j["build_seconds"] = probe_seconds;
      j["shade_seconds"] = img.stats.seconds;
    }
    print_json(j);
  }
}

// ---- gi converge ---------------------------------------------------------------------
struct GiConvergeOptions {
  GiRenderOptions scene;  // scene, lights, size, seed, threads, probe settings shared with render
  std::string out_dir, bands_list = "1,2,3,4", grids = "2,3,4,6,8", path_samples = "4,16";
  std::string radiosity_grids = "4,8,16", radiosity_bands = "1,2", radiosity_bounces = "0,1,2,3", lpv_grids = "8,16,32";
  int reference_samples = 256;
  bool netcdf = false;
};

std::vector<int> int_list(const std::string& text, const std::string& what, int lo, int hi) {
  std::vector<int> out;
  for (double v : parse_list(text, what)) {
    if (v != std::floor(v) || v < lo || v > hi)
      throw InputError(what + ": '" + text + "' needs integers in " + std::to_string(lo) + ".." + std::to_string(hi));
    out.push_back(static_cast<int>(v));
  }
  if (out.empty()) throw InputError(what + ": '" + text + "' is empty");
  return out;
}

void write_radiance(const fs::path& exr, const gi::RadianceImage& img, const gi::RadianceImage* ref,
                    const std::string& quantity, const io::Provenance& prov) {
  std::vector<std::string> names = {"R", "G", "B"};
  if (ref != nullptr) names.insert(names.end(), {"error.R", "error.G", "error.B"});
  io::ExrImage ex(img.width, img.height, names);
  for (int c = 0; c < 3; ++c) {
    ex.data[c] = img.mean[c];
    if (ref != nullptr) {
      ex.data[3 + c] = img.mean[c];
      for (std::size_t i = 0; i < ex.data[3 + c].size(); ++i) ex.data[3 + c][i] -= ref->mean[c][i];
    }
  }
  ex.string_attributes["atmosh:quantity"] = quantity + (ref != nullptr ? "; error.* = this minus the reference" : "");
  io::write_exr(exr, ex, prov);
  fs::path png = exr;
  png.replace_extension(".png");
  std::vector<float> lum(img.mean[1]);
  std::sort(lum.begin(), lum.end());
  const double p = lum.empty() ? 1.0 : lum[static_cast<std::size_t>(0.99 * (lum.size() - 1))];
  const double exposure = p > 0 ? 1.0 / p : 1.0;
  io::write_tonemapped_png(png, img.width, img.height, img.mean[0], img.mean[1], img.mean[2], exposure, "reinhard");
}

void run_converge(const GiConvergeOptions& co) {
  const GiRenderOptions& o = co.scene;
  if (o.builtin.empty() && o.mesh.empty()) throw InputError("give exactly one of --scene-builtin NAME or --mesh FILE");
  const auto bands = int_list(co.bands_list, "--bands-list", 1, 16);
  const auto grids = int_list(co.grids, "--grids", 1, 64);
  const auto pspp = int_list(co.path_samples, "--path-samples", 2, 10000000);
  gi::StudyOptions study;  // radiosity and lpv rows ("none": no rows)
  auto list_or_none = [](const std::string& t, const char* what, int lo, int hi) {
    return t == "none" ? std::vector<int>{} : int_list(t, what, lo, hi);
  };
  study.radiosity_grids = list_or_none(co.radiosity_grids, "--radiosity-grids", 1, 64);
  study.radiosity_bands = list_or_none(co.radiosity_bands, "--radiosity-bands", 1, 3);
  study.radiosity_bounces = list_or_none(co.radiosity_bounces, "--radiosity-bounces", 0, 16);
  study.lpv_grids = list_or_none(co.lpv_grids, "--lpv-grids", 1, 256);
  if (co.reference_samples < 2 || co.reference_samples > 10000000)
    throw InputError("--reference-samples: must be in 2..10000000, got " + std::to_string(co.reference_samples));
  check_output_dir(co.out_dir, "-o");
  int w = 0, h = 0;
  GiRenderOptions po = o;
  po.out = (fs::path(co.out_dir) / "reference.exr").string();
  po.method = "path";
  const gi::Scene s = prepare(po, w, h);
  const int threads = threads_option(o.threads);
  io::set_threads(threads);
  const fs::path dir(co.out_dir);
  const int max_bands = *std::max_element(bands.begin(), bands.end());
  const int max_grid = *std::max_element(grids.begin(), grids.end());
  check_memory(mul_bytes(static_cast<std::size_t>(max_grid) * max_grid * max_grid,
                         6ull * o.cube_size * o.cube_size, 128),
               "the probe grid");

  gi::TraceOptions to;
  to.samples = co.reference_samples;
  to.bounces = o.bounces;
  to.seed = o.seed;
  to.threads = threads;
  gi::RadianceImage ref;
  {
    ProgressStep step("gi converge: reference");
    to.progress = step.callback();
    ref = gi::render(s, s.camera, w, h, to);
  }
  auto prov = io::Provenance::current();
  prov.add("scene", s.name).add("reference_samples", std::to_string(co.reference_samples))
      .add("bounces", std::to_string(o.bounces)).add("seed", std::to_string(o.seed));
  write_radiance(dir / "reference.exr", ref, nullptr, "radiance (R, G, B), path-traced reference", prov);
  // Directly seen emitters (and a 1-pixel border) are left out of the errors: their edge
  // pixels depend on each renderer's camera-ray jitter, not on the lighting method.
  std::vector<unsigned char> mask(static_cast<std::size_t>(w) * h, 0);
  bool emitters = false;
  for (const auto& m : s.materials) emitters = emitters || m.emission.x + m.emission.y + m.emission.z > 0;
  if (emitters) {  // emission seen directly only: no reflections, no sky, no sun
    gi::Scene se = s;
    se.env_bands = 0;
    for (auto& c : se.env_sh) c.clear();
    se.env_map.reset();
    se.sun.reset();
    gi::TraceOptions d = to;
    d.bounces = 0;
    d.samples = 16;
    d.progress = nullptr;
    mask = gi::emitter_mask(gi::render(se, se.camera, w, h, d), 1);
  }
  std::size_t masked = 0;
  for (unsigned char m : mask) masked += m != 0;
  prov.add("error_mask_pixels", std::to_string(masked));

  io::StudySpec spec;
  spec.title = "gi converge: " + s.name + " (reference: " + std::to_string(co.reference_samples) + " paths/pixel)";
  spec.extra_columns = {"leak_rel", "build_s", "shade_s", "mean_rel"};
  std::vector<io::StudyRow> rows;
  for (int spp : pspp) {  // the path tracer itself at fewer samples, independent seed
    gi::TraceOptions t = to;
    t.samples = spp;
    t.seed = o.seed + 1000003;
    t.progress = nullptr;
    const gi::RadianceImage img = gi::render(s, s.camera, w, h, t);
    const gi::ImageError e = gi::image_error(img, ref, &mask);
    rows.push_back({"path", "spp=" + std::to_string(spp), e.max_rel, e.rms_rel,
                    img.stats.seconds + img.stats.setup_seconds,
                    {e.leak_rel, img.stats.setup_seconds, img.stats.seconds, e.mean_rel}});
  }
  ProgressStep step("gi converge: probes");
  for (int g : grids) {
    gi::ProbeOptions p;
    p.bands = max_bands;
    p.cube_size = o.cube_size;
    p.samples = o.samples;
    p.bounces = o.bounces;
    p.seed = o.seed + 7;
    p.threads = threads;
    const gi::ProbeGrid full = gi::build_probe_grid(s, g, p);
    for (int b : bands)
      for (bool vis : {false, true}) {
        const auto t0 = std::chrono::steady_clock::now();
        const gi::ProbeGrid gb = gi::truncate_grid(full, b, probe_window(o.window));
        gi::ProbeRenderOptions ro;
        ro.samples = o.pixel_samples;
        ro.seed = o.seed;
        ro.threads = threads;
        ro.visibility = vis;
        const gi::RadianceImage img = gi::render_probes(s, s.camera, w, h, gb, false, ro);
        const double shade = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const gi::ImageError e = gi::image_error(img, ref, &mask);
        const std::string method = vis ? "probes-visibility" : "probes";
        const std::string setting = "bands=" + std::to_string(b) + " grid=" + std::to_string(g);
        rows.push_back({method, setting, e.max_rel, e.rms_rel, full.seconds + shade, {e.leak_rel, full.seconds, shade, e.mean_rel}});
        auto pp = prov;
        pp.add("method", method).add("bands", std::to_string(b)).add("grid", std::to_string(g))
            .add("cube_size", std::to_string(o.cube_size)).add("texel_samples", std::to_string(o.samples))
            .add("window", o.window);
        write_radiance(dir / (method + "_b" + std::to_string(b) + "_g" + std::to_string(g) + ".exr"), img, &ref,
                       "radiance (R, G, B), radiance probes" + std::string(vis ? " with visibility" : ""), pp);
      }
  }
  study.cube_size = o.cube_size;
  study.pixel_samples = o.pixel_samples;
  study.threads = threads;
  study.seed = o.seed;
  gi::study_methods(s, w, h, study, [&](const gi::StudyRow& r) {
    const gi::ImageError e = gi::image_error(r.result.image, ref, &mask);
    rows.push_back({r.method, r.setting, e.max_rel, e.rms_rel, r.result.build_seconds + r.result.shade_seconds,
                    {e.leak_rel, r.result.build_seconds, r.result.shade_seconds, e.mean_rel}});
    auto pp = prov;
    pp.add("method", r.method).add("setting", r.setting);
    std::string stem = r.method + "_" + r.setting;
    std::replace(stem.begin(), stem.end(), ' ', '_');
    std::replace(stem.begin(), stem.end(), '=', '-');
    write_radiance(dir / (stem + ".exr"), r.result.image, &ref, "radiance (R, G, B), " + r.method + " " + r.setting, pp);
  });
  auto sp = prov;
  sp.add("cube_size", std::to_string(o.cube_size)).add("texel_samples", std::to_string(o.samples))
      .add("pixel_samples", std::to_string(o.pixel_samples)).add("window", o.window)
      .add("errors", "relative to the reference's mean radiance; leak_rel = sum max(0, a - r - 3 stderr) / sum r; "
                     "pixels seeing an emitter directly (and a 1-pixel border) left out");
  for (const auto& f : io::write_study(dir / "gi_converge", spec, rows, sp, co.netcdf)) std::printf("%s\n", f.string().c_str());
}

void add_probe_options(CLI::App* c, GiRenderOptions& o) {
  c->add_option("--bands", o.bands, "probes: SH bands, 1..16 (default 3)");
  c->add_option("--grid", o.grid, "probes: probes per axis over the scene's bounding box, 1..64 (default 4)");
  c->add_option("--cube-size", o.cube_size, "probes: cube-map texels per face edge (default 8)");
  c->add_option("--pixel-samples", o.pixel_samples, "probes: camera rays per pixel (default 4)");
  c->add_option("--window", o.window, "probes: window against ringing: none | hanning | lanczos | nonnegative");
  c->add_flag("--probe-visibility", o.probe_visibility,
              "probes: drop probes the receiver cannot see (behind its surface or occluded) from the interpolation");
  c->add_option("--iterations", o.iterations, "lpv: propagation steps (default -1: 2 x grid)");
}

void add_scene_options(CLI::App* c, GiRenderOptions& o) {
  c->add_option("--scene-builtin", o.builtin, "built-in scene: cornell-box | sphere-on-plane | box-occluder");
  c->add_option("--mesh", o.mesh, "mesh file (.obj, .ply), grey Lambertian");
  c->add_option("--light", o.light, "sun:AZ,EL — a sun at azimuth AZ (from north towards east) and elevation EL, degrees");
  c->add_option("--sun-irradiance", o.sun_irradiance, "sun irradiance R,G,B at normal incidence (default 1,1,1)");
  c->add_option("--sun-radius", o.sun_radius_deg, "sun angular radius in degrees (default 0: a point)");
  c->add_option("--sky-radiance", o.sky, "uniform sky radiance R,G,B (SH band 0)");
  c->add_option("--env-sh", o.env_sh, "environment as SH coefficients (CSV as `atmosh sh project` writes)");
  c->add_option("--env", o.env, "equirectangular environment EXR (R, G, B; row 0 at the zenith)");
  c->add_option("--albedo", o.albedo, "--mesh: albedo where the file gives none (default 0.8)");
  c->add_option("--resolution", o.resolution, "tessellation of sphere-on-plane / box-occluder (default 32)");
  c->add_option("--bounces", o.bounces, "largest number of reflections (default -1: unlimited, Russian roulette)");
  c->add_option("--seed", o.seed, "random seed (default 1)");
  c->add_option("--threads", o.threads, "worker threads (0 = the CPUs this process may use)");
}
}  // namespace

void register_gi_commands(CLI::App& app) {
  CLI::App* gic = app.add_subcommand("gi", "Diffuse global illumination: path-traced reference and radiance probes "
                                           "(render, converge)");
  gic->require_subcommand(1);
  auto o = std::make_shared<GiRenderOptions>();
  CLI::App* c = gic->add_subcommand("render", "Radiance image of a scene (EXR): path tracing with standard errors, or radiance probes");
  c->add_option("--scene-builtin", o->builtin, "built-in scene: cornell-box | sphere-on-plane | box-occluder");
  c->add_option("--mesh", o->mesh, "mesh file (.obj, .ply), grey Lambertian");
  c->add_option("--method", o->method, "path | probes | radiosity | lpv");
  c->add_option("--light", o->light, "sun:AZ,EL — a sun at azimuth AZ (from north towards east) and elevation EL, degrees");
  c->add_option("--sun-irradiance", o->sun_irradiance, "sun irradiance R,G,B at normal incidence (default 1,1,1)");
  c->add_option("--sun-radius", o->sun_radius_deg, "sun angular radius in degrees (default 0: a point)");
  c->add_option("--sky-radiance", o->sky, "uniform sky radiance R,G,B (SH band 0)");
  c->add_option("--env-sh", o->env_sh,
                "environment as SH coefficients (CSV as `atmosh sh project` writes; first three channel columns = "
                "R, G, B, one column = grey; frame x east, y north, z up)");
  c->add_option("--env", o->env, "equirectangular environment EXR (R, G, B; row 0 at the zenith)");
  c->add_option("--albedo", o->albedo, "--mesh: albedo where the file gives none (default 0.8)");
  c->add_option("--resolution", o->resolution, "tessellation of sphere-on-plane / box-occluder (default 32)");
  c->add_option("--bounces", o->bounces, "largest number of reflections (default -1: unlimited, Russian roulette)");
  c->add_option("--samples", o->samples, "paths per pixel (path) or per probe cube-map texel (probes) (default 16)");
  add_probe_options(c, *o);
  c->add_option("--device", o->device, "cpu | gpu | auto: lpv propagates on the GPU (other passes: CPU only)");
  c->add_option("--seed", o->seed, "random seed (default 1)");
  c->add_option("--threads", o->threads, "worker threads (0 = the CPUs this process may use)");
  c->add_option("--size", o->size, "image size WxH (default 256x256)");
  c->add_option("-o,--output", o->out, "radiance image (.exr: R, G, B, stderr.R, stderr.G, stderr.B)")->required();
  c->add_option("--png", o->png, "also a tone-mapped PNG");
  c->add_flag("--json", o->json, "print a JSON summary");
  c->callback([o] { run_render(*o); });

  auto co = std::make_shared<GiConvergeOptions>();
  co->scene.size = "64x64";
  co->scene.samples = 4;
  CLI::App* v = gic->add_subcommand(
      "converge", "Error against run time of radiance probes (bands x grid, plain and visibility-weighted) and of the path tracer at fewer samples, "
                  "against a path-traced reference at matched lighting: gi_converge.csv/.png and images");
  add_scene_options(v, co->scene);
  v->add_option("--samples", co->scene.samples, "paths per probe cube-map texel (default 4)");
  add_probe_options(v, co->scene);
  v->add_option("--bands-list", co->bands_list, "probe SH bands to study (default 1,2,3,4)");
  v->add_option("--grids", co->grids, "probes per axis to study (default 2,3,4,6,8)");
  v->add_option("--path-samples", co->path_samples, "path tracer samples per pixel to study (default 4,16)");
  v->add_option("--radiosity-grids", co->radiosity_grids, "radiosity probes per axis to study (default 4,8,16; none)");
  v->add_option("--radiosity-bands", co->radiosity_bands, "radiosity distance SH bands to study (default 1,2; none)");
  v->add_option("--radiosity-bounces", co->radiosity_bounces, "radiosity bounces to study (default 0,1,2,3; none)");
  v->add_option("--lpv-grids", co->lpv_grids, "LPV cells along the longest axis to study (default 8,16,32; none)");
  v->add_option("--reference-samples", co->reference_samples, "reference paths per pixel (default 256)");
  v->add_option("--size", co->scene.size, "image size WxH (default 64x64)");
  v->add_option("-o,--output", co->out_dir, "output folder")->required();
  add_format_option(v, co->netcdf);
  v->callback([co] { run_converge(*co); });
}

}  // namespace atmosh::cli
