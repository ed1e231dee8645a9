// libsh against SHTns (https://bitbucket.org/nschaeff/shtns, CeCILL licence), built from its
// public source outside the project and found through -DATMOSH_SHTNS_DIR=<folder holding
// shtns.h and libshtns.a>: the same Gauss grid, one thread, both libraries' benchmarks in one
// program, to be run interleaved and repeated, e.g.
//   build/bin/bench_sh_shtns --benchmark_enable_random_interleaving=true \
//     --benchmark_repetitions=5 --benchmark_min_time=0.2
// and compared by CPU time (docs/sh.md). SHTns runs in its native layout (BM_shtns_Analysis,
// BM_shtns_Synthesis) and on libsh's own ring-contiguous array (…Rings). Without
// ATMOSH_SHTNS_DIR only the libsh halves run.
#include <benchmark/benchmark.h>

#include <complex>
#include <map>
#include <tuple>
#include <memory>
#include <random>
#include <vector>

#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/rotation.hpp"
#include "atmosh/sh/transform.hpp"

#if ATMOSH_HAVE_SHTNS
#include <fftw3.h>

#include "shtns.h"
#endif

using namespace atmosh::sh;

namespace {
std::vector<double> random_coeffs(int L) {
  std::mt19937_64 rng(27);
  std::normal_distribution<double> nd;
  std::vector<double> c(sh_count(L));
  for (auto& v : c) v = nd(rng);
  return c;
}

// Gauss grid nlat = L, nphi = st.range(1) (0: 2L), one thread; into caller-provided arrays
// (as SHTns's interface), the grid and its set-up made once (as SHTns's shtns_set_grid),
// with a first transform before the timed ones (it completes the set-up).
void BM_libsh_Analysis(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0)), nphi = st.range(1) ? static_cast<int>(st.range(1)) : 2 * L;
  const GaussGrid g = gauss_grid(L, L, nphi);
  const auto c = random_coeffs(L);
  const auto f = synthesise(g, c.data());
  std::vector<double> out(c.size());
  for (auto _ : st) {
    analyse(g, f.data(), out.data(), 1);
    benchmark::DoNotOptimize(out.data());
  }
}
void BM_libsh_Synthesis(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0)), nphi = st.range(1) ? static_cast<int>(st.range(1)) : 2 * L;
  const GaussGrid g = gauss_grid(L, L, nphi);
  const auto c = random_coeffs(L);
  std::vector<double> out(static_cast<std::size_t>(g.nlat) * g.nphi);
  synthesise(g, c.data(), out.data(), 1);  // the plan's polar starts (found by the first transform)
  for (auto _ : st) {
    synthesise(g, c.data(), out.data(), 1);
    benchmark::DoNotOptimize(out.data());
  }
}
// Rotation of L bands with no reserved cache (z-y-z Euler angles 0.3, 1.9, 2.5).
void BM_libsh_RotationApply(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0));
  const Rotation R(L, EulerZYZ{0.3, 1.9, 2.5});
  const auto in = random_coeffs(L);
  std::vector<double> out(in.size());
  for (auto _ : st) {
    R.apply(in.data(), out.data());
    benchmark::DoNotOptimize(out.data());
  }
}

#if ATMOSH_HAVE_SHTNS
// layout: SHT_NATIVE_LAYOUT (SHTns's own: samples latitude-contiguous, v[j * nlat + i], the
// layout its FFTs are fastest in) or SHT_PHI_CONTIGUOUS (v[i * nphi + j], ring 0 nearest +z:
// the same array as libsh's grid, equirect images and (lat, lon) arrays; checked to give libsh's
// coefficients, up to SHTns's complex convention, to ~1e-15).
struct Shtns {
  shtns_cfg cfg;
  double* v;
  cplx* q;
  Shtns(int L, int nphi, int layout) {
    shtns_use_threads(1);
    cfg = shtns_create(L - 1, L - 1, 1, sht_orthonormal);
    shtns_set_grid(cfg, static_cast<shtns_type>(sht_gauss | layout), 1.e-10, L, nphi);
    v = static_cast<double*>(fftw_malloc(sizeof(double) * L * nphi));
    q = static_cast<cplx*>(fftw_malloc(sizeof(cplx) * cfg->nlm));
    std::mt19937_64 rng(27);
    std::normal_distribution<double> nd;
    for (unsigned i = 0; i < cfg->nlm; ++i) q[i] = cplx(nd(rng), cfg->mi[i] ? nd(rng) : 0.0);
    SH_to_spat(cfg, q, v);
  }
  ~Shtns() {
    fftw_free(v);
    fftw_free(q);
    shtns_destroy(cfg);
  }
};
// SHTns's set-up (its own FFTW planning and choice of algorithm by timing) is slow: one per
// size for the whole run, kept until exit.
Shtns& shtns_for(int L, int nphi, int layout) {
  static std::map<std::tuple<int, int, int>, std::unique_ptr<Shtns>> made;
  auto& p = made[{L, nphi, layout}];
  if (!p) p = std::make_unique<Shtns>(L, nphi, layout);
  return *p;
}
template <int Layout>
void shtns_analysis(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0)), nphi = st.range(1) ? static_cast<int>(st.range(1)) : 2 * L;
  Shtns& s = shtns_for(L, nphi, Layout);
  for (auto _ : st) {
    spat_to_SH(s.cfg, s.v, s.q);
    benchmark::DoNotOptimize(s.q);
  }
}
template <int Layout>
void shtns_synthesis(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0)), nphi = st.range(1) ? static_cast<int>(st.range(1)) : 2 * L;
  Shtns& s = shtns_for(L, nphi, Layout);
  for (auto _ : st) {
    SH_to_spat(s.cfg, s.q, s.v);
    benchmark::DoNotOptimize(s.v);
  }
}
void BM_shtns_Analysis(benchmark::State& st) { shtns_analysis<SHT_NATIVE_LAYOUT>(st); }
void BM_shtns_Synthesis(benchmark::State& st) { shtns_synthesis<SHT_NATIVE_LAYOUT>(st); }
// the same sample array as libsh (rings contiguous)
void BM_shtns_AnalysisRings(benchmark::State& st) { shtns_analysis<SHT_PHI_CONTIGUOUS>(st); }
void BM_shtns_SynthesisRings(benchmark::State& st) { shtns_synthesis<SHT_PHI_CONTIGUOUS>(st); }
void BM_shtns_RotationApply(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0));
  shtns_rot rot = shtns_rotation_create(L - 1, L - 1, sht_orthonormal);
  shtns_rotation_set_angles_ZYZ(rot, 0.3, 1.9, 2.5);
  const long nlm = nlm_calc(L - 1, L - 1, 1);
  std::vector<cplx> q(nlm, cplx(0.5, 0.25)), rq(nlm);
  for (auto _ : st) {
    shtns_rotation_apply_real(rot, q.data(), rq.data());
    benchmark::DoNotOptimize(rq.data());
  }
  shtns_rotation_destroy(rot);
}
// the same sizes as libsh's below: nphi other than a power of two go through FFTW's own
// plans of those sizes in SHTns
BENCHMARK(BM_shtns_Analysis)
    ->Args({256, 0})->Args({256, 511})->Args({256, 525})->Args({256, 768})->Args({1024, 0})->Args({1024, 2047})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_shtns_Synthesis)
    ->Args({256, 0})->Args({256, 511})->Args({256, 525})->Args({256, 768})->Args({1024, 0})->Args({1024, 2047})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_shtns_AnalysisRings)->Args({256, 0})->Args({256, 768})->Args({1024, 0})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_shtns_SynthesisRings)->Args({256, 0})->Args({256, 768})->Args({1024, 0})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_shtns_RotationApply)->Arg(1000)->Unit(benchmark::kMillisecond)->Iterations(3);
#endif
}  // namespace

BENCHMARK(BM_libsh_Analysis)
    ->Args({256, 0})->Args({256, 511})->Args({256, 525})->Args({256, 768})->Args({1024, 0})->Args({1024, 2047})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_libsh_Synthesis)
    ->Args({256, 0})->Args({256, 511})->Args({256, 525})->Args({256, 768})->Args({1024, 0})->Args({1024, 2047})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_libsh_RotationApply)->Arg(1000)->Unit(benchmark::kMillisecond)->Iterations(3);
