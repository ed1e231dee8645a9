// atmosh/gpu/gi_raster.hpp — rasterisation of lit triangle meshes through headless EGL
// (OpenGL 4.3 core) for the global-illumination passes (atmosh::gi): a G-buffer from a
// camera with the sun's direct light by a shadow map, and a reflective shadow map (RSM,
// Dachsbacher & Stamminger 2005) from the sun. The design is gpu/prt.hpp's: the mesh in
// float relative to its bounding-box centre, float render targets read back to double,
// the camera's projection of prt.hpp (PrtCamera: the pixel-centre rays of the CPU ray
// casters), the depth map of prt_depth.{vert,frag} (orthographic along the light).
//
// Mesh: flat per-triangle attributes (normal, albedo, emitted radiance, one-sidedness),
// drawn as a triangle soup; both faces are rasterised (surfaces are two-sided).
//
// G-buffer (gi_gbuffer.{vert,frag}), per pixel whose centre sees a surface:
//   position, the triangle's normal turned towards the eye (n . (eye - p) > 0), albedo,
//   emitted radiance towards the eye (0 for a one-sided emitter seen from behind), the
//   sun factor f = max(0, n . s) V(p), so that E_sun = sun irradiance x f, and on request the
//   area emitters' irradiance (GiEmitterOptions) and the environment's (GiSkyOptions).
// Sun visibility V by a shadow map: depth of the mesh along -s by orthographic projection
// over the bounding sphere (`resolution`^2 texels, texel edge t = 2 r / resolution), then at p:
//   the point moved off the surface by `normal_offset` t along n, its depth compared with the
//   stored depth plus `bias` t (1 + min(tan(angle(n, s)), 8)) (slope-scaled), the test made at
//   the (2 pcf + 1)^2 texels around it (percentage-closer filtering, Reeves et al. 1987) and
//   averaged: V in [0, 1]. A disc sun is treated as a point (its central direction): PCF
//   softens edges over about (2 pcf + 1) t; it is not the disc's penumbra.
// RSM (gi_rsm.{vert,frag}): an orthographic view along -s of the rectangle
// [t0, t1] x [b0, b1] in the light's frame (axes t, b ⊥ s), m_t x m_b texels; per texel whose
// centre sees a surface: position, the normal turned towards the sun, and the flux the
// texel's parallel beam (cross-section A = (t1 - t0)(b1 - b0) / (m_t m_b)) leaves after one
// diffuse reflection: albedo x E_sun x A (the light's irradiance at normal incidence times
// the beam's cross-section is the flux it brings; Lambertian reflection returns albedo of it).
//
// Precision: float on the GPU (positions relative to the bounding-box centre); depth 32F.
// Requires a current Context; throws Unavailable (no EGL), ShaderError, or
// std::invalid_argument for inconsistent input.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/prt.hpp"

namespace atmosh::gpu {

struct GiMeshView {
  const std::vector<glm::dvec3>* positions = nullptr;
  const std::vector<std::array<std::uint32_t, 3>>* triangles = nullptr;
  const std::vector<glm::dvec3>* normal = nullptr;    ///< per triangle, unit (counter-clockwise side)
  const std::vector<glm::dvec3>* albedo = nullptr;    ///< per triangle, 0..1 per channel
  const std::vector<glm::dvec3>* emission = nullptr;  ///< per triangle, radiance (>= 0)
  const std::vector<std::uint8_t>* one_sided = nullptr;  ///< per triangle: emits on the normal's side only
};

struct GiShadowOptions {
  int resolution = 1024;       ///< shadow-map texels a side, 16..16384
  int pcf = 1;                 ///< PCF kernel radius in texels (0: one tap), 0..4
  double normal_offset = 1.0;  ///< along the normal, in texels
  double bias = 1.0;           ///< depth bias, in texels (times 1 + slope)
};

struct GiSun {
  glm::dvec3 direction{0, 0, 1};  ///< towards the sun, unit
};

/// Area emitters' direct light on the GPU: every emitting triangle's exact unoccluded
/// irradiance (the shared gi_polygon_irradiance, atmosh/gi/shared/polygon.glsl.hpp, at p +
/// eval_offset n) times the mean visibility of `points_per_triangle` fixed points on it
/// (a Hammersley set mapped to the triangle); the visibility of a point y from the receiver
/// (moved shadow_offset along n) by a distance cube map rendered at y: six 90-degree
/// perspective faces of `resolution`^2 texels storing the distance from y to the nearest
/// surface; visible where |q - y| <= stored + bias, bias = 1.5 |q - y| (2 / resolution)
/// (1 + min(tan(angle between n and y - q), 8)) — a texel's footprint at that distance, slope
/// scaled. A one-sided emitter lights only its normal's side. At most 64 emitting triangles
/// (std::invalid_argument beyond).
struct GiEmitterOptions {
  int points_per_triangle = 4;  ///< 1..64
  int resolution = 256;         ///< cube-face texels a side, 16..4096
  double eval_offset = 0;       ///< height of the polygon formula's evaluation above p [mesh units]
  double shadow_offset = 0;     ///< height of the visibility test's origin above p [mesh units]
};

/// The environment's direct light on the GPU by a fixed quadrature: E = sum_k weight_k L_k
/// max(0, n . w_k) V(p, w_k) over the given directions, V by one orthographic depth map per
/// direction (`resolution`^2 texels over the bounding sphere, the sun's normal offset and
/// slope-scaled bias, one tap), at most 1024 directions.
struct GiSkyOptions {
  std::vector<glm::dvec3> directions;  ///< unit, towards the sky
  std::vector<glm::dvec3> radiance;    ///< L_k x weight_k per direction (weight: its solid angle)
  int resolution = 512;                ///< 16..8192
};

struct GiGBufferResult {
  int width = 0, height = 0;
  /// Per pixel, row 0 at the top (index row * width + col).
  std::vector<std::uint8_t> hit;
  std::vector<glm::dvec3> position, normal, albedo, emission;
  std::vector<double> sun;  ///< max(0, n . s) V, 0 without a sun
  std::vector<glm::dvec3> emitter;  ///< area emitters' irradiance (0 unless requested)
  std::vector<glm::dvec3> sky;      ///< the environment's irradiance (0 unless requested)
  double seconds = 0;       ///< upload, shadow map, G-buffer, read-back
};

/// The G-buffer of `camera` (PrtCamera's pixel-centre rays); `sun` null: no shadow map;
/// `emitters` null: no area-light term; `sky` null: no environment term.
GiGBufferResult gi_gbuffer(const Context& ctx, const GiMeshView& mesh, const PrtCamera& camera, const GiSun* sun,
                           const GiShadowOptions& shadow = {}, const GiEmitterOptions* emitters = nullptr,
                           const GiSkyOptions* sky = nullptr);

struct GiRsmView {
  glm::dvec3 direction{0, 0, 1};    ///< towards the sun, unit
  glm::dvec3 t{1, 0, 0}, b{0, 1, 0};  ///< unit axes ⊥ direction
  double t0 = -1, t1 = 1, b0 = -1, b1 = 1;  ///< the rectangle in (t, b) coordinates (world, not centred)
  int mt = 64, mb = 64;             ///< texels, 1..16384
  glm::dvec3 irradiance{1.0};       ///< at normal incidence, per channel
};

struct GiRsmResult {
  int width = 0, height = 0;
  /// Per texel (row * width + col; row 0 at b0, col 0 at t0) whose centre sees a surface.
  std::vector<std::uint8_t> hit;
  std::vector<glm::dvec3> position, normal, flux;
  double seconds = 0;
};

GiRsmResult gi_rsm(const Context& ctx, const GiMeshView& mesh, const GiRsmView& view);

/// Reflective shadow maps of the area emitters (the emitters' counterpart of gi_rsm): at each of
/// `points_per_triangle` fixed points y of every emitting triangle (the Hammersley set of
/// GiEmitterOptions' distance maps) a cube map of `resolution`^2 texels a face, whose texel
/// centre ray w from y meets the first surface x; that texel's VPL is x with its normal turned
/// towards y and the flux it reflects diffusely of the light the point sends into the texel:
///   Phi = albedo(x) L_e (A / K) c(n_e . w) Omega_texel,
/// A the triangle's area, K the points per triangle, c(t) = max(0, t) for a one-sided emitter
/// (the normal's side) and |t| otherwise, Omega_texel = (2/N)^2 / (1 + u^2 + v^2)^(3/2) the
/// texel's solid angle at its centre (u, v). The texels' c Omega sum to pi over a side's
/// hemisphere, so a side's VPLs carry albedo x its power pi L_e A (the CPU's photon VPLs,
/// atmosh/gi/lpv.hpp, are an unbiased estimate of the same). Each point is a point light: near
/// the emitter (closer than its size) the flux lands where a point, not the extended triangle,
/// sends it. Surface points from the texel ray and the triangle plane (gi_pixel_point.glsl).
struct GiEmitterRsmOptions {
  int points_per_triangle = 4;  ///< 1..64
  int resolution = 32;          ///< texels a cube face side, 2..1024
};
struct GiEmitterRsmResult {
  /// One entry per texel that sees a surface: position (world), unit normal, flux per channel.
  std::vector<glm::dvec3> position, normal, flux;
  std::size_t texels = 0;  ///< all texels of all cube maps
  double seconds = 0;      ///< upload, draws, read-back
};
/// std::invalid_argument for options out of range or more than 64 emitting triangles.
GiEmitterRsmResult gi_emitter_rsm(const Context& ctx, const GiMeshView& mesh, const GiEmitterRsmOptions& options);

// ---------------------------------------------------------------------------------------------
// A GPU-resident light propagation volume frame (Kaplanyan & Dachsbacher 2010; the method and
// its CPU form: atmosh/gi/lpv.hpp), every pass in one context, its data kept in GPU textures and
// storage buffers between the passes, only the final image read back:
//   1. the G-buffer of gi_gbuffer (sun shadow map, area emitters' distance maps, sky depth maps);
//   2. the sun's reflective shadow map (gi_rsm's texels);
//   3. injection: every RSM texel that sees a surface (and every given VPL) drawn as a point into
//      the cell atlas (nx x ny nz texels, 3 RGBA32F targets: the 4 SH coefficients of R, G, B)
//      with additive blending, its cell gi_lpv_cell_of(p + h/2 n) and its coefficients
//      Phi gi_lpv_lobe(n) (the shared block atmosh/gi/shared/lpv.glsl.hpp);
//   4. the atlas packed into a storage buffer (12 floats a cell) and the running sum;
//   5. `iterations` propagation dispatches (gi_lpv_propagate.comp, the shared gi_lpv_gather),
//      blocking (from the second iteration on, as the CPU's lpv_propagate) by a table of the
//      faces' open fractions made from the geometry volume's corners by the shared
//      gi_lpv_face_blocking (gi_lpv_open.comp);
//   6. application to the G-buffer (gi_lpv_frame_apply.comp, the shared
//      gi_lpv_receiver_irradiance): L = L_e + a / pi max(0, E_sun f + E_emitters + E_sky + E_lpv);
//   7. read-back of the image (RGBA float; alpha 1 where a surface is seen, else 0 and RGB 0).
// The geometry volume is injected once, at construction, from the given surfels (points into a
// corner atlas, additive blending), and its table of open faces made and kept (static geometry). Positions in float relative to the mesh's
// bounding-box centre. Requires a current Context; the frame keeps its programs (compiled once).
struct GiLpvGrid {
  glm::dvec3 lo{0.0};  ///< low corner of cell (0, 0, 0) [mesh units]
  double h = 1;        ///< cell edge
  int nx = 1, ny = 1, nz = 1;  ///< cells; ny nz <= 16384 and (ny + 1)(nz + 1) <= 16384 (atlas rows)
};
/// A surfel of the geometry volume: its corner index (k (ny + 1) + j)(nx + 1) + i, unit normal,
/// A_s / h^2 (the fraction of a cell's cross-section it covers).
struct GiLpvSurfel {
  std::uint32_t corner = 0;
  glm::dvec3 normal{0, 0, 1};
  double weight = 0;
};
/// A VPL given to the frame (e.g. area emitters' photons): position already moved h/2 along the
/// unit normal n, flux per channel.
struct GiLpvVpl {
  glm::dvec3 p{0.0}, n{0, 0, 1}, flux{0.0};
};
/// A 2-level nested cascade in the frame (the CPU form: atmosh/gi/lpv.hpp, LpvCascade; the same
/// shared functions). The frame's `grid` is the coarse level, held twice: the "inner" grid of the
/// VPLs inside the fine box and the "outer" grid of those outside it (one geometry volume for
/// both, from the frame's surfels); `fine` (edge grid.h / 2) holds the VPLs inside the fine box,
/// with its own geometry volume (`fine_surfels`, corners of `fine`). Every VPL — RSM texels
/// (moved `fine.h / 2` along n) and given VPLs (already moved so) — is classified by the shared
/// gi_lpv_in_box, then goes into the fine level as it is and into the coarse inner or outer grid
/// moved a further grid.h / 4 (the coarse half-cell shift). Every level propagates `iterations`
/// steps; the application reads E = E_outer + w E_fine + (1 - w) E_inner (gi_lpv_cascade_weight,
/// gi_lpv_cascade_blend). (fine.ny + 1)(fine.nz + 1) <= 16384.
struct GiLpvCascade {
  GiLpvGrid fine;
  glm::dvec3 fine_lo{0.0}, fine_hi{0.0};  ///< the fine box [mesh units], faces on the coarse lattice
  std::vector<GiLpvSurfel> fine_surfels;
};
struct GiLpvFrameOptions {
  int iterations = 16;             ///< 0..1024
  bool blocking = true;            ///< use the geometry volume
  int reemission = 0;              ///< 0 along the face's direction, 1 the paper's face-normal lobe (gi::LpvReemission)
  const GiSun* sun = nullptr;      ///< the sun's direction (null: no sun)
  glm::dvec3 sun_irradiance{0.0};  ///< its irradiance at normal incidence, per channel
  GiShadowOptions shadow;
  const GiEmitterOptions* emitters = nullptr;  ///< as gi_gbuffer
  const GiSkyOptions* sky = nullptr;           ///< as gi_gbuffer
  const GiRsmView* rsm = nullptr;  ///< the sun's RSM (null: no sun VPLs)
  /// The area emitters' RSMs (gi_emitter_rsm), injected as VPLs like the sun's (null: none; the
  /// emitters' light then comes only from the VPLs given at construction). Made by the first
  /// frame that asks for them and kept while the options are unchanged (static geometry).
  const GiEmitterRsmOptions* emitter_rsm = nullptr;
  bool read_grid = false;          ///< also read back the accumulated grid (for tests)
};
struct GiLpvFrameResult {
  int width = 0, height = 0;
  std::vector<float> radiance;  ///< RGBA per pixel, row 0 at the top
  std::vector<float> grid;      ///< with read_grid: 12 floats a cell (channel * 4 + SH index); a cascade's outer grid
  std::vector<float> inner, fine;  ///< with read_grid and a cascade: its inner and fine grids
  double seconds = 0;           ///< the passes, up to the image's read-back (glFinish included)
};
class GiLpvFrame {
 public:
  /// Uploads the mesh, the VPLs and the surfels, compiles the programs and injects the geometry
  /// volume. std::invalid_argument for a bad grid, a surfel outside it or inconsistent input.
  /// `cascade` (optional): a 2-level cascade over `grid` (GiLpvCascade); the VPLs are then at the
  /// fine level's shift.
  GiLpvFrame(const Context& ctx, const GiMeshView& mesh, const GiLpvGrid& grid, const std::vector<GiLpvSurfel>& surfels,
             const std::vector<GiLpvVpl>& vpls, const GiLpvCascade* cascade = nullptr);
  ~GiLpvFrame();
  GiLpvFrame(const GiLpvFrame&) = delete;
  GiLpvFrame& operator=(const GiLpvFrame&) = delete;
  GiLpvFrameResult render(const PrtCamera& camera, const GiLpvFrameOptions& options);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace atmosh::gpu
