// The measurements behind the work estimates (atmosh/work.hpp): the CPU time of one
// unit of each estimator's count on one core, as the `s_per_unit` counter (CPU time of
// the timed loop / units it ran). docs/hostile-input.md ("Work estimates") lists the
// results, the machine and the spread, and the constants the estimators use.
// Run: build/bin/bench_work (about a minute).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <tuple>
#include <vector>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/sh/projection.hpp"

#include "bench_spectra.hpp"

using namespace atmosh::atmo;

namespace {

using atmosh::bench::spec_with;

// Integrators are built once per setting (the orders tables take seconds).
struct Sky {
  std::unique_ptr<Atmosphere> atm;
  std::unique_ptr<SkyIntegrator> sky;
  SkyOptions options;
};
Sky& sky_for(int method, int segments, int samples, int wavelengths) {
  static std::map<std::tuple<int, int, int, int>, Sky> cache;
  auto& s = cache[{method, segments, samples, wavelengths}];
  if (!s.sky) {
    const AtmosphereSpec spec = spec_with(wavelengths);
    s.atm = std::make_unique<Atmosphere>(spec);
    s.options.lut.shells = std::max(32, segments + 1);
    s.options.segments = segments;
    s.options.samples_per_segment = samples;
    s.options.scattering.method = method == 0   ? ScatteringMethod::Single
                                  : method == 1 ? ScatteringMethod::Approximate
                                                : ScatteringMethod::Orders;
    s.sky = std::make_unique<SkyIntegrator>(*s.atm, solar_spectrum_for_bins(spec.spectrum), s.options);
  }
  return s;
}

}  // namespace

// A 128 x 64 equirect image on one thread, sun at 20 deg. Args: method (0 single,
// 1 approximate, 2 orders 4), segments, samples per segment, wavelengths.
// s_per_unit: per view-ray node and wavelength, the unit of atmo::sky_image_work.
static void BM_WorkSkyImage(benchmark::State& st) {
  const int w = 128, h = 64;
  Sky& s = sky_for(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)), static_cast<int>(st.range(2)),
                   static_cast<int>(st.range(3)));
  const glm::dvec3 sun = enu_direction_from_zenith(70.0, 180.0);
  for (auto _ : st) {
    const SkyImage img = render_sky(*s.sky, SkyProjection::Equirect, w, h, 0.0, sun, false, 1);
    benchmark::DoNotOptimize(img.Y.data());
  }
  const double units = sky_image_work(w, h, s.atm->wavelengths_nm().size(), s.options).units;
  st.counters["s_per_unit"] = benchmark::Counter(units, benchmark::Counter::kIsIterationInvariantRate |
                                                            benchmark::Counter::kInvert);
}
BENCHMARK(BM_WorkSkyImage)
    ->ArgNames({"method", "segments", "samples", "wavelengths"})
    ->Args({0, 16, 2, 16})
    ->Args({0, 8, 2, 16})
    ->Args({0, 32, 2, 16})
    ->Args({0, 4, 1, 16})
    ->Args({0, 16, 1, 16})
    ->Args({0, 16, 4, 16})
    ->Args({0, 16, 2, 8})
    ->Args({0, 16, 2, 47})
    ->Args({1, 16, 2, 16})
    ->Args({1, 16, 2, 47})
    ->Args({2, 16, 2, 16})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// One sky summary (summarize_sky: zenith, horizon toward and away from the sun, the
// sun's transmittance), as the studies compute per row, single scattering, 16
// wavelengths. s_per_unit: per summary; studies::kSummaryRays is this over the cost of
// one ray of BM_WorkSkyImage/method:0/segments:16/samples:2/wavelengths:16.
static void BM_WorkSkySummary(benchmark::State& st) {
  Sky& s = sky_for(0, 16, 2, 16);
  int i = 0;
  for (auto _ : st) {
    const glm::dvec3 sun = enu_direction_from_zenith(10.0 + (i++ % 80), 180.0);
    const SkySummary m = summarize_sky(*s.sky, 0.0, sun);
    benchmark::DoNotOptimize(m.zenith.xyz.Y);
  }
  st.counters["s_per_unit"] = benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate |
                                                        benchmark::Counter::kInvert);
}
BENCHMARK(BM_WorkSkySummary)->Unit(benchmark::kMicrosecond)->Iterations(200);

// The optical-depth tables (view and sun) of the earth-physical preset, one thread.
// Args: shells, directions. s_per_unit: per table entry (OpticalDepthLut::estimate_build_work).
static void BM_WorkLutBuild(benchmark::State& st) {
  const Atmosphere atm(spec_with(1));
  LutOptions o;
  o.shells = static_cast<int>(st.range(0));
  o.view_directions = o.sun_directions = static_cast<int>(st.range(1));
  o.threads = 1;
  for (auto _ : st) {
    const OpticalDepthLut lut(atm, o);
    benchmark::DoNotOptimize(lut.table_bytes());
  }
  st.counters["s_per_unit"] = benchmark::Counter(OpticalDepthLut::estimate_build_work(o).units,
                                                 benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
}
BENCHMARK(BM_WorkLutBuild)
    ->ArgNames({"shells", "directions"})
    ->Args({40, 64})
    ->Args({80, 64})
    ->Args({40, 256})
    ->Args({160, 256})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

// sh project --method uniform on a 3-channel 256 x 128 equirect image. Args: bands,
// samples. s_per_unit: per sample x coefficient x channel (sh::sampler_work).
static void BM_WorkShUniform(benchmark::State& st) {
  const int W = 256, H = 128, C = 3;
  std::vector<float> px(static_cast<std::size_t>(W) * H * C);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = static_cast<float>(0.5 + 0.4 * std::sin(0.001 * i));
  const atmosh::sh::ImageView img{W, H, C, px.data()};
  atmosh::sh::ProjectOptions po{atmosh::sh::Method::uniform, static_cast<int>(st.range(1)), 1, 1};
  const int bands = static_cast<int>(st.range(0));
  for (auto _ : st) {
    const auto c = atmosh::sh::project_equirect_sampled(img, bands, po);
    benchmark::DoNotOptimize(c.data());
  }
  st.counters["s_per_unit"] = benchmark::Counter(atmosh::sh::sampler_work(po, bands, C).units,
                                                 benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
}
BENCHMARK(BM_WorkShUniform)
    ->ArgNames({"bands", "samples"})
    ->Args({3, 200000})
    ->Args({8, 200000})
    ->Args({16, 50000})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
