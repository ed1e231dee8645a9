// atmosh/studies/studies_prt.hpp — precomputed radiance transfer's studies and drivers
// as library calls: the lights of a relight run, relit frames of a per-vertex or
// per-pixel transfer, the transfer error measures and the sample-count study
// (transfer against a high-sample reference, per vertex and per pixel, CPU and GPU).
// No printing and no command line: notices go through a callback; the writers take
// the output folder (its files: ao.exr/.png/.png.json and frame_NNNN.exr/.png/.png.json).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "atmosh/io/provenance.hpp"
#include "atmosh/io/transfer_exr.hpp"
#include "atmosh/prt/bake.hpp"
#include "atmosh/sh/prt.hpp"
#include "atmosh/studies/study_table.hpp"

namespace atmosh::studies {

// One frame's light: [channel][coefficient], SH of the incident radiance.
using ShLight = std::vector<std::vector<double>>;

// Directional lights of irradiance pi (a white Lambertian surface then shows rho V cos),
// each direction turned about +z in `frames` equal steps: frames x directions lights
// (direction-major), one channel each. InputError for a zero direction or frames < 1.
std::vector<ShLight> turning_lights(const std::vector<glm::dvec3>& directions, int frames, int bands);

// The exposure that maps the 99th percentile of the values to ~1 (1 when it is not > 0).
double auto_exposure(std::vector<float> values);

// How relit frames are imaged and tone-mapped.
struct RelightImageOptions {
  int width = 256, height = 256;      // per-vertex transfer only (per pixel: the image's own)
  glm::dvec3 view{1, -1.6, 1.1};      // from the scene centre towards the camera (per vertex)
  double exposure = 0.0;              // > 0: fixed; 0: auto_exposure of frame 0's first channel, every frame
  std::string given_exposure_rule = "given";  // the side files' exposure_rule for a fixed exposure
};

// Per-vertex transfer relit by each light: ao.* (band-0 occlusion, exposure 1) and
// frame_NNNN.* in `dir`; returns the files written in order.
std::vector<std::filesystem::path> relight_vertices_to(const prt::Transfer& transfer, const std::vector<ShLight>& lights,
                                                       const RelightImageOptions& options,
                                                       const std::filesystem::path& dir);
// A per-pixel transfer image relit by each light: sum_i T_i(pixel) light_i per channel;
// ao.* is the image's ao channel; the size and view are the image's own. `source`
// names the transfer file in the provenance.
std::vector<std::filesystem::path> relight_pixels_to(const io::TransferImage& transfer, const std::string& source,
                                                     const std::vector<ShLight>& lights,
                                                     const RelightImageOptions& options,
                                                     const std::filesystem::path& dir);

// A per-pixel bake as the transfer image io::write_transfer_exr writes: coefficients
// as float channels, ao, mask, and the attributes quantity, view (as given), samples,
// device and (GPU) depth_map.
io::TransferImage transfer_image(const prt::PixelTransfer& transfer, sh::prt::TransferMode mode,
                                 const std::string& view);

// Transfer error of `t` against `ref` (same mesh): per vertex |T - T_ref|_2 relative to
// max_v |T_ref,v|_2; {max, rms over vertices}.
std::pair<double, double> transfer_error(const prt::Transfer& t, const prt::Transfer& ref);
// Per pixel seen by both (mask), |T - T_ref|_2 relative to max_p |T_ref,p|_2; {max, rms}.
std::pair<double, double> pixel_error(const prt::PixelTransfer& t, const prt::PixelTransfer& ref);

struct PrtConvergenceOptions {
  int bands = 3;
  sh::prt::TransferMode mode = sh::prt::TransferMode::shadowed;  // shadowed or interreflected
  int reference_strata = 128;       // reference: n x n jittered samples, seed 12345
  std::vector<int> strata = {4, 8, 16, 32, 45};  // the rows: n x n samples, seed 1
  int threads = 0;                  // resolved by the caller's policy (0 = the CPUs available)
  // Per-pixel rows (shadowed only): camera image, view, device ("cpu": CPU ray
  // casting only; "gpu": also the depth-map method, or std::runtime_error "--device
  // gpu: <why>"; "auto": the depth-map method where it runs, else a notice: the
  // toolkit's one device policy, atmosh::resolve_device) and the depth-map sizes.
  int width = 96, height = 96;
  glm::dvec3 view{1, -1.6, 1.1};
  std::string device = "auto";
  std::vector<int> depth_maps = {256, 1024};
  std::function<void(const std::string&)> notice;  // one-line notices; empty: none
  // The provenance line gpu_method when device is "cpu" (how the caller chose it).
  std::string cpu_only_note = "not run (device cpu)";
};
// Rows cpu-<mode>-jittered (per vertex), cpu-pixel-<mode>-jittered and
// gpu-depthmap<N>-<mode>-jittered (per pixel), extra columns samples, rays, depth_map.
StudyTable prt_convergence(const prt::Mesh& mesh, const PrtConvergenceOptions& options);

// The mesh of a PRT command: a file (.obj, .ply) or a built-in scene, exactly one
// (InputError naming MESH and --scene-builtin otherwise).
prt::Mesh prt_input_mesh(const std::string& mesh_file, const std::string& builtin, int resolution);
// n x n jittered strata for a sample count n^2 (1..4000000); InputError naming `option`.
int strata_of_samples(int samples, const std::string& option = "--samples");

// `atmosh prt bake` as its options give it, checked into the bake's options (InputError
// naming --device cpu | gpu, --bounces 0..100, --albedo [0, 1], --depth-map 16..16384,
// --mode, --bands 1..16, --samples, --threads, and -o: .ply (per vertex, CPU) or .exr
// (per pixel, unshadowed or shadowed)). Threads resolved (0 = the CPUs this process may use).
struct PrtBakeRequest {
  std::string mode = "shadowed", device = "cpu", output;
  int bands = 3, samples = 2025, bounces = 2, threads = 0, depth_map = 1024;
  double albedo = 0.8;
  std::uint64_t seed = 1;
};
prt::BakeOptions prt_bake_options(const PrtBakeRequest& request);
// Bakes the mesh and writes the transfer to `file` (with the mesh's name in the
// provenance): .exr a per-pixel transfer image of `size` seen from `view` ("x,y,z",
// recorded as given; prt::bake_pixels), else a per-vertex .ply (prt::bake). Returns the
// JSON summary (prt_pixel_bake_json / prt_bake_json; time_s: the bake's wall clock).
nlohmann::json prt_bake_to(const prt::Mesh& mesh, const prt::BakeOptions& options, const std::string& file,
                           std::array<int, 2> size, const std::string& view);

// The PRT step of the main job (`atmosh demo`) into `dir`: an interreflected bake of
// the built-in sphere-on-plane (resolution 40, 4 bands, 45 x 45 samples, 2 bounces;
// quick: 12, 3 bands, 12 x 12) written as sphere_on_plane_transfer.ply, relit by a
// light turning about +z (12 frames of 384 x 384; quick: 2 of 96 x 96) into relight/,
// and prt_convergence of the shadowed transfer (device "auto": depth-map rows where an
// EGL device exists, else `notice`) as converge.csv/.png. Returns the files in order.
std::vector<std::filesystem::path> demo_prt(const std::filesystem::path& dir, bool quick,
                                            const std::function<void(const std::string&)>& notice = {});

}  // namespace atmosh::studies
