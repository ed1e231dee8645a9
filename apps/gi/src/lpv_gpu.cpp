// The GPU-resident LPV frame of a scene (LpvFrameGpu, atmosh/gi/lpv.hpp) over
// atmosh::gpu::GiLpvFrame (atmosh/gpu/gi_raster.hpp).
#include <chrono>
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

namespace {
using Clock = std::chrono::steady_clock;
bool sun_lit(const Scene& s) { return s.sun && s.sun->irradiance.x + s.sun->irradiance.y + s.sun->irradiance.z > 0; }
}  // namespace

#ifdef ATMOSH_GI_HAVE_GPU
struct LpvFrameGpu::Impl {
  Scene scene;
  LpvOptions opt;
  ShadowMapOptions shadow;
  LpvGrid grid;
  std::vector<Vpl> vpls;
  std::uint64_t rays = 0;
  gpu::Context ctx;
  detail::MeshAttrs attrs;
  std::unique_ptr<gpu::GiLpvFrame> frame;
  bool emitters = false, sky = false;
  gpu::GiEmitterOptions geo;
  gpu::GiSkyOptions gsky;
  gpu::GiRsmView rsm;
  gpu::GiEmitterRsmOptions ersm;  // with opt.emitter_rsm > 0: the emitters' RSMs instead of photons
  int iterations = 0;
  std::optional<LpvCascadeLayout> cascade;
  Impl(const Scene& s, const LpvOptions& o, const ShadowMapOptions& so) : scene(s), opt(o), shadow(so), attrs(scene) {}
};
#else
struct LpvFrameGpu::Impl {
  LpvGrid grid;
  std::vector<Vpl> vpls;
  std::uint64_t rays = 0;
  std::optional<LpvCascadeLayout> cascade;
};
#endif

LpvFrameGpu::LpvFrameGpu(const Scene& scene, const LpvOptions& opt, const ShadowMapOptions& so, int cascades) {
  validate(scene);
  LpvOptions o = opt;
  if (cascades != 1 && cascades != 2)
    throw InputError("gi lpv: cascades must be 1 or 2, got " + std::to_string(cascades));
  if (o.iterations < -1 || o.iterations > 1024)
    throw InputError("gi lpv: iterations must be -1 (2 x grid) or 0..1024, got " + std::to_string(o.iterations));
  if (o.emitter_rsm != 0 && (o.emitter_rsm < 2 || o.emitter_rsm > 1024))
    throw InputError("gi lpv: the emitters' RSM resolution must be 0 (photon rays) or 2..1024, got " +
                     std::to_string(o.emitter_rsm));
  const LpvGrid g = lpv_grid(scene, o.grid);
  if (static_cast<long long>(g.ny + 1) * (g.nz + 1) > 16384)
    throw InputError("gi lpv: the GPU frame's atlas needs (ny + 1)(nz + 1) <= 16384 cells, grid " +
                     std::to_string(o.grid));
  std::optional<LpvCascadeLayout> layout;
  if (cascades == 2) {
    layout = lpv_cascade_layout(scene, o);
    if (static_cast<long long>(layout->fine.ny + 1) * (layout->fine.nz + 1) > 16384)
      throw InputError("gi lpv: the GPU cascade's fine atlas needs (ny + 1)(nz + 1) <= 16384 cells, grid " +
                       std::to_string(o.grid));
  }
  // the VPLs' density and half-cell shift: the finest level's
  const LpvGrid& vg = layout ? layout->fine : g;
  if (so.resolution < 16 || so.resolution > 16384 || so.pcf < 0 || so.pcf > 4 ||
      !(so.normal_offset >= 0 && so.normal_offset < 1e6) || !(so.bias >= 0 && so.bias < 1e6) ||
      so.emitter_points < 0 || so.emitter_points > 64 || so.emitter_resolution < 16 || so.emitter_resolution > 4096 ||
      so.sky_directions < 0 || so.sky_directions > 1024 || so.sky_resolution < 16 || so.sky_resolution > 8192)
    throw InputError("gi lpv: shadow-map options out of range");
#ifdef ATMOSH_GI_HAVE_GPU
  impl_ = std::make_unique<Impl>(scene, o, so);
  Impl& I = *impl_;
  I.grid = g;
  I.iterations = o.iterations < 0 ? 2 * o.grid : o.iterations;
  std::size_t n_emitting = 0;
  for (const glm::dvec3& L : I.attrs.emission) n_emitting += L.x + L.y + L.z > 0 ? 1 : 0;
  I.emitters = n_emitting > 0;
  if (I.emitters && o.emitter_rsm > 0) check_emitter_rsm_size(scene, o.emitter_rsm, so.emitter_points);
  if (I.emitters && (so.emitter_points == 0 || n_emitting > 64))
    throw InputError("gi lpv: the GPU frame lights area emitters on the GPU only (1..64 emitting triangles, "
                     "emitter points > 0); this scene has " + std::to_string(n_emitting));
  I.sky = scene.env_bands > 0 || scene.env_map.has_value();
  if (I.sky && so.sky_directions == 0)
    throw InputError("gi lpv: the GPU frame lights the environment on the GPU only (sky directions > 0)");
  if (I.emitters) {
    glm::dvec3 lo, hi;
    detail::mesh_bounds(scene.mesh, lo, hi);
    const double off = 1e-4 * std::max(glm::length(hi - lo), 1e-30);  // prt::RayScene's ray offset
    I.geo.points_per_triangle = so.emitter_points;
    I.geo.resolution = so.emitter_resolution;
    I.geo.eval_offset = 0.01 * off;
    I.geo.shadow_offset = off;
    I.ersm.points_per_triangle = so.emitter_points;
    I.ersm.resolution = o.emitter_rsm;
    if (o.emitter_photons > 0 && o.emitter_rsm == 0) {  // the emitters' VPLs: photon rays on the CPU, once
      Scene rest = scene;
      rest.sun.reset();
      I.vpls = lpv_vpls(rest, o, vg, &I.rays);
    }
  }
  if (I.sky) I.gsky = detail::sky_quadrature(scene, so.sky_directions, so.sky_resolution);
  if (sun_lit(scene)) I.rsm = detail::rsm_view(scene, o, vg);
  gpu::GiLpvGrid gg;
  gg.lo = g.lo;
  gg.h = g.h;
  gg.nx = g.nx, gg.ny = g.ny, gg.nz = g.nz;
  std::vector<gpu::GiLpvVpl> vp;
  vp.reserve(I.vpls.size());
  for (const Vpl& v : I.vpls) vp.push_back({v.p, v.n, v.flux});
  const std::vector<gpu::GiLpvSurfel> surfels = o.blocking ? detail::lpv_surfels(scene, g) : std::vector<gpu::GiLpvSurfel>{};
  gpu::GiLpvCascade gc;
  if (layout) {
    I.cascade = layout;
    gc.fine.lo = layout->fine.lo;
    gc.fine.h = layout->fine.h;
    gc.fine.nx = layout->fine.nx, gc.fine.ny = layout->fine.ny, gc.fine.nz = layout->fine.nz;
    gc.fine_lo = layout->fine_lo;
    gc.fine_hi = layout->fine_hi;
    if (o.blocking) gc.fine_surfels = detail::lpv_surfels(scene, layout->fine);
  }
  I.frame = std::make_unique<gpu::GiLpvFrame>(I.ctx, I.attrs.view(), gg, surfels, vp, layout ? &gc : nullptr);
#else
  (void)vg;
  throw InputError("gi lpv: this build has no GPU library (atmosh::gpu)");
#endif
}

LpvFrameGpu::~LpvFrameGpu() = default;

const LpvGrid& LpvFrameGpu::grid() const { return impl_->grid; }
const std::vector<Vpl>& LpvFrameGpu::emitter_vpls() const { return impl_->vpls; }
const LpvCascadeLayout* LpvFrameGpu::cascade() const { return impl_->cascade ? &*impl_->cascade : nullptr; }
std::uint64_t LpvFrameGpu::rays() const { return impl_->rays; }

RadianceImage LpvFrameGpu::render(const Camera& cam, int width, int height, LpvGrid* accumulated, LpvGrid* inner,
                                  LpvGrid* fine) {
  check_view(cam, width, height);
#ifdef ATMOSH_GI_HAVE_GPU
  Impl& I = *impl_;
  const auto t0 = Clock::now();
  const gpu::PrtCamera pc = detail::pass_camera(cam, width, height);
  const bool sun = sun_lit(I.scene);
  gpu::GiSun gs;
  if (sun) gs.direction = glm::normalize(I.scene.sun->direction);
  gpu::GiLpvFrameOptions fo;
  fo.iterations = I.iterations;
  fo.blocking = I.opt.blocking;
  fo.reemission = I.opt.reemission == LpvReemission::face_lobe ? 1 : 0;
  fo.sun = sun ? &gs : nullptr;
  fo.sun_irradiance = sun ? I.scene.sun->irradiance : glm::dvec3(0.0);
  fo.shadow.resolution = I.shadow.resolution;
  fo.shadow.pcf = I.shadow.pcf;
  fo.shadow.normal_offset = I.shadow.normal_offset;
  fo.shadow.bias = I.shadow.bias;
  fo.emitters = I.emitters ? &I.geo : nullptr;
  fo.sky = I.sky ? &I.gsky : nullptr;
  fo.rsm = sun ? &I.rsm : nullptr;
  fo.emitter_rsm = I.emitters && I.opt.emitter_rsm > 0 ? &I.ersm : nullptr;
  fo.read_grid = accumulated != nullptr || inner != nullptr || fine != nullptr;
  const gpu::GiLpvFrameResult r = I.frame->render(pc, fo);
  RadianceImage img;
  img.width = width;
  img.height = height;
  img.samples = 1;
  const std::size_t np = static_cast<std::size_t>(width) * height;
  for (int c = 0; c < 3; ++c) {
    img.mean[c].assign(np, 0.0f);
    img.stderr_[c].assign(np, 0.0f);
  }
  // The misses' environment on the CPU, on opt.threads (0: all; a quarter of a 512^2 frame's sky would
  // otherwise take milliseconds on one core).
  parallel_for_ranges(np, 4096, I.opt.threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      if (r.radiance[4 * i + 3] == 0.0f) {
        if (I.sky) {
          const int row = static_cast<int>(i / width), col = static_cast<int>(i % width);
          const glm::dvec3 L = environment_radiance(I.scene, detail::pixel_ray(pc, col, row));
          for (int c = 0; c < 3; ++c) img.mean[c][i] = static_cast<float>(L[c]);
        }
        continue;
      }
      for (int c = 0; c < 3; ++c) img.mean[c][i] = r.radiance[4 * i + c];
    }
  });
  auto read = [](const LpvGrid& shape, const std::vector<float>& v, LpvGrid* dst) {
    if (dst == nullptr) return;
    *dst = shape;
    if (v.size() != dst->cells.size() * 12) {  // not a level of this frame
      dst->cells.clear();
      return;
    }
    for (std::size_t c = 0; c < dst->cells.size(); ++c)
      for (int q = 0; q < 12; ++q) dst->cells[c][q] = v[c * 12 + q];
  };
  read(I.grid, r.grid, accumulated);
  read(I.grid, r.inner, inner);
  read(I.cascade ? I.cascade->fine : I.grid, r.fine, fine);
  img.stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return img;
#else
  (void)accumulated;
  (void)inner;
  (void)fine;
  throw InputError("gi lpv: this build has no GPU library (atmosh::gpu)");
#endif
}

}  // namespace atmosh::gi
