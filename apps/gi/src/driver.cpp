// gi as a front end drives it (atmosh/gi/driver.hpp).
#include "atmosh/gi/driver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "atmosh/check.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/rgb_image.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "atmosh/memory.hpp"
#include "atmosh/parallel.hpp"

namespace atmosh::gi {

namespace {
namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

void check_range(int v, int lo, int hi, const std::string& option) {
  if (v < lo || v > hi)
    throw InputError(option + ": must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " +
                     std::to_string(v));
}

bool has_emitters(const Scene& s) {
  for (const auto& m : s.materials)
    if (m.emission.x + m.emission.y + m.emission.z > 0) return true;
  return false;
}

std::string num(int v) { return std::to_string(v); }

// ringing_rel of a probe image: sum |img - hi| / sum ref over the unmasked pixels and the three
// channels, hi the image of the same probes at more bands, unwindowed.
double ringing_rel(const RadianceImage& img, const RadianceImage& hi, const RadianceImage& ref,
                   const std::vector<unsigned char>& mask) {
  double ring = 0, sum_r = 0;
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < ref.mean[c].size(); ++i)
      if (mask[i] == 0) ring += std::abs(img.mean[c][i] - hi.mean[c][i]), sum_r += ref.mean[c][i];
  return ring / sum_r;
}

// An image of the study with, for a row, its error channels (this minus the reference);
// the PNG beside it (exposure: 1 / the 99th percentile of G).
void write_study_image(const fs::path& exr, const RadianceImage& img, const RadianceImage* ref,
                       const std::string& quantity, const io::Provenance& prov) {
  std::vector<std::string> names = {"R", "G", "B"};
  if (ref != nullptr) names.insert(names.end(), {"error.R", "error.G", "error.B"});
  io::ExrImage ex(img.width, img.height, names);
  for (int c = 0; c < 3; ++c) {
    ex.data[c] = img.mean[c];
    if (ref == nullptr) continue;
    ex.data[3 + c] = img.mean[c];
    for (std::size_t i = 0; i < ex.data[3 + c].size(); ++i) ex.data[3 + c][i] -= ref->mean[c][i];
  }
  ex.string_attributes["atmosh:quantity"] = quantity + (ref != nullptr ? "; error.* = this minus the reference" : "");
  fs::path png = exr;
  png.replace_extension(".png");
  io::write_rgb_image(exr, ex, png, io::percentile_exposure(img.mean[1]), "", prov);
}
}  // namespace

sh::Window probe_window(const std::string& w) {
  if (w != "none" && w != "hanning" && w != "lanczos" && w != "nonnegative")
    throw InputError("--window: unknown window '" + w + "' (none, hanning, lanczos, nonnegative)");
  return sh::parse_window(w);
}

std::size_t probe_grid_bytes(int grid, int cube_size) {
  return mul_bytes(static_cast<std::size_t>(grid) * grid * grid, 6ull * cube_size * cube_size, 128);
}

MethodOptions method_options(const RenderOptions& o) {
  MethodOptions m;
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
  m.lpv_cascades = o.cascades;
  m.lpv_reemission = lpv_reemission_from_name(o.lpv_reemission);
  m.lpv_emitter_rsm = o.lpv_emitter_rsm;
  m.device = parse_device_request(o.device, "--device");
  return m;
}

void check_render_request(const SceneRequest& s, const RenderOptions& o) {
  if (o.method != "path" && o.method != "probes" && o.method != "radiosity" && o.method != "lpv")
    throw InputError("--method: unknown method '" + o.method + "' (path, probes, radiosity, lpv)");
  if (s.builtin.empty() == s.mesh.empty()) throw InputError("give exactly one of --scene-builtin NAME or --mesh FILE");
  check_range(o.samples, 2, 10000000, "--samples");
  if (o.bounces < -1 || o.bounces > 100000)
    throw InputError("--bounces: must be -1 (unlimited) or 0..100000, got " + std::to_string(o.bounces));
  resolve_threads(o.threads, "--threads");
  check_range(o.bands, 1, 16, "--bands");
  check_range(o.grid, 1, 64, "--grid");
  check_range(o.cube_size, 1, 512, "--cube-size");
  check_range(o.pixel_samples, 1, 1000000, "--pixel-samples");
  check_method_options(method_options(o));
}

Scene scene_from_request(const SceneRequest& o) {
  require_range(o.sun_radius_deg, 0, 28, "--sun-radius (degrees)");
  require_range(o.albedo, 0, 1, "--albedo");
  const auto e = parse_triple(o.sun_irradiance, "--sun-irradiance");
  for (double v : e)
    if (v < 0) throw InputError("--sun-irradiance: '" + o.sun_irradiance + "' has a negative value");
  Scene s;
  if (!o.builtin.empty()) {
    const auto names = builtin_scene_names();
    if (std::find(names.begin(), names.end(), o.builtin) == names.end())
      throw InputError("--scene-builtin: unknown scene '" + o.builtin + "' (cornell-box, sphere-on-plane, box-occluder)");
    s = builtin_scene(o.builtin, o.resolution);
  } else {
    s = scene_from_mesh(o.mesh, o.albedo);
  }
  if (!o.light.empty()) {
    const auto bad = InputError("--light: '" + o.light + "' is not sun:AZ,EL (degrees)");
    if (o.light.rfind("sun:", 0) != 0) throw bad;
    const auto ae = parse_list(o.light.substr(4), "--light");
    if (ae.size() != 2) throw bad;
    if (ae[1] < -90 || ae[1] > 90) throw InputError("--light: elevation in '" + o.light + "' is outside [-90, 90]");
    s.sun = Sun{sun_direction(s, ae[0], ae[1]), glm::dvec3(e[0], e[1], e[2]), o.sun_radius_deg * kPi / 180};
  }
  if (!o.sky_radiance.empty()) {
    const auto L = parse_triple(o.sky_radiance, "--sky-radiance");
    for (double v : L)
      if (v < 0) throw InputError("--sky-radiance: '" + o.sky_radiance + "' has a negative value");
    s.env_bands = 1;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = {L[c] * 2 * std::sqrt(kPi)};  // Y_00 = 1 / (2 sqrt(pi))
  }
  if (!o.env_sh.empty()) {
    if (!o.sky_radiance.empty()) throw InputError("give at most one of --sky-radiance and --env-sh");
    const io::ShCoefficients sh = io::read_sh_coefficients(o.env_sh);
    if (sh.channels.empty() || sh.bands < 1 || sh.bands > 64)
      throw InputError("--env-sh: '" + o.env_sh + "' has no channel columns or more than 64 bands");
    s.env_bands = sh.bands;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = sh.channels[std::min<std::size_t>(c, sh.channels.size() - 1)];
  }
  if (!o.env.empty()) s.env_map = read_environment_map(o.env);
  if (!has_emitters(s) && !s.sun && s.env_bands == 0 && !s.env_map) {  // nothing lights it: a white sky of radiance 1
    s.env_bands = 1;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = {2 * std::sqrt(kPi)};
  }
  validate(s);
  return s;
}

MethodImage render_request(const Scene& s, int w, int h, const RenderOptions& o, const ProgressCallback& progress) {
  MethodOptions m = method_options(o);
  m.threads = resolve_threads(o.threads, "--threads");
  MethodImage r;
  if (o.method == "path" && m.device == DeviceRequest::cpu) {  // the one method that reports progress
    TraceOptions opt;
    opt.samples = o.samples;
    opt.bounces = o.bounces;
    opt.seed = o.seed;
    opt.threads = m.threads;
    opt.progress = progress;
    r.image = render(s, s.camera, w, h, opt);
    return r;
  }
  const MethodResult mr = render_method(s, s.camera, w, h, m);
  r.image = mr.image;
  r.device = mr.device;
  if (o.method != "path") {
    r.image.stats.seconds = mr.shade_seconds;
    r.probe_seconds = mr.build_seconds;
  }
  return r;
}

void write_method_image(const fs::path& exr, const fs::path& png, const Scene& s, const RenderOptions& o,
                        const MethodImage& r) {
  const RadianceImage& img = r.image;
  io::ExrImage ex(img.width, img.height, {"R", "G", "B", "stderr.R", "stderr.G", "stderr.B"});
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
  prov.add("scene", s.name).add("method", o.method).add("samples", num(o.samples)).add("bounces", num(o.bounces))
      .add("seed", std::to_string(o.seed)).add("rays", std::to_string(img.stats.rays))
      .add("seconds", img.stats.seconds + r.probe_seconds);
  if (o.method == "probes")
    prov.add("bands", num(o.bands)).add("grid", num(o.grid)).add("cube_size", num(o.cube_size)).add("window", o.window)
        .add("pixel_samples", num(o.pixel_samples)).add("probe_seconds", r.probe_seconds)
        .add("visibility", o.probe_visibility ? "on" : "off")
        .add("probe_cube_maps", o.device == "cpu" ? "path-traced at the probes (CPU)"
                                : r.device.gpu   ? "baked surface radiance, rasterised (GPU)"
                                                 : "baked surface radiance, ray cast (CPU)");
  if (o.method != "path") prov.add("device", r.device.gpu ? "gpu" : "cpu");
  if (o.method == "radiosity" || o.method == "lpv")
    prov.add("grid", num(o.grid)).add("bands", num(o.bands)).add("cube_size", num(o.cube_size))
        .add("iterations", num(o.iterations)).add("pixel_samples", num(o.pixel_samples))
        .add("build_seconds", r.probe_seconds);
  if (o.method == "lpv")
    prov.add("cascades", num(o.cascades)).add("lpv_reemission", o.lpv_reemission).add("lpv_emitter_rsm", num(o.lpv_emitter_rsm));
  if (s.sun)
    prov.add("sun_direction", io::format_double(s.sun->direction.x) + "," + io::format_double(s.sun->direction.y) + "," +
                                  io::format_double(s.sun->direction.z));
  io::write_rgb_image(exr, ex, png, io::percentile_exposure(img.mean[1]), png.empty() ? "" : "1 / (99th percentile of G)",
                      prov);
}

nlohmann::json render_json(const Scene& s, const RenderOptions& o, const MethodImage& r, const std::string& output) {
  const RadianceImage& img = r.image;
  double se_max = 0;
  for (int c = 0; c < 3; ++c)
    for (float v : img.stderr_[c]) se_max = std::max(se_max, static_cast<double>(v));
  const double secs = img.stats.seconds + r.probe_seconds;
  nlohmann::json j = {{"scene", s.name}, {"method", o.method}, {"width", img.width}, {"height", img.height},
                      {"samples", o.samples}, {"bounces", o.bounces}, {"seed", o.seed}, {"rays", img.stats.rays},
                      {"shadow_rays", img.stats.shadow_rays}, {"seconds", secs},
                      {"rays_per_second", secs > 0 ? img.stats.rays / secs : 0.0},
                      {"stderr_max", se_max}, {"output", output}};
  if (o.method == "probes") {
    j["bands"] = o.bands;
    j["grid"] = o.grid;
    j["cube_size"] = o.cube_size;
    j["window"] = o.window;
    j["probe_seconds"] = r.probe_seconds;
    j["visibility"] = o.probe_visibility;
    j["shade_seconds"] = img.stats.seconds;
  }
  j["device"] = r.device.gpu ? "gpu" : "cpu";
  if (o.method == "radiosity" || o.method == "lpv") {
    j["grid"] = o.grid;
    j["bands"] = o.bands;
    j["build_seconds"] = r.probe_seconds;
    j["shade_seconds"] = img.stats.seconds;
  }
  if (o.method == "lpv") {
    j["cascades"] = o.cascades;
    j["lpv_reemission"] = o.lpv_reemission;
    j["lpv_emitter_rsm"] = o.lpv_emitter_rsm;
  }
  return j;
}

ConvergeStudy converge_methods(const Scene& s, int w, int h, const ConvergeOptions& co, const fs::path& dir,
                               const StepRunner& step_runner) {
  const RenderOptions& o = co.method;
  const StepRunner step = step_runner ? step_runner : [](const std::string&, const std::function<void(const ProgressCallback&)>& work) { work({}); };
  const int threads = resolve_threads(o.threads, "--threads");
  // Every probe grid is built at the most bands listed: an empty list has no most.
  if (co.bands.empty()) throw InputError("--bands-list: the list of probe bands to study is empty");
  const int max_bands = *std::max_element(co.bands.begin(), co.bands.end());
  // --device gpu|auto: the GPU forms as extra rows ("<method>-gpu"); decided before any work.
  const DeviceRequest device = parse_device_request(o.device, "--device");
  bool gpu = false;
  ConvergeStudy st;
  if (device != DeviceRequest::cpu) {
    const DeviceDecision d = resolve_device(device, gpu_unusable(), "studying the CPU forms only");
    gpu = d.gpu;
    st.notice = d.notice;
  }
  TraceOptions to;
  to.samples = co.reference_samples;
  to.bounces = o.bounces;
  to.seed = o.seed;
  to.threads = threads;
  RadianceImage ref;
  step("gi converge: reference", [&](const ProgressCallback& progress) {
    to.progress = progress;
    ref = render(s, s.camera, w, h, to);
  });
  to.progress = nullptr;
  auto& prov = st.provenance;
  prov = io::Provenance::current();
  prov.add("scene", s.name).add("reference_samples", num(co.reference_samples)).add("bounces", num(o.bounces))
      .add("seed", std::to_string(o.seed));
  write_study_image(dir / "reference.exr", ref, nullptr, "radiance (R, G, B), path-traced reference", prov);
  // Directly seen emitters (and a 1-pixel border) are left out of the errors: their edge
  // pixels depend on each renderer's camera-ray jitter, not on the lighting method.
  std::vector<unsigned char> mask(static_cast<std::size_t>(w) * h, 0);
  if (has_emitters(s)) {  // emission seen directly only: no reflections, no sky, no sun
    Scene se = s;
    se.env_bands = 0;
    for (auto& c : se.env_sh) c.clear();
    se.env_map.reset();
    se.sun.reset();
    TraceOptions d = to;
    d.bounces = 0;
    d.samples = 16;
    mask = emitter_mask(render(se, se.camera, w, h, d), 1);
  }
  std::size_t masked = 0;
  for (unsigned char m : mask) masked += m != 0;
  prov.add("error_mask_pixels", std::to_string(masked));

  st.spec.title = "gi converge: " + s.name + " (reference: " + num(co.reference_samples) + " paths/pixel)";
  st.spec.extra_columns = {"leak_rel", "build_s", "shade_s", "mean_rel", "ringing_rel", "leak_ringfree_rel"};
  prov.add("device", gpu ? "gpu (rows <method>-gpu)" : "cpu");
  for (int spp : co.path_samples) {  // the path tracer itself at fewer samples, independent seed
    TraceOptions t = to;
    t.samples = spp;
    t.seed = o.seed + 1000003;
    const RadianceImage img = render(s, s.camera, w, h, t);
    const ImageError e = image_error(img, ref, &mask);
    st.rows.push_back({"path", "spp=" + num(spp), e.max_rel, e.rms_rel, img.stats.seconds + img.stats.setup_seconds,
                       {e.leak_rel, img.stats.setup_seconds, img.stats.seconds, e.mean_rel}});
  }
  // The probes' rows, from a grid built at kRingFree bands and truncated; the extra columns
  // split the error of each row into ringing (what the irradiance at `bands` differs from the
  // kRingFree-band irradiance of the same probes: the SH truncation, negative lobes included)
  // and leaking (the light the kRingFree-band image has beyond the reference: probes seen past
  // walls, inside objects and interpolation, with the ringing removed).
  constexpr int kRingFree = 8;
  auto probe_rows = [&](const ProbeGrid& full, double build_s, int g, const std::string& base) {
    for (bool vis : {false, true}) {
      ProbeRenderOptions ro;
      ro.samples = o.pixel_samples;
      ro.seed = o.seed;
      ro.threads = threads;
      ro.visibility = vis;
      const RadianceImage hi = render_probes(s, s.camera, w, h, truncate_grid(full, kRingFree, sh::Window::none), false, ro);
      const ImageError ehi = image_error(hi, ref, &mask);
      for (int b : co.bands) {
        const auto t0 = std::chrono::steady_clock::now();
        const ProbeGrid gb = truncate_grid(full, b, probe_window(o.window));
        const RadianceImage img = render_probes(s, s.camera, w, h, gb, false, ro);
        const double shade = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const ImageError e = image_error(img, ref, &mask);
        const std::string method = base + (vis ? "-visibility" : "");
        st.rows.push_back({method, "bands=" + num(b) + " grid=" + num(g), e.max_rel, e.rms_rel, build_s + shade,
                           {e.leak_rel, build_s, shade, e.mean_rel, ringing_rel(img, hi, ref, mask), ehi.leak_rel}});
        auto pp = prov;
        pp.add("method", method).add("bands", num(b)).add("grid", num(g)).add("cube_size", num(o.cube_size))
            .add("texel_samples", num(o.samples)).add("window", o.window);
        write_study_image(dir / (method + "_b" + num(b) + "_g" + num(g) + ".exr"), img, &ref,
                          "radiance (R, G, B), radiance probes" + std::string(vis ? " with visibility" : ""), pp);
      }
    }
  };
  ProbeOptions p;
  p.bands = std::max(max_bands, kRingFree);
  p.cube_size = o.cube_size;
  p.samples = o.samples;
  p.bounces = o.bounces;
  p.seed = o.seed + 7;
  p.threads = threads;
  step("gi converge: probes", [&](const ProgressCallback&) {
    for (int g : co.grids) {
      const ProbeGrid full = build_probe_grid(s, g, p);
      probe_rows(full, full.seconds, g, "probes");
    }
  });
  if (gpu)
    step("gi converge: probes on the GPU", [&](const ProgressCallback&) {
      const MethodOptions m = method_options(o);
      SurfaceRadianceOptions so;
      so.divisions = m.surface_divisions;
      so.samples = m.surface_samples;
      so.bounces = o.bounces;
      so.seed = o.seed + 11;
      so.threads = threads;
      const SurfaceRadiance f = bake_surface_radiance(s, so);
      const int supersample = std::clamp(std::min(m.surface_supersample, 512 / std::max(o.cube_size, 1)), 1, 16);
      // probes-gpu: the baked field's cube maps rasterised and projected to SH on the GPU
      // (ProbeRaster::gpu_sh; only the coefficients read back), shaded on the CPU as the probes.
      for (int g : co.grids) {
        const ProbeGrid full = build_probe_grid_surface(s, f, g, p, ProbeRaster::gpu_sh, supersample);
        probe_rows(full, f.seconds + full.seconds, g, "probes-gpu");
      }
      // probes-resident-gpu: the GPU-resident probe frame (ProbeFrameResident: cube maps, SH
      // projection, the sun's shadow map and the shading on the GPU, one read-back) per grid and
      // band count (every count of --bands-list, 1..16), pixel centres. time_s and shade_s: one
      // frame (the second: the first draws JIT-compile on llvmpipe); build_s: the bake and the
      // frame's setup (programs, uploads).
      // ringing_rel and leak_ringfree_rel as for the probes' rows, against the resident frame of
      // the same grid at kRingFree bands unwindowed (one more program per grid).
      auto frame_options = [&](int g, int b, sh::Window window) {
        ProbeFrameOptions fo;
        fo.grid = g;
        fo.probes.bands = b;
        fo.probes.cube_size = o.cube_size;
        fo.probes.window = window;
        fo.supersample = supersample;
        return fo;
      };
      for (int g : co.grids) {
        const RadianceImage hi =
            ProbeFrameResident(s, s.camera, w, h, f, frame_options(g, kRingFree, sh::Window::none)).render();
        const ImageError ehi = image_error(hi, ref, &mask);
        for (int b : co.bands) {
          const auto t0 = std::chrono::steady_clock::now();
          const ProbeFrameResident frame(s, s.camera, w, h, f, frame_options(g, b, probe_window(o.window)));
          (void)frame.render();
          const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          const RadianceImage img = frame.render();
          const double frame_s = img.stats.seconds;
          const ImageError e = image_error(img, ref, &mask);
          const std::string method = "probes-resident-gpu", setting = "bands=" + num(b) + " grid=" + num(g);
          st.rows.push_back({method, setting, e.max_rel, e.rms_rel, frame_s,
                             {e.leak_rel, f.seconds + setup, frame_s, e.mean_rel, ringing_rel(img, hi, ref, mask),
                              ehi.leak_rel}});
          auto pp = prov;
          pp.add("method", method).add("bands", num(b)).add("grid", num(g)).add("cube_size", num(o.cube_size))
              .add("supersample", num(supersample)).add("window", o.window).add("frame_seconds", frame_s);
          write_study_image(dir / (method + "_b" + num(b) + "_g" + num(g) + ".exr"), img, &ref,
                            "radiance (R, G, B), GPU-resident probe frame (pixel centres, sun by a shadow map)", pp);
        }
      }
      prov.add("surface_divisions", num(so.divisions)).add("surface_samples", num(so.samples))
          .add("surface_supersample", num(supersample))
          .add("surface_bake_seconds", f.seconds)
          .add("probes_gpu", "cube maps rasterised and projected to SH on the GPU (gpu_sh), shaded on the CPU")
          .add("probes_resident_gpu", "GPU-resident frame; time_s = shade_s = one frame (cube maps, projection, "
                                      "shadow map, shading, read-back), build_s = surface bake + frame setup");
    });
  StudyOptions study = co.study;
  study.gpu = gpu;
  study.cube_size = o.cube_size;
  study.pixel_samples = o.pixel_samples;
  study.threads = threads;
  study.seed = o.seed;
  if (!study.radiosity_grids.empty() || !study.lpv_grids.empty())
    step("gi converge: radiosity and lpv", [&](const ProgressCallback&) {
    study_methods(s, w, h, study, [&](const StudyRow& r) {
      const ImageError e = image_error(r.result.image, ref, &mask);
      st.rows.push_back({r.method, r.setting, e.max_rel, e.rms_rel, r.result.build_seconds + r.result.shade_seconds,
                         {e.leak_rel, r.result.build_seconds, r.result.shade_seconds, e.mean_rel}});
      auto pp = prov;
      pp.add("method", r.method).add("setting", r.setting);
      std::string stem = r.method + "_" + r.setting;
      std::replace(stem.begin(), stem.end(), ' ', '_');
      std::replace(stem.begin(), stem.end(), '=', '-');
      write_study_image(dir / (stem + ".exr"), r.result.image, &ref, "radiance (R, G, B), " + r.method + " " + r.setting, pp);
    });
  });
  prov.add("cube_size", num(o.cube_size)).add("texel_samples", num(o.samples))
      .add("pixel_samples", num(o.pixel_samples)).add("window", o.window)
      .add("errors", "relative to the reference's mean radiance; leak_rel = sum max(0, a - r - 3 stderr) / sum r; "
                     "probes: ringing_rel = sum |a - a8| / sum r, leak_ringfree_rel = leak_rel of a8, a8 the image "
                     "of the same probes at 8 bands unwindowed; pixels seeing an emitter directly (and a 1-pixel "
                     "border) left out");
  return st;
}

}  // namespace atmosh::gi
