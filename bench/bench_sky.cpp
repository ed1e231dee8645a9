// Sky benchmarks: time per view ray of the single-scattering integrator (16 and
// 40 wavelengths), per view of an image row, table build, a whole image with 1 and 2 threads, and the exact
// reference. Run: build/bin/bench_sky
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "bench_spectra.hpp"

using namespace atmosh::atmo;

namespace {
using atmosh::bench::spec_with;
}  // namespace

// One view ray, directions cycling over the upper hemisphere, sun at 20 deg.
static void BM_SkyRay(benchmark::State& st) {
  const AtmosphereSpec spec = spec_with(static_cast<int>(st.range(0)));
  const Atmosphere atm(spec);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
  const glm::dvec3 sun = enu_direction_from_zenith(70.0, 180.0);
  std::vector<double> L(atm.wavelengths_nm().size());
  int i = 0;
  for (auto _ : st) {
    const glm::dvec3 v = enu_direction_from_zenith((i % 89) + 0.5, (i * 37) % 360);
    sky.radiance(0.0, v, sun, L.data());
    benchmark::DoNotOptimize(L.data());
    ++i;
  }
  st.SetItemsProcessed(st.iterations());
  st.SetLabel("rays; " + std::to_string(L.size()) + " wavelengths");
}
BENCHMARK(BM_SkyRay)->Arg(16)->Arg(40);

// An image row: 1024 views at one elevation (the arg, deg; azimuths all around), sun at
// 20 deg, 40 wavelengths, through radiance_same_zenith (nodes shared by the row, the
// sun table reduced per node radius). Items: views. Compare with BM_SkyRay/40.
static void BM_SkyRow(benchmark::State& st) {
  const AtmosphereSpec spec = spec_with(40);
  const Atmosphere atm(spec);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
  const glm::dvec3 sun = enu_direction_from_zenith(70.0, 180.0);
  const int n = 1024;
  std::vector<glm::dvec3> views;
  for (int x = 0; x < n; ++x) views.push_back(enu_direction_from_zenith(90.0 - static_cast<double>(st.range(0)), (x + 0.5) * 360.0 / n));
  std::vector<double> L(views.size() * atm.wavelengths_nm().size());
  for (auto _ : st) {
    sky.radiance_same_zenith(0.0, views.data(), views.size(), sun, L.data());
    benchmark::DoNotOptimize(L.data());
  }
  st.SetItemsProcessed(st.iterations() * n);
  st.SetLabel("views; elevation " + std::to_string(st.range(0)) + " deg");
}
BENCHMARK(BM_SkyRow)->Arg(1)->Arg(30)->Arg(80)->Unit(benchmark::kMillisecond);

static void BM_SkyTables(benchmark::State& st) {
  const AtmosphereSpec spec = spec_with(16);
  const Atmosphere atm(spec);
  const auto solar = solar_spectrum_for_bins(spec.spectrum);
  for (auto _ : st) {
    SkyIntegrator sky(atm, solar);
    benchmark::DoNotOptimize(&sky);
  }
}
BENCHMARK(BM_SkyTables)->Unit(benchmark::kMillisecond);

// A 256x128 equirect image, 16 wavelengths, 1 and 2 threads (scaling).
static void BM_SkyImage(benchmark::State& st) {
  const AtmosphereSpec spec = spec_with(16);
  const Atmosphere atm(spec);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
  for (auto _ : st) {
    auto img = render_sky(sky, SkyProjection::Equirect, 256, 128, 0.0, enu_direction_from_zenith(70.0, 180.0), false,
                          static_cast<int>(st.range(0)));
    benchmark::DoNotOptimize(img.R.data());
  }
  st.SetItemsProcessed(st.iterations() * 256 * 128);
}
BENCHMARK(BM_SkyImage)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_SkyReferenceRay(benchmark::State& st) {
  const AtmosphereSpec spec = spec_with(16);
  const Atmosphere atm(spec);
  const SkyReference ref(atm, solar_spectrum_for_bins(spec.spectrum));
  for (auto _ : st) {
    auto r = ref.radiance(0.0, enu_direction_from_zenith(80.0, 30.0), enu_direction_from_zenith(70.0, 180.0));
    benchmark::DoNotOptimize(r.radiance.data());
  }
}
BENCHMARK(BM_SkyReferenceRay)->Unit(benchmark::kMillisecond)->Iterations(3);

// ------------------------------------------------------------ multiple scattering
namespace {
// The default scene's atmosphere shape (earth-graphics constituents, 100 km top,
// ground albedo 0.1) on 16 wavelengths.
AtmosphereSpec ms_spec() {
  AtmosphereSpec s = spec_with(16, "earth-graphics");
  s.planet.atmosphere_top_m = 100e3;
  s.planet.ground_albedo = 0.1;
  return s;
}
SkyOptions method(ScatteringMethod m) {
  SkyOptions o;
  o.scattering.method = m;
  return o;
}
}  // namespace

// Successive-orders tables at the default size, orders 2..N (the arg), 16 wavelengths,
// both cores. Target (issue 24): <= 10 s for 4 orders on a 2-core CPU.
static void BM_ScatteringOrdersBuild(benchmark::State& st) {
  const AtmosphereSpec spec = ms_spec();
  const Atmosphere atm(spec);
  MultipleScatteringOptions o = method(ScatteringMethod::Orders).scattering;
  o.orders = static_cast<int>(st.range(0));
  // Process CPU time (every thread) next to the wall clock: on a shared machine the
  // wall clock of a 2-thread build depends on the load, the CPU seconds much less.
  auto cpu_s = [] {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec + 1e-6 * u.ru_stime.tv_usec;
  };
  double cpu = 0;
  std::vector<double> passes;
  for (auto _ : st) {
    const double c0 = cpu_s();
    const ScatteringOrders t(atm, o);
    cpu += cpu_s() - c0;
    passes = t.pass_times_s();
    benchmark::DoNotOptimize(&t);
  }
  st.counters["cpu_s"] = cpu / static_cast<double>(st.iterations());
  // Wall seconds of the last build's passes: single scattering, then per order the
  // scattering density (J) and the radiance (S).
  if (!passes.empty()) st.counters["single_s"] = passes[0];
  double j = 0, s = 0;
  for (std::size_t k = 1; k < passes.size(); ++k) (k % 2 ? j : s) += passes[k];
  st.counters["density_s"] = j;
  st.counters["radiance_s"] = s;
  st.SetLabel(std::to_string(o.orders) + " orders, 16 wavelengths");
}
BENCHMARK(BM_ScatteringOrdersBuild)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// The approximation's table (Hillaire 2020) at the default size, 16 wavelengths.
static void BM_MultipleScatteringLutBuild(benchmark::State& st) {
  const AtmosphereSpec spec = ms_spec();
  const Atmosphere atm(spec);
  LutOptions lo;
  lo.view_tables = false;
  lo.shells = 32;
  const OpticalDepthLut lut(atm, lo);
  const MultipleScatteringOptions o = method(ScatteringMethod::Approximate).scattering;
  for (auto _ : st) {
    const MultipleScatteringLut t(atm, lut, o);
    benchmark::DoNotOptimize(&t);
  }
}
BENCHMARK(BM_MultipleScatteringLutBuild)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

// One view ray with each scattering method (arg: 0 single, 1 approximate, 2 orders),
// 16 wavelengths, sun at 20 deg: the per-pixel cost of multiple scattering.
static void BM_SkyRayMethod(benchmark::State& st) {
  const AtmosphereSpec spec = ms_spec();
  const Atmosphere atm(spec);
  const ScatteringMethod m = st.range(0) == 0 ? ScatteringMethod::Single
                             : st.range(0) == 1 ? ScatteringMethod::Approximate
                                                : ScatteringMethod::Orders;
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum), method(m));
  const glm::dvec3 sun = enu_direction_from_zenith(70.0, 180.0);
  std::vector<double> L(atm.wavelengths_nm().size());
  int i = 0;
  for (auto _ : st) {
    const glm::dvec3 v = enu_direction_from_zenith((i % 89) + 0.5, (i * 37) % 360);
    sky.radiance(0.0, v, sun, L.data());
    benchmark::DoNotOptimize(L.data());
    ++i;
  }
  st.SetItemsProcessed(st.iterations());
  st.SetLabel(scattering_method_name(m));
}
BENCHMARK(BM_SkyRayMethod)->Arg(0)->Arg(1)->Arg(2);
