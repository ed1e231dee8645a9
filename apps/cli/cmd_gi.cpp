// `atmosh gi render` — diffuse global illumination of a scene (atmosh/gi/driver.hpp: the
// path-traced reference, radiance probes, the multi-bounce radiosity approximation, light
// propagation volumes).
// `atmosh gi converge` — the methods against the path-traced reference at matched
// lighting: error against run time (io::write_study) and the images.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "atmosh/error.hpp"
#include "atmosh/gi/driver.hpp"
#include "atmosh/io/study.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {
namespace fs = std::filesystem;

struct GiCmd {
  gi::SceneRequest scene;
  gi::RenderOptions method;
  std::string size = "256x256", out, png;
  bool json = false;
};

struct GiConvergeCmd {
  GiCmd render;  // scene, lights, size, seed, threads, probe settings shared with render
  std::string bands = "1,2,3,4", grids = "2,3,4,6,8", path_samples = "4,16";
  std::string radiosity_grids = "4,8,16", radiosity_bands = "1,2", radiosity_bounces = "0,1,2,3", lpv_grids = "8,16,32";
  int reference_samples = 256;
  int lpv_cascade_max_grid = 16;
  int lpv_paper_max_grid = 16;
  int lpv_emitter_rsm = 32;
  bool netcdf = false;
};

// Everything checked before any work; returns the scene to render.
gi::Scene prepare(const GiCmd& o, int& w, int& h) {
  gi::check_render_request(o.scene, o.method);
  threads_option(o.method.threads);
  const auto sz = parse_size(o.size, "--size");
  w = sz[0];
  h = sz[1];
  if (w > 16384 || h > 16384) throw InputError("--size: '" + o.size + "' is larger than 16384 a side");
  check_output_file(o.out, {".exr"}, "-o");
  if (!o.png.empty()) check_output_file(o.png, {".png"}, "--png");
  check_memory(mul_bytes(static_cast<std::size_t>(w), static_cast<std::size_t>(h), 64), "the gi image");
  return gi::scene_from_request(o.scene);
}

void run_render(const GiCmd& o) {
  int w = 0, h = 0;
  const gi::Scene s = prepare(o, w, h);
  if (o.method.method == "probes") check_memory(gi::probe_grid_bytes(o.method.grid, o.method.cube_size), "the probe grid");
  gi::MethodImage img;
  run_step("gi " + std::string(o.method.method == "path" ? "render" : o.method.method),
           [&](const ProgressCallback& p) { img = gi::render_request(s, w, h, o.method, p); });
  if (!img.device.notice.empty()) notice(img.device.notice);
  gi::write_method_image(o.out, o.png, s, o.method, img);
  if (o.json) print_json(gi::render_json(s, o.method, img, o.out));
}

std::vector<int> int_list(const std::string& text, const std::string& what, int lo, int hi) {
  if (text == "none") return {};  // no rows of this kind
  return parse_int_list(text, what, lo, hi);
}

void run_converge(const GiConvergeCmd& co) {
  const GiCmd& o = co.render;
  if (o.scene.builtin.empty() && o.scene.mesh.empty())
    throw InputError("give exactly one of --scene-builtin NAME or --mesh FILE");
  gi::ConvergeOptions c;
  // The probe rows' lists take no "none": every probe grid is built with the most bands.
  c.bands = parse_int_list(co.bands, "--bands-list", 1, 16);
  c.grids = parse_int_list(co.grids, "--grids", 1, 64);
  c.path_samples = int_list(co.path_samples, "--path-samples", 2, 10000000);
  c.study.radiosity_grids = int_list(co.radiosity_grids, "--radiosity-grids", 1, 64);
  c.study.radiosity_bands = int_list(co.radiosity_bands, "--radiosity-bands", 1, 3);
  c.study.radiosity_bounces = int_list(co.radiosity_bounces, "--radiosity-bounces", 0, 16);
  c.study.lpv_grids = int_list(co.lpv_grids, "--lpv-grids", 1, 256);
  if (co.lpv_cascade_max_grid < 0 || co.lpv_cascade_max_grid > 256)
    throw InputError("--lpv-cascade-max-grid: must be in 0..256, got " + std::to_string(co.lpv_cascade_max_grid));
  c.study.lpv_cascade_max_grid = co.lpv_cascade_max_grid;
  if (co.lpv_paper_max_grid < 0 || co.lpv_paper_max_grid > 256)
    throw InputError("--lpv-paper-max-grid: must be in 0..256, got " + std::to_string(co.lpv_paper_max_grid));
  c.study.lpv_paper_max_grid = co.lpv_paper_max_grid;
  if (co.lpv_emitter_rsm != 0 && (co.lpv_emitter_rsm < 2 || co.lpv_emitter_rsm > 1024))
    throw InputError("--lpv-emitter-rsm: must be 0 (none) or 2..1024, got " + std::to_string(co.lpv_emitter_rsm));
  c.study.lpv_emitter_rsm = co.lpv_emitter_rsm;
  c.reference_samples = co.reference_samples;
  if (co.reference_samples < 2 || co.reference_samples > 10000000)
    throw InputError("--reference-samples: must be in 2..10000000, got " + std::to_string(co.reference_samples));
  check_output_dir(o.out, "-o");
  GiCmd po = o;
  po.out = (fs::path(o.out) / "reference.exr").string();
  po.method.method = "path";
  int w = 0, h = 0;
  const gi::Scene s = prepare(po, w, h);
  const std::size_t n_emitting = gi::emitting_triangles(s);
  if (co.lpv_emitter_rsm > 0 && o.method.device != "cpu" && n_emitting >= 1 && n_emitting <= 64 && !c.study.lpv_grids.empty())
    gi::check_emitter_rsm_size(s, co.lpv_emitter_rsm, gi::ShadowMapOptions{}.emitter_points);
  c.method = o.method;
  c.method.threads = threads_option(o.method.threads);
  check_memory(gi::probe_grid_bytes(*std::max_element(c.grids.begin(), c.grids.end()), o.method.cube_size),
               "the probe grid");
  const gi::ConvergeStudy st = gi::converge_methods(s, w, h, c, o.out, run_step);
  if (!st.notice.empty()) notice(st.notice);
  for (const auto& f : io::write_study(fs::path(o.out) / "gi_converge", st.spec, st.rows, st.provenance, co.netcdf))
    std::printf("%s\n", f.string().c_str());
}

void add_scene_and_method_options(CLI::App* c, GiCmd& o, const std::string& samples_help) {
  gi::SceneRequest& s = o.scene;
  gi::RenderOptions& m = o.method;
  c->add_option("--scene-builtin", s.builtin, "built-in scene: cornell-box | sphere-on-plane | box-occluder");
  c->add_option("--mesh", s.mesh, "mesh file (.obj, .ply), grey Lambertian");
  c->add_option("--light", s.light, "sun:AZ,EL — a sun at azimuth AZ (from north towards east) and elevation EL, degrees");
  c->add_option("--sun-irradiance", s.sun_irradiance, "sun irradiance R,G,B at normal incidence (default 1,1,1)");
  c->add_option("--sun-radius", s.sun_radius_deg, "sun angular radius in degrees (default 0: a point)");
  c->add_option("--sky-radiance", s.sky_radiance, "uniform sky radiance R,G,B (SH band 0)");
  c->add_option("--env-sh", s.env_sh,
                "environment as SH coefficients (CSV as `atmosh sh project` writes; first three channel columns = "
                "R, G, B, one column = grey; frame x east, y north, z up)");
  c->add_option("--env", s.env, "equirectangular environment EXR (R, G, B; row 0 at the zenith)");
  c->add_option("--albedo", s.albedo, "--mesh: albedo where the file gives none (default 0.8)");
  c->add_option("--resolution", s.resolution, "tessellation of sphere-on-plane / box-occluder (default 32)");
  c->add_option("--bounces", m.bounces, "largest number of reflections (default -1: unlimited, Russian roulette)");
  c->add_option("--samples", m.samples, samples_help);
  c->add_option("--seed", m.seed, "random seed (default 1)");
  add_threads_option(c, m.threads);
  c->add_option("--bands", m.bands, "probes: SH bands, 1..16 (default 3)");
  c->add_option("--grid", m.grid, "probes: probes per axis over the scene's bounding box, 1..64 (default 4)");
  c->add_option("--cube-size", m.cube_size, "probes: cube-map texels per face edge (default 8)");
  c->add_option("--pixel-samples", m.pixel_samples, "probes: camera rays per pixel (default 4)");
  c->add_option("--window", m.window, "probes: window against ringing: none | hanning | lanczos | nonnegative");
  c->add_flag("--probe-visibility", m.probe_visibility,
              "probes: drop probes the receiver cannot see (behind its surface or occluded) from the interpolation");
  c->add_option("--iterations", m.iterations, "lpv: propagation steps (default -1: 2 x grid)");
}
}  // namespace

void register_gi_commands(CLI::App& app) {
  CLI::App* gic = app.add_subcommand("gi", "Diffuse global illumination: path-traced reference, radiance probes, radiosity, LPV "
                                           "(render, converge)");
  gic->require_subcommand(1);
  auto o = std::make_shared<GiCmd>();
  CLI::App* c = gic->add_subcommand("render", "Radiance image of a scene (EXR): path tracing with standard errors, or radiance probes");
  add_scene_and_method_options(c, *o, "paths per pixel (path) or per probe cube-map texel (probes) (default 16)");
  c->add_option("--method", o->method.method, "path | probes | radiosity | lpv");
  c->add_option("--cascades", o->method.cascades,
                "lpv: 1 (one grid, default) or 2 (a 2-level nested cascade: cells of half the edge over the middle "
                "half of the scene; grid >= 2; on the GPU with --device gpu|auto)");
  c->add_option("--lpv-reemission", o->method.lpv_reemission,
                "lpv: how a propagation step re-emits a face's flux: direction (along the face's direction, keeps "
                "the light's direction; default) or paper (Kaplanyan & Dachsbacher 2010: a Lambertian lobe about "
                "the face normal)");
  c->add_option("--lpv-emitter-rsm", o->method.lpv_emitter_rsm,
                "lpv on the GPU frame: the area emitters' VPLs from reflective shadow maps of N x N texels a cube "
                "face (2..1024) instead of photon rays (0, default)");
  add_device_option(c, o->method.device, "radiosity, lpv and probes (rasterised cube maps of a baked surface radiance) on the GPU (path: CPU only)");
  c->add_option("--size", o->size, "image size WxH (default 256x256)");
  c->add_option("-o,--output", o->out, "radiance image (.exr: R, G, B, stderr.R, stderr.G, stderr.B)")->required();
  c->add_option("--png", o->png, "also a tone-mapped PNG");
  add_json_flag(c, o->json);
  c->callback([o] { run_render(*o); });

  auto co = std::make_shared<GiConvergeCmd>();
  co->render.size = "64x64";
  co->render.method.samples = 4;
  CLI::App* v = gic->add_subcommand(
      "converge", "Error against run time of radiance probes (bands x grid, plain and visibility-weighted), radiosity, LPV and the path tracer at fewer samples, "
                  "against a path-traced reference at matched lighting: gi_converge.csv/.png and images");
  add_scene_and_method_options(v, co->render, "paths per probe cube-map texel (default 4)");
  v->add_option("--bands-list", co->bands, "probe SH bands to study (default 1,2,3,4)");
  v->add_option("--grids", co->grids, "probes per axis to study (default 2,3,4,6,8)");
  v->add_option("--path-samples", co->path_samples, "path tracer samples per pixel to study (default 4,16)");
  v->add_option("--radiosity-grids", co->radiosity_grids, "radiosity probes per axis to study (default 4,8,16; none)");
  v->add_option("--radiosity-bands", co->radiosity_bands, "radiosity distance SH bands to study (default 1,2; none)");
  v->add_option("--radiosity-bounces", co->radiosity_bounces, "radiosity bounces to study (default 0,1,2,3; none)");
  v->add_option("--lpv-grids", co->lpv_grids, "LPV cells along the longest axis to study (default 8,16,32; none)");
  v->add_option("--lpv-cascade-max-grid", co->lpv_cascade_max_grid,
                "the 2-level LPV cascade rows (lpv cascades=2; lpv-cascade-gpu with --device gpu|auto) for the LPV grids "
                "2..N (default 16; 0: none; 32 adds the costly grid-32 cascade)");
  v->add_option("--lpv-paper-max-grid", co->lpv_paper_max_grid,
                "rows lpv-paper (the one-level LPV with Kaplanyan & Dachsbacher 2010's face-normal re-emission, CPU; "
                "lpv-paper-gpu with --device gpu|auto) "
                "beside the lpv rows, for the LPV grids 1..N (default 16; 0: none)");
  v->add_option("--lpv-emitter-rsm", co->lpv_emitter_rsm,
                "with --device gpu|auto and a scene with 1..64 emitting triangles: rows lpv-rsm-gpu, the GPU-resident "
                "LPV frame with the area emitters' reflective shadow maps of N x N texels a cube face instead of "
                "photon rays (default 32; 0: none)");
  v->add_option("--reference-samples", co->reference_samples, "reference paths per pixel (default 256)");
  add_device_option(v, co->render.method.device, "also the GPU forms of probes, radiosity and lpv (rows <method>-gpu)");
  add_format_option(v, co->netcdf);
  v->add_option("--size", co->render.size, "image size WxH (default 64x64)");
  v->add_option("-o,--output", co->render.out, "output folder")->required();
  v->callback([co] { run_converge(*co); });
}

}  // namespace atmosh::cli
