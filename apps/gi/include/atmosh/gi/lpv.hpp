// atmosh/gi/lpv.hpp — light propagation volumes (Kaplanyan & Dachsbacher 2010, "Cascaded
// light propagation volumes for real-time indirect illumination", I3D), on the CPU.
//
// Volume: cubic cells of edge h = (longest extent of the scene's bounding box) / grid,
// nx x ny x nz of them from the box's low corner (nx = ceil(extent_x / h), ...). Each cell
// holds the radiant intensity I(w) [lights' radiance unit x length^2, i.e. W/sr for
// radiance in W m^-2 sr^-1 and lengths in m] of the light travelling through it in
// direction w, as 4 real SH coefficients per channel (bands 0 and 1, atmosh/sh/basis.hpp).
//
// Injection (the reflective-shadow-map step, by rays on the CPU): virtual point lights at
// the surfaces the lights reach first —
//   * the sun (its central direction; a disc sun is treated as a point): an M x M grid of
//     jittered parallel rays over the box's cross-section seen from the sun, each ray a
//     bundle of cross-section A_ray carrying flux E_sun A_ray; where it hits, a VPL of flux
//     Phi = albedo E_sun A_ray;
//   * area emitters: `emitter_photons` rays, a triangle chosen ∝ area x summed emission, a
//     uniform point, a cosine-distributed direction on an emitting side, each carrying its
//     share of the emitted power (pi L_e A per side); where it hits, a VPL of albedo x that.
// A VPL of flux Phi at p with normal n (turned towards the light's side) is a Lambertian
// emitter, I(w) = Phi / pi max(0, n . w), whose SH coefficients are Phi / pi A_l Y_lm(n)
// (A_0 = pi, A_1 = 2 pi / 3); it goes into the cell holding p + h/2 n (the paper's half-cell
// shift). The environment is not injected (its direct light is added at the receiver).
//
// Propagation (one iteration): every cell sends its intensity to its 6 face neighbours.
// For the neighbour in direction e, the light that would cross each of the neighbour's 5
// faces other than the shared one — the far face (normal e) and the 4 side faces (normals
// a ⊥ e) — is the face's flux Phi_f = dOmega_f I(w_f) (1 - B(w_f)), w_f the unit direction
// from the source cell's centre to the face's centre, dOmega_f the face's exact solid angle
// seen from the source's centre (lpv_face_solid_angles(); derived in docs/gi.md), B the
// geometry volume's blocking at the shared face; it is re-emitted from the neighbour's
// centre along w_f, coefficients Phi_f Y_lm(w_f) (total flux Phi_f; the shared
// gi_lpv_reemit_sh). The 30 faces of the 6 neighbours partition the sphere of directions
// around the source's centre (their solid angles add up to 4 pi exactly), so without
// blocking one iteration conserves the flux sqrt(4 pi) c_00 summed over the cells exactly
// (band 1 integrates to 0 over the sphere and the face sum is symmetric), up to what leaves
// the volume, and, by the faces' cubic symmetry, the summed band 1 (the net flux vector) too.
// (Kaplanyan & Dachsbacher 2010 re-emit a Lambertian lobe about the face normal instead; that
// keeps 0.369 of band 1 a step, whatever the cell size, and made this LPV's error grow with its
// grid: docs/gi.md, "Why the LPV's error grew with its grid"; LpvOptions::reemission =
// LpvReemission::face_lobe brings it back for comparison.) The result of `iterations` steps is the sum of the injected field and every
// iteration's field.
//
// Geometry volume: cells centred at the LPV cells' corners; surfels sampled on every
// triangle (about 16 per h^2: the triangle cut into congruent sub-triangles, one at each centroid;
// those nearest to no corner of the grid, outside a cascade's sub-grid, left out) add to the nearest one the
// blocking A_s |n_s . w| / h^2 (the fraction of the cell's cross-section the surfel covers
// seen along w) as 3-band SH (|cos| is even: bands 0 and 2). At a shared face the blocking
// is the mean of its 4 corners, clamped to [0, 1]. No blocking in the first iteration (the
// paper's guard against the injecting surfaces shadowing their own light).
//
// Receiver (x, normal n towards the camera, albedo a): the accumulated intensity
// interpolated trilinearly at x + h/2 n (cell centres; clamped), read as radiance I / h^2:
//   E_lpv = (1/h^2) sum_lm A_l c_lm Y_lm(-n)   (light travelling against n),
//   L = L_e + a / pi (E_direct(x, n) + max(0, E_lpv)),
// E_direct as the radiosity method's (radiosity.hpp). The LPV carries one bounce of the sun's
// and the emitters' light (the light leaving the first surfaces they reach).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/radiosity.hpp"
#include "atmosh/gi/scene.hpp"

namespace atmosh::gi {

/// How a propagation step re-emits the flux that crosses a face of the neighbour cell (both from
/// the shared atmosh/gi/shared/lpv.glsl.hpp, gi_lpv_reemit_choice, on the CPU and the GPU):
///   direction: along the face's direction w_f, Phi_f Y_lm(w_f) (keeps the flux and the net flux
///              vector; the default, docs/gi.md "Why the LPV's error grew with its grid");
///   face_lobe: Kaplanyan & Dachsbacher 2010's Lambertian lobe about the face normal n_f,
///              Phi_f / pi A_l Y_lm(n_f) (keeps the flux, 0.369 of the net flux vector a step).
enum class LpvReemission { direction = 0, face_lobe = 1 };
/// "direction" | "paper" (the command line's names); lpv_reemission_from_name throws InputError
/// naming the value for any other.
const char* lpv_reemission_name(LpvReemission r);
LpvReemission lpv_reemission_from_name(const std::string& name);

struct LpvOptions {
  int grid = 32;                 ///< cells along the box's longest axis, 1..256
  int iterations = -1;           ///< propagation steps, 0..1024 (-1: 2 x grid)
  int sun_rays = 16;             ///< sun injection rays per cell edge of the box's cross-section, 1..256
  int emitter_photons = 65536;   ///< injection rays from area emitters, 0..1e8
  /// The GPU-resident frame (LpvFrameGpu) only: 0 injects the area emitters' photon VPLs above
  /// (made once per frame object on the CPU); N in 2..1024 instead rasterises the emitters'
  /// reflective shadow maps every frame object keeps (lpv_vpls_emitter_rsm: N x N texels a cube
  /// face at ShadowMapOptions::emitter_points points per triangle).
  int emitter_rsm = 0;
  bool blocking = true;          ///< use the geometry volume
  LpvReemission reemission = LpvReemission::direction;  ///< the propagation's re-emission (above)
  int samples = 4;               ///< camera rays per pixel, 1..1e6
  std::uint64_t seed = 1;
  int threads = 0;               ///< 0 = atmosh::resolve_threads(0)
};

/// Intensity SH per cell: [channel * 4 + i], i = sh_index(l, m) for l <= 1.
using LpvCell = std::array<double, 12>;

struct LpvGrid {
  glm::dvec3 lo{0.0};  ///< low corner of cell (0, 0, 0)
  double h = 1;        ///< cell edge
  int nx = 1, ny = 1, nz = 1;
  std::vector<LpvCell> cells;  ///< index (k ny + j) nx + i
  std::size_t index(int i, int j, int k) const { return (static_cast<std::size_t>(k) * ny + j) * nx + i; }
  glm::dvec3 centre(int i, int j, int k) const { return lo + h * glm::dvec3(i + 0.5, j + 0.5, k + 0.5); }
};

/// Blocking per LPV cell corner ((nx+1)(ny+1)(nz+1), index (k (ny+1) + j) (nx+1) + i),
/// 3-band SH (9 coefficients).
struct GeometryVolume {
  int nx = 0, ny = 0, nz = 0;  ///< of the LPV it belongs to
  std::vector<std::array<double, 9>> corners;
};

/// Exact solid angles of a destination cell's far face and of one side face, seen from the
/// source cell's centre (unit cells: far face at distance 3/2, side faces at 1/2 from the axis):
/// front = 4 asin(1/10), side = 2 (atan(3/sqrt(11)) - pi/6) (docs/gi.md), front + 4 side = 2 pi/3.
struct LpvFaceAngles {
  double front = 0, side = 0;
};
LpvFaceAngles lpv_face_solid_angles();

/// An empty grid over the scene's bounding box (see above). InputError for a bad grid.
LpvGrid lpv_grid(const Scene& scene, int grid);
/// Adds a Lambertian VPL of flux `flux` (per channel) at p with unit normal n to the cell
/// holding p (clamped into the grid); `isotropic`: I = flux / (4 pi) instead.
void lpv_add_vpl(LpvGrid& g, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& flux, bool isotropic = false);
/// A virtual point light of the injection: position (already moved h/2 along n, the cell
/// it goes into holds it), unit normal, flux per channel.
struct Vpl {
  glm::dvec3 p, n, flux;
};
/// The VPLs of the injection (the rays described above, in their order; deterministic for
/// opt.seed); lpv_inject adds them to `g`'s cells with lpv_add_vpl.
std::vector<Vpl> lpv_vpls(const Scene& scene, const LpvOptions& opt, const LpvGrid& g, std::uint64_t* rays = nullptr);
/// Injection of the scene's lights (see above), deterministic for opt.seed.
LpvGrid lpv_inject(const Scene& scene, const LpvOptions& opt, std::uint64_t* rays = nullptr);
GeometryVolume lpv_geometry(const Scene& scene, const LpvGrid& g);
/// The sun's VPLs from a reflective shadow map rasterised on the GPU (atmosh::gpu::gi_rsm, its
/// own EGL context; Kaplanyan & Dachsbacher 2010's injection): the CPU injection's rectangle
/// (the box's cross-section seen from the sun) and its m x m texels (m = sun_rays x ceil(longer
/// side / h)), one VPL per texel whose centre sees a surface: flux albedo x E_sun x the texel's
/// cross-section, normal turned towards the sun, position moved h/2 along it — the CPU's
/// jittered rays replaced by the texel centres (the same estimator of the reflected flux,
/// without the jitter). A disc sun as a point. Empty without a sun. Errors as
/// lpv_propagate_gpu; gpu_seconds: the RSM's upload, draw and read-back.
std::vector<Vpl> lpv_vpls_rsm(const Scene& scene, const LpvOptions& opt, const LpvGrid& g,
                              double* gpu_seconds = nullptr);
/// The area emitters' VPLs from reflective shadow maps rasterised on the GPU (atmosh::gpu::
/// gi_emitter_rsm, its own EGL context): at `points` fixed points of every emitting triangle a
/// cube map of opt.emitter_rsm texels a face side (2 when 0), one VPL per texel whose centre ray
/// sees a surface: flux albedo L_e (A / points) c(n_e . w) Omega_texel, normal turned towards
/// the point, position moved h/2 along it — the photon rays of lpv_vpls replaced by the texel
/// rays of point lights (the same expected reflected flux; no noise, but each point is a point
/// light near the emitter). Empty without emitters. InputError for options out of range or
/// more than 64 emitting triangles; errors otherwise as lpv_propagate_gpu. gpu_seconds: upload,
/// draws and read-back.
std::vector<Vpl> lpv_vpls_emitter_rsm(const Scene& scene, const LpvOptions& opt, const LpvGrid& g, int points = 4,
                                      double* gpu_seconds = nullptr);
/// The most texels the emitters' RSM atlas may hold (6 faces x points x emitting triangles x
/// resolution^2; 4 floats x 3 targets + depth = 52 bytes a texel: 218 MB).
inline constexpr long long kMaxEmitterRsmTexels = 1LL << 22;
/// InputError naming the resolution where the scene's emitters' RSMs at `resolution` texels a
/// face and `points` per triangle exceed kMaxEmitterRsmTexels, or the scene has more than 64
/// emitting triangles; checked before any work by the CLI, render_method and LpvFrameGpu.
void check_emitter_rsm_size(const Scene& scene, int resolution, int points);
/// The VPLs injected into `g`'s cells on the GPU: binned by cell on the CPU (a stable
/// counting sort: each bin in the given order), then one compute invocation per cell
/// (gpu/shaders/gi_lpv_inject.comp) sums its VPLs' Lambertian lobes in float (as lpv_add_vpl);
/// g's cells are replaced. gpu_seconds: uploads, dispatch and read-back.
LpvGrid lpv_inject_vpls_gpu(const LpvGrid& g, const std::vector<Vpl>& vpls, double* gpu_seconds = nullptr);
/// The injection on the GPU (atmosh::gpu, its own EGL contexts; errors as lpv_propagate_gpu):
/// the sun's VPLs from the reflective shadow map (lpv_vpls_rsm), the area emitters' VPLs by
/// rays on the CPU (lpv_vpls of the scene without its sun: `rays` counts those), injected by
/// lpv_inject_vpls_gpu. The geometry volume's surfels are binned by corner on the CPU, then one
/// invocation per corner (gi_lpv_geometry.comp) sums their |cos| SH, in float. gpu_seconds:
/// the RSM and the injection pass (uploads, dispatch and read-back).
LpvGrid lpv_inject_gpu(const Scene& scene, const LpvOptions& opt, std::uint64_t* rays = nullptr,
                       double* gpu_seconds = nullptr);
GeometryVolume lpv_geometry_gpu(const Scene& scene, const LpvGrid& g, double* gpu_seconds = nullptr);
/// One propagation step of `field` (gv null: no blocking), re-emitting as `reemission` says.
LpvGrid lpv_step(const LpvGrid& field, const GeometryVolume* gv,
                 LpvReemission reemission = LpvReemission::direction);
/// injected + sum of `iterations` steps (blocking from the second step on, when gv is given).
LpvGrid lpv_propagate(const LpvGrid& injected, const GeometryVolume* gv, int iterations,
                      LpvReemission reemission = LpvReemission::direction);
/// lpv_propagate on the GPU: one compute dispatch per iteration of
/// gpu/shaders/gi_lpv_propagate.comp (the same gather in float), the blocking table computed on
/// the CPU as for lpv_propagate. Makes its own EGL context (atmosh::gpu). gpu_seconds
/// (optional): wall time of the uploads, dispatches and read-back (context and compilation
/// excluded). Throws std::runtime_error (atmosh::gpu::Unavailable) where no EGL context can be
/// made, InputError where atmosh was built without atmosh::gpu.
LpvGrid lpv_propagate_gpu(const LpvGrid& injected, const GeometryVolume* gv, int iterations,
                          double* gpu_seconds = nullptr, LpvReemission reemission = LpvReemission::direction);
/// Total flux sum over cells and channels' mean of sqrt(4 pi) c_00 (per channel).
glm::dvec3 lpv_flux(const LpvGrid& g);
/// Trilinear (cell centres, clamped) interpolation of the intensity coefficients at p.
LpvCell lpv_sample(const LpvGrid& g, const glm::dvec3& p);

struct Lpv {
  LpvGrid injected, accumulated;
  GeometryVolume geometry;
  double inject_seconds = 0, propagate_seconds = 0;
  std::uint64_t rays = 0;
  int iterations = 0;
};
/// Injection, geometry volume and propagation.
Lpv build_lpv(const Scene& scene, const LpvOptions& opt);
/// Image lit by the LPV (opt.samples, seed, threads used here). stats.seconds: shading.
RadianceImage render_lpv(const Scene& scene, const Camera& camera, int width, int height, const Lpv& lpv,
                         const LpvOptions& opt);

/// The LPV applied to receivers (a G-buffer, radiosity.hpp's RadiosityReceivers with their
/// direct light): L = L_e + a / pi max(0, E_direct + max(0, E_lpv)), E_lpv as render_lpv's,
/// from lpv_sample at x + h/2 n — in double on the CPU and in float on the GPU
/// (gpu/shaders/gi_lpv_apply.comp; errors as lpv_propagate_gpu; gpu_seconds: uploads,
/// dispatch and read-back).
std::vector<glm::dvec3> shade_lpv_receivers_cpu(const LpvGrid& accumulated, const RadiosityReceivers& r);
std::vector<glm::dvec3> shade_lpv_receivers_gpu(const LpvGrid& accumulated, const RadiosityReceivers& r,
                                                double* gpu_seconds = nullptr);
/// The image by the G-buffer (gpu: the rasterised radiosity_gbuffer_gpu; else
/// radiosity_gbuffer: one ray per pixel centre; opt.samples direct-light estimates) and shade_lpv_receivers_gpu (gpu) or _cpu. stats.seconds: G-buffer +
/// shading.
RadianceImage render_lpv_gbuffer(const Scene& scene, const Camera& camera, int width, int height, const Lpv& lpv,
                                 const LpvOptions& opt, bool gpu);

/// A 2-level nested cascade (Kaplanyan & Dachsbacher 2010 nest grids of doubling cell size
/// around the viewer; here two levels and a fixed focus). The coarse level is the LPV of
/// lpv_grid(scene, opt.grid) (edge h); the fine level has cells of edge h/2 over the box
/// `fine_lo`..`fine_hi`: half the scene box's extent per axis about `focus` (default: the box's
/// centre), moved inside the box, its low corner on the coarse lattice. The VPLs are made once
/// at the fine level's density (lpv_vpls with the fine cell edge: sun_rays per fine cell edge)
/// and each goes into exactly one place, so no light is counted twice: a VPL whose (h/4-shifted)
/// position lies in the fine box into the fine level and into the coarse "inner" grid, the
/// others into the coarse "outer" grid (shifted h/2, as the one-level LPV). Each grid has its own
/// geometry volume (opt.blocking; surfels outside the fine grid left out) and propagates
/// opt.iterations steps (-1: 2 x grid). At a receiver x (normal n) with fine-box weight w(x)
/// (0 outside the fine box; inside, min(1, distance to its nearest face / h) over the faces that
/// lie inside the coarse grid — a face on the grid's boundary neither fades nor bounds, so a
/// receiver rounded past it still reads the fine level; the shared gi_lpv_cascade_weight):
///   E_lpv = E_outer(x) + w E_fine(x) + (1 - w) E_inner(x),
/// each E as the one-level LPV's (lpv_sample at x + h_level/2 n, read as I / h_level^2, clamped
/// at 0): near the focus the light of the nearby VPLs comes from the fine level, the far
/// VPLs' light from the coarse one; away from it the coarse level carries all. The
/// fine level's light that leaves the fine box is lost to receivers inside it.
struct LpvCascade {
  Lpv fine, inner, outer;        ///< fine level; coarse level: VPLs inside / outside the fine box
  glm::dvec3 fine_lo{0.0}, fine_hi{0.0};
  double inject_seconds = 0, propagate_seconds = 0;
  std::uint64_t rays = 0;
  int iterations = 0;
};
LpvCascade build_lpv_cascade(const Scene& scene, const LpvOptions& opt, const glm::dvec3* focus = nullptr);
/// The cascade's grids before injection: the coarse grid (lpv_grid(scene, opt.grid)), the fine
/// grid (edge h/2) and its box. InputError for a grid outside 2..256 or a focus not finite.
struct LpvCascadeLayout {
  LpvGrid coarse, fine;
  glm::dvec3 fine_lo{0.0}, fine_hi{0.0};
};
LpvCascadeLayout lpv_cascade_layout(const Scene& scene, const LpvOptions& opt, const glm::dvec3* focus = nullptr);
/// The cascade of given VPLs, at the fine level's half-cell shift (h/4 along n: lpv_vpls or
/// lpv_vpls_rsm with layout.fine), each put into one place by the shared gi_lpv_in_box
/// (atmosh/gi/shared/lpv.glsl.hpp), then the geometry volumes and propagation as
/// build_lpv_cascade (which is lpv_cascade_layout, lpv_vpls at the fine density and this).
/// `rays` is left 0.
LpvCascade lpv_cascade_from_vpls(const Scene& scene, const LpvOptions& opt, const LpvCascadeLayout& layout,
                                 const std::vector<Vpl>& vpls);
/// E_lpv of the cascade at x with unit normal n (see above; the weight and the blend are the
/// shared gi_lpv_cascade_weight and gi_lpv_cascade_blend, as the GPU frame's).
glm::dvec3 lpv_cascade_irradiance(const LpvCascade& c, const glm::dvec3& x, const glm::dvec3& n);
/// Image lit by the cascade, as render_lpv (opt.samples, seed, threads). stats.seconds: shading.
RadianceImage render_lpv_cascade(const Scene& scene, const Camera& camera, int width, int height,
                                 const LpvCascade& c, const LpvOptions& opt);

/// The GPU-resident LPV frame (atmosh::gpu::GiLpvFrame, gpu/gi_raster.hpp: one EGL context, every
/// pass on the GPU, only the image read back). Made once: the context, the programs, the mesh,
/// the grid (lpv_grid(scene, opt.grid)), the geometry volume injected from lpv_geometry's
/// surfels (opt.blocking) and the area emitters' VPLs (lpv_vpls of the scene without its sun:
/// opt.emitter_photons photon rays on the CPU, as lpv_inject_gpu; uploaded once — they do not
/// depend on the camera or the sun). Each render(): the G-buffer with the sun's shadow map, the
/// emitters' distance maps and the sky's depth maps (ShadowMapOptions, as radiosity_gbuffer_gpu;
/// here the emitters and the sky must be on the GPU: InputError where the scene has more than 64
/// emitting triangles or the options ask for the CPU's estimator), the sun's reflective shadow
/// map (lpv_vpls_rsm's rectangle and texels), injection, opt.iterations propagation steps
/// (-1: 2 grid; blocking from the second on), the application to the G-buffer
/// (L = L_e + a / pi max(0, E_direct + E_lpv), the shared gi_lpv_receiver_irradiance) and the
/// image's read-back; misses get environment_radiance on the CPU afterwards. The math is the
/// shared block of atmosh/gi/shared/lpv.glsl.hpp, as the CPU LPV's. `cascades` 2: the 2-level
/// nested cascade of build_lpv_cascade (lpv_cascade_layout with the default focus; the emitters'
/// VPLs and the RSM at the fine level's density and half-cell shift; each VPL into one place by
/// the shared gi_lpv_in_box; a geometry volume per lattice; every level propagated; the shared
/// gi_lpv_cascade_weight / gi_lpv_cascade_blend at the receivers), all on the GPU, one read-back.
/// Throws InputError (bad options, cascades not 1 or 2, no GPU library), gpu::Unavailable (a
/// std::runtime_error) without an EGL context.
class LpvFrameGpu {
 public:
  LpvFrameGpu(const Scene& scene, const LpvOptions& opt, const ShadowMapOptions& shadow = {}, int cascades = 1);
  ~LpvFrameGpu();
  LpvFrameGpu(const LpvFrameGpu&) = delete;
  LpvFrameGpu& operator=(const LpvFrameGpu&) = delete;
  /// One frame of `camera` at width x height (one sample per pixel centre, stderr 0);
  /// stats.seconds: the GPU passes up to the read-back plus the misses' environment.
  /// `accumulated` (optional): the propagated grid read back as well (for tests); a cascade's
  /// outer grid, and its `inner` and `fine` grids (optional; empty cells for a one-level frame).
  RadianceImage render(const Camera& camera, int width, int height, LpvGrid* accumulated = nullptr,
                       LpvGrid* inner = nullptr, LpvGrid* fine = nullptr);
  /// The grid and the emitters' VPLs it was made with.
  const LpvGrid& grid() const;
  const std::vector<Vpl>& emitter_vpls() const;
  /// The cascade's layout (null for one level).
  const LpvCascadeLayout* cascade() const;
  /// The photon rays cast on the CPU for the emitters' VPLs.
  std::uint64_t rays() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace atmosh::gi
