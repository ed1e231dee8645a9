// GPU against CPU: the single-scattering sky image (16 wavelengths) rendered by
// atmo::render_sky (all cores) and gpu::render_sky (headless EGL, OpenGL 4.3
// compute), at 512x256 and at the 2048x1024 of the GPU issue; and the
// optical-depth table build on the CPU (one core) and on the GPU; and the sky's
// per-node sun-table lookup on one CPU core and on the GPU (ns_per_lookup). Without
// an EGL device the GPU cases are skipped.
// Run: build/bin/bench_gpu  (add --benchmark_filter=512 for the quick sizes)
#include <benchmark/benchmark.h>

#include <chrono>
#include <ctime>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "bench_spectra.hpp"
#if __has_include("atmosh/gpu/sky.hpp")  // built with ATMOSH_WITH_GPU
#define ATMOSH_BENCH_GPU 1
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/sky.hpp"
#endif

using namespace atmosh::atmo;

namespace {
using atmosh::bench::spec16;

struct Scene {
  AtmosphereSpec spec = spec16();
  Atmosphere atm{spec};
  SkyIntegrator sky{atm, solar_spectrum_for_bins(spec.spectrum)};
};

Scene& scene() {
  static Scene s;
  return s;
}

#ifdef ATMOSH_BENCH_GPU
atmosh::gpu::Context* context(std::string& why) {
  static std::unique_ptr<atmosh::gpu::Context> ctx;
  static std::string error;
  static bool tried = false;
  if (!tried) {
    tried = true;
    try {
      ctx = std::make_unique<atmosh::gpu::Context>();
    } catch (const atmosh::gpu::Unavailable& e) {
      error = e.what();
    }
  }
  why = error;
  return ctx.get();
}

// The context, or nullptr after marking the benchmark skipped.
atmosh::gpu::Context* context_or_skip(benchmark::State& st) {
  std::string why;
  atmosh::gpu::Context* ctx = context(why);
  if (!ctx) st.SkipWithError(("no EGL device: " + why).c_str());
  return ctx;
}
#endif
}  // namespace

static void BM_TablesCpu(benchmark::State& st) {
  Scene& s = scene();
  for (auto _ : st) {
    OpticalDepthLut lut(s.atm);
    benchmark::DoNotOptimize(&lut);
  }
  st.SetLabel("OpticalDepthLut build, 32 shells x 64 directions, one core");
}
BENCHMARK(BM_TablesCpu)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_SkyCpu(benchmark::State& st) {
  Scene& s = scene();
  const int w = static_cast<int>(st.range(0)), h = w / 2;
  for (auto _ : st) {
    auto img = render_sky(s.sky, SkyProjection::Equirect, w, h, 0.0, enu_direction_from_zenith(70.0, 180.0), false, 0);
    benchmark::DoNotOptimize(img.Y.data());
  }
  st.SetItemsProcessed(st.iterations() * w * h);
  st.SetLabel(std::to_string(w) + "x" + std::to_string(h) + ", 16 wavelengths, all cores");
}
BENCHMARK(BM_SkyCpu)->Arg(512)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

#ifdef ATMOSH_BENCH_GPU
static void BM_TablesGpu(benchmark::State& st) {
  atmosh::gpu::Context* ctx = context_or_skip(st);
  if (!ctx) return;
  Scene& s = scene();
  const OpticalDepthLut lut(s.atm);  // shells and options; its tables are rebuilt on the GPU
  for (auto _ : st) {
    int og = 0, os = 0;
    auto t = atmosh::gpu::build_lut_tables(*ctx, lut, s.atm, og, os);
    benchmark::DoNotOptimize(t.data());
  }
  st.SetLabel("same tables on the GPU (compile, upload, dispatch, read-back), " + ctx->info().renderer);
}
BENCHMARK(BM_TablesGpu)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_SkyGpu(benchmark::State& st) {
  atmosh::gpu::Context* ctx = context_or_skip(st);
  if (!ctx) return;
  Scene& s = scene();
  const int w = static_cast<int>(st.range(0)), h = w / 2;
  for (auto _ : st) {
    auto img = atmosh::gpu::render_sky(*ctx, s.sky, SkyProjection::Equirect, w, h, 0.0,
                                       enu_direction_from_zenith(70.0, 180.0), false);
    benchmark::DoNotOptimize(img.Y.data());
  }
  st.SetItemsProcessed(st.iterations() * w * h);
  st.SetLabel(std::to_string(w) + "x" + std::to_string(h) + ", 16 wavelengths, " + ctx->info().renderer);
}
BENCHMARK(BM_SkyGpu)->Arg(512)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
#endif

namespace {
// 2^20 seeded sun-lookup origins (altitude uniform in [0, top), mu uniform in
// [-1, 1]) for the lookup benchmarks.
const std::vector<glm::vec2>& lookup_origins() {
  static const std::vector<glm::vec2> o = [] {
    std::vector<glm::vec2> v;
    std::mt19937_64 rng(20261123);
    auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
    const double top = scene().atm.top_altitude();
    for (int i = 0; i < (1 << 20); ++i) {
      const double u = uniform(), w = uniform();
      v.push_back(glm::vec2(static_cast<float>(u * top), static_cast<float>(2.0 * w - 1.0)));
    }
    return v;
  }();
  return o;
}
}  // namespace

// Sun-table lookups, the sky's per-node query (earth-physical: interpolated U.S. 1976
// Rayleigh with its subtracted kinks, Mie, closed-form ozone), over the same 2^20
// origins: OpticalDepthLut::sun on one CPU core (double) ...
static void BM_SunLookupsCpu(benchmark::State& st) {
  Scene& s = scene();
  const auto& o = lookup_origins();
  const double R = s.atm.ground_radius();
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : st)
    for (const glm::vec2& p : o) {
      auto c = s.sky.lut().sun(R + double(p.x), double(p.y));
      benchmark::DoNotOptimize(c);
    }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  st.SetItemsProcessed(st.iterations() * static_cast<long>(o.size()));
  st.counters["ns_per_lookup"] = 1e9 * seconds / static_cast<double>(st.iterations() * o.size());
  st.SetLabel("2^20 origins, one core");
}
BENCHMARK(BM_SunLookupsCpu)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

#ifdef ATMOSH_BENCH_GPU
// ... and gpu::sun_lookups (sky_lib.glsl's sun_lookup, one invocation per origin):
// the time of 4 dispatches over the origins, after a warm-up one (no compilation,
// upload or read-back).
static void BM_SunLookupsGpu(benchmark::State& st) {
  atmosh::gpu::Context* ctx = context_or_skip(st);
  if (!ctx) return;
  Scene& s = scene();
  const auto& o = lookup_origins();
  long lookups = 0;
  double seconds = 0.0;
  for (auto _ : st) {
    const auto r = atmosh::gpu::sun_lookups(*ctx, s.sky, o, 4);
    st.SetIterationTime(r.seconds);
    lookups += r.lookups;
    seconds += r.seconds;
  }
  st.SetItemsProcessed(lookups);
  st.counters["ns_per_lookup"] = 1e9 * seconds / static_cast<double>(lookups);
  st.SetLabel("2^20 origins x 4 dispatches, " + ctx->info().renderer);
}
BENCHMARK(BM_SunLookupsGpu)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(2);
#endif


// Multiple scattering, the all-orders approximation (ScatteringMethod::Approximate; a
// table of 16 altitudes x 32 sun cosines, 8 x 4 directions x 16 steps per entry, a
// sixteenth of the default's work: the GPU build on llvmpipe takes minutes at the
// default size), 16 wavelengths, sun at 20 deg: the table build on the CPU (all cores) and on the GPU
// (gpu::build_ms_table: compile, upload, dispatch, read-back), and a 256x128 sky with the
// approximation on the CPU (all cores) and on the GPU (its table uploaded from the
// integrator, as `atmosh sky --device gpu` does), against the same sky with single
// scattering (BM_SkyCpu / BM_SkyGpu at 512 for a larger one).
namespace {
struct MsScene {
  AtmosphereSpec spec = spec16();
  Atmosphere atm{spec};
  SkyOptions options = [] {
    SkyOptions o;
    o.scattering.method = ScatteringMethod::Approximate;
    o.scattering.ms_altitudes = 16;
    o.scattering.ms_sun_directions = 32;
    o.scattering.ms_zenith_directions = 8;
    o.scattering.ms_azimuth_directions = 4;
    o.scattering.ms_ray_steps = 16;
    return o;
  }();
  SkyIntegrator sky{atm, solar_spectrum_for_bins(spec.spectrum), options};
};
MsScene& ms_scene() {
  static MsScene s;
  return s;
}
}  // namespace

static void BM_MsTableCpu(benchmark::State& st) {
  MsScene& s = ms_scene();
  for (auto _ : st) {
    MultipleScatteringLut t(s.atm, s.sky.lut(), s.options.scattering);
    benchmark::DoNotOptimize(&t);
  }
  st.SetLabel("MultipleScatteringLut 16 x 32 x 16 wavelengths, all cores");
}
BENCHMARK(BM_MsTableCpu)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

static void BM_SkyApproxCpu(benchmark::State& st) {
  const bool ms = st.range(0) != 0;
  const SkyIntegrator& sky = ms ? ms_scene().sky : scene().sky;
  for (auto _ : st) {
    auto img = render_sky(sky, SkyProjection::Equirect, 256, 128, 0.0, enu_direction_from_zenith(70.0, 180.0), false, 0);
    benchmark::DoNotOptimize(img.Y.data());
  }
  st.SetItemsProcessed(st.iterations() * 256 * 128);
  st.SetLabel(std::string(ms ? "approximate" : "single") + ", 256x128, 16 wavelengths, all cores");
}
BENCHMARK(BM_SkyApproxCpu)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

#ifdef ATMOSH_BENCH_GPU
static void BM_MsTableGpu(benchmark::State& st) {
  atmosh::gpu::Context* ctx = context_or_skip(st);
  if (!ctx) return;
  MsScene& s = ms_scene();
  for (auto _ : st) {
    auto t = atmosh::gpu::build_ms_table(*ctx, s.sky);
    benchmark::DoNotOptimize(t.data());
  }
  st.SetLabel("same table on the GPU (compile, upload, dispatch, read-back), " + ctx->info().renderer);
}
BENCHMARK(BM_MsTableGpu)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

static void BM_SkyApproxGpu(benchmark::State& st) {
  atmosh::gpu::Context* ctx = context_or_skip(st);
  if (!ctx) return;
  const bool ms = st.range(0) != 0;
  const SkyIntegrator& sky = ms ? ms_scene().sky : scene().sky;
  for (auto _ : st) {
    auto img = atmosh::gpu::render_sky(*ctx, sky, SkyProjection::Equirect, 256, 128, 0.0,
                                       enu_direction_from_zenith(70.0, 180.0), false);
    benchmark::DoNotOptimize(img.Y.data());
  }
  st.SetItemsProcessed(st.iterations() * 256 * 128);
  st.SetLabel(std::string(ms ? "approximate" : "single") + ", 256x128, 16 wavelengths, " + ctx->info().renderer);
}
BENCHMARK(BM_SkyApproxGpu)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
#endif

// The sky image with the successive-orders term (ScatteringMethod::Orders, 4 orders, the
// default table size: 14 x 48 x 48 x 16, built once on the CPU) against the same sky
// with single scattering, on the CPU (all cores) and on the GPU (the tables uploaded,
// as `atmosh sky --device gpu|auto --scattering orders` does with CPU-built tables):
// args {orders 0|1, width}; height = width / 2. The orders term is one table lookup per
// pixel (16 corners x 16 wavelengths), next to single scattering's per-node work.
// Tables built on the GPU: bench_orders (BM_OrdersGpu, BM_OrdersSky).
namespace {
struct OrdersScene {
  AtmosphereSpec spec = spec16();
  Atmosphere atm{spec};
  SkyOptions options = [] {
    SkyOptions o;
    o.scattering.method = ScatteringMethod::Orders;
    o.scattering.orders = 4;
    return o;
  }();
  SkyIntegrator sky{atm, solar_spectrum_for_bins(spec.spectrum), options};
};
OrdersScene& orders_scene() {
  static OrdersScene s;
  return s;
}
}  // namespace

static void BM_SkyOrdersCpu(benchmark::State& st) {
  const bool orders = st.range(0) != 0;
  const int w = static_cast<int>(st.range(1)), h = w / 2;
  const SkyIntegrator& sky = orders ? orders_scene().sky : scene().sky;
  for (auto _ : st) {
    auto img = render_sky(sky, SkyProjection::Equirect, w, h, 0.0, enu_direction_from_zenith(70.0, 180.0), false, 0);
    benchmark::DoNotOptimize(img.Y.data());
  }
  st.SetItemsProcessed(st.iterations() * w * h);
  st.SetLabel(std::string(orders ? "orders 4" : "single") + ", " + std::to_string(w) + "x" + std::to_string(h) +
              ", 16 wavelengths, all cores");
}
BENCHMARK(BM_SkyOrdersCpu)->Args({0, 256})->Args({1, 256})->Args({0, 512})->Args({1, 512})
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)->Repetitions(3);

#ifdef ATMOSH_BENCH_GPU
static void BM_SkyOrdersGpu(benchmark::State& st) {
  atmosh::gpu::Context* ctx = context_or_skip(st);
  if (!ctx) return;
  const bool orders = st.range(0) != 0;
  const int w = static_cast<int>(st.range(1)), h = w / 2;
  const SkyIntegrator& sky = orders ? orders_scene().sky : scene().sky;
  // Process CPU time (all threads): on a software renderer (llvmpipe runs the shader on
  // the CPU's threads) the work itself, less sensitive to a loaded machine than wall time.
  double cpu_s = 0;
  for (auto _ : st) {
    const std::clock_t c0 = std::clock();
    auto img = atmosh::gpu::render_sky(*ctx, sky, SkyProjection::Equirect, w, h, 0.0,
                                       enu_direction_from_zenith(70.0, 180.0), false);
    benchmark::DoNotOptimize(img.Y.data());
    cpu_s += double(std::clock() - c0) / CLOCKS_PER_SEC;
  }
  st.counters["process_cpu_s"] = cpu_s / double(st.iterations());
  st.SetItemsProcessed(st.iterations() * w * h);
  st.SetLabel(std::string(orders ? "orders 4 (tables uploaded)" : "single") + ", " + std::to_string(w) + "x" +
              std::to_string(h) + ", 16 wavelengths, " + ctx->info().renderer);
}
BENCHMARK(BM_SkyOrdersGpu)->Args({0, 256})->Args({1, 256})->Args({0, 512})->Args({1, 512})->Args({0, 2048})
    ->Args({1, 2048})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)->Repetitions(3);
#endif
