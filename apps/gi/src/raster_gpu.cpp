// The rasterised passes of the GPU forms of radiosity and LPV (atmosh/gpu/gi_raster.hpp):
// the camera's G-buffer with the sun's shadow map (radiosity_gbuffer_gpu, radiosity.hpp) and
// the sun's reflective shadow map (lpv_vpls_rsm, lpv.hpp).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/gi/lpv.hpp"
#include "atmosh/gi/radiosity.hpp"
#include "atmosh/parallel.hpp"
#include "raster_gpu.hpp"
#include "receivers.hpp"

#ifdef ATMOSH_GI_HAVE_GPU
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/gi_raster.hpp"
#endif

namespace atmosh::gi {

#ifdef ATMOSH_GI_HAVE_GPU
namespace detail {
MeshAttrs::MeshAttrs(const Scene& scene) : s(scene) {
  normal = detail::triangle_normals(scene.mesh);
  const std::size_t nt = scene.mesh.triangles.size();
  albedo.resize(nt);
  emission.resize(nt);
  one_sided.resize(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const Material& m = scene.materials[scene.material[t]];
    albedo[t] = m.albedo;
    emission[t] = m.emission;
    one_sided[t] = m.one_sided ? 1 : 0;
  }
}
gpu::GiMeshView MeshAttrs::view() const {
  gpu::GiMeshView v;
  v.positions = &s.mesh.positions;
  v.triangles = &s.mesh.triangles;
  v.normal = &normal;
  v.albedo = &albedo;
  v.emission = &emission;
  v.one_sided = &one_sided;
  return v;
}

gpu::PrtCamera pass_camera(const Camera& cam, int width, int height) {
  const glm::dvec3 f = glm::normalize(cam.forward), right = glm::normalize(glm::cross(cam.forward, cam.up));
  gpu::PrtCamera pc;
  pc.eye = cam.eye;
  pc.right = right;
  pc.up = glm::cross(right, f);
  pc.back = -f;
  pc.tan_half_fov = std::tan(0.5 * cam.vertical_fov_deg * std::numbers::pi / 180);
  pc.width = width;
  pc.height = height;
  return pc;
}

glm::dvec3 pixel_ray(const gpu::PrtCamera& pc, int col, int row) {
  const double th = pc.tan_half_fov, aspect = static_cast<double>(pc.width) / pc.height;
  const double x = (2.0 * (col + 0.5) / pc.width - 1.0) * th * aspect, y = (1.0 - 2.0 * (row + 0.5) / pc.height) * th;
  return glm::normalize(-pc.back + x * pc.right + y * pc.up);
}

gpu::GiSkyOptions sky_quadrature(const Scene& scene, int n, int resolution) {
  gpu::GiSkyOptions gsky;  // spherical Fibonacci directions, weight 4 pi / N each
  const double golden = std::numbers::pi * (1 + std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1 - 2 * (k + 0.5) / n, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = golden * (k + 0.5);
    const glm::dvec3 w = glm::normalize(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z));
    gsky.directions.push_back(w);
    gsky.radiance.push_back(environment_radiance(scene, w) * (4 * std::numbers::pi / n));
  }
  gsky.resolution = resolution;
  return gsky;
}

gpu::GiRsmView rsm_view(const Scene& scene, const LpvOptions& opt, const LpvGrid& g) {
  // The CPU injection's rectangle and texel count (lpv_vpls): the box's cross-section seen
  // from the sun, m = sun_rays x ceil(longer side / h) texels a side.
  glm::dvec3 lo, hi;
  detail::mesh_bounds(scene.mesh, lo, hi);
  gpu::GiRsmView v;
  v.direction = glm::normalize(scene.sun->direction);
  detail::onb(v.direction, v.t, v.b);
  v.t0 = 1e300, v.t1 = -1e300, v.b0 = 1e300, v.b1 = -1e300;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 q(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
    v.t0 = std::min(v.t0, glm::dot(q, v.t)), v.t1 = std::max(v.t1, glm::dot(q, v.t));
    v.b0 = std::min(v.b0, glm::dot(q, v.b)), v.b1 = std::max(v.b1, glm::dot(q, v.b));
  }
  const int m = std::max(1, opt.sun_rays * static_cast<int>(std::ceil(std::max(v.t1 - v.t0, v.b1 - v.b0) / g.h)));
  if (m > 16384) throw InputError("gi lpv: the reflective shadow map would exceed 16384 texels a side");
  v.mt = v.mb = m;
  v.irradiance = scene.sun->irradiance;
  return v;
}
}  // namespace detail
#endif

namespace {

[[maybe_unused]] bool has_emitters(const Scene& s) {
  for (const Material& m : s.materials)
    if (m.emission.x + m.emission.y + m.emission.z > 0) return true;
  return false;
}

bool sun_lit(const Scene& s) {
  return s.sun && s.sun->irradiance.x + s.sun->irradiance.y + s.sun->irradiance.z > 0;
}
}  // namespace

RadiosityGBuffer radiosity_gbuffer_gpu(const Scene& scene, const Camera& cam, int width, int height, int samples,
                                       std::uint64_t seed, int threads, const ShadowMapOptions& so,
                                       double* gpu_seconds) {
  validate(scene);
  check_view(cam, width, height);
  if (samples < 1 || samples > 1000000)
    throw InputError("gi radiosity: direct-light samples per pixel must be in 1..1000000, got " + std::to_string(samples));
  if (so.resolution < 16 || so.resolution > 16384)
    throw InputError("gi: shadow-map resolution must be in 16..16384, got " + std::to_string(so.resolution));
  if (so.pcf < 0 || so.pcf > 4) throw InputError("gi: shadow-map PCF radius must be in 0..4, got " + std::to_string(so.pcf));
  if (!(so.normal_offset >= 0 && so.normal_offset < 1e6) || !(so.bias >= 0 && so.bias < 1e6))
    throw InputError("gi: shadow-map offsets must be finite and >= 0");
  if (so.emitter_points < 0 || so.emitter_points > 64)
    throw InputError("gi: emitter points per triangle must be in 0..64, got " + std::to_string(so.emitter_points));
  if (so.sky_directions < 0 || so.sky_directions > 1024)
    throw InputError("gi: sky directions must be in 0..1024, got " + std::to_string(so.sky_directions));
  if (so.sky_resolution < 16 || so.sky_resolution > 8192)
    throw InputError("gi: sky depth-map resolution must be in 16..8192, got " + std::to_string(so.sky_resolution));
  if (so.emitter_resolution < 16 || so.emitter_resolution > 4096)
    throw InputError("gi: emitter distance-map resolution must be in 16..4096, got " +
                     std::to_string(so.emitter_resolution));
#ifdef ATMOSH_GI_HAVE_GPU
  const gpu::Context ctx;
  const detail::MeshAttrs attrs(scene);
  const gpu::PrtCamera pc = detail::pass_camera(cam, width, height);
  const bool sun = sun_lit(scene);
  gpu::GiSun gs;
  if (sun) gs.direction = glm::normalize(scene.sun->direction);
  gpu::GiShadowOptions gso;
  gso.resolution = so.resolution;
  gso.pcf = so.pcf;
  gso.normal_offset = so.normal_offset;
  gso.bias = so.bias;
  std::size_t n_emitting = 0;
  for (const glm::dvec3& L : attrs.emission) n_emitting += L.x + L.y + L.z > 0 ? 1 : 0;
  const bool gpu_emitters = so.emitter_points > 0 && n_emitting > 0 && n_emitting <= 64;
  gpu::GiEmitterOptions geo;
  if (gpu_emitters) {
    glm::dvec3 lo, hi;
    detail::mesh_bounds(scene.mesh, lo, hi);
    const double off = 1e-4 * std::max(glm::length(hi - lo), 1e-30);  // prt::RayScene's ray offset
    geo.points_per_triangle = so.emitter_points;
    geo.resolution = so.emitter_resolution;
    geo.eval_offset = 0.01 * off;  // as DirectLight: the receiver's own plane drops out
    geo.shadow_offset = off;
  }
  const bool has_env = scene.env_bands > 0 || scene.env_map.has_value();
  const bool gpu_sky = has_env && so.sky_directions > 0;
  gpu::GiSkyOptions gsky;
  if (gpu_sky) gsky = detail::sky_quadrature(scene, so.sky_directions, so.sky_resolution);
  const gpu::GiGBufferResult gb = gpu::gi_gbuffer(ctx, attrs.view(), pc, sun ? &gs : nullptr, gso,
                                                  gpu_emitters ? &geo : nullptr, gpu_sky ? &gsky : nullptr);
  if (gpu_seconds != nullptr) *gpu_seconds = gb.seconds;

  // The rest of the direct light (the environment; area emitters unless on the GPU) by the
  // CPU's estimator.
  Scene rest_scene = scene;
  rest_scene.sun.reset();
  if (gpu_emitters)
    for (Material& m : rest_scene.materials) m.emission = glm::dvec3(0.0);
  if (gpu_sky) {
    rest_scene.env_bands = 0;
    for (auto& c : rest_scene.env_sh) c.clear();
    rest_scene.env_map.reset();
  }
  const bool rest = (has_env && !gpu_sky) || (!gpu_emitters && has_emitters(scene));
  std::optional<prt::RayScene> rays;
  std::optional<detail::DirectLight> direct;
  if (rest) {
    rays.emplace(rest_scene.mesh);
    direct.emplace(rest_scene, *rays);
  }
  const std::size_t np = static_cast<std::size_t>(width) * height;
  std::vector<glm::dvec3> E(np, glm::dvec3(0.0));
  RadiosityGBuffer g;
  g.background.assign(np, glm::dvec3(0.0));
  std::vector<std::uint64_t> counts(np, 0);
  const glm::dvec3 e_sun = sun ? scene.sun->irradiance : glm::dvec3(0.0);
  parallel_for_ranges(np, 64, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      if (!gb.hit[i]) {
        if (has_env) {
          const int row = static_cast<int>(i / width), col = static_cast<int>(i % width);
          g.background[i] = environment_radiance(scene, detail::pixel_ray(pc, col, row));
        }
        continue;
      }
      glm::dvec3 Ed = e_sun * gb.sun[i] + gb.emitter[i] + gb.sky[i];
      if (rest) {
        detail::Rng rng(seed, i, detail::kReceiverSalt);
        glm::dvec3 acc(0.0);
        for (int s = 0; s < samples; ++s) acc += direct->irradiance(rng, gb.position[i], gb.normal[i], counts[i]);
        Ed += acc / static_cast<double>(samples);
      }
      E[i] = Ed;
    }
  });
  for (std::size_t i = 0; i < np; ++i) {
    g.rays += counts[i];
    if (!gb.hit[i]) continue;
    g.pixel.push_back(i);
    g.receivers.position.push_back(gb.position[i]);
    g.receivers.normal.push_back(gb.normal[i]);
    g.receivers.albedo.push_back(gb.albedo[i]);
    g.receivers.emission.push_back(gb.emission[i]);
    g.receivers.direct.push_back(E[i]);
  }
  return g;
#else
  (void)seed;
  (void)threads;
  (void)gpu_seconds;
  throw InputError("gi: this build has no GPU library (atmosh::gpu)");
#endif
}

namespace {
// An RSM texel's VPL (flux > 0): moved half of g's cell edge along its normal.
void add_rsm_vpl(std::vector<Vpl>& out, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& phi, const LpvGrid& g) {
  if (phi.x + phi.y + phi.z > 0) out.push_back({p + 0.5 * g.h * n, n, phi});
}
}  // namespace

std::vector<Vpl> lpv_vpls_rsm(const Scene& scene, const LpvOptions& opt, const LpvGrid& g, double* gpu_seconds) {
  validate(scene);
  if (opt.sun_rays < 1 || opt.sun_rays > 256)
    throw InputError("gi lpv: sun rays per cell must be in 1..256, got " + std::to_string(opt.sun_rays));
  if (!(g.h > 0) || g.nx < 1 || g.ny < 1 || g.nz < 1) throw InputError("gi lpv: empty grid");
  std::vector<Vpl> out;
  if (gpu_seconds != nullptr) *gpu_seconds = 0;
  if (!sun_lit(scene)) return out;
#ifdef ATMOSH_GI_HAVE_GPU
  const gpu::GiRsmView v = detail::rsm_view(scene, opt, g);
  const gpu::Context ctx;
  const detail::MeshAttrs attrs(scene);
  const gpu::GiRsmResult r = gpu::gi_rsm(ctx, attrs.view(), v);
  if (gpu_seconds != nullptr) *gpu_seconds = r.seconds;
  for (std::size_t i = 0; i < r.hit.size(); ++i)
    if (r.hit[i]) add_rsm_vpl(out, r.position[i], r.normal[i], r.flux[i], g);
  return out;
#else
  throw InputError("gi lpv: this build has no GPU library (atmosh::gpu)");
#endif
}

void check_emitter_rsm_size(const Scene& scene, int resolution, int points) {
  const std::size_t n_emitting = emitting_triangles(scene);
  if (n_emitting > 64)
    throw InputError("gi lpv: the emitters' RSM takes 1..64 emitting triangles; this scene has " + std::to_string(n_emitting));
  const long long texels = 6LL * points * static_cast<long long>(n_emitting) * resolution * resolution;
  if (texels > kMaxEmitterRsmTexels)
    throw InputError("gi lpv: the emitters' RSM at " + std::to_string(resolution) + " texels a face would hold " +
                     std::to_string(texels) + " texels (6 faces x " + std::to_string(points) + " points x " +
                     std::to_string(n_emitting) + " emitting triangles), more than " +
                     std::to_string(kMaxEmitterRsmTexels) + ": lower --lpv-emitter-rsm");
}

std::vector<Vpl> lpv_vpls_emitter_rsm(const Scene& scene, const LpvOptions& opt, const LpvGrid& g, int points,
                                      double* gpu_seconds) {
  validate(scene);
  const int res = opt.emitter_rsm == 0 ? 2 : opt.emitter_rsm;
  if (res < 2 || res > 1024)
    throw InputError("gi lpv: the emitters' RSM resolution must be 0 (photon rays) or 2..1024, got " +
                     std::to_string(opt.emitter_rsm));
  if (points < 1 || points > 64) throw InputError("gi lpv: emitter points must be in 1..64, got " + std::to_string(points));
  if (!(g.h > 0) || g.nx < 1 || g.ny < 1 || g.nz < 1) throw InputError("gi lpv: empty grid");
  check_emitter_rsm_size(scene, res, points);
  std::vector<Vpl> out;
  if (gpu_seconds != nullptr) *gpu_seconds = 0;
  if (emitting_triangles(scene) == 0) return out;
#ifdef ATMOSH_GI_HAVE_GPU
  const gpu::Context ctx;
  const detail::MeshAttrs attrs(scene);
  gpu::GiEmitterRsmOptions o;
  o.points_per_triangle = points;
  o.resolution = res;
  const gpu::GiEmitterRsmResult r = gpu::gi_emitter_rsm(ctx, attrs.view(), o);
  if (gpu_seconds != nullptr) *gpu_seconds = r.seconds;
  for (std::size_t i = 0; i < r.flux.size(); ++i) add_rsm_vpl(out, r.position[i], r.normal[i], r.flux[i], g);
  return out;
#else
  throw InputError("gi lpv: this build has no GPU library (atmosh::gpu)");
#endif
}

}  // namespace atmosh::gi
