// One entry point for every lighting method (see methods.hpp).
#include "atmosh/gi/methods.hpp"

#include <algorithm>
#include <chrono>
#include <optional>
#include <stdexcept>

#include "atmosh/error.hpp"
#include "atmosh/gi/lpv.hpp"
#include "atmosh/gi/probes.hpp"
#include "atmosh/gi/radiosity.hpp"
#include "atmosh/prt/mesh.hpp"

namespace atmosh::gi {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

RadiosityOptions radiosity_options(const MethodOptions& o) {
  RadiosityOptions r;
  r.grid = o.grid;
  r.bands = o.bands;
  r.cube_size = o.cube_size;
  r.bounces = o.bounces < 0 ? 3 : o.bounces;
  r.samples = o.pixel_samples;
  r.seed = o.seed;
  r.threads = o.threads;
  return r;
}


LpvOptions lpv_options(const MethodOptions& o) {
  LpvOptions l;
  l.grid = o.grid;
  l.iterations = o.iterations;
  l.blocking = o.lpv_blocking;
  l.reemission = o.lpv_reemission;
  l.emitter_rsm = o.lpv_emitter_rsm;
  l.samples = o.pixel_samples;
  l.seed = o.seed;
  l.threads = o.threads;
  return l;
}

// Runs f, a pass on the GPU; what made the GPU unusable, if it failed: not built where
// atmosh was built without atmosh::gpu (f is not run), a runtime_error where no EGL context
// opened (gpu::Unavailable) or the driver refused. An InputError from f is bad input, as
// it would be on the CPU: it goes to the caller (exit 2), never taken for a missing GPU.
template <class F>
std::optional<GpuUnusable> try_gpu(F&& f) {
#ifdef ATMOSH_GI_HAVE_GPU
  try {
    f();
  } catch (const std::runtime_error& e) {
    return GpuUnusable{GpuUnusable::Why::no_device, e.what(), ""};
  }
  return std::nullopt;
#else
  (void)f;
  return GpuUnusable{GpuUnusable::Why::not_built, "atmosh::gpu is not built", ""};
#endif
}

void need(bool ok, const std::string& msg) {
  if (!ok) throw InputError(msg);
}
}  // namespace

std::vector<std::string> method_names() { return {"path", "probes", "radiosity", "lpv"}; }

std::optional<GpuUnusable> gpu_unusable() {
  return try_gpu([] {  // a context and the probes' program; no probes
    prt::Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}};
    prt::compute_normals(m);
    const Scene s = scene_from_mesh(m, Material{});
    SurfaceRadianceOptions so;
    so.bounces = 0;
    (void)surface_probe_cubes(s, bake_surface_radiance(s, so), {}, 1, ProbeRaster::gpu);
  });
}

void check_method_options(const MethodOptions& o) {
  const auto names = method_names();
  need(std::find(names.begin(), names.end(), o.method) != names.end(),
       "gi: unknown method '" + o.method + "' (path, probes, radiosity, lpv)");
  if (o.method == "probes" && o.device != DeviceRequest::cpu) {
    need(o.surface_divisions >= 1 && o.surface_divisions <= 1024,
         "gi probes: surface divisions must be in 1..1024, got " + std::to_string(o.surface_divisions));
    need(o.surface_samples >= 2 && o.surface_samples <= 1000000,
         "gi probes: surface samples must be in 2..1000000, got " + std::to_string(o.surface_samples));
  }
  need(o.pixel_samples >= 1 && o.pixel_samples <= 1000000,
       "gi: --pixel-samples must be in 1..1000000, got " + std::to_string(o.pixel_samples));
  if (o.method == "radiosity") {
    need(o.grid >= 1 && o.grid <= 64, "gi radiosity: --grid must be in 1..64, got " + std::to_string(o.grid));
    need(o.bands >= 1 && o.bands <= 3, "gi radiosity: --bands must be in 1..3, got " + std::to_string(o.bands));
    need(o.cube_size >= 1 && o.cube_size <= 128,
         "gi radiosity: --cube-size must be in 1..128, got " + std::to_string(o.cube_size));
    need(o.bounces >= -1 && o.bounces <= 16,
         "gi radiosity: --bounces must be -1 (3) or 0..16, got " + std::to_string(o.bounces));
  }
  if (o.method == "lpv") {
    need(o.grid >= 1 && o.grid <= 256, "gi lpv: --grid must be in 1..256, got " + std::to_string(o.grid));
    need(o.iterations >= -1 && o.iterations <= 1024,
         "gi lpv: --iterations must be -1 (2 x grid) or 0..1024, got " + std::to_string(o.iterations));
    need(o.lpv_cascades == 1 || o.lpv_cascades == 2,
         "gi lpv: --cascades must be 1 or 2, got " + std::to_string(o.lpv_cascades));
    need(o.lpv_cascades == 1 || o.grid >= 2, "gi lpv: --cascades 2 needs --grid >= 2, got " + std::to_string(o.grid));
    need(o.lpv_emitter_rsm == 0 || (o.lpv_emitter_rsm >= 2 && o.lpv_emitter_rsm <= 1024),
         "gi lpv: --lpv-emitter-rsm must be 0 (photon rays) or 2..1024, got " + std::to_string(o.lpv_emitter_rsm));
  }
}

MethodResult render_method(const Scene& scene, const Camera& camera, int width, int height, const MethodOptions& o) {
  check_method_options(o);
  validate(scene);  // what every method checks, here before the first pass on either device
  if (o.method == "lpv" && o.lpv_emitter_rsm > 0 && o.device != DeviceRequest::cpu)
    check_emitter_rsm_size(scene, o.lpv_emitter_rsm, ShadowMapOptions{}.emitter_points);
  check_view(camera, width, height);
  MethodResult r;
  if (o.method == "path" && o.device != DeviceRequest::cpu)
    r.device = resolve_device(o.device, GpuUnusable{GpuUnusable::Why::unsupported, "method '" + o.method + "'", ""},
                              "rendering on the CPU");
  if (o.method == "path") {
    TraceOptions t;
    t.samples = o.samples;
    t.bounces = o.bounces;
    t.seed = o.seed;
    t.threads = o.threads;
    const auto t0 = Clock::now();
    r.image = render(scene, camera, width, height, t);
    r.shade_seconds = since(t0);
  } else if (o.method == "probes") {
    ProbeOptions p;
    p.bands = o.bands;
    p.cube_size = o.cube_size;
    p.samples = o.samples;
    p.bounces = o.bounces;
    p.seed = o.seed;
    p.window = o.window;
    p.threads = o.threads;
    ProbeGrid g;
    if (o.device == DeviceRequest::cpu) {  // cube maps path-traced at the probes
      g = build_probe_grid(scene, o.grid, p);
      r.build_seconds = g.seconds;
    } else {  // cube maps of a baked surface radiance, rasterised (or ray cast where the GPU is unusable)
      SurfaceRadianceOptions so;
      so.divisions = o.surface_divisions;
      so.samples = o.surface_samples;
      so.bounces = o.bounces;
      so.seed = o.seed;
      so.threads = o.threads;
      const SurfaceRadiance f = bake_surface_radiance(scene, so);
      // supersampling within the cube-size limit (the largest s with cube_size x s <= 512)
      const int supersample = std::clamp(std::min(o.surface_supersample, 512 / std::max(o.cube_size, 1)), 1, 16);
      // Without visibility weighting the whole frame is GPU-resident, at every band count of
      // the probes (ProbeFrameResident: cube maps, their projection, the sun's shadow map and the
      // shading in one context, only the image read back); with it the cube maps are rasterised
      // and projected on the GPU (only the coefficients read back) and the frame shaded by the
      // CPU's camera rays.
      const bool resident = !o.probe_visibility;
      const std::optional<GpuUnusable> unusable = try_gpu([&] {
        if (resident) {
          ProbeFrameOptions fo;
          fo.grid = o.grid;
          fo.probes = p;
          fo.supersample = supersample;
          const auto tb = Clock::now();
          const ProbeFrameResident frame(scene, camera, width, height, f, fo);
          r.build_seconds = f.seconds + since(tb);
          const auto ts = Clock::now();
          r.image = frame.render();
          r.shade_seconds = since(ts);
          r.image.stats.rays += f.stats.rays;
          r.image.stats.shadow_rays += f.stats.shadow_rays;
        } else {
          g = build_probe_grid_surface(scene, f, o.grid, p, ProbeRaster::gpu_sh, supersample);
        }
      });
      r.device = resolve_device(o.device, unusable, "ray casting the probes' cube maps on the CPU");
      if (r.device.gpu && resident) return r;
      if (!r.device.gpu) g = build_probe_grid_surface(scene, f, o.grid, p, ProbeRaster::cpu_rays, supersample);
      r.build_seconds = f.seconds + g.seconds;
      g.stats.rays += f.stats.rays;
      g.stats.shadow_rays += f.stats.shadow_rays;
    }
    ProbeRenderOptions ro;
    ro.samples = o.pixel_samples;
    ro.seed = o.seed;
    ro.threads = o.threads;
    ro.visibility = o.probe_visibility;
    const auto t0 = Clock::now();
    r.image = render_probes(scene, camera, width, height, g, false, ro);
    r.shade_seconds = since(t0);
    r.image.stats.rays += g.stats.rays;
    r.image.stats.shadow_rays += g.stats.shadow_rays;
  } else if (o.method == "radiosity") {
    const RadiosityOptions ro = radiosity_options(o);
    RadiosityVolume v = build_radiosity_volume(scene, ro);
    bool done = false;
    if (o.device != DeviceRequest::cpu) {  // the walk as a GPU pass over a G-buffer
      add_direct_volume(scene, v, 32, 4, ro.seed, ro.threads);
      const auto t0 = Clock::now();
      const std::optional<GpuUnusable> unusable = try_gpu([&] {
        r.image = render_radiosity_gbuffer(scene, camera, width, height, v, ro, true);
        done = true;
      });
      r.device = resolve_device(o.device, unusable, "rendering on the CPU");
      r.shade_seconds = since(t0);
    }
    r.build_seconds = v.seconds;
    if (!done) {
      const auto t0 = Clock::now();
      r.image = render_radiosity(scene, camera, width, height, v, ro);
      r.shade_seconds = since(t0);
    }
    r.image.stats.rays += v.rays;
  } else if (o.lpv_cascades == 2) {  // the 2-level nested cascade
    const LpvOptions lo = lpv_options(o);
    bool done = false;
    if (o.device != DeviceRequest::cpu) {  // the GPU-resident frame with the cascade
      const std::size_t n_emitting = emitting_triangles(scene);
      std::optional<GpuUnusable> unusable;
      if (n_emitting > 64)
        unusable = GpuUnusable{GpuUnusable::Why::unsupported,
                               "the LPV cascade on the GPU lights at most 64 emitting triangles, this scene has " +
                                   std::to_string(n_emitting),
                               ""};
      else
        unusable = try_gpu([&] {
          const auto t0 = Clock::now();
          LpvFrameGpu frame(scene, lo, {}, 2);
          r.build_seconds = since(t0);  // set-up: context, programs, emitters' VPLs, geometry volumes
          r.image = frame.render(camera, width, height);
          r.shade_seconds = r.image.stats.seconds;  // the frame: every pass, the image's read-back
          r.image.stats.rays += frame.rays();
          done = true;
        });
      r.device = resolve_device(o.device, unusable, "building the LPV cascade on the CPU");
    }
    if (!done) {
      const LpvCascade c = build_lpv_cascade(scene, lo);
      r.build_seconds = c.inject_seconds + c.propagate_seconds;
      const auto t0 = Clock::now();
      r.image = render_lpv_cascade(scene, camera, width, height, c, lo);
      r.shade_seconds = since(t0);
      r.image.stats.rays += c.rays;
    }
  } else {
    const LpvOptions lo = lpv_options(o);
    Lpv l;
    bool shaded = false;  // the GPU path shades its G-buffer
    if (o.device == DeviceRequest::cpu) {
      l = build_lpv(scene, lo);
    } else {  // the GPU-resident frame where the scene allows it (<= 64 emitting triangles), else the
              // separate passes (injection, geometry and propagation on the GPU, emitters' VPLs by rays)
      l.iterations = lo.iterations < 0 ? 2 * lo.grid : lo.iterations;
      const std::size_t n_emitting = emitting_triangles(scene);
      const auto t0 = Clock::now();
      const std::optional<GpuUnusable> unusable = try_gpu([&] {
        if (n_emitting <= 64) {
          LpvFrameGpu frame(scene, lo);
          l.rays = frame.rays();
          l.inject_seconds = since(t0);  // set-up: context, programs, emitters' VPLs, geometry volume
          r.image = frame.render(camera, width, height);
          r.shade_seconds = r.image.stats.seconds;  // the frame: every pass, the image's read-back
          shaded = true;
          return;
        }
        l.injected = lpv_inject_gpu(scene, lo, &l.rays);
        if (lo.blocking) l.geometry = lpv_geometry_gpu(scene, l.injected);
        l.inject_seconds = since(t0);
        const auto t1 = Clock::now();
        l.accumulated =
            lpv_propagate_gpu(l.injected, lo.blocking ? &l.geometry : nullptr, l.iterations, nullptr, lo.reemission);
        l.propagate_seconds = since(t1);
        const auto t2 = Clock::now();
        r.image = render_lpv_gbuffer(scene, camera, width, height, l, lo, true);
        r.shade_seconds = since(t2);
        shaded = true;
      });
      r.device = resolve_device(o.device, unusable, "building the LPV on the CPU");
      if (!r.device.gpu) {
        l = build_lpv(scene, lo);
        shaded = false;
      }
    }
    r.build_seconds = l.inject_seconds + l.propagate_seconds;
    if (!shaded) {
      const auto t0 = Clock::now();
      r.image = render_lpv(scene, camera, width, height, l, lo);
      r.shade_seconds = since(t0);
    }
    r.image.stats.rays += l.rays;
  }
  r.image.stats.seconds = r.build_seconds + r.shade_seconds;
  return r;
}

void study_methods(const Scene& scene, int width, int height, const StudyOptions& o,
                   const std::function<void(const StudyRow&)>& row) {
  for (int b : o.radiosity_bands) need(b >= 1 && b <= 3, "gi converge: radiosity bands must be in 1..3, got " + std::to_string(b));
  for (int g : o.radiosity_grids) need(g >= 1 && g <= 64, "gi converge: radiosity grids must be in 1..64, got " + std::to_string(g));
  for (int b : o.radiosity_bounces)
    need(b >= 0 && b <= 16, "gi converge: radiosity bounces must be in 0..16, got " + std::to_string(b));
  for (int g : o.lpv_grids) need(g >= 1 && g <= 256, "gi converge: lpv grids must be in 1..256, got " + std::to_string(g));
  need(o.lpv_cascade_max_grid >= 0 && o.lpv_cascade_max_grid <= 256,
       "gi converge: the largest LPV cascade grid must be in 0..256, got " + std::to_string(o.lpv_cascade_max_grid));
  need(o.lpv_paper_max_grid >= 0 && o.lpv_paper_max_grid <= 256,
       "gi converge: the largest LPV paper-re-emission grid must be in 0..256, got " +
           std::to_string(o.lpv_paper_max_grid));
  const std::size_t n_emitting = emitting_triangles(scene);
  for (int g : o.radiosity_grids) {
    if (o.radiosity_bands.empty()) break;
    RadiosityOptions ro;
    ro.grid = g;
    ro.bands = *std::max_element(o.radiosity_bands.begin(), o.radiosity_bands.end());
    ro.cube_size = o.cube_size;
    ro.samples = o.pixel_samples;
    ro.seed = o.seed;
    ro.threads = o.threads;
    const RadiosityVolume full = build_radiosity_volume(scene, ro);
    RadiosityVolume full_direct;  // the GPU form's: with the direct-light SH at the probes
    if (o.gpu) {
      full_direct = full;
      add_direct_volume(scene, full_direct, 32, 4, ro.seed, ro.threads);
    }
    for (int b : o.radiosity_bands) {
      const RadiosityVolume v = truncate_volume(full, b);
      RadiosityVolume vg = o.gpu ? truncate_volume(full_direct, b) : RadiosityVolume{};
      for (int B : o.radiosity_bounces) {
        ro.bounces = B;
        StudyRow r;
        r.method = "radiosity";
        r.setting = "bands=" + std::to_string(b) + " grid=" + std::to_string(g) + " bounces=" + std::to_string(B);
        const auto t0 = Clock::now();
        r.result.image = render_radiosity(scene, scene.camera, width, height, v, ro);
        r.result.shade_seconds = since(t0);
        r.result.build_seconds = full.seconds;
        row(r);
        if (o.gpu) {
          StudyRow rg;
          rg.method = "radiosity-gpu";
          rg.setting = r.setting;
          const auto t1 = Clock::now();
          rg.result.image = render_radiosity_gbuffer(scene, scene.camera, width, height, vg, ro, true);
          rg.result.shade_seconds = since(t1);
          rg.result.build_seconds = full_direct.seconds;
          rg.result.device.gpu = true;
          row(rg);
        }
      }
    }
  }
  for (int g : o.lpv_grids)
    for (bool block : {true, false}) {
      LpvOptions lo;
      lo.grid = g;
      lo.blocking = block;
      lo.samples = o.pixel_samples;
      lo.seed = o.seed;
      lo.threads = o.threads;
      StudyRow r;
      r.method = block ? "lpv" : "lpv-noblock";
      const Lpv l = build_lpv(scene, lo);
      r.setting = "grid=" + std::to_string(g) + " iterations=" + std::to_string(l.iterations);
      const auto t0 = Clock::now();
      r.result.image = render_lpv(scene, scene.camera, width, height, l, lo);
      r.result.shade_seconds = since(t0);
      r.result.build_seconds = l.inject_seconds + l.propagate_seconds;
      row(r);
      // A GPU row of this grid: render_method's LPV on the GPU, `set` choosing its variant.
      auto gpu_row = [&](const std::string& method, const std::string& setting, auto&& set) {
        MethodOptions m;
        m.method = "lpv";
        m.grid = g;
        m.pixel_samples = o.pixel_samples;
        m.seed = o.seed;
        m.threads = o.threads;
        m.device = DeviceRequest::gpu;
        set(m);
        StudyRow rg;
        rg.method = method;
        rg.setting = setting;
        rg.result = render_method(scene, scene.camera, width, height, m);
        row(rg);
      };
      if (o.gpu)  // injection, geometry, propagation and shading on the GPU
        gpu_row(r.method + "-gpu", r.setting, [&](MethodOptions& m) { m.lpv_blocking = block; });
      if (o.gpu && block && o.lpv_emitter_rsm > 0 && n_emitting >= 1 && n_emitting <= 64)  // emitters by RSMs
        gpu_row("lpv-rsm-gpu", r.setting + " emitter_rsm=" + std::to_string(o.lpv_emitter_rsm),
                [&](MethodOptions& m) { m.lpv_emitter_rsm = o.lpv_emitter_rsm; });
      if (block && g <= o.lpv_paper_max_grid) {  // the published re-emission, side by side (CPU)
        LpvOptions lp = lo;
        lp.reemission = LpvReemission::face_lobe;
        StudyRow rp;
        rp.method = "lpv-paper";
        const Lpv lpaper = build_lpv(scene, lp);
        rp.setting = r.setting;
        const auto t1 = Clock::now();
        rp.result.image = render_lpv(scene, scene.camera, width, height, lpaper, lp);
        rp.result.shade_seconds = since(t1);
        rp.result.build_seconds = lpaper.inject_seconds + lpaper.propagate_seconds;
        row(rp);
        if (o.gpu)  // the same on the GPU (the propagation's table row, no other program)
          gpu_row("lpv-paper-gpu", rp.setting, [](MethodOptions& m) { m.lpv_reemission = LpvReemission::face_lobe; });
      }
      if (block && g >= 2 && g <= o.lpv_cascade_max_grid) {  // the 2-level nested cascade (CPU)
        StudyRow rc;
        rc.method = "lpv";
        const LpvCascade c = build_lpv_cascade(scene, lo);
        rc.setting = r.setting + " cascades=2";
        const auto t1 = Clock::now();
        rc.result.image = render_lpv_cascade(scene, scene.camera, width, height, c, lo);
        rc.result.shade_seconds = since(t1);
        rc.result.build_seconds = c.inject_seconds + c.propagate_seconds;
        rc.result.image.stats.rays += c.rays;
        row(rc);
        if (o.gpu && n_emitting <= 64)  // the same in the GPU-resident frame
          gpu_row("lpv-cascade-gpu", rc.setting, [](MethodOptions& m) { m.lpv_cascades = 2; });
      }
    }
}

}  // namespace atmosh::gi
