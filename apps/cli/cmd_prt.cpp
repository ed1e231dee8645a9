// `atmosh prt bake|relight|converge` — precomputed radiance transfer on meshes
// (per-vertex, CPU, Embree), relit images, the sample-count study; and the PRT part
// of the main job (demo_prt).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/prt/bake.hpp"
#include "atmosh/sh/basis.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

#ifdef ATMOSH_HAVE_GPU
#include "atmosh/gpu/context.hpp"
#endif

namespace atmosh::cli {

namespace {
namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;
using Clock = std::chrono::steady_clock;

int strata_of_samples(int n) {
  const int s = static_cast<int>(std::lround(std::sqrt(static_cast<double>(std::max(n, 0)))));
  if (n < 1 || s * s != n || s > 2000)
    throw InputError("--samples: " + std::to_string(n) +
                     " is not a square count of jittered strata n x n in 1..4000000 (e.g. 2025 = 45 x 45)");
  return s;
}

prt::Mesh load_input(const std::string& mesh_file, const std::string& builtin, int resolution) {
  if (!mesh_file.empty() && !builtin.empty()) throw InputError("give either MESH or --scene-builtin, not both");
  if (mesh_file.empty() && builtin.empty()) throw InputError("no mesh: give MESH (.obj, .ply) or --scene-builtin NAME");
  return builtin.empty() ? prt::load_mesh(mesh_file) : prt::builtin_scene(builtin, resolution);
}

// Writes STEM.exr, STEM.png (tone-mapped) and STEM.png.json (the tone mapping, as for
// sky images).
std::vector<fs::path> write_image(const fs::path& stem, const std::vector<std::vector<float>>& img, int w, int h,
                                  double exposure, const std::string& exposure_rule, const io::Provenance& prov,
                                  const std::string& what) {
  io::ExrImage ex(w, h, {"R", "G", "B"});
  for (int c = 0; c < 3; ++c) ex.data[c] = img[std::min<std::size_t>(c, img.size() - 1)];
  ex.string_attributes["atmosh:quantity"] = what;
  ex.string_attributes["atmosh:units"] = "units of the light (exit radiance = transfer . light)";
  const fs::path exr = stem.string() + ".exr", png = stem.string() + ".png";
  io::write_exr(exr, ex, prov);
  io::write_tonemapped_png(png, w, h, ex.data[0], ex.data[1], ex.data[2], exposure, "reinhard");
  const fs::path side = io::write_tone_map_side_file(png, "reinhard v/(1+v) on linear RGB, then the sRGB transfer curve",
                                                     exposure, exposure_rule, exr.filename().string());
  return {exr, png, side};
}

struct RelightOptions {
  std::vector<std::string> light_dirs;
  std::string light_csv;
  int frames = 1;
  int width = 256, height = 256;
  std::string view = "1,-1.6,1.1";
  double exposure = 0.0;  // 0 = auto
};

// The lights of a relight run: [frame][channel][coefficient].
std::vector<std::vector<std::vector<double>>> relight_lights(const RelightOptions& o, int bands) {
  if (o.light_csv.empty() == o.light_dirs.empty()) throw InputError("give exactly one of --light CSV or --light-dir x,y,z");
  if (o.frames < 1 || o.frames > 3600) throw InputError("--frames: must be in 1..3600, got " + std::to_string(o.frames));
  std::vector<std::vector<std::vector<double>>> lights;
  if (!o.light_csv.empty()) {
    lights.push_back(io::read_sh_light(o.light_csv, bands));
    return lights;
  }
  for (const auto& s : o.light_dirs) {
    const auto d = parse_triple(s, "--light-dir");
    glm::dvec3 dir(d[0], d[1], d[2]);
    if (glm::length(dir) == 0) throw InputError("--light-dir: zero vector '" + s + "'");
    for (int f = 0; f < o.frames; ++f) {  // the light turned about +z in `frames` steps
      const double a = 2 * kPi * f / o.frames;
      const glm::dvec3 r(std::cos(a) * dir.x - std::sin(a) * dir.y, std::sin(a) * dir.x + std::cos(a) * dir.y, dir.z);
      lights.push_back({sh::prt::directional_light(bands, r, kPi)});  // E = pi: white Lambertian -> rho V cos
    }
  }
  return lights;
}

// Auto exposure: the 99th percentile of the first channel maps to ~1.
double auto_exposure(std::vector<float> v) {
  std::sort(v.begin(), v.end());
  const double p = v.empty() ? 1.0 : v[static_cast<std::size_t>(0.99 * (v.size() - 1))];
  return p > 0 ? 1.0 / p : 1.0;
}

// Writes the frames of `lights` rendered by `render(light)` and returns the files.
template <class Render>
std::vector<fs::path> write_frames(const std::vector<std::vector<std::vector<double>>>& lights, const Render& render,
                                   const RelightOptions& o, int w, int h, const io::Provenance& prov, const fs::path& dir) {
  std::vector<fs::path> written;
  double exposure = o.exposure;
  for (std::size_t f = 0; f < lights.size(); ++f) {
    const std::vector<std::vector<float>> img = render(lights[f]);
    if (exposure <= 0) exposure = auto_exposure(img[0]);  // fixed by the first frame
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04zu", f);
    const std::string rule = o.exposure > 0 ? "given (--exposure)"
                                            : "1 / (99th percentile of the first channel of frame 0), every frame";
    auto wr = write_image(dir / name, img, w, h, exposure, rule, prov, "relit exit radiance");
    written.insert(written.end(), wr.begin(), wr.end());
  }
  return written;
}

// Writes frame_NNNN.(exr|png) for each light and ao.(exr|png) (band-0 simple occlusion).
std::vector<fs::path> relight_to(const prt::Transfer& t, const RelightOptions& o, const fs::path& dir) {
  const auto lights = relight_lights(o, t.bands);
  const auto vv = parse_triple(o.view, "--view");
  const glm::dvec3 view(vv[0], vv[1], vv[2]);
  if (glm::length(view) == 0) throw InputError("--view: zero vector '" + o.view + "'");
  std::vector<fs::path> written;
  const prt::RayScene scene(t.mesh);
  auto prov = io::Provenance::current();
  prov.add("transfer_bands", std::to_string(t.bands)).add("transfer_mode", sh::prt::transfer_mode_name(t.mode));
  // Simple occlusion: band 0 scaled to ambient occlusion.
  {
    std::vector<std::vector<double>> ao(t.mesh.positions.size(), std::vector<double>(1));
    for (std::size_t v = 0; v < ao.size(); ++v)
      ao[v][0] = t.mesh.albedo[v] > 0 ? sh::prt::ambient_occlusion(t.at(v)[0], t.mesh.albedo[v]) : t.ao[v];
    const auto img = prt::render_vertex_values(scene, t.mesh, ao, o.width, o.height, view);
    auto w = write_image(dir / "ao", img, o.width, o.height, 1.0, "1 (occlusion is in [0, 1])", prov,
                         "ambient occlusion from SH band 0");
    written.insert(written.end(), w.begin(), w.end());
  }
  auto render = [&](const std::vector<std::vector<double>>& light) {
    return prt::render_vertex_values(scene, t.mesh, prt::relight_vertices(t, light), o.width, o.height, view);
  };
  const auto frames = write_frames(lights, render, o, o.width, o.height, prov, dir);
  written.insert(written.end(), frames.begin(), frames.end());
  return written;
}

// Per-pixel relighting of a per-pixel transfer EXR (prt bake -o X.exr): each frame is
// sum_i T_i(pixel) light_i per channel; ao.(exr|png) is the image's `ao` channel. The
// image size and view are the EXR's own.
std::vector<fs::path> relight_pixels_to(const fs::path& file, const RelightOptions& o, const fs::path& dir) {
  const io::ExrImage ex = io::read_exr(file, memory_budget());
  std::vector<std::size_t> coeff_ch;
  for (int l = 0;; ++l) {
    bool all = true;
    std::vector<std::size_t> band;
    for (int m = -l; m <= l && all; ++m) {
      const auto it = std::find(ex.channels.begin(), ex.channels.end(), "sh_l" + std::to_string(l) + "_m" + std::to_string(m));
      if (it == ex.channels.end()) all = false;
      else band.push_back(static_cast<std::size_t>(it - ex.channels.begin()));
    }
    if (!all) break;
    coeff_ch.insert(coeff_ch.end(), band.begin(), band.end());
  }
  const int bands = static_cast<int>(std::lround(std::sqrt(static_cast<double>(coeff_ch.size()))));
  const auto ao_it = std::find(ex.channels.begin(), ex.channels.end(), "ao");
  if (bands < 1 || ao_it == ex.channels.end())
    throw InputError(file.string() + ": not a per-pixel transfer image (needs channels sh_l0_m0 ... and ao)");
  const auto lights = relight_lights(o, bands);
  const std::size_t np = static_cast<std::size_t>(ex.width) * ex.height;
  auto prov = io::Provenance::current();
  prov.add("transfer_bands", std::to_string(bands)).add("transfer_file", file.string());
  std::vector<fs::path> written =
      write_image(dir / "ao", {ex.data[static_cast<std::size_t>(ao_it - ex.channels.begin())]}, ex.width, ex.height,
                  1.0, "1 (occlusion is in [0, 1])", prov, "ambient occlusion (cosine-weighted visible fraction)");
  auto render = [&](const std::vector<std::vector<double>>& light) {
    std::vector<std::vector<float>> img(light.size(), std::vector<float>(np, 0.0f));
    for (std::size_t c = 0; c < light.size(); ++c)
      for (std::size_t p = 0; p < np; ++p) {
        double v = 0;
        for (std::size_t i = 0; i < coeff_ch.size(); ++i) v += ex.data[coeff_ch[i]][p] * light[c][i];
        img[c][p] = static_cast<float>(v);
      }
    return img;
  };
  const auto frames = write_frames(lights, render, o, ex.width, ex.height, prov, dir);
  written.insert(written.end(), frames.begin(), frames.end());
  return written;
}

// Transfer error of `t` against `ref` (same mesh): per vertex |T - T_ref|_2 relative to
// max_v |T_ref,v|_2; returns {max, rms}.
std::pair<double, double> transfer_error(const prt::Transfer& t, const prt::Transfer& ref) {
  const std::size_t nv = ref.mesh.positions.size(), K = static_cast<std::size_t>(ref.bands) * ref.bands;
  double scale = 0, emax = 0, esum = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    double s = 0;
    for (std::size_t i = 0; i < K; ++i) s += ref.at(v)[i] * ref.at(v)[i];
    scale = std::max(scale, std::sqrt(s));
  }
  for (std::size_t v = 0; v < nv; ++v) {
    double e = 0;
    for (std::size_t i = 0; i < K; ++i) e += std::pow(t.at(v)[i] - ref.at(v)[i], 2);
    emax = std::max(emax, std::sqrt(e));
    esum += e;
  }
  scale = scale > 0 ? scale : 1.0;
  return {emax / scale, std::sqrt(esum / static_cast<double>(nv)) / scale};
}

// Per-pixel transfer error of `t` against `ref` (same camera): per pixel seen by both,
// |T - T_ref|_2 relative to max_p |T_ref,p|_2; returns {max, rms}.
std::pair<double, double> pixel_error(const prt::PixelTransfer& t, const prt::PixelTransfer& ref) {
  const std::size_t np = ref.mask.size(), K = static_cast<std::size_t>(ref.bands) * ref.bands;
  double scale = 0, emax = 0, esum = 0, n = 0;
  for (std::size_t p = 0; p < np; ++p) {
    double s = 0;
    for (std::size_t i = 0; i < K; ++i) s += ref.coeffs[p * K + i] * ref.coeffs[p * K + i];
    scale = std::max(scale, std::sqrt(s));
  }
  for (std::size_t p = 0; p < np; ++p) {
    if (t.mask[p] == 0 || ref.mask[p] == 0) continue;
    double e = 0;
    for (std::size_t i = 0; i < K; ++i) e += std::pow(t.coeffs[p * K + i] - ref.coeffs[p * K + i], 2);
    emax = std::max(emax, std::sqrt(e));
    esum += e;
    n += 1;
  }
  scale = scale > 0 ? scale : 1.0;
  return {emax / scale, n > 0 ? std::sqrt(esum / n) / scale : 0.0};
}

// What the per-pixel rows of a converge study cover: the camera image size, and whether
// (and at which depth-map resolutions) the GPU depth-map method runs.
struct PixelStudy {
  int width = 96, height = 96;
  std::string device = "auto";       // cpu: CPU rows only; gpu: GPU rows or an error; auto: GPU rows if possible
  std::vector<int> depth_maps = {256, 1024};
  glm::dvec3 view{1, -1.6, 1.1};
};

std::vector<fs::path> converge_study(const prt::Mesh& mesh, int bands, sh::prt::TransferMode mode, int ref_strata,
                                     const std::vector<int>& strata, int threads, const PixelStudy& px,
                                     const fs::path& stem) {
  prt::BakeOptions bo;
  bo.bands = bands;
  bo.mode = mode;
  bo.threads = threads;
  bo.strata = ref_strata;
  bo.seed = 12345;  // the reference uses its own seed: independent of the rows
  const prt::Transfer ref = prt::bake(mesh, bo);
  std::vector<io::StudyRow> rows;
  bo.strata = 1;
  prt::bake(mesh, bo);  // warm-up: one-time library start-up is not part of any row's time
  const std::string mode_name = sh::prt::transfer_mode_name(mode);
  for (int s : strata) {
    bo.strata = s;
    bo.seed = 1;
    const auto t0 = Clock::now();
    const prt::Transfer t = prt::bake(mesh, bo);
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    const auto [emax, erms] = transfer_error(t, ref);
    rows.push_back({"cpu-" + mode_name + "-jittered", std::to_string(s * s) + " samples", emax, erms, dt,
                    {static_cast<double>(s * s), static_cast<double>(t.rays), 0.0}});
  }
  auto prov = io::Provenance::current();
  // Per-pixel rows (shadowed only): CPU ray casting and the GPU depth-map method against
  // a per-pixel reference of the same camera.
  std::string gpu_note = "not run (--device cpu)";
  if (mode == sh::prt::TransferMode::shadowed) {
    bo.strata = ref_strata;
    bo.seed = 12345;
    bo.device = prt::Device::cpu;
    const prt::PixelTransfer pref = prt::bake_pixels(mesh, bo, px.width, px.height, px.view);
    const DeviceRequest request = check_device(px.device);
    bool gpu = request != DeviceRequest::cpu;
    if (gpu) {
      std::optional<GpuUnusable> unusable;
#ifdef ATMOSH_HAVE_GPU
      bo.device = prt::Device::gpu;
      bo.strata = 1;
      bo.depth_resolution = px.depth_maps.front();
      try {
        prt::bake_pixels(mesh, bo, px.width, px.height, px.view);  // warm-up (driver start-up, shader compile)
        gpu_note = "depth-map method, per pixel";
      } catch (const gpu::Unavailable& e) {
        unusable = GpuUnusable{GpuUnusable::Why::no_device, e.what(), {}};
        gpu_note = std::string("not run (") + e.what() + ")";
      }
#else
      unusable = GpuUnusable{GpuUnusable::Why::not_built, {}, {}};
      gpu_note = "not run (built without GPU support)";
#endif
      const DeviceDecision decision = resolve_device(request, unusable, "the study has no GPU rows");
      device_notice(decision);
      gpu = decision.gpu;
    }
    std::vector<std::vector<io::StudyRow>> gpu_rows(px.depth_maps.size());  // one line per depth map
    for (int s : strata) {
      bo.strata = s;
      bo.seed = 1;
      bo.device = prt::Device::cpu;
      auto t0 = Clock::now();
      const prt::PixelTransfer c = prt::bake_pixels(mesh, bo, px.width, px.height, px.view);
      double dt = std::chrono::duration<double>(Clock::now() - t0).count();
      auto [emax, erms] = pixel_error(c, pref);
      rows.push_back({"cpu-pixel-" + mode_name + "-jittered", std::to_string(s * s) + " samples", emax, erms, dt,
                      {static_cast<double>(s * s), static_cast<double>(c.rays), 0.0}});
      if (!gpu) continue;
      bo.device = prt::Device::gpu;
      for (std::size_t k = 0; k < px.depth_maps.size(); ++k) {
        const int d = px.depth_maps[k];
        bo.depth_resolution = d;
        t0 = Clock::now();
        const prt::PixelTransfer g = prt::bake_pixels(mesh, bo, px.width, px.height, px.view);
        dt = std::chrono::duration<double>(Clock::now() - t0).count();
        std::tie(emax, erms) = pixel_error(g, pref);
        gpu_rows[k].push_back({"gpu-depthmap" + std::to_string(d) + "-" + mode_name + "-jittered",
                        std::to_string(s * s) + " samples", emax, erms, dt,
                        {static_cast<double>(s * s), 0.0, static_cast<double>(d)}});
      }
    }
    for (const auto& g : gpu_rows) rows.insert(rows.end(), g.begin(), g.end());
    prov.add("pixel_image", std::to_string(px.width) + "x" + std::to_string(px.height));
    prov.add("pixel_error_definition",
             "per pixel seen by both: |T - T_ref|_2 / max_p |T_ref|_2, reference: CPU ray casting, same camera");
  } else {
    gpu_note = "not run (per-pixel rows are shadowed only)";
  }
  io::StudySpec spec;
  spec.title = "PRT transfer (" + mesh.name + ", " + std::to_string(bands) + " bands) vs " +
               std::to_string(ref_strata * ref_strata) + "-sample reference";
  spec.extra_columns = {"samples", "rays", "depth_map"};
  prov.add("mesh", mesh.name).add("bands", std::to_string(bands)).add("mode", mode_name);
  prov.add("reference_samples", std::to_string(ref_strata * ref_strata));
  prov.add("error_definition", "per-vertex rows: per-vertex |T - T_ref|_2 / max_v |T_ref|_2");
  prov.add("gpu_method", gpu_note);
  return io::write_study(stem, spec, rows, prov);
}

}  // namespace

void register_prt_commands(CLI::App& app) {
  CLI::App* prtc = app.add_subcommand("prt", "Precomputed radiance transfer on meshes: bake, relight, converge");
  prtc->require_subcommand(1);
  // bake
  {
    struct Opt {
      std::string mesh, builtin, mode = "shadowed", device = "cpu", out, size = "256x256", view = "1,-1.6,1.1";
      int bands = 3, samples = 2025, bounces = 2, threads = 0, resolution = 32, depth_map = 1024;
      double albedo = 0.8;
      std::uint64_t seed = 1;
      bool json = false, quiet = false;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = prtc->add_subcommand("bake", "Per-vertex diffuse transfer (SH) of a mesh, by Embree ray casting");
    c->add_option("mesh", o->mesh, "mesh file (.obj, .ply)");
    c->add_option("--scene-builtin", o->builtin, "built-in scene: sphere-on-plane | box-occluder | torus | sphere");
    c->add_option("--resolution", o->resolution, "tessellation of a built-in scene (default 32)");
    c->add_option("--bands", o->bands, "number of SH bands L (L^2 coefficients; 1..16, default 3)");
    c->add_option("--samples", o->samples, "jittered sample directions n x n (default 2025 = 45 x 45)");
    c->add_option("--mode", o->mode, "unshadowed | shadowed | interreflected (default shadowed)");
    c->add_option("--bounces", o->bounces, "interreflection bounces (default 2)");
    c->add_option("--albedo", o->albedo, "albedo where the mesh gives none (default 0.8)");
    c->add_option("--seed", o->seed, "random seed of the sample set (default 1)");
    c->add_option("--threads", o->threads, "worker threads (0 = all cores)");
    c->add_option("--device", o->device, "cpu (ray casting) | gpu (depth-map method; per-pixel .exr output only)");
    c->add_option("--depth-map", o->depth_map, "GPU: depth-map texels per side (16..16384, default 1024)");
    c->add_option("--size", o->size, "per-pixel (.exr) output: image size WxH (default 256x256)");
    c->add_option("--view", o->view, "per-pixel (.exr) output: direction from the scene centre to the camera");
    c->add_option("-o,--output", o->out, "transfer file: .ply per-vertex, .exr per-pixel (camera view)")->required();
    c->add_flag("--json", o->json, "print a JSON summary");
    c->add_flag("--quiet", o->quiet, "no progress on stderr");
    c->callback([o] {
      prt::BakeOptions bo;
      bo.device = prt::parse_device(o->device);
      bo.depth_resolution = o->depth_map;
      if (o->depth_map < 16 || o->depth_map > 16384)
        throw InputError("--depth-map: must be in 16..16384, got " + std::to_string(o->depth_map));
      bo.mode = sh::prt::parse_transfer_mode(o->mode);
      bo.bands = o->bands;
      if (o->bands < 1 || o->bands > 16) throw InputError("--bands: must be in 1..16, got " + std::to_string(o->bands));
      bo.strata = strata_of_samples(o->samples);
      bo.bounces = o->bounces;
      bo.default_albedo = o->albedo;
      bo.seed = o->seed;
      bo.threads = threads_option(o->threads);
      const std::string ext = fs::path(o->out).extension().string();
      if (ext != ".ply" && ext != ".exr")
        throw InputError("-o: '" + o->out + "' must end in .ply (per-vertex) or .exr (per-pixel)");
      if (bo.device == prt::Device::gpu && ext != ".exr")
        throw InputError("--device gpu: the depth-map method is per-pixel; write an .exr (per-vertex bakes use --device cpu)");
      const auto sz = parse_size(o->size, "--size");
      const auto vv = parse_triple(o->view, "--view");
      const prt::Mesh mesh = load_input(o->mesh, o->builtin, o->resolution);
      if (o->quiet) set_progress_quiet(true);
      const bool show = !progress_quiet() && ::isatty(STDERR_FILENO);
      if (show) bo.progress = [](double f) { std::fprintf(stderr, "\rprt bake: %3d%%", static_cast<int>(100 * f)); };
      if (ext == ".exr") {  // per-pixel transfer: CPU ray casting or the GPU depth-map method
        const auto t0 = Clock::now();
        const prt::PixelTransfer px = prt::bake_pixels(mesh, bo, sz[0], sz[1], {vv[0], vv[1], vv[2]});
        const bool gpu_run = px.device == prt::Device::gpu;
        const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
        if (show) std::fprintf(stderr, "\n");
        std::vector<std::string> names;
        for (int l = 0; l < px.bands; ++l)
          for (int m = -l; m <= l; ++m) names.push_back("sh_l" + std::to_string(l) + "_m" + std::to_string(m));
        names.push_back("ao");
        names.push_back("mask");
        io::ExrImage ex(px.width, px.height, names);
        const std::size_t K = static_cast<std::size_t>(px.bands) * px.bands, np = px.mask.size();
        for (std::size_t i = 0; i < K; ++i)
          for (std::size_t p = 0; p < np; ++p) ex.data[i][p] = static_cast<float>(px.coeffs[p * K + i]);
        for (std::size_t p = 0; p < np; ++p) ex.data[K][p] = static_cast<float>(px.ao[p]), ex.data[K + 1][p] = px.mask[p];
        ex.string_attributes["atmosh:quantity"] = std::string("per-pixel diffuse transfer, ") + sh::prt::transfer_mode_name(bo.mode);
        ex.string_attributes["atmosh:sh_convention"] = "real orthonormal, Condon-Shortley phase, index l(l+1)+m";
        ex.string_attributes["atmosh:view"] = o->view;
        ex.string_attributes["atmosh:samples"] = std::to_string(px.samples);
        ex.string_attributes["atmosh:device"] = gpu_run ? "gpu" : "cpu";
        if (gpu_run) ex.string_attributes["atmosh:depth_map"] = std::to_string(px.depth_resolution);
        auto prov = io::Provenance::current();
        prov.add("mesh", mesh.name);
        io::write_exr(o->out, ex, prov);
        if (o->json)
          print_json({{"file", o->out}, {"width", px.width}, {"height", px.height}, {"bands", px.bands},
                      {"coefficients", px.bands * px.bands}, {"samples", px.samples},
                      {"mode", sh::prt::transfer_mode_name(bo.mode)}, {"device", gpu_run ? "gpu" : "cpu"},
                      {"rays", px.rays}, {"ray_seconds", px.ray_seconds},
                      {"rays_per_s", px.ray_seconds > 0 ? static_cast<double>(px.rays) / px.ray_seconds : 0.0},
                      {"depth_map", px.depth_resolution}, {"seconds_per_direction", px.seconds_per_direction},
                      {"time_s", dt}});
        else
          std::cout << "wrote " << o->out << " (" << px.width << "x" << px.height << " pixels, " << K << " coefficients)\n";
        return;
      }
      const auto t0 = Clock::now();
      const prt::Transfer t = prt::bake(mesh, bo);
      const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
      if (show) std::fprintf(stderr, "\n");
      auto prov = io::Provenance::current();
      prov.add("mesh", mesh.name);
      prt::write_transfer(o->out, t, prov);
      double ao_min = 1, ao_mean = 0;
      for (double a : t.ao) ao_min = std::min(ao_min, a), ao_mean += a;
      ao_mean /= static_cast<double>(t.ao.size());
      if (o->json) {
        print_json({{"file", o->out}, {"vertices", t.mesh.positions.size()}, {"triangles", t.mesh.triangles.size()},
                    {"bands", t.bands}, {"coefficients", t.bands * t.bands}, {"samples", t.samples},
                    {"mode", sh::prt::transfer_mode_name(t.mode)}, {"bounces", t.bounces}, {"rays", t.rays},
                    {"ray_seconds", t.ray_seconds},
                    {"rays_per_s", t.ray_seconds > 0 ? static_cast<double>(t.rays) / t.ray_seconds : 0.0},
                    {"time_s", dt}, {"ao_min", ao_min}, {"ao_mean", ao_mean}, {"bounce_energy", t.bounce_energy}});
      } else {
        std::cout << "wrote " << o->out << " (" << t.mesh.positions.size() << " vertices, " << t.bands * t.bands
                  << " coefficients, " << t.rays << " rays in " << t.ray_seconds << " s)\n";
      }
    });
  }
  // relight
  {
    struct Opt {
      std::string transfer, out, size = "256x256";
      RelightOptions r;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = prtc->add_subcommand("relight", "Relight a transfer file: frames (EXR + PNG) and the band-0 occlusion image");
    c->add_option("transfer", o->transfer, "transfer file from prt bake: .ply (per vertex) or .exr (per pixel)")->required();
    c->add_option("--light", o->r.light_csv, "SH coefficient CSV of the light (l, m, index, channels), e.g. from sh project");
    c->add_option("--light-dir", o->r.light_dirs, "direction towards a distant light x,y,z (repeatable)");
    c->add_option("--frames", o->r.frames, "turn each --light-dir about +z in this many frames (default 1)");
    c->add_option("--size", o->size, "image size WxH (default 256x256; per-vertex transfer only)");
    c->add_option("--view", o->r.view, "direction from the scene centre to the camera x,y,z (per-vertex transfer only)");
    c->add_option("--exposure", o->r.exposure, "tone-mapping exposure (0 = auto)");
    c->add_option("-o,--output", o->out, "output folder")->required();
    c->callback([o] {
      if (!std::isfinite(o->r.exposure) || o->r.exposure < 0)
        throw InputError("--exposure " + io::format_double(o->r.exposure) + ": must be finite and >= 0 (0 = auto)");
      const auto sz = parse_size(o->size, "--size");
      o->r.width = sz[0];
      o->r.height = sz[1];
      if (sz[0] > 8192 || sz[1] > 8192) throw InputError("--size: '" + o->size + "' exceeds 8192x8192");
      const auto written = fs::path(o->transfer).extension() == ".exr"
                               ? relight_pixels_to(o->transfer, o->r, o->out)
                               : relight_to(prt::read_transfer(o->transfer), o->r, o->out);
      std::cout << "wrote " << written.size() << " files to " << o->out << "\n";
    });
  }
  // converge
  {
    struct Opt {
      std::string mesh, builtin = "sphere-on-plane", mode = "shadowed", out, strata = "4,8,16,32,45";
      std::string device = "auto", pixels = "96x96", depth_maps = "256,1024", view = "1,-1.6,1.1";
      int bands = 3, resolution = 16, reference_samples = 16384, threads = 0;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = prtc->add_subcommand("converge", "Transfer error against a high-sample reference versus run time (CSV + PNG)");
    c->add_option("mesh", o->mesh, "mesh file (.obj, .ply); default: --scene-builtin sphere-on-plane");
    c->add_option("--scene-builtin", o->builtin, "built-in scene (default sphere-on-plane)");
    c->add_option("--resolution", o->resolution, "tessellation of a built-in scene (default 16)");
    c->add_option("--bands", o->bands, "SH bands (default 3)");
    c->add_option("--mode", o->mode, "shadowed | interreflected (default shadowed)");
    c->add_option("--strata", o->strata, "jittered strata per side of the rows (default 4,8,16,32,45)");
    c->add_option("--reference-samples", o->reference_samples, "samples of the reference (square, default 16384)");
    c->add_option("--threads", o->threads, "worker threads (0 = all cores)");
    c->add_option("--device", o->device,
                  "per-pixel rows: cpu (ray casting only) | gpu (also the depth-map method) | auto (GPU if an EGL "
                  "device exists; default)");
    c->add_option("--pixels", o->pixels, "per-pixel rows: camera image size WxH (default 96x96)");
    c->add_option("--depth-maps", o->depth_maps, "GPU rows: depth-map sizes (default 256,1024)");
    c->add_option("--view", o->view, "per-pixel rows: direction from the scene centre to the camera");
    c->add_option("-o,--output", o->out, "output stem (writes STEM.csv and STEM.png)")->required();
    c->callback([o] {
      check_device(o->device);
      ProgressStep step("prt converge");
      PixelStudy px;
      px.device = o->device;
      const auto sz = parse_size(o->pixels, "--pixels");
      px.width = sz[0];
      px.height = sz[1];
      if (sz[0] > 4096 || sz[1] > 4096) throw InputError("--pixels: '" + o->pixels + "' exceeds 4096x4096");
      px.depth_maps.clear();
      for (double d : parse_list(o->depth_maps, "--depth-maps")) {
        if (d < 16 || d > 16384 || d != std::floor(d))
          throw InputError("--depth-maps: " + io::format_double(d) + " is not an integer in 16..16384");
        px.depth_maps.push_back(static_cast<int>(d));
      }
      if (px.depth_maps.empty()) throw InputError("--depth-maps: empty list");
      const auto vv = parse_triple(o->view, "--view");
      px.view = {vv[0], vv[1], vv[2]};
      if (glm::length(px.view) == 0) throw InputError("--view: zero vector '" + o->view + "'");
      const prt::Mesh mesh = load_input(o->mesh, o->mesh.empty() ? o->builtin : "", o->resolution);
      const auto mode = sh::prt::parse_transfer_mode(o->mode);
      if (mode == sh::prt::TransferMode::unshadowed)
        throw InputError("--mode: unshadowed transfer is exact (closed form); converge takes shadowed or interreflected");
      if (o->bands < 1 || o->bands > 16) throw InputError("--bands: must be in 1..16, got " + std::to_string(o->bands));
      std::vector<int> strata;
      for (double s : parse_list(o->strata, "--strata")) {
        if (s < 1 || s > 2000 || s != std::floor(s)) throw InputError("--strata: " + io::format_double(s) + " is not an integer in 1..2000");
        strata.push_back(static_cast<int>(s));
      }
      const auto files = converge_study(mesh, o->bands, mode, strata_of_samples(o->reference_samples), strata,
                                        threads_option(o->threads), px, o->out);
      for (const auto& f : files) std::cout << "wrote " << f.string() << "\n";
    });
  }
}

void demo_prt(DemoContext& ctx) {
  ProgressStep step("demo: precomputed radiance transfer");
  const fs::path dir = ctx.out_dir / "prt";
  const int res = ctx.quick ? 12 : 40;
  prt::BakeOptions bo;
  bo.bands = ctx.quick ? 3 : 4;
  bo.strata = ctx.quick ? 12 : 45;
  bo.mode = sh::prt::TransferMode::interreflected;
  bo.bounces = 2;
  const prt::Mesh mesh = prt::builtin_scene("sphere-on-plane", res);
  const prt::Transfer t = prt::bake(mesh, bo);
  auto prov = io::Provenance::current();
  prov.add("mesh", mesh.name);
  const fs::path tf = dir / "sphere_on_plane_transfer.ply";
  prt::write_transfer(tf, t, prov);
  ctx.written.push_back(tf);
  RelightOptions ro;
  ro.light_dirs = {"1,0.3,1.2"};
  ro.frames = ctx.quick ? 2 : 12;
  ro.width = ro.height = ctx.quick ? 96 : 384;
  for (const auto& f : relight_to(t, ro, dir / "relight")) ctx.written.push_back(f);
  const std::vector<int> strata = ctx.quick ? std::vector<int>{3, 6} : std::vector<int>{4, 8, 16, 32, 45};
  PixelStudy px;  // GPU rows where an EGL device exists (llvmpipe included)
  px.width = px.height = ctx.quick ? 32 : 96;
  px.depth_maps = ctx.quick ? std::vector<int>{64, 256} : std::vector<int>{256, 1024};
  for (const auto& f : converge_study(prt::builtin_scene("sphere-on-plane", ctx.quick ? 6 : 16), 3,
                                      sh::prt::TransferMode::shadowed, ctx.quick ? 24 : 128, strata, 0, px,
                                      dir / "converge"))
    ctx.written.push_back(f);
}

}  // namespace atmosh::cli
