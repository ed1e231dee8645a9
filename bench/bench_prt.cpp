// Benchmarks of the PRT bake (docs/prt.md; run: build/bin/bench_prt).
// Goal: the shadowed per-vertex bake (a mesh of >= 100k vertices) reaches >= 50% of
// Embree's own occlusion-ray throughput on the same rays and the same threads.
#include <benchmark/benchmark.h>

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <vector>

#include <glm/geometric.hpp>

#include "atmosh/parallel.hpp"
#include "atmosh/prt/bake.hpp"
#include "atmosh/sh/prt.hpp"

using namespace atmosh;

namespace {
// Torus 448 x 224 = 100352 vertices.
const prt::Mesh& big_mesh() {
  static const prt::Mesh m = prt::builtin_scene("torus", 224);
  return m;
}
constexpr int kStrata = 10;  // 100 directions per vertex keeps one bake near a second
int threads() { return atmosh::available_cpus(); }  // the CPUs this process may use

void BM_BakeShadowed(benchmark::State& state) {
  const prt::Mesh& m = big_mesh();
  prt::BakeOptions o;
  o.bands = static_cast<int>(state.range(0));
  o.strata = kStrata;
  o.threads = threads();
  std::uint64_t rays = 0;
  double secs = 0;
  for (auto _ : state) {
    const auto t = prt::bake(m, o);
    rays += t.rays;
    secs += t.ray_seconds;
    benchmark::DoNotOptimize(t.coeffs.data());
  }
  state.counters["vertices"] = static_cast<double>(m.vertex_count());
  state.counters["rays_per_s"] = static_cast<double>(rays) / secs;
}
BENCHMARK(BM_BakeShadowed)->Arg(3)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();

// Embree alone: the same scene, the same rays (vertex origins offset along the normal,
// the sample directions above the tangent plane), rtcOccluded1 or rtcOccluded16, same threads.
template <int Packet>
void BM_EmbreeOccluded(benchmark::State& state) {
  const prt::Mesh& m = big_mesh();
  const auto samples = sh::prt::jittered_samples(1, kStrata, 1);
  RTCDevice dev = rtcNewDevice("verbose=0");
  RTCScene sc = rtcNewScene(dev);
  rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, m.positions.size()));
  auto* ib = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, m.triangles.size()));
  for (std::size_t i = 0; i < m.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) vb[3 * i + k] = static_cast<float>(m.positions[i][k]);
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) ib[3 * i + k] = m.triangles[i][k];
  rtcCommitGeometry(g);
  rtcAttachGeometry(sc, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(sc);
  const double eps = 1e-4 * prt::bounding_diagonal(m);
  std::uint64_t rays_total = 0;
  for (auto _ : state) {
    std::atomic<std::uint64_t> rays{0}, free{0};
    // Blocks of 16 vertices from the toolkit's parallel loop, as prt::bake takes them.
    auto make_context = [] {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      return ctx;
    };
    auto work = [&](RTCIntersectContext& ctx, std::size_t v0, std::size_t v1) {
      std::uint64_t nr = 0, nf = 0;
      for (std::size_t v = v0; v < v1; ++v) {
        const glm::dvec3 n = m.normals[v], o = m.positions[v] + eps * n;
        if constexpr (Packet == 1) {
          for (const auto& d : samples.dirs) {
            if (glm::dot(n, d) <= 0) continue;
            RTCRay r{static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z), static_cast<float>(eps),
                     static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z), 0.f, 1e30f, 0xffffffffu, 0, 0};
            rtcOccluded1(sc, &ctx, &r);
            ++nr;
            nf += r.tfar >= 0;
          }
        } else {
          alignas(64) RTCRay16 r;
          alignas(64) int valid[16];
          int k = 0;
          auto flush = [&] {
            for (int i = k; i < 16; ++i) valid[i] = 0;
            rtcOccluded16(valid, sc, &ctx, &r);
            for (int i = 0; i < k; ++i) nf += r.tfar[i] >= 0;
            nr += k;
            k = 0;
          };
          for (const auto& d : samples.dirs) {
            if (glm::dot(n, d) <= 0) continue;
            r.org_x[k] = static_cast<float>(o.x), r.org_y[k] = static_cast<float>(o.y), r.org_z[k] = static_cast<float>(o.z);
            r.dir_x[k] = static_cast<float>(d.x), r.dir_y[k] = static_cast<float>(d.y), r.dir_z[k] = static_cast<float>(d.z);
            r.tnear[k] = static_cast<float>(eps), r.tfar[k] = 1e30f, r.time[k] = 0, r.mask[k] = 0xffffffffu;
            r.id[k] = 0, r.flags[k] = 0;
            valid[k] = -1;
            if (++k == 16) flush();
          }
          if (k) flush();
        }
      }
      rays += nr;
      free += nf;
    };
    parallel_for_ranges_local(m.vertex_count(), 16, threads(), make_context, work);
    rays_total += rays.load();
    benchmark::DoNotOptimize(free.load());
  }
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(rays_total), benchmark::Counter::kIsRate);
  rtcReleaseScene(sc);
  rtcReleaseDevice(dev);
}
BENCHMARK(BM_EmbreeOccluded<1>)->Name("BM_EmbreeOccluded1")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EmbreeOccluded<16>)->Name("BM_EmbreeOccluded16")->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Interreflect(benchmark::State& state) {
  const prt::Mesh m = prt::builtin_scene("box-occluder", 64);
  prt::BakeOptions o;
  o.bands = 3;
  o.strata = 20;
  o.mode = sh::prt::TransferMode::interreflected;
  o.bounces = static_cast<int>(state.range(0));
  o.threads = threads();
  for (auto _ : state) benchmark::DoNotOptimize(prt::bake(m, o).coeffs.data());
  state.counters["vertices"] = static_cast<double>(m.vertex_count());
}
BENCHMARK(BM_Interreflect)->Arg(0)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();

// Per-pixel transfer, 256 x 256 pixels of the 100k-vertex torus, 100 directions:
// the GPU depth-map method (time per sample direction: one depth map of
// range(1)^2 texels + the accumulation pass) against CPU ray casting (range(0): 0 = CPU,
// 1 = GPU). Skipped when no EGL device exists.
void BM_PixelTransfer(benchmark::State& state) {
  const prt::Mesh& m = big_mesh();
  prt::BakeOptions o;
  o.bands = 4;
  o.strata = kStrata;
  o.threads = threads();
  o.device = state.range(0) == 0 ? prt::Device::cpu : prt::Device::gpu;
  o.depth_resolution = static_cast<int>(state.range(1));
  double per_dir = 0;
  try {
    for (auto _ : state) {
      const auto px = prt::bake_pixels(m, o, 256, 256, {1, -1.6, 1.1});
      per_dir += px.device == prt::Device::gpu ? px.seconds_per_direction : px.ray_seconds / px.samples;
      benchmark::DoNotOptimize(px.coeffs.data());
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  state.counters["ms_per_direction"] = 1e3 * per_dir / static_cast<double>(state.iterations());
}
BENCHMARK(BM_PixelTransfer)
    ->Args({0, 0})
    ->Args({1, 512})
    ->Args({1, 2048})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);
}  // namespace
