// Benchmarks of atmosh::sh (targets in docs/sh.md; run: build/bin/bench_sh).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/fast.hpp"
#include "atmosh/sh/projection.hpp"
#include "atmosh/sh/rotation.hpp"
#include "atmosh/sh/transform.hpp"

using namespace atmosh::sh;

namespace {
template <class T>
struct Dirs {
  std::vector<T> x, y, z;
  explicit Dirs(std::size_t n) {
    std::mt19937_64 rng(1);
    std::normal_distribution<double> nd;
    for (std::size_t i = 0; i < n; ++i) {
      const glm::dvec3 d = glm::normalize(glm::dvec3(nd(rng), nd(rng), nd(rng)));
      x.push_back(T(d.x));
      y.push_back(T(d.y));
      z.push_back(T(d.z));
    }
  }
};

// Output buffer starting `offset` values past a 64-byte boundary (0: aligned). Where
// a plain std::vector happens to start decides whether 64-byte stores straddle cache
// lines, which changes the batch kernels' speed by up to 2x: the benchmarks fix it.
template <class T>
struct Out {
  std::vector<T> buf;
  T* p;
  Out(std::size_t n, std::size_t offset) : buf(n + 64 / sizeof(T) + offset) {
    p = buf.data();
    while (reinterpret_cast<std::uintptr_t>(p) % 64) ++p;
    p += offset;
  }
};

// Output of one call: L^2 * n values, coefficient-major, rows 64-byte aligned (third
// argument 0) or starting one value past (1: the kernel's first directions go one by
// one until its stores are aligned). At n = 256 and L = 4 that is 16 KiB (float) and
// stays in L1; at n = 1024 it is 64 KiB and the loop is bound by stores to L2.
template <class T>
void BM_EvalFastBatch(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0));
  const std::size_t n = static_cast<std::size_t>(st.range(1));
  Dirs<T> d(n);
  // stride padded off a multiple of 4 KiB: equal-offset streams would alias in L1
  const std::size_t stride = n + 16;
  Out<T> out(static_cast<std::size_t>(L) * L * stride, static_cast<std::size_t>(st.range(2)));
  for (auto _ : st) {
    evaluate_fast_batch(L, n, d.x.data(), d.y.data(), d.z.data(), out.p, stride);
    benchmark::DoNotOptimize(out.p);
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(st.iterations() * n);  // directions
}

// The generated per-direction loop inlined into the caller (the batch path before the
// compiled kernel), for comparison.
template <class T>
void BM_EvalFastBatchInline(benchmark::State& st) {
  const std::size_t n = static_cast<std::size_t>(st.range(1));
  Dirs<T> d(n);
  const std::size_t stride = n + 16;
  std::vector<T> out(16 * stride);
  for (auto _ : st) {
    generated::eval_batch_4(n, d.x.data(), d.y.data(), d.z.data(), out.data(), stride);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(st.iterations() * n);
}

void BM_EvalGeneral(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0));
  Dirs<double> d(256);
  std::vector<double> out(sh_count(L));
  std::size_t k = 0;
  for (auto _ : st) {
    evaluate(L, {d.x[k], d.y[k], d.z[k]}, out.data());
    benchmark::DoNotOptimize(out.data());
    k = (k + 1) & 255;
  }
  st.SetItemsProcessed(st.iterations());
}

// sum_i c_i Y_i(d) at one direction (reconstruct): L <= 8 on the straight-line code and
// the stack, above through a per-thread buffer.
void BM_Reconstruct(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0));
  Dirs<double> d(256);
  std::vector<double> c(sh_count(L), 0.5);
  std::size_t k = 0;
  double s = 0;
  for (auto _ : st) {
    s += reconstruct(L, c.data(), {d.x[k], d.y[k], d.z[k]});
    k = (k + 1) & 255;
  }
  benchmark::DoNotOptimize(s);
  st.SetItemsProcessed(st.iterations());
}

// n directions at once (general path, recurrence vectorised across directions), per
// direction. Output L^2 * n doubles, coefficient-major, stride padded by 16, rows
// 64-byte aligned (third argument 0) or one value past (1).
// Template argument: double, or float (the recurrence in single precision).
template <class T>
void BM_EvalBatch(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0));
  const std::size_t n = static_cast<std::size_t>(st.range(1));
  Dirs<T> d(n);
  const std::size_t stride = n + 16;
  Out<T> out(static_cast<std::size_t>(L) * L * stride, static_cast<std::size_t>(st.range(2)));
  for (auto _ : st) {
    evaluate_batch(L, n, d.x.data(), d.y.data(), d.z.data(), out.p, stride);
    benchmark::DoNotOptimize(out.p);
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(st.iterations() * n);
}

void BM_EvalGeneralFloat(benchmark::State& st) {
  // general path in double, converted to float (the float use of high bands)
  const int L = static_cast<int>(st.range(0));
  Dirs<double> d(256);
  std::vector<double> out(sh_count(L));
  std::vector<float> outf(sh_count(L));
  std::size_t k = 0;
  for (auto _ : st) {
    evaluate(L, {d.x[k], d.y[k], d.z[k]}, out.data());
    for (int i = 0; i < sh_count(L); ++i) outf[i] = static_cast<float>(out[i]);
    benchmark::DoNotOptimize(outf.data());
    k = (k + 1) & 255;
  }
  st.SetItemsProcessed(st.iterations());
}

void BM_CubeProject(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0)), N = 256;
  CubeMap cube;
  cube.size = N;
  cube.channels = 1;
  for (auto& f : cube.faces) f.assign(N * N, 1.0f);
  for (auto _ : st) benchmark::DoNotOptimize(project_cube(cube, L));
  st.SetItemsProcessed(st.iterations() * 6 * N * N);
}

void BM_RotationBuild(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0));
  Rotation warm(L, EulerZYZ{0.1, 0.2, 0.3});  // fills the Ry(90) cache once
  for (auto _ : st) benchmark::DoNotOptimize(Rotation(L, EulerZYZ{0.3, 1.9, 2.5}));
}

void BM_RotationApply(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0));
  const Rotation R(L, EulerZYZ{0.3, 1.9, 2.5});
  std::vector<double> in(sh_count(L), 0.5), out(sh_count(L));
  R.apply(in.data(), out.data());
  for (auto _ : st) {
    R.apply(in.data(), out.data());
    benchmark::DoNotOptimize(out.data());
  }
}

// Arguments: bands, threads, nphi (0: the default power of two >= 2L - 1).
// Bands from 256 on apply Ry(90) on the fly in every application (no stored matrices);
// second argument 1: reserve_rotation_cache(L) first (it now keeps only bands < 256).
void BM_RotationApplyHigh(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0));
  if (st.range(1)) reserve_rotation_cache(L);
  const Rotation R(L, EulerZYZ{0.3, 1.9, 2.5});
  std::vector<double> in(sh_count(L), 0.5), out(sh_count(L));
  for (auto _ : st) {
    R.apply(in.data(), out.data());
    benchmark::DoNotOptimize(out.data());
  }
}

// One band matrix (band L - 1) of a rotation.
void BM_RotationBandMatrix(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0));
  const Rotation R(L, EulerZYZ{0.3, 1.9, 2.5});
  for (auto _ : st) benchmark::DoNotOptimize(R.band_matrix(L - 1));
}

// Arguments: bands, threads, nphi (0: the default), and (optional) 1: FftPlanning::measure.
void BM_Analysis(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0)), threads = static_cast<int>(st.range(1));
  GaussGrid g = gauss_grid(L, 0, static_cast<int>(st.range(2)));
  if (st.range(3)) g.fft = FftPlanning::measure;
  std::vector<double> c(sh_count(L), 0.01);
  const auto f = synthesise(g, c.data());
  for (auto _ : st) benchmark::DoNotOptimize(analyse(g, f.data(), threads));
}

void BM_Synthesis(benchmark::State& st) {
  const int L = static_cast<int>(st.range(0)), threads = static_cast<int>(st.range(1));
  GaussGrid g = gauss_grid(L, 0, static_cast<int>(st.range(2)));
  if (st.range(3)) g.fft = FftPlanning::measure;
  std::vector<double> c(sh_count(L), 0.01);
  benchmark::DoNotOptimize(synthesise(g, c.data(), threads));  // plans and polar starts
  for (auto _ : st) benchmark::DoNotOptimize(synthesise(g, c.data(), threads));
}
}  // namespace

BENCHMARK_TEMPLATE(BM_EvalFastBatch, float)->ArgsProduct({{2, 4, 8}, {256, 1024}, {0}})->Args({4, 256, 1});
BENCHMARK_TEMPLATE(BM_EvalFastBatch, double)->ArgsProduct({{2, 4, 8}, {256, 1024}, {0}})->Args({4, 256, 1});
BENCHMARK_TEMPLATE(BM_EvalFastBatchInline, float)->Args({4, 256})->Args({4, 1024});
BENCHMARK(BM_EvalGeneral)->Arg(2)->Arg(4)->Arg(8)->Arg(16)->Arg(64);
BENCHMARK(BM_Reconstruct)->Arg(4)->Arg(8)->Arg(16);
BENCHMARK_TEMPLATE(BM_EvalBatch, double)->ArgsProduct({{4, 8, 16, 64}, {8, 32, 64, 256}, {0}})->Args({16, 8, 1})->Args({16, 256, 1});
BENCHMARK_TEMPLATE(BM_EvalBatch, float)->ArgsProduct({{4, 8, 16, 64}, {16, 64, 256}, {0}})->Args({16, 16, 1})->Args({16, 256, 1});
BENCHMARK(BM_EvalGeneralFloat)->Arg(16)->Arg(64);
BENCHMARK(BM_CubeProject)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RotationBuild)->Arg(4)->Arg(16)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RotationApply)->Arg(4)->Arg(16)->Arg(64)->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RotationApplyHigh)->Args({512, 0})->Args({1000, 0})->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_RotationBandMatrix)->Arg(64)->Arg(256)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Analysis)
    ->Args({256, 1, 0, 0})->Args({256, 1, 511, 0})->Args({256, 1, 768, 0})->Args({256, 2, 0, 0})
    ->Args({1024, 1, 0, 0})->Args({1024, 1, 2047, 0})->Args({1024, 1, 3072, 0})->Args({1024, 2, 0, 0})
    ->Args({256, 1, 0, 1})->Args({256, 1, 511, 1})->Args({256, 1, 768, 1})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Synthesis)
    ->Args({256, 1, 0, 0})->Args({256, 1, 511, 0})->Args({256, 1, 768, 0})->Args({1024, 1, 0, 0})
    ->Args({1024, 1, 2047, 0})->Args({256, 1, 0, 1})->Args({256, 1, 511, 1})->Args({256, 1, 768, 1})
    ->Unit(benchmark::kMillisecond);
