// Benchmarks of the atmosphere core: LUT build and lookup (targets: build
// <= 50 ms, lookup <= 20 ns), exact reference per ray, phase evaluation.
#include <benchmark/benchmark.h>

#include <cmath>

#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/presets.hpp"

using namespace atmosh::atmo;

// Args: preset (0 earth-graphics, 1 earth-physical), shells, directions,
// LutOptions::threads (0: every hardware thread). Wall time (the build is threaded).
static void BM_LutBuild(benchmark::State& st) {
  Atmosphere atm(preset(st.range(0) == 0 ? "earth-graphics" : "earth-physical"));
  LutOptions o;
  o.shells = static_cast<int>(st.range(1));
  o.view_directions = o.sun_directions = static_cast<int>(st.range(2));
  o.threads = static_cast<int>(st.range(3));
  for (auto _ : st) {
    OpticalDepthLut lut(atm, o);
    benchmark::DoNotOptimize(lut.table_bytes());
  }
}
BENCHMARK(BM_LutBuild)
    ->Args({0, 32, 64, 1})
    ->Args({0, 40, 64, 1})
    ->Args({0, 40, 64, 0})
    ->Args({1, 40, 64, 1})
    ->Args({1, 40, 64, 0})
    ->Args({0, 64, 128, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Args: preset (0 earth-graphics, 1 earth-physical), LutOptions::subtracted_kinks,
// LutOptions::subtract_curvature.
static void BM_LutLookupView(benchmark::State& st) {
  Atmosphere atm(preset(st.range(0) ? "earth-physical" : "earth-graphics"));
  LutOptions o;
  o.subtracted_kinks = static_cast<int>(st.range(1));
  o.subtract_curvature = st.range(2) != 0;
  OpticalDepthLut lut(atm, o);
  const double R = atm.ground_radius();
  int i = 0;
  for (auto _ : st) {
    double mu = -1.0 + 2.0 * ((i * 7919) % 1000) / 1000.0;
    auto c = lut.view(R + 100.0 * (i % 500), mu);
    benchmark::DoNotOptimize(c);
    ++i;
  }
}
BENCHMARK(BM_LutLookupView)->Args({0, 8, 1})->Args({1, 0, 1})->Args({1, 8, 0})->Args({1, 8, 1});

static void BM_LutLookupSun(benchmark::State& st) {
  Atmosphere atm(preset("earth-graphics"));
  OpticalDepthLut lut(atm);
  const double R = atm.ground_radius();
  int i = 0;
  for (auto _ : st) {
    double mu = ((i * 7919) % 1000) / 1000.0;
    auto c = lut.sun(R + 100.0 * (i % 500), mu);
    benchmark::DoNotOptimize(c);
    ++i;
  }
}
BENCHMARK(BM_LutLookupSun);

// Sun lookups the way the sky integrator makes them (docs/sky.md): an image row's
// node at one radius meets the row's pixels, whose sun directions span a range of
// mu. Arg: pixels per row. The fit (sun_at with a range, built per row and node) is
// included, so the time per item is the amortised cost of one lookup.
static void BM_LutSunRow(benchmark::State& st) {
  Atmosphere atm(preset("earth-graphics"));
  LutOptions o;
  o.view_tables = false;
  OpticalDepthLut lut(atm, o);
  const double R = atm.ground_radius();
  const int n = static_cast<int>(st.range(0));
  int row = 0;
  for (auto _ : st) {
    const double r = R + 250.0 * (row % 200);         // node altitudes 0-50 km
    const double lo = -0.05 + 0.004 * (row % 100), hi = lo + 0.5;  // the row's sun cosines
    auto at = lut.sun_at(r, lo, hi, n / 4);
    double acc = 0.0;
    for (int i = 0; i < n; ++i) acc += at(lo + (hi - lo) * (i + 0.5) / n).column.x;
    benchmark::DoNotOptimize(acc);
    ++row;
  }
  st.SetItemsProcessed(st.iterations() * n);
}
BENCHMARK(BM_LutSunRow)->Arg(256)->Arg(1024)->Arg(4096);

// Closed-form column of the ozone tent alone (rays as in BM_LutLookupView).
static void BM_TentColumnClosedForm(benchmark::State& st) {
  Atmosphere atm(preset("earth-graphics"));
  PiecewiseLinearColumn col(atm.profile(kOzone), atm.ground_radius());
  const double R = atm.ground_radius();
  int i = 0;
  for (auto _ : st) {
    double mu = -1.0 + 2.0 * ((i * 7919) % 1000) / 1000.0;
    benchmark::DoNotOptimize(col(R + 100.0 * (i % 500), mu, 3e5));
    ++i;
  }
}
BENCHMARK(BM_TentColumnClosedForm);

static void BM_ReferenceHorizontal(benchmark::State& st) {
  Atmosphere atm(preset(st.range(0) ? "earth-physical" : "earth-graphics"));
  OpticalDepthReference ref(atm);
  for (auto _ : st) benchmark::DoNotOptimize(ref.column(atm.ground_radius() + 10.0, 0.0));
}
BENCHMARK(BM_ReferenceHorizontal)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

static void BM_PhaseCornetteShanks(benchmark::State& st) {
  PhaseSpec s;
  s.model = PhaseSpec::Model::CornetteShanks;
  s.g = 0.8;
  PhaseFunction p(s);
  double mu = -1.0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(p.value(mu));
    mu = mu > 1.0 ? -1.0 : mu + 1e-3;
  }
}
BENCHMARK(BM_PhaseCornetteShanks);
