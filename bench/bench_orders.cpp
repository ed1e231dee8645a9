// The successive-orders tables (atmo::ScatteringOrders, 4 orders, 16 wavelengths)
// built on the CPU (all cores) and with the passes of orders >= 2 on the GPU
// (gpu::build_scattering_orders; the set-up and S_1 stay on the CPU): at the default
// table size (16 x 64 x 48 x 8, sphere rule 12 x 12, 32 steps) and at a quarter of it
// (8 x 32 x 24 x 8, 8 x 8, 16 steps). Counters: the GPU's share (gpu_passes_s: the
// passes with their read-backs; compile_s, upload_s). Without an EGL device the GPU
// cases are skipped.
// Run: build/bin/bench_orders  (--benchmark_filter=default:0 for the quick size)
#include <benchmark/benchmark.h>

#include <memory>

#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/scattering_orders.hpp"
#if __has_include("atmosh/gpu/orders.hpp")  // built with ATMOSH_WITH_GPU
#define ATMOSH_BENCH_GPU 1
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/orders.hpp"
#endif

using namespace atmosh::atmo;

namespace {
AtmosphereSpec spec16() {
  AtmosphereSpec s = preset("earth-physical");
  s.spectrum.wavelengths_nm.clear();
  s.spectrum.from_nm = 380;
  s.spectrum.to_nm = 780;
  s.spectrum.count = 16;
  return s;
}

MultipleScatteringOptions options(bool small) {
  MultipleScatteringOptions o;
  o.method = ScatteringMethod::Orders;
  o.orders = 4;
  if (small) {
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
  const MultipleScatteringOptions o = options(state.range(0) == 0);
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
  const MultipleScatteringOptions o = options(state.range(0) == 0);
  atmosh::gpu::OrdersGpuTimes t;
  long runs = 0;
  for (auto _ : state) {
    auto g = atmosh::gpu::build_scattering_orders(*ctx, atm, o, &t);
    benchmark::DoNotOptimize(g->radiance_table().data());
    ++runs;
  }
  state.counters["gpu_passes_s"] = t.passes_s / runs;
  state.counters["compile_s"] = t.compile_s / runs;
  state.counters["upload_s"] = t.upload_s / runs;
}
#endif
}  // namespace

// Arg 0: the quarter size (Small), 1: the default size.
BENCHMARK(BM_OrdersCpu)->ArgName("default")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(3);
#ifdef ATMOSH_BENCH_GPU
BENCHMARK(BM_OrdersGpu)->ArgName("default")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(3);
#endif
