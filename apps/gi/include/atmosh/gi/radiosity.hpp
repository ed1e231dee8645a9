// atmosh/gi/radiosity.hpp — the real-time multi-bounce radiosity approximation, on the CPU:
// a low-resolution volume of probes that stores, per probe, the SH projection of its
// distance cube map and a bent normal from its normal cube map, and a material volume
// (reflectivity); each receiver walks a few bounces through it (the per-receiver math is
// atmosh/gi/shared/radiosity.glsl.hpp, written once for C++ and GLSL; the GPU pass: render_radiosity_gbuffer below).
//
// Volume (n^3 probes at the cell centres of the scene's bounding box [lo, hi], as ProbeGrid):
//   * distance cube map: cube_size^2 texels a face (libsh's layout), each the distance from
//     the probe to the first surface along the texel-centre ray (Embree ray casting); rays
//     that hit nothing store the box's diagonal (so a walk along them leaves the box);
//   * distance SH: the cube projected with libsh's exact texel solid angles
//     (sh::project_cube) to `bands` bands (1: the mean distance, 2: plus the linear band —
//     SH orders 1 and 2 — or 3);
//   * bent normal: sum_t w_t n_t / sum_t w_t, w_t = Omega_t / d_t^2, over the texels that
//     hit, n_t the surface's normal turned towards the probe — the normal of the surfaces
//     near the probe (1/d^2: near surfaces dominate); its length (0..1) says how coherent
//     they are: a probe amid surfaces facing every way (the centre of a room) has a short
//     one, and the walk does not trust a fetched normal shorter than 0.3 (it turns back,
//     shared/radiosity.glsl.hpp); zero when every ray missed;
//   * material volume: the albedo of the hit surfaces averaged with the same weights.
// Fetches at a point are trilinear over the 8 surrounding probes (positions clamped to the
// span of the centres, as interpolate() in probes.hpp). The trilinear blend of each probe's
// distance from its own position needs no parallax term: the blended probe positions are
// the point itself inside the span (trilinear interpolation reproduces linear functions).
//
// Receiver (first hit of a camera ray at x, normal n towards the camera, albedo a):
//   L = L_e + a / pi (E_direct(x, n) + pi L_in(x, n)),  L_in by gi_radiosity_incident
// (bounces B: the walk along n, reflections about the fetched normals; B = 0: direct light
// only; the walk ends where it leaves the box grown by 10 % a side: the sky seen there is
// direct light, already in the E_direct of the vertex it left). E_direct is a one-sample estimate per camera ray (sun and emitters with a shadow ray
// each, the environment with one cosine-distributed shadow ray), at the receiver and at every
// walk vertex — so the images are noisy at few camera rays; the noise is in stderr_.
// Units: lengths in the scene's unit; radiance in the lights' units (scene.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/scene.hpp"

namespace atmosh::gi {

struct RadiosityOptions {
  int grid = 16;       ///< probes per axis, 1..64
  int bands = 2;       ///< SH bands of the distance, 1..3
  int cube_size = 8;   ///< distance / normal cube-map texels per face edge, 1..128
  int bounces = 2;     ///< walk steps per receiver, 0..16
  int samples = 4;     ///< camera rays per pixel, 1..1e6
  std::uint64_t seed = 1;
  int threads = 0;     ///< 0 = atmosh::resolve_threads(0)
};

struct RadiosityVolume {
  glm::dvec3 lo{0.0}, hi{1.0};
  int n = 1, bands = 1;
  std::vector<std::array<double, 9>> distance;  ///< per probe, bands^2 used; index (k n + j) n + i
  std::vector<glm::dvec3> normal;               ///< bent normal per probe (length 0..1: coherence)
  std::vector<glm::dvec3> albedo;               ///< reflectivity per probe and channel
  /// Per probe the direct irradiance at the probe as an SH function of the surface normal,
  /// bands 0-1 per channel ([channel 4 + i]); empty unless add_direct_volume filled it. It
  /// is the direct light of the GPU pass's walk vertices (see below).
  std::vector<std::array<double, 12>> direct;
  double seconds = 0;                           ///< wall time of the build
  std::uint64_t rays = 0;
  glm::dvec3 position(int i, int j, int k) const;
};

/// Builds the volume (InputError for bad options or an invalid scene).
RadiosityVolume build_radiosity_volume(const Scene& scene, const RadiosityOptions& opt);
/// The volume truncated to fewer distance bands (1 <= bands <= v.bands).
RadiosityVolume truncate_volume(const RadiosityVolume& v, int bands);
/// Trilinear fetches at p: SH distance along unit d, bent normal (not normalised), albedo.
double volume_distance(const RadiosityVolume& v, const glm::dvec3& p, const glm::dvec3& d);
glm::dvec3 volume_normal(const RadiosityVolume& v, const glm::dvec3& p);
glm::dvec3 volume_albedo(const RadiosityVolume& v, const glm::dvec3& p);

/// Image lit by the volume; opt.bounces, samples, seed, threads are used here. stats.seconds:
/// the shading loop.
RadianceImage render_radiosity(const Scene& scene, const Camera& camera, int width, int height,
                               const RadiosityVolume& volume, const RadiosityOptions& opt);

// ---- The GPU pass (and its CPU twin) ---------------------------------------------------
// The per-receiver walk runs in a compute shader (gpu/shaders/gi_radiosity_shade.comp) that
// pastes the shared block of atmosh/gi/shared/radiosity.glsl.hpp; the volume goes up as
// storage buffers. A shader casts no shadow rays, so at the walk's vertices the direct
// irradiance is the volume's: E(q, n) = max(0, sum_i e_i(q) Y_i(n)), e(q) the trilinear blend
// of the probes' `direct` SH (bands 0-1). The receivers' own direct light comes with them.

/// Fills v.direct: at each probe, E_direct at `normals` directions (a spherical Fibonacci
/// set), each the mean of `samples` one-sample estimates (the CPU's DirectLight: sun,
/// emitters, sky with shadow rays), projected to SH bands 0-1 with equal weights 4 pi /
/// normals. Seeded; InputError for bad counts. Adds its wall time to v.seconds.
void add_direct_volume(const Scene& scene, RadiosityVolume& v, int normals = 32, int samples = 4,
                       std::uint64_t seed = 1, int threads = 0);

/// Receivers of the pass (a G-buffer's texels): position, unit normal (the side the light
/// comes from), albedo, emitted radiance towards the camera, direct irradiance E_direct.
struct RadiosityReceivers {
  std::vector<glm::dvec3> position, normal, albedo, emission, direct;
  std::size_t size() const { return position.size(); }
};

/// The box the walk stays in: the volume's box grown by 10 % of its extent a side.
void radiosity_walk_box(const RadiosityVolume& v, glm::dvec3& lo, glm::dvec3& hi);

/// L = L_e + a / pi max(0, E_direct + pi L_in), L_in the shared walk through the volume
/// with the direct-light SH at the walk's vertices: in double on the CPU (the reference of
/// the GPU pass), and in float on the GPU (std::runtime_error / gpu::Unavailable without a
/// context, InputError in a build without atmosh::gpu). v.direct must be filled.
std::vector<glm::dvec3> shade_receivers_cpu(const RadiosityVolume& v, const RadiosityReceivers& r, int bounces);
std::vector<glm::dvec3> shade_receivers_gpu(const RadiosityVolume& v, const RadiosityReceivers& r, int bounces,
                                            double* gpu_seconds = nullptr);

/// The G-buffer of `camera`: the first hit of one ray through each pixel's centre (pixels
/// whose ray misses get no receiver: `pixel` maps receivers to pixels, the misses see the
/// environment in `background`), E_direct the mean of `samples` DirectLight estimates.
struct RadiosityGBuffer {
  RadiosityReceivers receivers;
  std::vector<std::size_t> pixel;
  std::vector<glm::dvec3> background;  ///< per pixel (misses only; 0 elsewhere)
  std::uint64_t rays = 0;
};
RadiosityGBuffer radiosity_gbuffer(const Scene& scene, const Camera& camera, int width, int height, int samples,
                                   std::uint64_t seed, int threads = 0);

/// The sun's shadow map of the rasterised G-buffer (atmosh/gpu/gi_raster.hpp): resolution^2
/// texels over the scene's bounding sphere (texel t = 2 r / resolution), percentage-closer
/// filtering over (2 pcf + 1)^2 texels, the point moved normal_offset t along its normal and
/// compared with the stored depth + bias t (1 + min(tan(angle to the sun), 8)).
struct ShadowMapOptions {
  int resolution = 1024;       ///< 16..16384
  int pcf = 1;                 ///< 0..4
  double normal_offset = 1.0;  ///< texels, >= 0
  double bias = 1.0;           ///< texels, >= 0
  /// Area emitters on the GPU (gpu::GiEmitterOptions): sample points per emitting triangle, each
  /// with a distance cube map of `emitter_resolution`^2 texels a face; 0: the CPU's estimator.
  /// Scenes with more than 64 emitting triangles use the CPU's estimator.
  int emitter_points = 4;          ///< 0..64
  int emitter_resolution = 256;    ///< 16..4096
  /// The environment on the GPU (gpu::GiSkyOptions): a spherical-Fibonacci set of
  /// `sky_directions` directions of equal weight 4 pi / N, each with an orthographic depth map of
  /// `sky_resolution`^2 texels; E = sum 4 pi / N L(w_k) max(0, n . w_k) V. 0: the CPU's estimator.
  int sky_directions = 128;        ///< 0..1024
  int sky_resolution = 256;        ///< 16..8192
};

/// The G-buffer of `camera` rasterised on the GPU (atmosh::gpu::gi_gbuffer, its own EGL
/// context): the surface at each pixel's centre (position, normal towards the camera, albedo,
/// emission towards the camera) as radiosity_gbuffer's ray would find it, except at edge
/// pixels (the rasteriser's coverage rule against Embree's ray test); E_direct =
///   the sun's by the shadow map (E_sun max(0, n . s) V, V by PCF; a disc sun as a point),
///   + the area emitters' on the GPU where shadow.emitter_points > 0 and the scene has 1..64
///     emitting triangles: each triangle's exact unoccluded irradiance (the shared polygon
///     formula, evaluated as the CPU's: 1 % of the ray offset above p) times the mean
///     visibility of emitter_points fixed points on it by distance cube maps (the CPU's
///     estimator takes one uniform random point per sample instead); otherwise on the CPU,
///   + the environment's on the GPU where shadow.sky_directions > 0: a fixed quadrature over
///     the sphere with a depth map per direction (unoccluded uniform sky: E within 0.66 % of
///     pi L at 128 directions); otherwise on the CPU,
/// lights left on the CPU: the mean of `samples` one-sample DirectLight estimates at the
/// rasterised points (the same per-pixel random streams as radiosity_gbuffer).
/// Misses see the environment. `rays`: the CPU's shadow rays (0 when every light is on the
/// GPU). gpu_seconds: the rasterisation (upload, shadow and distance maps, G-buffer,
/// read-back). std::runtime_error (gpu::Unavailable) without an EGL context, InputError for
/// bad input or a build without atmosh::gpu.
RadiosityGBuffer radiosity_gbuffer_gpu(const Scene& scene, const Camera& camera, int width, int height, int samples,
                                       std::uint64_t seed, int threads = 0, const ShadowMapOptions& shadow = {},
                                       double* gpu_seconds = nullptr);

/// The image by the GPU pass (gpu = true: rasterised G-buffer, radiosity_gbuffer_gpu) or its CPU twin: G-buffer, then
/// shade_receivers_*; fills volume.direct first where it is empty (opt.seed, opt.threads).
/// stderr_ is 0 (one G-buffer ray per pixel). stats.seconds: G-buffer + shading.
RadianceImage render_radiosity_gbuffer(const Scene& scene, const Camera& camera, int width, int height,
                                       RadiosityVolume& volume, const RadiosityOptions& opt, bool gpu);

}  // namespace atmosh::gi
