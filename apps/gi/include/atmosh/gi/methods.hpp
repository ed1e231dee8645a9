// atmosh/gi/methods.hpp — one entry point for every lighting method of atmosh::gi, by name:
// path (path_tracer.hpp), probes (probes.hpp), radiosity (radiosity.hpp), lpv (lpv.hpp);
// and the settings `atmosh gi converge` studies for radiosity and lpv.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "atmosh/device.hpp"
#include "atmosh/gi/lpv.hpp"
#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/sh/convolution.hpp"

namespace atmosh::gi {

struct MethodOptions {
  std::string method = "path";  ///< path | probes | radiosity | lpv
  int samples = 16;             ///< path: paths per pixel; probes: paths per cube-map texel
  int bounces = -1;             ///< path, probes: reflections (-1 unlimited); radiosity: walk steps (-1: 3)
  std::uint64_t seed = 1;
  int threads = 0;
  int bands = 3;                ///< probes: SH bands 1..16; radiosity: distance SH bands 1..3
  int grid = 4;                 ///< probes, radiosity: probes per axis; lpv: cells along the longest axis
  int cube_size = 8;            ///< probes, radiosity: cube-map texels per face edge
  int pixel_samples = 4;        ///< probes, radiosity, lpv: camera rays per pixel
  sh::Window window = sh::Window::none;  ///< probes
  bool probe_visibility = false;         ///< probes
  int iterations = -1;          ///< lpv: propagation steps (-1: 2 x grid)
  bool lpv_blocking = true;     ///< lpv: geometry volume
  LpvReemission lpv_reemission = LpvReemission::direction;  ///< lpv: the propagation's re-emission (lpv.hpp)
  /// lpv: 1 (one grid) or 2 (the 2-level nested cascade, grid >= 2: build_lpv_cascade /
  /// render_lpv_cascade on the CPU; on the GPU the resident frame with cascades = 2, scenes with
  /// <= 64 emitting triangles; beyond that gpu is an error and auto a notice and the CPU cascade)
  int lpv_cascades = 1;
  /// lpv on the GPU-resident frame: 0 (the emitters' photon VPLs) or 2..1024, the area emitters'
  /// reflective shadow maps of that many texels a cube face side instead (LpvOptions::emitter_rsm).
  /// Ignored on the CPU and by the separate GPU passes (more than 64 emitting triangles).
  int lpv_emitter_rsm = 0;
  /// cpu | gpu | auto (atmosh/device.hpp). gpu/auto: LPV injection, geometry, propagation and
  /// shading and the radiosity walk run on the GPU; probes are built from a baked surface
  /// radiance (bake_surface_radiance, surface_divisions / surface_samples) whose cube maps are
  /// rasterised (build_probe_grid_surface; where auto finds no GPU, the same cube maps by CPU
  /// rays); without probe visibility the whole frame is GPU-resident (any bands, 1..16)
  /// (ProbeFrameResident: cube maps, their SH projection, the sun's shadow map and the shading
  /// in one context; one sample per pixel centre, stderr 0); cpu
  /// path-traces the probes' cube maps (build_probe_grid). The path tracer is CPU only: gpu is
  /// an error for it, auto a notice.
  DeviceRequest device = DeviceRequest::cpu;
  int surface_divisions = 16;   ///< probes on the GPU: SurfaceRadianceOptions::divisions
  int surface_samples = 64;     ///< probes on the GPU: paths per surface vertex and side
  int surface_supersample = 4;  ///< probes on the GPU: cube maps rendered at cube_size x this, texel means
};

/// path, probes, radiosity, lpv.
std::vector<std::string> method_names();
/// nullopt if the GPU passes can run here, else why not (no EGL context, a driver that
/// refuses the probes' program, or a build without atmosh::gpu). Opens a context.
std::optional<GpuUnusable> gpu_unusable();
/// InputError naming the option for a bad method name or a value outside the method's range.
void check_method_options(const MethodOptions& opt);

struct MethodResult {
  RadianceImage image;
  double build_seconds = 0;  ///< probe grid / radiosity volume / LPV injection + propagation
  double shade_seconds = 0;  ///< the image (for path: the whole render)
  DeviceDecision device;     ///< gpu: the GPU passes ran; notice: auto's fallback, for the caller
};
/// Renders `scene` from `camera` by opt.method. A gpu request the method cannot meet throws
/// std::runtime_error ("--device gpu: ..."), as resolve_device says.
MethodResult render_method(const Scene& scene, const Camera& camera, int width, int height, const MethodOptions& opt);

/// The radiosity and LPV settings of `atmosh gi converge`:
///   radiosity: every grid in `radiosity_grids` x bands in `radiosity_bands` (1..3) x
///              bounces in `radiosity_bounces` (the volume built once per grid);
///   lpv:       every grid in `lpv_grids`, with and without the geometry volume
///              (method names "lpv" and "lpv-noblock"), iterations 2 x grid, and the 2-level
///              cascade (lpv_cascade below).
struct StudyOptions {
  std::vector<int> radiosity_grids{4, 8, 16}, radiosity_bands{1, 2}, radiosity_bounces{0, 1, 2, 3};
  std::vector<int> lpv_grids{8, 16, 32};
  int cube_size = 8, pixel_samples = 4, threads = 0;
  std::uint64_t seed = 1;
  /// Also the GPU forms, each after its CPU row, method "radiosity-gpu" (the walk over a
  /// G-buffer, render_radiosity_gbuffer; the volume and its direct-light SH built once per
  /// grid), "lpv-gpu" / "lpv-noblock-gpu" (render_method with device gpu). The caller decides
  /// (gpu_unusable()); a GPU failure then throws.
  bool gpu = false;
  /// Also, for every LPV grid in 2..lpv_cascade_max_grid (after its rows), the 2-level nested
  /// cascade (build_lpv_cascade, CPU; method "lpv", setting "grid=N iterations=K cascades=2") and,
  /// with `gpu` and <= 64 emitting triangles, the cascade in the GPU-resident frame (method
  /// "lpv-cascade-gpu", the same setting; render_method with lpv_cascades = 2). 0: none. The
  /// default leaves out grid 32 (its CPU cascade row costs ~28 s and did not lower the error on
  /// the Cornell box; docs/gi.md).
  int lpv_cascade_max_grid = 16;
  /// Also, for every LPV grid in 1..lpv_paper_max_grid (after its rows), the one-level LPV with
  /// Kaplanyan & Dachsbacher 2010's re-emission (LpvReemission::face_lobe; geometry volume on; CPU;
  /// method "lpv-paper", the "lpv" row's setting), beside the default re-emission's "lpv" row;
  /// with `gpu`, the same on the GPU after it (method "lpv-paper-gpu", render_method with
  /// lpv_reemission = face_lobe). 0: none. It costs what the "lpv" rows of the same grid cost.
  int lpv_paper_max_grid = 16;
  /// With `gpu`, for every LPV grid (geometry volume on) of a scene with 1..64 emitting
  /// triangles, the GPU-resident frame with the area emitters' reflective shadow maps of this
  /// many texels a face side instead of their photon VPLs (method "lpv-rsm-gpu", the "lpv"
  /// row's setting plus " emitter_rsm=N"; render_method with lpv_emitter_rsm). 0: none.
  int lpv_emitter_rsm = 32;
};
struct StudyRow {
  std::string method, setting;  ///< e.g. "radiosity", "bands=2 grid=8 bounces=2"
  MethodResult result;
};
/// Calls `row` once per setting, in order (InputError for bad lists).
void study_methods(const Scene& scene, int width, int height, const StudyOptions& opt,
                   const std::function<void(const StudyRow&)>& row);

}  // namespace atmosh::gi
