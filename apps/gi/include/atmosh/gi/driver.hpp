// atmosh/gi/driver.hpp — diffuse global illumination as a front end drives it (`atmosh gi
// render|converge`, the Python module): a scene from a request (a built-in scene or a
// mesh, and its lights), the one dispatch over the rendering methods, the image files of
// a render, its JSON summary, and the convergence study of the methods against the
// path-traced reference at matched lighting.
//
// Every method is rendered through gi::render_method (atmosh/gi/methods.hpp); a new
// method is one more branch there (and its quantity in write_method_image, its settings in
// render_json); the command line passes --method through. Checks throw atmosh::InputError naming the option as the command line spells
// it (--method, --samples, --light, ...).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "atmosh/gi/methods.hpp"
#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/probes.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/progress.hpp"

namespace atmosh::gi {

// What is rendered and how it is lit, as given.
struct SceneRequest {
  std::string builtin, mesh;  // exactly one: cornell-box | sphere-on-plane | box-occluder, or a mesh file
  std::string light;          // "sun:AZ,EL" (degrees; azimuth from north towards east), or empty
  std::string sun_irradiance = "1,1,1";  // R,G,B at normal incidence
  double sun_radius_deg = 0;  // 0: a point sun; at most 28
  std::string sky_radiance;   // uniform sky R,G,B (SH band 0), or empty
  std::string env_sh;         // SH coefficient CSV of the environment, or empty
  std::string env;            // equirectangular environment EXR, or empty
  double albedo = 0.8;        // a mesh's albedo where the file gives none
  int resolution = 32;        // tessellation of the curved built-in scenes
};
// The scene, its lights set; nothing lights it: a white sky of radiance 1. Checked
// (gi::validate).
Scene scene_from_request(const SceneRequest& request);

// How a scene is rendered, as a front end gives it (names as typed; method_options turns
// it into gi::MethodOptions).
struct RenderOptions {
  std::string method = "path";  // path | probes | radiosity | lpv
  int samples = 16;             // paths per pixel (path) or per probe cube-map texel (probes)
  int bounces = -1;             // -1: unlimited (Russian roulette); radiosity: walk steps (-1: 3)
  std::uint64_t seed = 1;
  int threads = 0;              // 0 = the CPUs this process may use
  // probes, radiosity, lpv
  int bands = 3, grid = 4, cube_size = 8, pixel_samples = 4;
  std::string window = "none";  // probes: none | hanning | lanczos | nonnegative
  bool probe_visibility = false;
  int iterations = -1;          // lpv: propagation steps (-1: 2 x grid)
  int cascades = 1;             // lpv: 1 grid, or 2 (the 2-level nested cascade, grid >= 2)
  std::string lpv_reemission = "direction";  // lpv: direction | paper (gi::LpvReemission, lpv.hpp)
  int lpv_emitter_rsm = 0;      // lpv on the GPU frame: 0 photon VPLs, or the emitters' RSM texels a face side
  std::string device = "cpu";   // cpu | gpu | auto (radiosity shading and lpv run on the GPU)
};
// The method's options, checked (InputError naming the option).
MethodOptions method_options(const RenderOptions& options);
// The options of a render (and the scene request's one-of), checked before any work.
void check_render_request(const SceneRequest& scene, const RenderOptions& options);
// The window of the probes' SH (InputError naming --window).
sh::Window probe_window(const std::string& name);
// Memory of a probe grid of grid^3 probes (bytes, saturating).
std::size_t probe_grid_bytes(int grid, int cube_size);

struct MethodImage {
  RadianceImage image;       // mean and standard error per pixel; stats of every ray
  double probe_seconds = 0;  // probes: building the grid; radiosity, lpv: building the volume
  DeviceDecision device;     // where the GPU passes ran; auto's fallback notice
};
// The scene rendered by options.method into width x height pixels (the scene's camera),
// through gi::render_method. progress: fractions done, where the method reports them.
MethodImage render_request(const Scene& scene, int width, int height, const RenderOptions& options,
                           const ProgressCallback& progress = {});

// The render as EXR (R, G, B, stderr.R, stderr.G, stderr.B) with its provenance and, if
// png is non-empty, a tone-mapped PNG (exposure: 1 / the 99th percentile of G) with its
// side file.
void write_method_image(const std::filesystem::path& exr, const std::filesystem::path& png, const Scene& scene,
                        const RenderOptions& options, const MethodImage& image);
// The JSON summary of a render (`atmosh gi render --json`).
nlohmann::json render_json(const Scene& scene, const RenderOptions& options, const MethodImage& image,
                           const std::string& output);

// The convergence study: probes (each grid, each band count, plain and visibility-weighted),
// the path tracer at fewer samples, and the radiosity and LPV settings of `study`, against
// a path-traced reference.
struct ConvergeOptions {
  RenderOptions method;  // samples per probe texel, bounces, seed, threads, cube_size, pixel_samples, window
  StudyOptions study;    // radiosity and lpv rows (empty lists: none)
  std::vector<int> bands = {1, 2, 3, 4}, grids = {2, 3, 4, 6, 8}, path_samples = {4, 16};
  int reference_samples = 256;
};
struct ConvergeStudy {
  io::StudySpec spec;
  std::vector<io::StudyRow> rows;  // path "spp=N", probes[-visibility] "bands=B grid=G", radiosity, lpv;
                                   // with --device gpu|auto also probes-gpu[-visibility] (projected on the GPU,
                                   // shaded on the CPU), probes-resident-gpu "bands=B grid=G" (B <= 16; the
                                   // GPU-resident frame, time_s = one frame), radiosity-gpu, lpv[-noblock]-gpu,
                                   // lpv-cascade-gpu (the 2-level cascade in the GPU-resident LPV frame),
                                   // lpv-paper[-gpu] (the published re-emission, StudyOptions::lpv_paper_max_grid),
                                   // lpv-rsm-gpu (the emitters' RSMs, StudyOptions::lpv_emitter_rsm)
  io::Provenance provenance;
  std::string notice;  // --device auto without a usable GPU: one line for the user
};
// Runs a named step of work with a progress callback (a front end shows it); empty: runs it.
using StepRunner = std::function<void(const std::string& name, const std::function<void(const ProgressCallback&)>& work)>;
// Renders the reference and every row; writes dir/reference.exr|png and, per probe row,
// dir/<method>_b<B>_g<G>.exr|png (error.* = the row minus the reference). Directly seen
// emitters (and a 1-pixel border) are left out of the errors. Throws InputError naming
// --bands-list, before any work, when options.bands is empty.
ConvergeStudy converge_methods(const Scene& scene, int width, int height, const ConvergeOptions& options,
                               const std::filesystem::path& dir, const StepRunner& step = {});

}  // namespace atmosh::gi
