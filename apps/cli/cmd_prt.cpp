// `atmosh prt bake|relight|converge` — precomputed radiance transfer on meshes
// (per-vertex, CPU, Embree), relit images, the sample-count study.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/io/transfer_exr.hpp"
#include "atmosh/studies/studies_prt.hpp"
#include "atmosh/studies/summaries.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {
namespace fs = std::filesystem;

glm::dvec3 view_option(const std::string& text, const std::string& option) {
  const auto v = parse_triple(text, option);
  if (glm::length(glm::dvec3(v[0], v[1], v[2])) == 0) throw InputError(option + ": zero vector '" + text + "'");
  return {v[0], v[1], v[2]};
}

struct RelightCmd {
  std::string transfer, out, size = "256x256", view = "1,-1.6,1.1", light_csv;
  std::vector<std::string> light_dirs;
  int frames = 1;
  double exposure = 0.0;  // 0 = auto
};

// The lights of a relight run: [frame][channel][coefficient].
std::vector<studies::ShLight> relight_lights(const RelightCmd& o, int bands) {
  if (o.light_csv.empty() == o.light_dirs.empty()) throw InputError("give exactly one of --light CSV or --light-dir x,y,z");
  if (o.frames < 1 || o.frames > 3600) throw InputError("--frames: must be in 1..3600, got " + std::to_string(o.frames));
  if (!o.light_csv.empty()) return {io::read_sh_light(o.light_csv, bands)};
  std::vector<glm::dvec3> dirs;
  for (const auto& s : o.light_dirs) dirs.push_back(view_option(s, "--light-dir"));
  return studies::turning_lights(dirs, o.frames, bands);
}

void run_relight(const RelightCmd& o) {
  if (!std::isfinite(o.exposure) || o.exposure < 0)
    throw InputError("--exposure " + io::format_double(o.exposure) + ": must be finite and >= 0 (0 = auto)");
  const auto sz = parse_size(o.size, "--size");
  if (sz[0] > 8192 || sz[1] > 8192) throw InputError("--size: '" + o.size + "' exceeds 8192x8192");
  studies::RelightImageOptions ro{sz[0], sz[1], {}, o.exposure, "given (--exposure)"};
  std::vector<fs::path> written;
  if (fs::path(o.transfer).extension() == ".exr") {  // per-pixel transfer (prt bake -o X.exr)
    const io::TransferImage ex = io::read_transfer_exr(o.transfer, memory_budget());
    const auto lights = relight_lights(o, ex.bands);
    ro.view = view_option(o.view, "--view");
    written = studies::relight_pixels_to(ex, o.transfer, lights, ro, o.out);
  } else {
    const prt::Transfer t = prt::read_transfer(o.transfer);
    const auto lights = relight_lights(o, t.bands);
    ro.view = view_option(o.view, "--view");
    written = studies::relight_vertices_to(t, lights, ro, o.out);
  }
  std::cout << "wrote " << written.size() << " files to " << o.out << "\n";
}

}  // namespace

void register_prt_commands(CLI::App& app) {
  CLI::App* prtc = app.add_subcommand("prt", "Precomputed radiance transfer on meshes: bake, relight, converge");
  prtc->require_subcommand(1);
  {  // bake
    struct Opt {
      studies::PrtBakeRequest r;
      std::string mesh, builtin, size = "256x256", view = "1,-1.6,1.1";
      int resolution = 32;
      bool json = false, quiet = false;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = prtc->add_subcommand("bake", "Per-vertex diffuse transfer (SH) of a mesh, by Embree ray casting");
    c->add_option("mesh", o->mesh, "mesh file (.obj, .ply)");
    c->add_option("--scene-builtin", o->builtin, "built-in scene: sphere-on-plane | box-occluder | torus | sphere");
    c->add_option("--resolution", o->resolution, "tessellation of a built-in scene (default 32)");
    c->add_option("--bands", o->r.bands, "number of SH bands L (L^2 coefficients; 1..16, default 3)");
    c->add_option("--samples", o->r.samples, "jittered sample directions n x n (default 2025 = 45 x 45)");
    c->add_option("--mode", o->r.mode, "unshadowed | shadowed | interreflected (default shadowed)");
    c->add_option("--bounces", o->r.bounces, "interreflection bounces (default 2)");
    c->add_option("--albedo", o->r.albedo, "albedo where the mesh gives none (default 0.8)");
    c->add_option("--seed", o->r.seed, "random seed of the sample set (default 1)");
    add_threads_option(c, o->r.threads);
    c->add_option("--device", o->r.device, "cpu (ray casting) | gpu (depth-map method; per-pixel .exr output only)");
    c->add_option("--depth-map", o->r.depth_map, "GPU: depth-map texels per side (16..16384, default 1024)");
    c->add_option("--size", o->size, "per-pixel (.exr) output: image size WxH (default 256x256)");
    c->add_option("--view", o->view, "per-pixel (.exr) output: direction from the scene centre to the camera");
    c->add_option("-o,--output", o->r.output, "transfer file: .ply per-vertex, .exr per-pixel (camera view)")->required();
    add_json_flag(c, o->json);
    c->add_flag("--quiet", o->quiet, "no progress on stderr");
    c->callback([o] {
      prt::BakeOptions bo = studies::prt_bake_options(o->r);
      io::set_threads(bo.threads);
      const auto sz = parse_size(o->size, "--size");
      parse_triple(o->view, "--view");
      const prt::Mesh mesh = studies::prt_input_mesh(o->mesh, o->builtin, o->resolution);
      if (o->quiet) set_progress_quiet(true);
      const bool show = !progress_quiet() && ::isatty(STDERR_FILENO);
      if (show) bo.progress = [](double f) { std::fprintf(stderr, "\rprt bake: %3d%%", static_cast<int>(100 * f)); };
      const nlohmann::json j = studies::prt_bake_to(mesh, bo, o->r.output, sz, o->view);
      if (show) std::fprintf(stderr, "\n");
      if (o->json) return print_json(j);
      std::cout << studies::prt_bake_text(j);
    });
  }
  {  // relight
    auto o = std::make_shared<RelightCmd>();
    CLI::App* c = prtc->add_subcommand("relight", "Relight a transfer file: frames (EXR + PNG) and the band-0 occlusion image");
    c->add_option("transfer", o->transfer, "transfer file from prt bake: .ply (per vertex) or .exr (per pixel)")->required();
    c->add_option("--light", o->light_csv, "SH coefficient CSV of the light (l, m, index, channels), e.g. from sh project");
    c->add_option("--light-dir", o->light_dirs, "direction towards a distant light x,y,z (repeatable)");
    c->add_option("--frames", o->frames, "turn each --light-dir about +z in this many frames (default 1)");
    c->add_option("--size", o->size, "image size WxH (default 256x256; per-vertex transfer only)");
    c->add_option("--view", o->view, "direction from the scene centre to the camera x,y,z (per-vertex transfer only)");
    c->add_option("--exposure", o->exposure, "tone-mapping exposure (0 = auto)");
    c->add_option("-o,--output", o->out, "output folder")->required();
    c->callback([o] { run_relight(*o); });
  }
  {  // converge
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
    add_threads_option(c, o->threads);
    add_device_option(c, o->device, "per-pixel rows: cpu (ray casting only) | gpu (also the depth-map method)");
    c->add_option("--pixels", o->pixels, "per-pixel rows: camera image size WxH (default 96x96)");
    c->add_option("--depth-maps", o->depth_maps, "GPU rows: depth-map sizes (default 256,1024)");
    c->add_option("--view", o->view, "per-pixel rows: direction from the scene centre to the camera");
    c->add_option("-o,--output", o->out, "output stem (writes STEM.csv and STEM.png)")->required();
    add_format_option(c, o->out);
    c->callback([o] {
      check_device(o->device);
      check_study_stem(o->out, "-o");
      ProgressStep step("prt converge");
      studies::PrtConvergenceOptions p;
      p.device = o->device;
      const auto sz = parse_size(o->pixels, "--pixels");
      p.width = sz[0];
      p.height = sz[1];
      if (sz[0] > 4096 || sz[1] > 4096) throw InputError("--pixels: '" + o->pixels + "' exceeds 4096x4096");
      p.depth_maps = parse_int_list(o->depth_maps, "--depth-maps", 16, 16384);
      p.view = view_option(o->view, "--view");
      const prt::Mesh mesh = studies::prt_input_mesh(o->mesh, o->mesh.empty() ? o->builtin : "", o->resolution);
      p.mode = sh::prt::parse_transfer_mode(o->mode);
      if (p.mode == sh::prt::TransferMode::unshadowed)
        throw InputError("--mode: unshadowed transfer is exact (closed form); converge takes shadowed or interreflected");
      if (o->bands < 1 || o->bands > 16) throw InputError("--bands: must be in 1..16, got " + std::to_string(o->bands));
      p.bands = o->bands;
      p.strata = parse_int_list(o->strata, "--strata", 1, 2000);
      p.reference_strata = studies::strata_of_samples(o->reference_samples, "--samples");
      p.threads = threads_option(o->threads);
      p.notice = notice;
      p.cpu_only_note = "not run (--device cpu)";
      const studies::StudyTable t = studies::prt_convergence(mesh, p);  // "--device gpu: <why>" without a GPU
      print_files(io::write_study(o->out, t.spec, t.rows, t.provenance), "wrote ");
    });
  }
}

}  // namespace atmosh::cli
