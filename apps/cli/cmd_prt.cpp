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
#include "atmosh/io/transfer_exr.hpp"
#include "atmosh/prt/bake.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/studies/studies_prt.hpp"
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

struct RelightOptions {
  std::vector<std::string> light_dirs;
  std::string light_csv;
  int frames = 1;
  int width = 256, height = 256;
  std::string view = "1,-1.6,1.1";
  double exposure = 0.0;  // 0 = auto
};

// The lights of a relight run: [frame][channel][coefficient].
std::vector<studies::ShLight> relight_lights(const RelightOptions& o, int bands) {
  if (o.light_csv.empty() == o.light_dirs.empty()) throw InputError("give exactly one of --light CSV or --light-dir x,y,z");
  if (o.frames < 1 || o.frames > 3600) throw InputError("--frames: must be in 1..3600, got " + std::to_string(o.frames));
  if (!o.light_csv.empty()) return {io::read_sh_light(o.light_csv, bands)};
  std::vector<glm::dvec3> dirs;
  for (const auto& s : o.light_dirs) {
    const auto d = parse_triple(s, "--light-dir");
    dirs.emplace_back(d[0], d[1], d[2]);
    if (glm::length(dirs.back()) == 0) throw InputError("--light-dir: zero vector '" + s + "'");
  }
  return studies::turning_lights(dirs, o.frames, bands);
}

studies::RelightImageOptions image_options(const RelightOptions& o) {
  const auto vv = parse_triple(o.view, "--view");
  studies::RelightImageOptions io;
  io.width = o.width;
  io.height = o.height;
  io.view = {vv[0], vv[1], vv[2]};
  if (glm::length(io.view) == 0) throw InputError("--view: zero vector '" + o.view + "'");
  io.exposure = o.exposure;
  io.given_exposure_rule = "given (--exposure)";
  return io;
}

// Writes frame_NNNN.(exr|png) for each light and ao.(exr|png) (band-0 simple occlusion).
std::vector<fs::path> relight_to(const prt::Transfer& t, const RelightOptions& o, const fs::path& dir) {
  const auto lights = relight_lights(o, t.bands);
  return studies::relight_vertices_to(t, lights, image_options(o), dir);
}

// Per-pixel relighting of a per-pixel transfer EXR (prt bake -o X.exr).
std::vector<fs::path> relight_pixels_to(const fs::path& file, const RelightOptions& o, const fs::path& dir) {
  const io::TransferImage ex = io::read_transfer_exr(file, memory_budget());
  const auto lights = relight_lights(o, ex.bands);
  return studies::relight_pixels_to(ex, file.string(), lights, image_options(o), dir);
}

// What the per-pixel rows of a converge study cover (studies::PrtConvergenceOptions).
struct PixelStudy {
  int width = 96, height = 96;
  std::string device = "auto";
  std::vector<int> depth_maps = {256, 1024};
  glm::dvec3 view{1, -1.6, 1.1};
};

std::vector<fs::path> converge_study(const prt::Mesh& mesh, int bands, sh::prt::TransferMode mode, int ref_strata,
                                     const std::vector<int>& strata, int threads, const PixelStudy& px,
                                     const fs::path& stem) {
  studies::PrtConvergenceOptions o;
  o.bands = bands;
  o.mode = mode;
  o.reference_strata = ref_strata;
  o.strata = strata;
  o.threads = threads;
  o.width = px.width;
  o.height = px.height;
  o.view = px.view;
  o.device = px.device;
  o.depth_maps = px.depth_maps;
  o.notice = [](const std::string& m) { std::cerr << "atmosh: " << m << "\n"; };
  o.cpu_only_note = "not run (--device cpu)";
  const studies::StudyTable t = studies::prt_convergence(mesh, o);  // "--device gpu: <why>" without a GPU
  return io::write_study(stem, t.spec, t.rows, t.provenance);
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
      if (o->device != "cpu" && o->device != "gpu")
        throw InputError("--device: unknown device '" + o->device + "' (cpu, gpu)");
      bo.device = prt::parse_device(o->device);
      if (o->bounces < 0 || o->bounces > 100) throw InputError("--bounces: must be in 0..100, got " + std::to_string(o->bounces));
      if (!(o->albedo >= 0 && o->albedo <= 1))
        throw InputError("--albedo: must be in [0, 1], got " + std::to_string(o->albedo));
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
      check_output_file(o->out, {".ply", ".exr"}, "-o");
      if (bo.device == prt::Device::gpu && ext != ".exr")
        throw InputError("--device gpu: the depth-map method is per-pixel; write an .exr (per-vertex bakes use --device cpu)");
      if (ext == ".exr" && bo.mode == sh::prt::TransferMode::interreflected)
        throw InputError("--mode interreflected: per-pixel transfer is unshadowed or shadowed");
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
        const std::size_t K = static_cast<std::size_t>(px.bands) * px.bands;
        const io::TransferImage ex = studies::transfer_image(px, bo.mode, o->view);
        auto prov = io::Provenance::current();
        prov.add("mesh", mesh.name);
        io::write_transfer_exr(o->out, ex, prov);
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
    add_format_option(c, o->out);
    c->callback([o] {
      check_device(o->device);
      check_study_stem(o->out, "-o");
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
  for (const auto& f : studies::demo_prt(ctx.out_dir / "prt", ctx.quick, [](const std::string& m) {
         std::cerr << "atmosh: " << m << "\n";
       }))
    ctx.written.push_back(f);
}

}  // namespace atmosh::cli
