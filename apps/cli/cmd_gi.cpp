// `atmosh gi render` — diffuse global illumination of a scene: the path-traced reference
// (atmosh::gi); the approximate methods (probes, radiosity, lpv) are named but not built yet.
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "atmosh/error.hpp"
#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {
constexpr double kPi = std::numbers::pi;

struct GiRenderOptions {
  std::string builtin, mesh, method = "path", light, sun_irradiance = "1,1,1", sky, env, env_sh, size = "256x256", out, png;
  double sun_radius_deg = 0, albedo = 0.8;
  int bounces = -1, samples = 16, threads = 0, resolution = 32;
  std::uint64_t seed = 1;
  bool json = false;
};

// Everything checked before any work; returns the scene to render.
gi::Scene prepare(const GiRenderOptions& o, int& w, int& h) {
  if (o.method == "probes" || o.method == "radiosity" || o.method == "lpv")
    throw InputError("--method: not implemented yet: '" + o.method + "' (only 'path' is built)");
  if (o.method != "path")
    throw InputError("--method: unknown method '" + o.method + "' (path, probes, radiosity, lpv)");
  if (o.builtin.empty() == o.mesh.empty()) throw InputError("give exactly one of --scene-builtin NAME or --mesh FILE");
  if (o.samples < 2 || o.samples > 10000000)
    throw InputError("--samples: must be in 2..10000000, got " + std::to_string(o.samples));
  if (o.bounces < -1 || o.bounces > 100000)
    throw InputError("--bounces: must be -1 (unlimited) or 0..100000, got " + std::to_string(o.bounces));
  threads_option(o.threads);
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
  gi::RadianceImage img;
  {
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
      "radiance (R, G, B) and its standard error (stderr.*), path tracer, pinhole camera";
  ex.string_attributes["atmosh:units"] = "units of the lights' radiance (W m^-2 sr^-1 for a sun in W m^-2)";
  auto prov = io::Provenance::current();
  prov.add("scene", s.name).add("method", "path").add("samples", std::to_string(o.samples))
      .add("bounces", std::to_string(o.bounces)).add("seed", std::to_string(o.seed))
      .add("rays", std::to_string(img.stats.rays)).add("seconds", img.stats.seconds);
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
    print_json({{"scene", s.name}, {"method", "path"}, {"width", w}, {"height", h}, {"samples", o.samples},
                {"bounces", o.bounces}, {"seed", o.seed}, {"rays", img.stats.rays},
                {"shadow_rays", img.stats.shadow_rays}, {"seconds", img.stats.seconds},
                {"rays_per_second", img.stats.seconds > 0 ? img.stats.rays / img.stats.seconds : 0.0},
                {"stderr_max", se_max}, {"output", o.out}});
  }
}
}  // namespace

void register_gi_commands(CLI::App& app) {
  CLI::App* gic = app.add_subcommand("gi", "Diffuse global illumination: the path-traced reference (render)");
  gic->require_subcommand(1);
  auto o = std::make_shared<GiRenderOptions>();
  CLI::App* c = gic->add_subcommand("render", "Radiance image of a scene with standard errors (EXR), by path tracing");
  c->add_option("--scene-builtin", o->builtin, "built-in scene: cornell-box | sphere-on-plane | box-occluder");
  c->add_option("--mesh", o->mesh, "mesh file (.obj, .ply), grey Lambertian");
  c->add_option("--method", o->method, "path (probes, radiosity, lpv: not implemented yet)");
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
  c->add_option("--samples", o->samples, "paths per pixel (default 16)");
  c->add_option("--seed", o->seed, "random seed (default 1)");
  c->add_option("--threads", o->threads, "worker threads (0 = the CPUs this process may use)");
  c->add_option("--size", o->size, "image size WxH (default 256x256)");
  c->add_option("-o,--output", o->out, "radiance image (.exr: R, G, B, stderr.R, stderr.G, stderr.B)")->required();
  c->add_option("--png", o->png, "also a tone-mapped PNG");
  c->add_flag("--json", o->json, "print a JSON summary");
  c->callback([o] { run_render(*o); });
}

}  // namespace atmosh::cli
