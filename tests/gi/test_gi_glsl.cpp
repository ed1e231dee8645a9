// The shared radiosity math (atmosh/gi/shared/radiosity.glsl.hpp) compiled as GLSL by the
// driver (Mesa llvmpipe here, any EGL device) and run in a compute shader against the C++
// build of the same block: the SH evaluation, the SH irradiance and the bounce walk between
// two plates (the closed-form context of test_gi_radiosity.cpp) agree within float
// tolerance. Skipped where no EGL context can be made.
#ifdef ATMOSH_GI_HAVE_GPU
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <numbers>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "atmosh/gi/lpv.hpp"
#include "atmosh/gi/radiosity.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/gi/shared/radiosity.glsl.hpp"
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/program.hpp"

namespace glsl_walk {
// Two plates z = 0 and z = H, uniform direct irradiance E, reflectivity rho (the CPU side).
struct Plates {
  double H, E, rho;
};
inline double gi_fetch_distance(const Plates& c, const glm::dvec3& p, const glm::dvec3& d) {
  if (d.z > 1e-6) return (c.H - p.z) / d.z;
  if (d.z < -1e-6) return -p.z / d.z;
  return 1e9;
}
inline glm::dvec3 gi_fetch_normal(const Plates&, const glm::dvec3& q) { return {0, 0, q.z > 0.5 ? -1.0 : 1.0}; }
inline glm::dvec3 gi_fetch_albedo(const Plates& c, const glm::dvec3&) { return glm::dvec3(c.rho); }
inline glm::dvec3 gi_direct_irradiance(const Plates& c, const glm::dvec3&, const glm::dvec3&) { return glm::dvec3(c.E); }
// The same plates with every fetched distance 1e-9 too long: each step lands just beyond the
// plate it hits, as a float walk's rounding may put it (outside the box by a few ulps).
struct OvershootPlates {
  Plates p;
};
inline double gi_fetch_distance(const OvershootPlates& c, const glm::dvec3& p, const glm::dvec3& d) {
  return gi_fetch_distance(c.p, p, d) * (1 + 1e-9);
}
inline glm::dvec3 gi_fetch_normal(const OvershootPlates& c, const glm::dvec3& q) { return gi_fetch_normal(c.p, q); }
inline glm::dvec3 gi_fetch_albedo(const OvershootPlates& c, const glm::dvec3& q) { return gi_fetch_albedo(c.p, q); }
inline glm::dvec3 gi_direct_irradiance(const OvershootPlates& c, const glm::dvec3& q, const glm::dvec3& n) {
  return gi_direct_irradiance(c.p, q, n);
}
}  // namespace glsl_walk

namespace {
using namespace atmosh;

// The block between the markers with "glm::" deleted (what cmake/AtmoshEmbedGlsl.cmake
// embeds for the libatmo headers), with its first line.
gpu::ShaderPart shared_block(const std::string& rel) {
  std::ifstream f(std::string(ATMOSH_SOURCE_DIR) + "/" + rel);
  std::string line, text;
  int n = 0, first = 0;
  bool in = false;
  while (std::getline(f, line)) {
    ++n;
    if (line.find("// ATMOSH_GLSL_BEGIN") != std::string::npos) {
      in = true;
      first = n + 1;
      continue;
    }
    if (line.find("// ATMOSH_GLSL_END") != std::string::npos) break;
    if (!in) continue;
    for (auto p = line.find("glm::"); p != std::string::npos; p = line.find("glm::")) line.erase(p, 5);
    text += line + "\n";
  }
  return {rel, first, text};
}

constexpr const char* kPrelude = R"glsl(
#define ATMOSH_GI_TEMPLATE
#define ATMOSH_GI_CTX
#define ATMOSH_GI_CTX_ARG
uniform float plate_h;
uniform float plate_e;
uniform float plate_rho;
float gi_fetch_distance(vec3 p, vec3 d) {
  if (d.z > 1e-6) return (plate_h - p.z) / d.z;
  if (d.z < -1e-6) return -p.z / d.z;
  return 1e9;
}
vec3 gi_fetch_normal(vec3 q) { return vec3(0.0, 0.0, q.z > 0.5 ? -1.0 : 1.0); }
vec3 gi_fetch_albedo(vec3 q) { return vec3(plate_rho); }
vec3 gi_direct_irradiance(vec3 q, vec3 n) { return vec3(plate_e); }
)glsl";

constexpr const char* kMain = R"glsl(
layout(local_size_x = 64) in;
struct Case { float c[9]; float dx, dy, dz; float bounces; float pad[3]; };
layout(std430, binding = 0) readonly buffer In { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Out { float result[]; };
uniform int n_cases;
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= n_cases) return;
  float c[9];
  for (int k = 0; k < 9; ++k) c[k] = cases[i].c[k];
  vec3 d = normalize(vec3(cases[i].dx, cases[i].dy, cases[i].dz));
  for (int b = 1; b <= 3; ++b) {
    result[i * 8 + b - 1] = gi_sh_eval(c, b, d);
    result[i * 8 + 2 + b] = gi_sh_irradiance(c, b, d);
  }
  vec3 up = vec3(d.x, d.y, abs(d.z) + 0.2);
  vec3 L = gi_radiosity_incident(vec3(0.1, 0.2, 0.0), normalize(up), int(cases[i].bounces),
                                 vec3(-10.0, -10.0, 0.0), vec3(10.0, 10.0, 1.0));
  result[i * 8 + 6] = L.x;
  result[i * 8 + 7] = 0.0;
}
)glsl";

TEST(GiGlsl, SharedRadiosityMathAgreesWithTheCppBuild) {
  std::unique_ptr<gpu::Context> ctx;
  try {
    ctx = std::make_unique<gpu::Context>();
  } catch (const gpu::Unavailable& e) {
    GTEST_SKIP() << e.what();
  }
  const gpu::ShaderPart block = shared_block("apps/gi/include/atmosh/gi/shared/radiosity.glsl.hpp");
  ASSERT_FALSE(block.text.empty());
  gpu::Program prog({{"tests/gi/test_gi_glsl.cpp (prelude)", 1, kPrelude}, block,
                     {"tests/gi/test_gi_glsl.cpp (main)", 1, kMain}});
  struct Case {
    float c[9];
    float dx, dy, dz, bounces, pad[3];
  };
  std::vector<Case> cases;
  for (int i = 0; i < 50; ++i) {
    Case k{};
    for (int j = 0; j < 9; ++j) k.c[j] = static_cast<float>(std::sin(1.7 * i + 0.9 * j) * (1 + j % 3));
    k.dx = static_cast<float>(std::cos(0.37 * i)), k.dy = static_cast<float>(std::sin(0.61 * i + 0.3)),
    k.dz = static_cast<float>(std::cos(0.23 * i + 1.1));
    k.bounces = static_cast<float>(i % 5);
    cases.push_back(k);
  }
  const int n = static_cast<int>(cases.size());
  gpu::Buffer bin(cases.size() * sizeof(Case), cases.data()), bout(static_cast<std::size_t>(n) * 8 * sizeof(float));
  bin.bind(0);
  bout.bind(1);
  prog.use();
  prog.set("n_cases", n);
  prog.set("plate_h", 1.0f);
  prog.set("plate_e", 2.0f);
  prog.set("plate_rho", 0.6f);
  prog.dispatch((n + 63) / 64);
  std::vector<float> out(static_cast<std::size_t>(n) * 8);
  bout.download(out.data(), out.size() * sizeof(float));
  const glsl_walk::Plates plates{1.0, 2.0, 0.6};
  for (int i = 0; i < n; ++i) {
    const Case& k = cases[static_cast<std::size_t>(i)];
    double c[9];
    for (int j = 0; j < 9; ++j) c[j] = k.c[j];
    const glm::dvec3 d = glm::normalize(glm::dvec3(k.dx, k.dy, k.dz));
    const float* o = &out[static_cast<std::size_t>(i) * 8];
    for (int b = 1; b <= 3; ++b) {
      // float: a few ulps of the terms' magnitudes (|c| <= 3, |Y| <= 1.1)
      EXPECT_NEAR(o[b - 1], gi::shared::gi_sh_eval(c, b, d), 2e-5) << "case " << i << " bands " << b;
      EXPECT_NEAR(o[2 + b], gi::shared::gi_sh_irradiance(c, b, d), 5e-5) << "case " << i << " bands " << b;
    }
    const glm::dvec3 up = glm::normalize(glm::dvec3(d.x, d.y, std::abs(d.z) + 0.2));
    const glm::dvec3 L = gi::shared::gi_radiosity_incident(plates, glm::dvec3(0.1, 0.2, 0.0), up,
                                                           static_cast<int>(k.bounces), glm::dvec3(-10, -10, 0),
                                                           glm::dvec3(10, 10, 1));
    EXPECT_NEAR(o[6], L.x, 1e-5 * (1 + L.x)) << "case " << i;
  }
}

// Between two parallel plates (z = 0 and z = H, the walk's box [-10, 10]^2 x [0, H]) with
// uniform direct irradiance E and reflectivity rho, the walk from the lower plate meets a plate
// at every bounce, so b bounces give the closed form L = E / pi (rho + rho^2 + ... + rho^b). A
// step that lands a rounding error beyond the plate (here 1e-9 of the step) must still count as
// inside the box: on an NVIDIA H200 the float walk of SharedRadiosityMathAgreesWithTheCppBuild
// stopped after its first bounce this way until gi_inside_box allowed a slack.
TEST(GiGlsl, WalkBetweenPlatesKeepsItsBouncesWhenAStepLandsJustOutside) {
  const glsl_walk::Plates plates{1.0, 2.0, 0.6};
  for (const glm::dvec3 n : {glm::dvec3(0, 0, 1), glm::normalize(glm::dvec3(0.3, -0.2, 1.0))}) {
    double closed = 0, rb = 1;
    for (int b = 1; b <= 6; ++b) {
      rb *= plates.rho;
      closed += plates.E / std::numbers::pi * rb;
      for (const bool overshoot : {false, true}) {
        const glm::dvec3 L =
            overshoot ? gi::shared::gi_radiosity_incident(glsl_walk::OvershootPlates{plates}, glm::dvec3(0.1, 0.2, 0.0), n,
                                                          b, glm::dvec3(-10, -10, 0), glm::dvec3(10, 10, 1))
                      : gi::shared::gi_radiosity_incident(plates, glm::dvec3(0.1, 0.2, 0.0), n, b,
                                                          glm::dvec3(-10, -10, 0), glm::dvec3(10, 10, 1));
        EXPECT_NEAR(L.x, closed, 1e-12) << "bounces " << b << (overshoot ? ", steps 1e-9 long" : "");
      }
    }
  }
}

// LPV propagation on the GPU (gpu/shaders/gi_lpv_propagate.comp, float) against the CPU's
// (double): the Cornell box's injected light, with the geometry volume, 16 iterations.
TEST(GiGlsl, LpvPropagationOnTheGpuAgreesWithTheCpu) {
  try {
    gpu::Context probe;
  } catch (const gpu::Unavailable& e) {
    GTEST_SKIP() << e.what();
  }
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::LpvOptions o;
  o.grid = 8;
  o.emitter_photons = 4096;
  const gi::LpvGrid inj = gi::lpv_inject(s, o);
  const gi::GeometryVolume gv = gi::lpv_geometry(s, inj);
  // without blocking the default re-emission; with blocking Kaplanyan & Dachsbacher 2010's
  // face-normal lobe (LpvReemission::face_lobe: the shader's uniform; no further compilation)
  for (const gi::GeometryVolume* g : {static_cast<const gi::GeometryVolume*>(nullptr), &gv}) {
    const gi::LpvReemission re = g != nullptr ? gi::LpvReemission::face_lobe : gi::LpvReemission::direction;
    const gi::LpvGrid cpu = gi::lpv_propagate(inj, g, 16, re);
    double secs = -1;
    const gi::LpvGrid gpu_grid = gi::lpv_propagate_gpu(inj, g, 16, &secs, re);
    EXPECT_GE(secs, 0.0);
    double scale = 0;
    for (const auto& c : cpu.cells)
      for (double v : c) scale = std::max(scale, std::abs(v));
    ASSERT_GT(scale, 0);
    double worst = 0;
    for (std::size_t i = 0; i < cpu.cells.size(); ++i)
      for (int q = 0; q < 12; ++q) worst = std::max(worst, std::abs(gpu_grid.cells[i][q] - cpu.cells[i][q]));
    // float storage, float face constants and sums over 16 iterations: measured 3.5e-5 of
    // the largest coefficient with blocking, below 1e-5 without
    EXPECT_LT(worst, 1e-4 * scale) << (g ? "with" : "without") << " blocking";
  }
}

// The radiosity walk as a GPU pass (gpu/shaders/gi_radiosity_shade.comp, float, the shared
// block pasted) against its CPU twin (double, the same block): the Cornell box's G-buffer,
// the volume at bands 1..3 and 0..4 bounces. The references are independent of the code
// under test only in precision; the walk's closed forms are tested in test_gi_radiosity.cpp.
TEST(GiGlsl, RadiosityPassOnTheGpuAgreesWithTheCpu) {
  try {
    gpu::Context probe;
  } catch (const gpu::Unavailable& e) {
    GTEST_SKIP() << e.what();
  }
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::RadiosityOptions o;
  o.grid = 6;
  o.bands = 3;
  o.cube_size = 6;
  gi::RadiosityVolume full = gi::build_radiosity_volume(s, o);
  gi::add_direct_volume(s, full, 16, 1, 7);
  const gi::RadiosityGBuffer g = gi::radiosity_gbuffer(s, s.camera, 48, 48, 1, 3);
  ASSERT_GT(g.receivers.size(), 1000u);
  double worst_all = 0;
  for (int bands = 1; bands <= 3; ++bands) {
    const gi::RadiosityVolume v = gi::truncate_volume(full, bands);
    gi::RadiosityVolume vd = v;
    vd.direct = full.direct;
    for (int B : {0, 1, 4}) {
      const auto cpu = gi::shade_receivers_cpu(vd, g.receivers, B);
      double secs = -1;
      const auto gpu_l = gi::shade_receivers_gpu(vd, g.receivers, B, &secs);
      EXPECT_GE(secs, 0.0);
      ASSERT_EQ(cpu.size(), gpu_l.size());
      double scale = 0;
      for (const auto& L : cpu) scale = std::max({scale, L.x, L.y, L.z});
      ASSERT_GT(scale, 0);
      // A walk is a chain of fetches, reflections and a box test: a vertex within float
      // rounding of the box's face or of the normal's 0.3 coherence threshold may go either
      // way, so count outliers and bound the rest.
      std::vector<double> rel;
      for (std::size_t i = 0; i < cpu.size(); ++i) {
        ASSERT_TRUE(std::isfinite(gpu_l[i].x + gpu_l[i].y + gpu_l[i].z)) << i;
        double d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(gpu_l[i][c] - cpu[i][c]));
        rel.push_back(d / scale);
      }
      std::sort(rel.begin(), rel.end());
      const double p999 = rel[rel.size() * 999 / 1000], worst = rel.back();
      worst_all = std::max(worst_all, worst);
      EXPECT_LT(p999, 2e-6) << "bands " << bands << " bounces " << B;
      EXPECT_LT(worst, 1e-5) << "bands " << bands << " bounces " << B;  // measured 3.3e-7
      if (B == 0) {
        EXPECT_LT(worst, 1e-6) << "bands " << bands;  // no walk: L_e + a / pi E_direct only
      }
    }
  }
  RecordProperty("worst_rel", std::to_string(worst_all));
  std::printf("radiosity GPU pass vs CPU: largest difference %.3g of the largest radiance\n", worst_all);
}

// Stiff inputs: a volume of huge distances and zero (incoherent) normals, receivers far
// outside the box, zero and huge direct light, albedo 1 and 16 bounces: finite everywhere,
// and equal to the CPU's (to float rounding up to 3 bounces, to 5 % at 16).
TEST(GiGlsl, RadiosityPassStiffCasesStayFinite) {
  try {
    gpu::Context probe;
  } catch (const gpu::Unavailable& e) {
    GTEST_SKIP() << e.what();
  }
  gi::RadiosityVolume v;
  v.lo = glm::dvec3(-1.0);
  v.hi = glm::dvec3(1.0);
  v.n = 3;
  v.bands = 2;
  const std::size_t np = 27;
  v.distance.assign(np, {});
  v.normal.assign(np, glm::dvec3(0.0));
  v.albedo.assign(np, glm::dvec3(1.0));
  v.direct.assign(np, {});
  for (std::size_t p = 0; p < np; ++p) {
    v.distance[p][0] = p % 3 == 0 ? 1e6 : 0.5;
    v.distance[p][2] = p % 2 == 0 ? -3.0 : 3.0;
    if (p % 4 == 1) v.normal[p] = glm::dvec3(0, 0, 0.9);
    for (int c = 0; c < 3; ++c) v.direct[p][static_cast<std::size_t>(c * 4)] = p % 5 == 0 ? 1e20 : 1.0;
  }
  gi::RadiosityReceivers r;
  const double xs[] = {0.0, 0.99, -5.0, 1e30, -1e-30};
  for (double x : xs)
    for (const glm::dvec3 n : {glm::dvec3(0, 0, 1), glm::dvec3(1, 0, 0), glm::normalize(glm::dvec3(1, -1, 1))}) {
      r.position.push_back({x, 0.1, -0.2});
      r.normal.push_back(n);
      r.albedo.push_back(glm::dvec3(1.0));
      r.emission.push_back(glm::dvec3(0.0));
      r.direct.push_back(glm::dvec3(x > 1 ? 1e20 : 0.0));
    }
  for (int B : {0, 3, 16}) {
    const auto cpu = gi::shade_receivers_cpu(v, r, B);
    const auto gpu_l = gi::shade_receivers_gpu(v, r, B);
    for (std::size_t i = 0; i < cpu.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(gpu_l[i][c])) << "receiver " << i << " bounces " << B;
        ASSERT_TRUE(std::isfinite(cpu[i][c])) << "receiver " << i << " bounces " << B;
        // 16 undamped bounces (albedo 1) through 1e20-scale light: a late vertex of a few walks
        // lands elsewhere in float (measured 2 % of the radiance); up to 3 bounces they agree
        EXPECT_NEAR(gpu_l[i][c], cpu[i][c], (B > 3 ? 5e-2 : 1e-5) * (1 + std::abs(cpu[i][c])))
            << "receiver " << i << " bounces " << B;
      }
  }
}

// LPV injection and geometry volume on the GPU (gi_lpv_inject.comp, gi_lpv_geometry.comp,
// float) against the CPU's (double), and the whole LPV (injection, geometry, propagation) on
// the GPU against the CPU's: the Cornell box (area light) and sphere-on-plane (sun), grid 8.
TEST(GiGlsl, LpvInjectionOnTheGpuAgreesWithTheCpu) {
  try {
    gpu::Context probe;
  } catch (const gpu::Unavailable& e) {
    GTEST_SKIP() << e.what();
  }
  auto worst_rel = [](const auto& a, const auto& b) {
    double scale = 0, worst = 0;
    for (const auto& c : a)
      for (double v : c) scale = std::max(scale, std::abs(v));
    for (std::size_t i = 0; i < a.size(); ++i)
      for (std::size_t q = 0; q < a[i].size(); ++q) worst = std::max(worst, std::abs(a[i][q] - b[i][q]));
    return scale > 0 ? worst / scale : -1.0;
  };
  for (const char* name : {"cornell-box", "sphere-on-plane"}) {
    gi::Scene s = gi::builtin_scene(name);
    if (!s.sun) s.sun = gi::Sun{glm::normalize(glm::dvec3(0.3, 0.4, 1.0)), glm::dvec3(2.0)};
    gi::LpvOptions o;
    o.grid = 8;
    o.emitter_photons = 8192;
    o.sun_rays = 4;
    std::uint64_t rc = 0, rg = 0;
    const gi::LpvGrid cpu = gi::lpv_inject(s, o, &rc);
    double secs = -1;
    // the ray-cast VPLs through the GPU's injection pass (lpv_inject_gpu takes the sun's from
    // a reflective shadow map instead: test_gi_raster.cpp)
    const std::vector<gi::Vpl> vpls = gi::lpv_vpls(s, o, gi::lpv_grid(s, o.grid), &rg);
    const gi::LpvGrid gpu_grid = gi::lpv_inject_vpls_gpu(gi::lpv_grid(s, o.grid), vpls, &secs);
    EXPECT_GE(secs, 0.0);
    EXPECT_EQ(rc, rg) << name;
    ASSERT_EQ(cpu.cells.size(), gpu_grid.cells.size());
    const double wi = worst_rel(cpu.cells, gpu_grid.cells);
    EXPECT_GE(wi, 0.0) << name << ": nothing injected";
    EXPECT_LT(wi, 1e-5) << name << " injection";  // measured 1.6e-6
    const gi::GeometryVolume gc = gi::lpv_geometry(s, cpu), gg = gi::lpv_geometry_gpu(s, cpu);
    const double wg = worst_rel(gc.corners, gg.corners);
    EXPECT_GE(wg, 0.0) << name;
    EXPECT_LT(wg, 3e-5) << name << " geometry";  // float sums of many surfels: measured 6.7e-6
    // the whole LPV on the GPU against the CPU's
    const gi::LpvGrid acc_c = gi::lpv_propagate(cpu, &gc, 16), acc_g = gi::lpv_propagate_gpu(gpu_grid, &gg, 16);
    const double wa = worst_rel(acc_c.cells, acc_g.cells);
    EXPECT_LT(wa, 1e-4) << name << " propagated";  // measured 3.4e-5
    std::printf("%s: LPV GPU vs CPU: injection %.3g, geometry %.3g, propagated %.3g of the largest coefficient\n", name,
                wi, wg, wa);
  }
}

// The LPV applied to the Cornell box's G-buffer on the GPU (gi_lpv_apply.comp, float, the
// shared gi_sh_irradiance) against the CPU twin (double).
TEST(GiGlsl, LpvApplyOnTheGpuAgreesWithTheCpu) {
  try {
    gpu::Context probe;
  } catch (const gpu::Unavailable& e) {
    GTEST_SKIP() << e.what();
  }
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::LpvOptions o;
  o.grid = 8;
  o.emitter_photons = 4096;
  const gi::Lpv l = gi::build_lpv(s, o);
  const gi::RadiosityGBuffer g = gi::radiosity_gbuffer(s, s.camera, 48, 48, 1, 3);
  ASSERT_GT(g.receivers.size(), 1000u);
  const auto cpu = gi::shade_lpv_receivers_cpu(l.accumulated, g.receivers);
  double secs = -1;
  const auto gpu_l = gi::shade_lpv_receivers_gpu(l.accumulated, g.receivers, &secs);
  EXPECT_GE(secs, 0.0);
  ASSERT_EQ(cpu.size(), gpu_l.size());
  // against the largest indirect radiance (the LPV's part: L - L_e - a / pi E_direct), the
  // emitter's and the direct light's radiance being far larger
  double scale = 0, worst = 0;
  for (std::size_t i = 0; i < cpu.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(gpu_l[i][c]));
      scale = std::max(scale, cpu[i][c] - g.receivers.emission[i][c] -
                                  g.receivers.albedo[i][c] / 3.14159265358979324 * g.receivers.direct[i][c]);
      worst = std::max(worst, std::abs(gpu_l[i][c] - cpu[i][c]));
    }
  ASSERT_GT(scale, 0) << "the LPV adds light";
  EXPECT_LT(worst, 2e-5 * scale);  // measured 2.2e-6 (float rounding of the direct term included)
  std::printf("LPV apply GPU vs CPU: largest difference %.3g of the largest indirect radiance\n", worst / scale);
}

}  // namespace
#endif  // ATMOSH_GI_HAVE_GPU
