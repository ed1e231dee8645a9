// Monte-Carlo radiative-transfer benchmarks: paths per second per core of the
// spherical reference (default-scene atmosphere: 16 wavelengths 380-780 nm, 100 km
// top, Rayleigh + Mie + ozone, black ground; zenith view), and the bounded study of
// the time to reach 0.3 % standard error in zenith luminance at sun 30 and -9 deg
// (rt_time_to_rel_stderr, all cores; a run predicted to take over 120 s is not started: the
// counters then give the standard error reached and its time). Also the slab mode.
// Run: build/bin/bench_rt
#include <benchmark/benchmark.h>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/radiative_transfer.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/parallel.hpp"

using namespace atmosh::atmo;

namespace {
// The built-in default scene's atmosphere (apps/scene/src/default_scene.cpp): the
// AtmosphereSpec defaults with its 16-wavelength spectrum.
AtmosphereSpec default_scene_atmosphere() {
  AtmosphereSpec s;
  s.spectrum.from_nm = 380;
  s.spectrum.to_nm = 780;
  s.spectrum.count = 16;
  return s;
}
struct Fixture {
  AtmosphereSpec spec = default_scene_atmosphere();
  Atmosphere atm{spec};
  MonteCarloSky mc{atm, solar_spectrum_for_bins(spec.spectrum)};
};
Fixture& fixture() {
  static Fixture f;
  return f;
}
}  // namespace

// Paths per second on one thread (= per core): zenith view, sun at the arg (deg).
static void BM_RtSkyPathsPerCore(benchmark::State& st) {
  Fixture& f = fixture();
  RtOptions o;
  o.paths = 16 * 1000;
  o.threads = 1;
  const glm::dvec3 sun = enu_direction(static_cast<double>(st.range(0)), 180.0);
  double orders = 0;
  for (auto _ : st) {
    const RtSkyResult r = f.mc.radiance(0.0, {0, 0, 1}, sun, o);
    benchmark::DoNotOptimize(r.luminance);
    orders = r.mean_orders;
    ++o.seed;
  }
  st.SetItemsProcessed(st.iterations() * o.paths);
  st.counters["mean_orders"] = orders;
  st.SetLabel("paths; sun " + std::to_string(st.range(0)) + " deg, 1 thread");
}
BENCHMARK(BM_RtSkyPathsPerCore)->Arg(30)->Arg(-9)->Unit(benchmark::kMillisecond);

// Time to 0.3 % standard error of the zenith luminance (all cores), sun at the arg.
static void BM_RtTimeToThreeTenthsPercent(benchmark::State& st) {
  Fixture& f = fixture();
  RtConvergence c;
  for (auto _ : st) c = rt_time_to_rel_stderr(f.mc, static_cast<double>(st.range(0)), 0.003, 120.0, 32000);
  st.counters["time_s"] = c.time_s;
  st.counters["extrapolated_s"] = c.extrapolated_time_s;
  st.counters["paths"] = static_cast<double>(c.paths);
  st.counters["rel_stderr"] = c.reached_rel_stderr;
  st.counters["reached"] = c.reached ? 1 : 0;
  st.counters["luminance_cd_m2"] = c.luminance;
  st.counters["threads"] = c.threads;
  st.SetLabel("sun " + std::to_string(st.range(0)) + " deg");
}
BENCHMARK(BM_RtTimeToThreeTenthsPercent)->Arg(30)->Arg(-9)->Iterations(1)->Unit(benchmark::kSecond);

// Time to 1 % standard error of the zenith luminance in twilight (all cores; the
// guided scattering is on by default below -5 deg, its pilot included in the time),
// sun at the arg; the same with the guide off for comparison (arg + 1000 = off).
static void BM_RtTimeToOnePercentTwilight(benchmark::State& st) {
  const bool off = st.range(0) > 500;
  const double sun = static_cast<double>(off ? st.range(0) - 1000 : st.range(0));
  Fixture& f = fixture();
  RtSkyOptions so;
  if (off) so.guide = RtLineEstimate::Off;
  const MonteCarloSky mc(f.atm, solar_spectrum_for_bins(f.spec.spectrum), so);
  RtConvergence c;
  for (auto _ : st) c = rt_time_to_rel_stderr(mc, sun, 0.01, 120.0, 32000);
  st.counters["time_s"] = c.time_s;
  st.counters["extrapolated_s"] = c.extrapolated_time_s;
  st.counters["paths"] = static_cast<double>(c.paths);
  st.counters["rel_stderr"] = c.reached_rel_stderr;
  st.counters["reached"] = c.reached ? 1 : 0;
  st.counters["luminance_cd_m2"] = c.luminance;
  st.SetLabel("sun " + std::to_string(static_cast<int>(sun)) + " deg, guide " + (off ? "off" : "default"));
}
BENCHMARK(BM_RtTimeToOnePercentTwilight)->Arg(-6)->Arg(-9)->Arg(-12)->Arg(994)->Arg(991)->Arg(988)->Iterations(1)->Unit(benchmark::kSecond);

// Slab paths per second (one thread): tau = 1, omega = 0.9, HG g = 0.75, R and T.
static void BM_RtSlabPathsPerCore(benchmark::State& st) {
  RtOptions o;
  o.paths = 20000;
  o.threads = 1;
  const SlabSpec s{1.0, 0.9, SlabPhase::HenyeyGreenstein, 0.75, 0.2};
  for (auto _ : st) {
    const SlabResult r = slab_reflection_transmission(s, 0.5, 0.7, 0.0, o);
    benchmark::DoNotOptimize(r.reflection);
  }
  st.SetItemsProcessed(st.iterations() * o.paths * 2);
  st.SetLabel("paths; 1 thread");
}
BENCHMARK(BM_RtSlabPathsPerCore)->Unit(benchmark::kMillisecond);
