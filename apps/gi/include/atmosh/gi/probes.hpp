// atmosh/gi/probes.hpp — radiance probes (CPU, by ray casting): cube maps of the lit scene's
// radiance at probe positions, projected to SH; receivers shaded by the probe's SH irradiance
// at their normal (Ramamoorthi & Hanrahan 2001); probe volumes on a regular 3D grid with
// trilinear interpolation of the coefficients. Probes rasterised on the GPU: see "Probes of a
// baked surface radiance" below.
//
// A probe at position x:
//   * cube map (sh::CubeMap, faces +X -X +Y -Y +Z -Z, OpenGL orientation, see
//     atmosh/sh/projection.hpp) of size N: texel value = the path tracer's estimate of the
//     radiance arriving at x (radiance_along(): emission seen directly, the surface's
//     reflected light with all bounces, or the environment), `samples` paths per texel,
//     seeded — each texel an unbiased estimate of the mean radiance over the texel's solid
//     angle (ProbeOptions::jitter, the default) or of the radiance along its centre ray;
//   * projected to SH up to `bands` bands with libsh's exact texel solid angles
//     (sh::project_cube: texel-centre basis value x exact solid angle; second-order accurate
//     in N for smooth radiance, exact for a constant one);
//   * the distant sun is a delta direction that a cube map cannot hold: it is left out of
//     the probe (the renderer adds the sun's direct light with a shadow ray), unless
//     ProbeOptions::include_sun, which adds its exact SH projection E Y_lm(s) (unshadowed).
//   * optional window (sh::window_weights: hanning, lanczos, nonnegative) multiplies band l
//     of the radiance coefficients.
// Irradiance at normal n: E(n) = sum_lm A_l c_lm Y_lm(n), A_l the clamped-cosine factors
// (sh::irradiance_at); not clamped here (ringing may make it negative; the renderer clamps
// at 0).
//
// Probe grid over the scene's bounding box [lo, hi] with n probes per axis: probe (i, j, k)
// at the cell centre lo + ((i + 1/2)/n) (hi - lo) (cell-centred, so no probe lies on the box's
// faces, e.g. on a ground plane); trilinear interpolation of the coefficients between the 8
// surrounding probes, positions outside the span of the centres clamped to it. Probes inside
// solid objects see their insides (black back faces) and probes beyond a thin wall see the
// other side: both show as error (light leaking / darkening) against the path tracer.
//
// Units: radiance in the lights' units (scene.hpp), irradiance that times sr. Deterministic:
// the texel rays use the path tracer's per-ray streams seeded from (seed, ray index).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/sh/convolution.hpp"
#include "atmosh/sh/projection.hpp"

namespace atmosh::gi {

struct ProbeOptions {
  int bands = 3;             ///< SH bands of the probes, 1..16
  int cube_size = 8;         ///< cube-map texels per face edge, 1..512
  int samples = 4;           ///< paths per texel, 2..1e6
  int bounces = -1;          ///< as TraceOptions::bounces
  std::uint64_t seed = 1;
  sh::Window window = sh::Window::none;
  bool include_sun = false;  ///< add the sun's exact (unshadowed) SH projection to the probe
  /// true: each path leaves along a uniform random point of its texel's (u, v) square,
  /// weighted by the solid-angle Jacobian over its mean on the texel, so a texel is an
  /// unbiased estimate of its mean radiance over the texel's solid angle (small bright
  /// emitters between texel centres are not missed); false: every path along the
  /// texel-centre ray (a point sample; exact for a constant environment).
  bool jitter = true;
  int threads = 0;           ///< 0 = atmosh::resolve_threads(0)
};

/// SH coefficients of the incoming radiance, per channel, bands^2 each (world frame of the
/// mesh: SH +z = the mesh's +z axis).
using ShRgb = std::array<std::vector<double>, 3>;

struct Probe {
  glm::dvec3 position{0.0};
  int bands = 0;
  ShRgb radiance;
  Stats stats;  ///< of the cube-map rays
};

/// The radiance cube map seen at `position` (3 channels, size opt.cube_size). InputError for
/// bad options or an invalid scene.
sh::CubeMap render_probe_cube(const Scene& scene, const glm::dvec3& position, const ProbeOptions& opt,
                              Stats* stats = nullptr);
/// A probe: render_probe_cube, projection, sun (include_sun), window.
Probe render_probe(const Scene& scene, const glm::dvec3& position, const ProbeOptions& opt);
/// Irradiance at normal n (any length > 0) from radiance coefficients of `bands` bands.
glm::dvec3 probe_irradiance(const ShRgb& radiance, int bands, const glm::dvec3& n);

struct ProbeGrid {
  glm::dvec3 lo{0.0}, hi{1.0};  ///< box the probes' cells cover
  int n = 1;                    ///< probes per axis
  int bands = 0;
  std::vector<ShRgb> probes;    ///< index (k n + j) n + i, i along x
  Stats stats;                  ///< of all cube-map rays
  double seconds = 0;           ///< wall time of building the grid (rays and projections)
  glm::dvec3 position(int i, int j, int k) const;
};

/// n^3 probes over the scene's bounding box (n in 1..64). The sun is left out of the probes
/// unless opt.include_sun. Window applied as in render_probe.
ProbeGrid build_probe_grid(const Scene& scene, int n, const ProbeOptions& opt);
/// The grid's coefficients truncated to `bands` (<= grid.bands) with window `w` applied.
ProbeGrid truncate_grid(const ProbeGrid& grid, int bands, sh::Window w);

// ---- Probes of a baked surface radiance (rasterised on the GPU, ray cast on the CPU) ----
//
// A rasteriser cannot path-trace, so the GPU probes see a radiance field stored on the
// surfaces: every triangle cut into congruent sub-triangles (k^2 of them, k the least
// integer with longest edge / k <= bounding-box diagonal / divisions, k <= 64), and at each
// sub-triangle vertex and side s (front = counter-clockwise)
//   L_s = L_e,s + a / pi * E_s,
// E_s the path tracer's irradiance there with normal +-n (irradiance(): every light,
// `bounces` reflections as TraceOptions; evaluated 1e-3 x the diagonal inside the vertex's
// scene triangle, so that grazing rays from edges and corners do not slip past the adjacent
// surfaces), L_e,s the emission (0 on the back of a one-sided
// emitter). Inside a sub-triangle L is interpolated linearly (barycentric), so it is
// continuous over each of the scene's triangles and may jump at their edges (corners of
// rooms), as the true radiance does. A probe texel then holds the field at the first surface
// its centre ray meets (depth along the face's axis in [near, far] = [1e-3, 2] x diagonal
// beyond the farthest corner), the side facing the probe; where the ray meets nothing, the
// environment radiance along the texel centre (environment_radiance; the sun is not in it).
// The same function is evaluated two ways:
//   * GPU: gpu::render_cube_maps (atmosh/gpu/cube_raster.hpp), the sub-triangles rasterised
//     through EGL (float; perspective-correct interpolation = barycentric at the hit);
//   * CPU (the reference of the GPU one): one Embree ray per texel centre against the same
//     sub-triangles, the barycentric interpolation in double.
// They differ only where a texel centre's ray passes within float rounding of a triangle's
// edge (silhouettes, creases; measured in tests/gi/test_gi_probes_gpu.cpp and docs/gi.md).
// The cube maps are projected on the CPU after read-back by the same sh::project_cube
// (libsh's exact texel solid angles) as the path-traced probes: the read-back is 6 N^2
// RGBA floats a probe (6 KiB at N = 8) and the projection O(6 N^2 L^2) in double, so both
// forms share every step but the rasterisation, which is what their comparison isolates.
// Against the path-traced probes (render_probe_cube) the baked field differs by its
// discretisation (linear between vertices spaced ~ diagonal / divisions) and its noise.

struct SurfaceRadianceOptions {
  int divisions = 16;       ///< sub-triangle edge <= bounding-box diagonal / divisions; 1..1024
  int samples = 64;         ///< paths per vertex and side, 2..1e6
  int bounces = -1;         ///< reflections as TraceOptions (0: emission only)
  std::uint64_t seed = 1;
  int threads = 0;
};

struct SurfaceRadiance {
  std::vector<glm::dvec3> positions;  ///< per vertex (vertices are not shared between scene triangles)
  std::vector<glm::dvec3> normals;    ///< per vertex: unit geometric normal of its scene triangle
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< sub-triangles, the scene triangle's winding
  std::vector<glm::dvec3> front, back;  ///< radiance leaving the front / back side, per vertex
  std::vector<glm::dvec3> front_stderr, back_stderr;  ///< their standard errors
  Stats stats;            ///< of the irradiance paths
  double seconds = 0;     ///< wall time of the bake
};

/// The baked surface radiance of `scene` (InputError for bad options or an invalid scene).
SurfaceRadiance bake_surface_radiance(const Scene& scene, const SurfaceRadianceOptions& opt);

/// Where probe cube maps of a baked field are rendered (and projected): cpu_rays and gpu
/// project on the CPU (sh::project_cube after read-back); gpu_sh rasterises and projects on
/// the GPU (gpu::ProbeProjector, gpu/shaders/gi_probe_project.comp: the same texel-centre
/// basis and exact texel solid angles, from the shared block
/// atmosh/sh/shared/cube.glsl.hpp, summed in float) and reads back only the coefficients.
enum class ProbeRaster { cpu_rays, gpu, gpu_sh };

/// Cube maps (size N, 3 channels) of the field seen at `positions` (see above). gpu: throws
/// InputError if atmosh was built without atmosh::gpu, gpu::Unavailable (a runtime_error)
/// where no EGL context opens. `gpu_seconds` (optional): the rasterisation's own time
/// (upload, draws, read-back) or the CPU rays' time.
std::vector<sh::CubeMap> surface_probe_cubes(const Scene& scene, const SurfaceRadiance& field,
                                             const std::vector<glm::dvec3>& positions, int cube_size, ProbeRaster where,
                                             double* raster_seconds = nullptr);
/// n^3 probes at ProbeGrid::position from the baked field: cube maps by `where`, projected
/// as build_probe_grid (opt.bands, window, include_sun; opt.samples, bounces, seed, jitter
/// unused). supersample s (1..16, cube_size x s <= 512): the cube maps are rendered at
/// cube_size x s and each texel is the mean of its s^2 sub-texels weighted by their exact
/// solid angles (which sum to the texel's) — the texel's mean radiance to the midpoint rule,
/// so small bright emitters between texel centres are not missed or over-counted (the
/// rasterised counterpart of the path-traced probes' jitter). seconds: cube maps and
/// projections (not the bake); stats.rays: CPU rays (0 on the GPU).
ProbeGrid build_probe_grid_surface(const Scene& scene, const SurfaceRadiance& field, int n, const ProbeOptions& opt,
                                   ProbeRaster where, int supersample = 1);
/// Trilinear interpolation of the coefficients at p (clamped to the span of the centres).
ShRgb interpolate(const ProbeGrid& grid, const glm::dvec3& p);

struct ProbeRenderOptions {
  int samples = 4;  ///< camera rays per pixel (uniform jitter in the pixel), 1..1e6
  std::uint64_t seed = 1;
  /// Visibility-weighted interpolation: each of the 8 probes keeps its trilinear weight only
  /// if it lies on the front side of the receiver's surface (n . (x - p) > 0) and a ray from the
  /// receiver point reaches the probe's position unoccluded; the kept
  /// weights are renormalised (none kept: plain trilinear). Removes probes inside objects and
  /// behind walls (8 shadow rays per camera ray). Off: plain trilinear.
  bool visibility = false;
  int threads = 0;
};

/// Pinhole image lit by a probe grid. Per camera ray: miss -> the environment radiance;
/// hit at p with albedo a, normal n (flat, towards the camera), E_probe the irradiance of the
/// interpolated probe coefficients (interpolate(), or visibility-weighted) ->
///   L = emission seen directly (as the path tracer)
///     + a / pi * ( max(0, E_probe(p, n))               [area emitters, environment and
///                                                       all interreflected light]
///                 + E_sun cos * visible(p, sun) )      [direct sun, one shadow ray; a disc
///                                                       sun sampled as in the path tracer]
/// i.e. the probe term replaces the path tracer's whole incident-light integral at the first
/// hit except the sun's direct light (which the probes do not hold unless include_sun: then
/// the sun term is not added here). stderr_ is the standard error over the pixel's rays
/// (pixel jitter only; the probes' own noise is not in it). stats.seconds: shading time only.
RadianceImage render_probes(const Scene& scene, const Camera& camera, int width, int height, const ProbeGrid& grid,
                            bool grid_includes_sun, const ProbeRenderOptions& opt);

/// A frame shaded by a probe grid with one ray per pixel centre: miss -> the environment
/// radiance; hit at p (flat normal n towards the eye, albedo a) ->
///   L = emission of the side seen + a / pi max(0, E(p, n)),
/// E the irradiance of the trilinear blend of the probes (no visibility weighting). The sun
/// is not added: the scene must have none, or the grid must hold it (grid_includes_sun). On
/// the GPU (gpu = true): the scene rasterised through EGL, the blend and per fragment in float
/// E = sum_i A_l c_i Y_i(n) with the Y_i of the shared block's sh_basis_all
/// (atmosh/sh/shared/cube.glsl.hpp: the normalised associated-Legendre recurrence, any band)
/// and libsh's clamped-cosine factors A_l (sh::irradiance_factors), gpu/shaders/gi_probe_shade.*;
/// otherwise its CPU twin: Embree rays at the pixel centres, the same sum in double
/// (interpolate(), probe_irradiance(), i.e. libsh's sh::irradiance_at) — they differ by float
/// rounding except at pixels whose centre grazes an edge. bands 1..16, those of the CPU probe
/// method (InputError otherwise, and for a sun the grid does not hold); stderr_ 0; stats.seconds: the frame (GPU: upload, draw,
/// read-back and the misses' environment; program compilation excluded).
RadianceImage render_probes_frame(const Scene& scene, const Camera& camera, int width, int height, const ProbeGrid& grid,
                                  bool grid_includes_sun, bool gpu);

/// The GPU form of render_probes_frame kept for repeated frames (dynamic probes): the EGL
/// context, the program (compiled, and on llvmpipe JIT-compiled at its first draw), the scene's
/// triangles and the render target are made once; render() uploads the grid's coefficients,
/// draws, reads back and fills the misses with the environment (the program is made for 3 bands
/// and remade by the first render() of a grid with another band count: its basis array is sized
/// for the bands it shades). Throws as render_probes_frame
/// (InputError; gpu::Unavailable, a runtime_error, without a context).
class ProbeFrameGpu {
 public:
  ProbeFrameGpu(const Scene& scene, const Camera& camera, int width, int height);
  ~ProbeFrameGpu();
  ProbeFrameGpu(const ProbeFrameGpu&) = delete;
  ProbeFrameGpu& operator=(const ProbeFrameGpu&) = delete;
  /// One frame; stats.seconds: upload, draw, read-back and the misses.
  RadianceImage render(const ProbeGrid& grid, bool grid_includes_sun) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A GPU-resident probe frame (one EGL context; nothing read back between the passes):
///   1. the probes' cube maps of the baked field rasterised (gpu::ProbeProjector; atlas
///      batches) and 2. projected to SH by a compute pass into a storage buffer (as
///      ProbeRaster::gpu_sh; environment where no surface is drawn: the sky is in the probes);
///   3. the sun's shadow map (gpu::SunShadowMap, gi_raster.hpp's map: 1024^2 over the
///      bounding sphere, PCF 3 x 3, normal offset and slope-scaled bias of 1 texel);
///   4. the scene rasterised from the camera, per fragment (gi_probe_shade.frag) the
///      trilinear blend of the probes' SH irradiance read from that buffer plus the sun:
///        L = L_e (side seen) + a / pi (max(0, E_probe(p, n)) + E_sun max(0, n . s) V(p)),
///      misses keep the environment radiance along the pixel centre (computed once for the
///      camera and kept on the GPU);
///   5. the image read back (the frame's only read-back).
/// It is render_probes (the CPU method: probes without the sun, the sun's direct light with
/// a shadow ray) with the baked field's rasterised probes, pixel centres instead of jittered
/// camera rays, a shadow map instead of shadow rays, and a disc sun taken as a point at its
/// centre. bands 1..16 (every band count of the CPU probe method; the window applied at every
/// band in the projection, as build_probe_grid_surface does; the irradiance with libsh's A_l
/// of every band), no visibility weighting; stderr_ 0.
struct ProbeFrameOptions {
  int grid = 4;             ///< probes per axis, 1..64
  ProbeOptions probes;      ///< bands (1..16), cube_size, window (include_sun must be false)
  int supersample = 4;      ///< as build_probe_grid_surface
  int shadow_resolution = 1024;  ///< texels a side, 16..16384
  int shadow_pcf = 1;       ///< PCF radius in texels, 0..4
  double shadow_normal_offset = 1.0, shadow_bias = 1.0;  ///< in texels (as gpu::GiShadowOptions)
};

class ProbeFrameResident {
 public:
  /// Throws InputError (bad options, bands outside 1..16, include_sun), gpu::Unavailable without a
  /// context, InputError if atmosh was built without atmosh::gpu.
  ProbeFrameResident(const Scene& scene, const Camera& camera, int width, int height, const SurfaceRadiance& field,
                     const ProbeFrameOptions& opt);
  ~ProbeFrameResident();
  ProbeFrameResident(const ProbeFrameResident&) = delete;
  ProbeFrameResident& operator=(const ProbeFrameResident&) = delete;
  /// One frame (passes 1–5); stats.seconds: the frame, upload of uniforms to read-back.
  /// `pass_seconds` (optional, 4 entries): the cube maps' draws, their projection, the sun's
  /// shadow map, the shading + read-back — each pass then waits for the GPU (glFinish) before
  /// the next starts, which serialises the frame (for profiling; the frame's own time is
  /// without it).
  RadianceImage render(double* pass_seconds = nullptr) const;
  /// The probes' coefficients of the last frame, read back (diagnostics; not part of a frame).
  ProbeGrid grid() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Error of an image against a reference of the same size, relative to the reference's mean
/// radiance over pixels and channels (so dark pixels do not blow it up):
///   max_rel = max |a - r| / mean(r), rms_rel = sqrt(mean (a - r)^2) / mean(r),
///   leak_rel = sum max(0, a - r - 3 stderr_r) / sum r (light where the reference has less:
///   light leaking through walls, probes seeing past occluders; noise of the reference removed
///   at 3 standard errors),
///   mean_rel = sum a / sum r (the share of the reference's light the image has: what each
///   bounce of an approximation adds).
struct ImageError {
  double max_rel = 0, rms_rel = 0, leak_rel = 0, mean_rel = 0;
};
/// `skip` (optional, one entry per pixel): pixels where it is nonzero are left out of all
/// three (e.g. directly seen emitters, whose edge pixels depend on the camera-ray jitter).
ImageError image_error(const RadianceImage& approx, const RadianceImage& reference,
                       const std::vector<unsigned char>* skip = nullptr);
/// Pixels to leave out of image_error: those where `direct` (e.g. a render with bounces = 0,
/// emission seen directly only) is nonzero in any channel, grown by `border` pixels.
std::vector<unsigned char> emitter_mask(const RadianceImage& direct, int border = 1);

}  // namespace atmosh::gi
