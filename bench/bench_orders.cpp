// The successive-orders tables (atmo::ScatteringOrders, 4 orders or the default 5, 16 wavelengths)
// built on the CPU (all cores) and with S_1 and the passes of orders >= 2 on the GPU
// (gpu::build_scattering_orders; the set-up stays on the CPU): at the default table size
// (14 x 48 x 48 x 16, sphere rule 16 x 16, 32 steps) and at a smaller one (8 x 32 x 24 x
// 16, 8 x 8, 16 steps). Counters of the GPU build, seconds per build (gpu::OrdersGpuTimes):
// compile_s, upload_s, single_s (S_1), gpu_passes_s (orders >= 2 with their read-backs),
// and cpu_s, the rest of the wall time (the CPU's set-up, the sum's read-back and its
// logarithm). Without an EGL device the GPU cases are skipped.
// BM_OrdersSky: what `atmosh sky --scattering orders` computes, end to end: the sky
// integrator (its optical-depth and orders tables) and a 512x256 image, all on the CPU
// (device 0), or the orders tables and the image on the GPU (device 1: the tables by
// gpu::make_orders_passes, the image by gpu::render_sky with them uploaded), or the
// tables on the CPU and the image on the GPU (device 2: `--device auto` on a software
// renderer), or the tables and the image on the GPU with the tables kept there
// (device 3: gpu::OrdersTables::Resident; nothing read back or uploaded; the sky pass
// binds the kept table). Counters: tables_s (the integrator's build), image_s.
// Run: build/bin/bench_orders  (--benchmark_filter=default:0 for the quick size)
#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>

#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/scattering_orders.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "bench_spectra.hpp"
#if __has_include("atmosh/gpu/orders.hpp")  // built with ATMOSH_WITH_GPU
#define ATMOSH_BENCH_GPU 1
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/orders.hpp"
#include "atmosh/gpu/sky.hpp"
#endif

using namespace atmosh::atmo;

namespace {
using atmosh::bench::spec16;

// size 0: the quarter size, 4 orders; 1: the default size, 4 orders; 2: the default
// size and the default number of orders (MultipleScatteringOptions::orders).
MultipleScatteringOptions options(long size) {
  MultipleScatteringOptions o;
  o.method = ScatteringMethod::Orders;
  if (size != 2) o.orders = 4;
  if (size == 0) {
    o.orders_radii = 8;
    o.orders_view_directions = 32;
    o.orders_sun_directions = 24;
    o.orders_sphere_zenith = 8;
    o.orders_sphere_azimuth = 8;
    o.orders_ray_steps = 16;
  }
  return o;
}

void BM_OrdersCpu(benchmark::State& state) {
  const Atmosphere atm(spec16());
  const MultipleScatteringOptions o = options(state.range(0));
  for (auto _ : state) {
    ScatteringOrders t(atm, o);
    benchmark::DoNotOptimize(t.radiance_table().data());
  }
}

#ifdef ATMOSH_BENCH_GPU
void BM_OrdersGpu(benchmark::State& state) {
  std::unique_ptr<atmosh::gpu::Context> ctx;
  try {
    ctx = std::make_unique<atmosh::gpu::Context>();
  } catch (const atmosh::gpu::Unavailable& e) {
    state.SkipWithError(e.what());
    return;
  }
  const Atmosphere atm(spec16());
  const MultipleScatteringOptions o = options(state.range(0));
  atmosh::gpu::OrdersGpuTimes t;
  long runs = 0;
  double wall = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    auto g = atmosh::gpu::build_scattering_orders(*ctx, atm, o, &t);
    benchmark::DoNotOptimize(g->radiance_table().data());
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++runs;
  }
  state.counters["gpu_passes_s"] = t.passes_s / runs;
  state.counters["compile_s"] = t.compile_s / runs;
  state.counters["upload_s"] = t.upload_s / runs;
  state.counters["single_s"] = t.single_s / runs;
  state.counters["cpu_s"] = (wall - t.passes_s - t.compile_s - t.upload_s - t.single_s) / runs;
}
#endif

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void BM_OrdersSky(benchmark::State& state) {
  const int device = static_cast<int>(state.range(0));
  const bool small = state.range(1) == 0;
  const AtmosphereSpec spec = spec16();
  const Atmosphere atm(spec);
  SkyOptions so;
  so.scattering = options(small ? 0 : 2);
  const glm::dvec3 sun = enu_direction_from_zenith(96.0, 180.0);  // sun -6 deg
  std::shared_ptr<const atmosh::gpu::Context> ctx;
#ifdef ATMOSH_BENCH_GPU
  if (device != 0) {
    try {
      ctx = std::make_shared<const atmosh::gpu::Context>();
    } catch (const atmosh::gpu::Unavailable& e) {
      state.SkipWithError(e.what());
      return;
    }
    if (device == 1) so.scattering.orders_passes = atmosh::gpu::make_orders_passes(ctx);
    if (device == 3)
      so.scattering.orders_passes =
          atmosh::gpu::make_orders_passes(ctx, nullptr, atmosh::gpu::OrdersTables::Resident);
  }
#else
  if (device != 0) {
    state.SkipWithError("built without ATMOSH_WITH_GPU");
    return;
  }
#endif
  double tables_s = 0, image_s = 0;
  long runs = 0;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum), so);
    tables_s += since(t0);
    t0 = std::chrono::steady_clock::now();
#ifdef ATMOSH_BENCH_GPU
    const SkyImage img = device != 0 ? atmosh::gpu::render_sky(*ctx, sky, SkyProjection::Equirect, 512, 256, 0.0, sun, false)
                                     : render_sky(sky, SkyProjection::Equirect, 512, 256, 0.0, sun, false, 0);
#else
    const SkyImage img = render_sky(sky, SkyProjection::Equirect, 512, 256, 0.0, sun, false, 0);
#endif
    image_s += since(t0);
    benchmark::DoNotOptimize(img.Y.data());
    ++runs;
  }
  state.counters["tables_s"] = tables_s / runs;
  state.counters["image_s"] = image_s / runs;
  state.SetLabel(device == 0   ? "all CPU"
                 : device == 1 ? "tables and image on the GPU"
                 : device == 2 ? "CPU tables, GPU image"
                               : "tables and image on the GPU, tables kept there");
}
}  // namespace

// Arg 0: the quarter size, 4 orders; 1: the default size, 4 orders; 2: the default size
// and the default number of orders.
BENCHMARK(BM_OrdersCpu)->ArgName("default")->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(3);
#ifdef ATMOSH_BENCH_GPU
BENCHMARK(BM_OrdersGpu)->ArgName("default")->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(3);
#endif
// Args {device 0 CPU | 1 GPU | 2 CPU tables + GPU image | 3 GPU, tables kept there,
// default size 0|1}.
BENCHMARK(BM_OrdersSky)->ArgNames({"device", "default"})->Args({0, 0})->Args({2, 0})->Args({1, 0})->Args({3, 0})
    ->Args({0, 1})->Args({2, 1})->Args({1, 1})->Args({3, 1})->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(3);
