// Benchmark of the diffuse path tracer (docs/gi.md; run: build/bin/bench_gi).
// Goal (issue: lighting scenes with SH): the path tracer's rays per second on the Cornell
// box reach >= 50 % of Embree's own single-ray rate — rtcIntersect1 of the very rays the
// path tracer cast (recorded once), on the same scene, in a tight loop, one thread each.
// Each iteration runs both, one after the other (interleaved), and the counters report
// both rates and their ratio.
#include <benchmark/benchmark.h>

#include <embree3/rtcore.h>

#include <array>
#include <chrono>
#include <memory>
#include <vector>

#include <glm/common.hpp>

#include "atmosh/gi/lpv.hpp"
#include "atmosh/gi/methods.hpp"
#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/radiosity.hpp"
#include "atmosh/gi/probes.hpp"
#include "atmosh/gi/scene.hpp"

using namespace atmosh;

namespace {
using Clock = std::chrono::steady_clock;

void BM_PathTracerVsEmbree(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  const int size = static_cast<int>(state.range(0));
  gi::TraceOptions opt;
  opt.samples = 4;
  opt.threads = 1;
  std::vector<std::array<float, 8>> log;
  opt.ray_log = &log;
  gi::render(s, s.camera, size, size, opt);  // the rays, recorded
  opt.ray_log = nullptr;

  RTCDevice dev = rtcNewDevice("verbose=0");
  RTCScene sc = rtcNewScene(dev);
  rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, s.mesh.positions.size()));
  auto* ib = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, s.mesh.triangles.size()));
  for (std::size_t i = 0; i < s.mesh.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) vb[3 * i + k] = static_cast<float>(s.mesh.positions[i][k]);
  for (std::size_t i = 0; i < s.mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) ib[3 * i + k] = s.mesh.triangles[i][k];
  rtcCommitGeometry(g);
  rtcAttachGeometry(sc, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(sc);

  double pt_rays = 0, pt_s = 0, em_rays = 0, em_s = 0;
  for (auto _ : state) {
    const auto img = gi::render(s, s.camera, size, size, opt);
    pt_rays += static_cast<double>(img.stats.rays);
    pt_s += img.stats.seconds;
    benchmark::DoNotOptimize(img.mean[0].data());

    const auto t0 = Clock::now();
    unsigned hits = 0;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (const auto& r : log) {
      RTCRayHit rh;
      rh.ray.org_x = r[0], rh.ray.org_y = r[1], rh.ray.org_z = r[2];
      rh.ray.dir_x = r[3], rh.ray.dir_y = r[4], rh.ray.dir_z = r[5];
      rh.ray.tnear = r[6], rh.ray.tfar = r[7];
      rh.ray.time = 0, rh.ray.mask = 0xffffffffu, rh.ray.id = 0, rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(sc, &ctx, &rh);
      hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    em_s += std::chrono::duration<double>(Clock::now() - t0).count();
    em_rays += static_cast<double>(log.size());
    benchmark::DoNotOptimize(hits);
  }
  rtcReleaseScene(sc);
  rtcReleaseDevice(dev);
  state.counters["rays_per_path"] = static_cast<double>(log.size()) / (double(size) * size * opt.samples);
  state.counters["pt_rays_per_s"] = pt_rays / pt_s;
  state.counters["embree_rays_per_s"] = em_rays / em_s;
  state.counters["ratio"] = (pt_rays / pt_s) / (em_rays / em_s);
}
BENCHMARK(BM_PathTracerVsEmbree)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

// Whole-machine throughput of a 256 x 256 Cornell box image, 8 paths per pixel.
void BM_CornellBoxImage(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::TraceOptions opt;
  opt.samples = 8;
  opt.threads = static_cast<int>(state.range(0));
  double rays = 0, secs = 0;
  for (auto _ : state) {
    const auto img = gi::render(s, s.camera, 256, 256, opt);
    rays += static_cast<double>(img.stats.rays);
    secs += img.stats.seconds;
  }
  state.counters["rays_per_s"] = rays / secs;
}
BENCHMARK(BM_CornellBoxImage)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Radiance probes on the CPU (docs/gi.md): building an n^3 grid on the Cornell box (cube 8,
// 4 paths per texel, bands 3) and shading one 512 x 512 frame from a 4^3 grid (one camera ray
// per pixel, plain trilinear and visibility-weighted), one thread.
void BM_ProbeGridBuild(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::ProbeOptions o;
  o.threads = 1;
  for (auto _ : state) benchmark::DoNotOptimize(gi::build_probe_grid(s, static_cast<int>(state.range(0)), o));
  state.counters["probes"] = static_cast<double>(state.range(0) * state.range(0) * state.range(0));
}
BENCHMARK(BM_ProbeGridBuild)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ProbeShade512(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::ProbeOptions o;
  const gi::ProbeGrid g = gi::build_probe_grid(s, 4, o);
  gi::ProbeRenderOptions ro;
  ro.samples = 1;
  ro.threads = 1;
  ro.visibility = state.range(0) != 0;
  for (auto _ : state) benchmark::DoNotOptimize(gi::render_probes(s, s.camera, 512, 512, g, false, ro));
}
BENCHMARK(BM_ProbeShade512)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// One 512 x 512 frame (one camera ray per pixel) of the Cornell box lit by a radiosity volume
// (16^3, 2 bands, 2 bounces) or an LPV (grid 16), the volume built once.
void BM_RadiosityShade512(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::RadiosityOptions o;
  o.grid = 16;
  o.bands = 2;
  o.bounces = 2;
  o.samples = 1;
  o.threads = 1;
  const gi::RadiosityVolume v = gi::build_radiosity_volume(s, o);
  for (auto _ : state) benchmark::DoNotOptimize(gi::render_radiosity(s, s.camera, 512, 512, v, o));
}
BENCHMARK(BM_RadiosityShade512)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_LpvShade512(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::LpvOptions o;
  o.grid = 16;
  o.samples = 1;
  o.threads = 1;
  const gi::Lpv l = gi::build_lpv(s, o);
  for (auto _ : state) benchmark::DoNotOptimize(gi::render_lpv(s, s.camera, 512, 512, l, o));
}
BENCHMARK(BM_LpvShade512)->Unit(benchmark::kMillisecond)->UseRealTime();

// LPV propagation (2 x grid iterations, with the geometry volume) of the Cornell box's
// injected light: arg 0 the grid, arg 1: 0 CPU (all threads), 1 GPU (EGL; skipped without).
void BM_LpvPropagate(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::LpvOptions o;
  o.grid = static_cast<int>(state.range(0));
  const gi::LpvGrid inj = gi::lpv_inject(s, o);
  const gi::GeometryVolume gv = gi::lpv_geometry(s, inj);
  const int it = 2 * o.grid;
  try {
    for (auto _ : state) {
      if (state.range(1) == 0) {
        benchmark::DoNotOptimize(gi::lpv_propagate(inj, &gv, it));
      } else {
        double secs = 0;
        benchmark::DoNotOptimize(gi::lpv_propagate_gpu(inj, &gv, it, &secs));
        state.SetIterationTime(secs);
      }
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
}
BENCHMARK(BM_LpvPropagate)->Args({16, 0})->Args({32, 0})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LpvPropagate)->Args({16, 1})->Args({32, 1})->Unit(benchmark::kMillisecond)->UseManualTime();
// One 512 x 512 frame of the Cornell box on the GPU (EGL; llvmpipe where no GPU is present) or
// its CPU twin, the G-buffer (one ray per pixel centre, CPU) and the volumes made once:
// arg 0: 0 CPU twin (all threads, wall time), 1 GPU (uploads + dispatch + read-back per frame;
// context and shader compilation excluded).
//   BM_RadiosityFrame512: the radiosity walk (16^3, 2 bands, 2 bounces, the volume's direct
//                         light at the walk's vertices: 16 normals, 1 sample);
//   BM_LpvFrame512:       LPV propagation (grid 16, 32 iterations, geometry volume) + its
//                         application to the G-buffer.
void BM_RadiosityFrame512(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::RadiosityOptions o;
  o.grid = 16;
  o.bands = 2;
  o.bounces = 2;
  gi::RadiosityVolume v = gi::build_radiosity_volume(s, o);
  gi::add_direct_volume(s, v, 16, 1, 1);
  const gi::RadiosityGBuffer g = gi::radiosity_gbuffer(s, s.camera, 512, 512, 1, 1);
  try {
    for (auto _ : state) {
      if (state.range(0) == 0) {
        benchmark::DoNotOptimize(gi::shade_receivers_cpu(v, g.receivers, o.bounces));
      } else {
        double secs = 0;
        benchmark::DoNotOptimize(gi::shade_receivers_gpu(v, g.receivers, o.bounces, &secs));
        state.SetIterationTime(secs);
      }
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
  state.counters["receivers"] = static_cast<double>(g.receivers.size());
}
BENCHMARK(BM_RadiosityFrame512)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_RadiosityFrame512)->Arg(1)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(3);

void BM_LpvFrame512(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::LpvOptions o;
  o.grid = 16;
  const gi::LpvGrid inj = gi::lpv_inject(s, o);
  const gi::GeometryVolume gv = gi::lpv_geometry(s, inj);
  const int it = 2 * o.grid;
  const gi::RadiosityGBuffer g = gi::radiosity_gbuffer(s, s.camera, 512, 512, 1, 1);
  try {
    for (auto _ : state) {
      if (state.range(0) == 0) {
        const gi::LpvGrid acc = gi::lpv_propagate(inj, &gv, it);
        benchmark::DoNotOptimize(gi::shade_lpv_receivers_cpu(acc, g.receivers));
      } else {
        double s1 = 0, s2 = 0;
        const gi::LpvGrid acc = gi::lpv_propagate_gpu(inj, &gv, it, &s1);
        benchmark::DoNotOptimize(gi::shade_lpv_receivers_gpu(acc, g.receivers, &s2));
        state.SetIterationTime(s1 + s2);
      }
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
}
BENCHMARK(BM_LpvFrame512)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_LpvFrame512)->Arg(1)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(3);

// Radiance probes rasterised on the GPU (docs/gi.md, "Probes on the GPU"), Cornell box:
//   BM_ProbeCubes/n/d:  the cube maps (N = 8) of n^3 probes from the baked surface radiance
//                       (divisions 16): d = 1 rasterised (upload, draws, read-back), d = 0 by
//                       CPU rays (all threads); the projection to SH not included;
//   BM_ProbeFrame512/d: one 512 x 512 frame shaded by a 4^3 grid (bands 3, one sample per pixel
//                       centre): d = 1 on the GPU (gi::ProbeFrameGpu: the grid's upload, draw,
//                       read-back and misses; context, program and the first draw made before),
//                       d = 0 its CPU twin (Embree rays, all threads).
void BM_ProbeCubes(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::SurfaceRadianceOptions so;
  so.samples = 4;
  const gi::SurfaceRadiance f = gi::bake_surface_radiance(s, so);
  const int n = static_cast<int>(state.range(0));
  gi::ProbeGrid g;
  g.n = n;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : s.mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  g.lo = lo;
  g.hi = hi;
  std::vector<glm::dvec3> pos;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) pos.push_back(g.position(i, j, k));
  const gi::ProbeRaster where = state.range(1) != 0 ? gi::ProbeRaster::gpu : gi::ProbeRaster::cpu_rays;
  try {
    for (auto _ : state) {
      double secs = 0;
      benchmark::DoNotOptimize(gi::surface_probe_cubes(s, f, pos, 8, where, &secs));
      state.SetIterationTime(secs);
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
  state.counters["probes"] = static_cast<double>(pos.size());
  state.counters["triangles"] = static_cast<double>(f.triangles.size());
}
BENCHMARK(BM_ProbeCubes)->Args({4, 0})->Args({4, 1})->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(3);

void BM_ProbeFrame512(benchmark::State& state) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::SurfaceRadianceOptions so;
  so.samples = 4;
  const gi::SurfaceRadiance f = gi::bake_surface_radiance(s, so);
  gi::ProbeOptions po;
  po.bands = 3;
  const gi::ProbeGrid g = gi::build_probe_grid_surface(s, f, 4, po, gi::ProbeRaster::cpu_rays);
  const bool gpu = state.range(0) != 0;
  try {
    std::unique_ptr<gi::ProbeFrameGpu> frame;
    if (gpu) {  // context, program and the first draw (llvmpipe compiles the shader there) outside the timing
      frame = std::make_unique<gi::ProbeFrameGpu>(s, s.camera, 512, 512);
      benchmark::DoNotOptimize(frame->render(g, false).mean[0].data());
    }
    for (auto _ : state) {
      const gi::RadianceImage img = gpu ? frame->render(g, false) : gi::render_probes_frame(s, s.camera, 512, 512, g, false, false);
      benchmark::DoNotOptimize(img.mean[0].data());
      state.SetIterationTime(img.stats.seconds);
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
}
BENCHMARK(BM_ProbeFrame512)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(5);

}  // namespace

// The whole 512 x 512 frame on the GPU (EGL; llvmpipe where no GPU is present): the G-buffer
// rasterised with its direct light (radiosity_gbuffer_gpu: the sun's shadow map, the area
// emitters' distance cube maps, the sky's depth maps), then
//   arg 0 = 0: the radiosity walk (shade_receivers_gpu; 16^3, 2 bands, 2 bounces; the volume
//              and its direct-light SH made once, by rays on the CPU);
//   arg 0 = 1: the LPV: the sun's reflective shadow map injected (lpv_inject_gpu; area
//              emitters' VPLs by rays on the CPU), propagated (grid 16, 32 iterations, the
//              geometry volume made once) and applied.
// arg 1: the scene: 0 sphere-on-plane under the sun (135, 40) and a uniform sky of 0.3, 1 the
// Cornell box (its area light). arg 2: 1 the lights on the GPU (ShadowMapOptions defaults:
// 4 points per emitting triangle with 256^2 cube faces; 128 sky directions with 256^2 depth
// maps), 0 the area light and the sky by the CPU's estimator at the rasterised points (one
// sample per pixel).
// Wall time per frame, each pass with its own EGL context and shader compilation (as the
// library runs them); counter gpu_ms: the passes' own times (uploads, draws / dispatches,
// read-back), contexts and compilation excluded; raster_ms: the G-buffer's rasterisation
// (upload, shadow / distance / sky maps, G-buffer, read-back) alone.
void BM_GpuFrame512(benchmark::State& state) {
  const bool lpv = state.range(0) == 1;
  gi::Scene s = gi::builtin_scene(state.range(1) == 0 ? "sphere-on-plane" : "cornell-box");
  if (state.range(1) == 0) {
    s.sun = gi::Sun{gi::sun_direction(s, 135, 40), glm::dvec3(3.0)};
    s.env_bands = 1;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = {0.3 * 3.5449077018110318};  // 0.3 / Y_00
  }
  gi::RadiosityOptions o;
  o.grid = 16;
  o.bands = 2;
  o.bounces = 2;
  gi::LpvOptions lo;
  lo.grid = 16;
  lo.emitter_photons = 16384;
  gi::RadiosityVolume v;
  gi::GeometryVolume gv;
  if (lpv) {
    gv = gi::lpv_geometry(s, gi::lpv_grid(s, lo.grid));
  } else {
    v = gi::build_radiosity_volume(s, o);
    gi::add_direct_volume(s, v, 16, 1, 1);
  }
  double gpu_total = 0, raster_total = 0;
  std::size_t receivers = 0;
  try {
    for (auto _ : state) {
      double g_s = 0, a = 0, b = 0, c = 0;
      gi::ShadowMapOptions so;
      if (state.range(2) == 0) so.emitter_points = so.sky_directions = 0;
      const gi::RadiosityGBuffer g = gi::radiosity_gbuffer_gpu(s, s.camera, 512, 512, 1, 1, 0, so, &g_s);
      receivers = g.receivers.size();
      if (lpv) {
        const gi::LpvGrid inj = gi::lpv_inject_gpu(s, lo, nullptr, &a);
        const gi::LpvGrid acc = gi::lpv_propagate_gpu(inj, &gv, 2 * lo.grid, &b);
        benchmark::DoNotOptimize(gi::shade_lpv_receivers_gpu(acc, g.receivers, &c));
      } else {
        benchmark::DoNotOptimize(gi::shade_receivers_gpu(v, g.receivers, o.bounces, &a));
      }
      gpu_total += g_s + a + b + c;
      raster_total += g_s;
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
  state.counters["gpu_ms"] = 1e3 * gpu_total / static_cast<double>(std::max<std::int64_t>(state.iterations(), 1));
  state.counters["raster_ms"] = 1e3 * raster_total / static_cast<double>(std::max<std::int64_t>(state.iterations(), 1));
  state.counters["receivers"] = static_cast<double>(receivers);
}
BENCHMARK(BM_GpuFrame512)
    ->Args({0, 0, 1})
    ->Args({1, 0, 1})
    ->Args({0, 0, 0})
    ->Args({0, 1, 1})
    ->Args({1, 1, 1})
    ->Args({0, 1, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

// The GPU-resident probe frame at 512 x 512 (gi::ProbeFrameResident, docs/gi.md "Radiance
// probes on the GPU, resident"): per frame the cube maps of the 4^3 probes (N = 8 rendered at
// 32: supersample 4, from the baked field, divisions 16) rasterised, projected to 3 bands by
// the compute pass, the sun's shadow map (1024^2) where the scene has a sun, the receivers
// shaded from the SH buffer, and the image read back — one context, no read-back between the
// passes. arg 0: the scene (0 the Cornell box and its light; 1 sphere-on-plane under the sun
// 135°, 40° and a uniform sky of 0.3). Context, programs and the first frame (llvmpipe
// compiles shaders at their first use) outside the timing. Counters: each pass's share, from
// a separate serialised frame per iteration (glFinish after each pass).
// One resident probe frame per iteration at `bands` bands: the body of BM_ProbeResidentFrame512
// and BM_ProbeResidentBands512.
void probe_resident_frame_512(benchmark::State& state, int scene, int bands) {
  gi::Scene s = gi::builtin_scene(scene == 0 ? "cornell-box" : "sphere-on-plane");
  if (scene == 1) {
    s.sun = gi::Sun{gi::sun_direction(s, 135, 40), glm::dvec3(1.0), 0.0};
    s.env_bands = 1;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = {0.3 * 2 * 1.7724538509055160273};  // L / Y_00
  }
  gi::SurfaceRadianceOptions so;
  so.samples = 4;
  const gi::SurfaceRadiance f = gi::bake_surface_radiance(s, so);
  gi::ProbeFrameOptions fo;
  fo.grid = 4;
  fo.probes.bands = bands;
  fo.probes.cube_size = 8;
  fo.supersample = 4;
  double passes[4] = {0, 0, 0, 0}, sums[4] = {0, 0, 0, 0};
  try {
    const gi::ProbeFrameResident frame(s, s.camera, 512, 512, f, fo);
    benchmark::DoNotOptimize(frame.render().mean[0].data());
    for (auto _ : state) {
      const gi::RadianceImage img = frame.render();
      benchmark::DoNotOptimize(img.mean[0].data());
      state.SetIterationTime(img.stats.seconds);
      state.PauseTiming();
      benchmark::DoNotOptimize(frame.render(passes).mean[0].data());
      for (int k = 0; k < 4; ++k) sums[k] += passes[k];
      state.ResumeTiming();
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
  const double n = static_cast<double>(std::max<std::int64_t>(state.iterations(), 1));
  state.counters["cubes_ms"] = 1e3 * sums[0] / n;
  state.counters["project_ms"] = 1e3 * sums[1] / n;
  state.counters["shadow_ms"] = 1e3 * sums[2] / n;
  state.counters["shade_read_ms"] = 1e3 * sums[3] / n;
}
void BM_ProbeResidentFrame512(benchmark::State& state) {
  probe_resident_frame_512(state, static_cast<int>(state.range(0)), 3);
}
BENCHMARK(BM_ProbeResidentFrame512)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(5);

// The GPU-resident LPV frame (gi::LpvFrameGpu over gpu::GiLpvFrame; docs/gi.md, "The GPU-resident
// LPV frame") at 512 x 512: per frame the G-buffer with the sun's shadow map and the lights'
// maps (default ShadowMapOptions: sun 1024^2, area light 4 points x 6 faces x 256^2, sky 128 x
// 256^2), the sun's RSM (sun_rays 16 per cell edge), point injection, 2 grid propagation steps
// with the geometry volume, the application to the G-buffer and the image's read-back (wall
// time, the misses' environment on the CPU included). Made once before: the context, the
// programs, the emitters' VPLs (65536 photons) and the geometry volume; one frame is rendered
// before timing (llvmpipe compiles a shader's code at its first draw). The lights' maps (shadow
// map, emitter distance maps, sky depth maps) are made by that first frame and kept, as the
// lights do not change: counter first_ms is the first frame's time, which makes them (and, on
// llvmpipe, compiles the shaders' code), frame_ms the mean of the timed frames. Arguments: scene (0
// sphere-on-plane under the sun 135 deg, 40 deg and a uniform sky of 0.3; 1 the Cornell box, its
// light; 2 sphere-on-plane under the sun alone), grid (cells along the longest axis).
// One resident LPV frame per iteration with `cascades` levels: the body of
// BM_LpvResidentFrame512 and BM_LpvCascadeFrame512.
void lpv_resident_frame_512(benchmark::State& state, int scene, int grid, int cascades, int emitter_rsm = 0) {
  gi::Scene s = gi::builtin_scene(scene == 1 ? "cornell-box" : "sphere-on-plane");
  if (scene != 1) s.sun = gi::Sun{gi::sun_direction(s, 135, 40), glm::dvec3(3.0, 2.0, 1.0)};
  if (scene == 0) {
    s.env_bands = 1;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = {0.3 * 2 * std::sqrt(3.14159265358979324)};
  } else if (scene == 2) {
    s.env_bands = 0;
    for (auto& c : s.env_sh) c.clear();
  }
  gi::LpvOptions o;
  o.grid = grid;
  o.emitter_rsm = emitter_rsm;
  double passes = 0, first = 0;
  try {
    gi::LpvFrameGpu frame(s, o, {}, cascades);
    first = frame.render(s.camera, 512, 512).stats.seconds;
    for (auto _ : state) {
      const gi::RadianceImage img = frame.render(s.camera, 512, 512);
      passes += img.stats.seconds;
      benchmark::DoNotOptimize(img.mean[0].data());
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
  state.counters["frame_ms"] = 1e3 * passes / static_cast<double>(std::max<std::int64_t>(state.iterations(), 1));
  state.counters["first_ms"] = 1e3 * first;
}
void BM_LpvResidentFrame512(benchmark::State& state) {
  lpv_resident_frame_512(state, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), 1);
}
BENCHMARK(BM_LpvResidentFrame512)
    ->Args({0, 8})
    ->Args({0, 16})
    ->Args({1, 8})
    ->Args({1, 16})
    ->Args({2, 8})
    ->Args({2, 16})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

// The resident LPV frame of the Cornell box with its light's VPLs from the emitters' reflective
// shadow maps (LpvOptions::emitter_rsm: 4 points a triangle, N x N texels a cube face; made by the
// first frame and kept, as the light does not move; first_ms) instead of photon rays made on the
// CPU at construction (BM_LpvResidentFrame512/1/grid). Arguments: grid, N.
void BM_LpvEmitterRsmFrame512(benchmark::State& state) {
  lpv_resident_frame_512(state, 1, static_cast<int>(state.range(0)), 1, static_cast<int>(state.range(1)));
}
BENCHMARK(BM_LpvEmitterRsmFrame512)
    ->Args({8, 32})
    ->Args({16, 32})
    ->Args({16, 64})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

// The GPU-resident probe frame at 512 x 512 by band count (docs/gi.md, "The resident probe
// frame at more bands"): BM_ProbeResidentFrame512's frame (4^3 probes, N = 8 rendered at 32, the
// baked field of divisions 16, shadow map 1024^2) with the probes projected to and shaded at
// `bands` bands (the shading program's basis array sized for them). Arguments: scene (0 the
// Cornell box and its light; 1 sphere-on-plane under the sun 135°, 40° and a uniform sky of
// 0.3), bands. Context, programs and the first frame outside the timing; counters as
// BM_ProbeResidentFrame512's (each pass of a separate serialised frame).
void BM_ProbeResidentBands512(benchmark::State& state) {
  probe_resident_frame_512(state, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
}
BENCHMARK(BM_ProbeResidentBands512)
    ->Args({0, 3})
    ->Args({0, 5})
    ->Args({0, 8})
    ->Args({1, 3})
    ->Args({1, 5})
    ->Args({1, 8})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(3);

// The 2-level nested LPV cascade in the GPU-resident frame (LpvFrameGpu with cascades = 2: the
// RSM at the fine level's density, three grids injected and propagated, the blend at the
// receivers, the image's read-back) against the one-level frame of the same coarse grid, in the
// same benchmark so that runs interleave: one 512 x 512 frame (wall time). Made once before: the
// context, the programs, the emitters' VPLs and the geometry volumes; one frame before timing.
// Arguments: scene (1 the Cornell box, its light; 2 sphere-on-plane under the sun 135 deg, 40 deg
// alone, as BM_LpvResidentFrame512), grid (coarse cells along the longest axis), cascades (1, 2).
void BM_LpvCascadeFrame512(benchmark::State& state) {
  lpv_resident_frame_512(state, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                         static_cast<int>(state.range(2)));
}
BENCHMARK(BM_LpvCascadeFrame512)
    ->Args({2, 8, 1})
    ->Args({2, 8, 2})
    ->Args({2, 16, 1})
    ->Args({2, 16, 2})
    ->Args({1, 8, 1})
    ->Args({1, 8, 2})
    ->Args({1, 16, 1})
    ->Args({1, 16, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);
