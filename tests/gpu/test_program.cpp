// GLSL assembly from the shared C++/GLSL headers: driver messages map back to
// the shared source's file and line, and the GLSL (float) build of the shared
// functions agrees with the C++ (double) build to float precision.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/shared/lut.glsl.hpp"
#include "atmosh/atmo/shared/view_ray.glsl.hpp"
#include "atmosh/gpu/program.hpp"
#include "atmosh/gpu/sky.hpp"
#include "gpu_fixture.hpp"

namespace gpu = atmosh::gpu;
namespace sg = atmosh::atmo::shared;

namespace {
// The source tree (tests/CMakeLists.txt defines it: __FILE__ is not reliably absolute,
// a compiler cache may hand the compiler relative paths).
std::string source_root() { return std::string(ATMOSH_SOURCE_DIR) + "/"; }
const std::string kGeometry = "libatmo/include/atmosh/atmo/shared/geometry.glsl.hpp";

// Line (1-based) of the first line of `path` (in the source tree) that contains `needle`.
int line_of(const std::string& path, const std::string& needle) {
  std::ifstream in(source_root() + path);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    if (line.find(needle) != std::string::npos) return n;
  return -1;
}
}  // namespace

TEST(GpuProgram, EmbedsTheSharedBlockWithoutGlmQualifiers) {
  const auto part = gpu::embedded_source(kGeometry);
  EXPECT_EQ(part.text.find("glm::"), std::string::npos);
  EXPECT_EQ(part.text.find("ATMOSH_GLSL_BEGIN"), std::string::npos);
  EXPECT_NE(part.text.find("ATMOSH_FN real radius_along("), std::string::npos);
  // first_line is the line right after the BEGIN marker in the real file.
  EXPECT_EQ(part.first_line, line_of(kGeometry, "// ATMOSH_GLSL_BEGIN") + 1);
  // The first taken line is the file's line first_line.
  std::istringstream t(part.text);
  std::string first;
  std::getline(t, first);
  std::ifstream in(source_root() + kGeometry);
  std::string line;
  for (int n = 1; std::getline(in, line) && n < part.first_line; ++n) {
  }
  EXPECT_EQ(first, line);
  EXPECT_THROW(gpu::embedded_source("no/such/file.glsl"), std::out_of_range);
}

TEST(GpuProgram, MapsMesaAndNvidiaLogLines) {
  const std::vector<gpu::ShaderPart> parts = {{"a/shared.glsl.hpp", 40, ""}, {"gpu/shaders/x.comp", 1, ""}};
  EXPECT_EQ(gpu::map_shader_log("0:7(12): error: syntax error", parts), "<preamble>:7:12: error: syntax error");
  EXPECT_EQ(gpu::map_shader_log("2:15(3): error: `foo' undeclared", parts),
            "gpu/shaders/x.comp:15:3: error: `foo' undeclared");
  EXPECT_EQ(gpu::map_shader_log("1(52) : error C1008: undefined variable \"q\"", parts),
            "a/shared.glsl.hpp:52: error C1008: undefined variable \"q\"");
  EXPECT_EQ(gpu::map_shader_log("plain text", parts), "plain text");
}

TEST(GpuProgram, CompileErrorNamesTheSharedFileAndLine) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  // A shared part with a deliberate error on its 3rd line, said to start at line 100
  // of a shared header; then the real geometry block and a driver part.
  const gpu::ShaderPart broken{"libatmo/include/atmosh/atmo/shared/broken.glsl.hpp", 100,
                               "ATMOSH_FN real fine(real x) { return x; }\n"
                               "\n"
                               "ATMOSH_FN real broken(real x) { return x + undeclared_name; }\n"};
  const gpu::ShaderPart main_part{"gpu/shaders/test_main.comp", 1,
                                  "layout(local_size_x = 1) in;\nvoid main() {}\n"};
  try {
    gpu::Program p({gpu::embedded_source(kGeometry), broken, main_part});
    FAIL() << "the broken shader compiled";
  } catch (const gpu::ShaderError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("libatmo/include/atmosh/atmo/shared/broken.glsl.hpp:102"), std::string::npos) << msg;
  }
  // An error inside the real shared header's block maps to its real line.
  const int target = line_of(kGeometry, "ATMOSH_FN real radius_along(");
  ASSERT_GT(target, 0);
  auto geo = gpu::embedded_source(kGeometry);
  geo.text.replace(geo.text.find("ATMOSH_FN real radius_along("), 0, "#error deliberate\n");
  // The inserted line takes radius_along's line number.
  try {
    gpu::Program p({geo, main_part});
    FAIL() << "the #error shader compiled";
  } catch (const gpu::ShaderError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(kGeometry + ":" + std::to_string(target)), std::string::npos) << msg;
  }
}

TEST(GpuProgram, SharedFunctionsAgreeWithTheCppBuild) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  gpu::Program prog({gpu::embedded_source(kGeometry),
                     gpu::embedded_source("libatmo/include/atmosh/atmo/shared/lut.glsl.hpp"),
                     gpu::embedded_source("gpu/shaders/shared_check.comp")});
  const double R = 6360e3, T = 6460e3;
  struct In {
    float r, mu, s, h, cos_theta, g, pad0, pad1;
  };
  std::vector<In> in;
  // Inputs exactly representable in float, so both builds see the same numbers.
  const float radii[] = {6360e3f, 6360010.f, 6361500.f, 6400e3f, 6459e3f};
  const float mus[] = {-1.f, -0.5f, -0.0625f, -0.0078125f, 0.f, 0.0078125f, 0.25f, 1.f};
  const float cs[] = {-1.f, -0.5f, 0.f, 0.875f, 0.9990234375f, 1.f};
  const float gs[] = {0.f, 0.75f, 0.9375f, -0.5f};
  int k = 0;
  for (float r : radii)
    for (float mu : mus) {
      const float c = cs[k % 6], g = gs[k % 4];
      in.push_back({r, mu, 12500.f * float(k % 5), 2000.f * float(k % 23), c, g, 0, 0});
      ++k;
    }
  const int n = static_cast<int>(in.size()), kOut = 16;
  gpu::Buffer bin(in.size() * sizeof(In), in.data()), bout(std::size_t(n) * kOut * sizeof(float));
  bin.bind(0);
  bout.bind(1);
  prog.set("n_cases", n);
  prog.set("ground_radius", float(R));
  prog.set("top_radius", float(T));
  prog.dispatch((n + 63) / 64);
  std::vector<float> out(std::size_t(n) * kOut);
  bout.download(out.data(), out.size() * sizeof(float));
  // Float tolerance: relative 1e-5 of the value (a few float ulps times the
  // condition number of the expression), absolute floor per quantity scale.
  auto expect_close = [&](double gpu_v, double cpu_v, double abs_floor, const char* what, int i) {
    EXPECT_LE(std::fabs(gpu_v - cpu_v), 1e-5 * std::fabs(cpu_v) + abs_floor)
        << what << " case " << i << ": gpu " << gpu_v << " cpu " << cpu_v;
  };
  int ramp_cases = 0;
  for (int i = 0; i < n; ++i) {
    const In& c = in[std::size_t(i)];
    const float* o = &out[std::size_t(i) * kOut];
    const double r = c.r, mu = c.mu, s = c.s;
    const double rs = sg::radius_along(r, mu, s);
    expect_close(o[0], rs, 1.0, "radius_along", i);  // float spacing at 6.4e6 m is 0.5 m
    expect_close(o[1], sg::distance_to_top(r, mu, T), 2.0, "distance_to_top", i);
    expect_close(o[2], sg::ray_hits_ground(r, mu, R) ? sg::distance_to_ground(r, mu, R) : -1.0, 2.0,
                 "distance_to_ground", i);
    expect_close(o[3], sg::mu_horizon(r, R), 1e-6, "mu_horizon", i);
    expect_close(o[4], sg::density_exponential(c.h, 8000.0), 1e-12, "density_exponential", i);
    expect_close(o[5], sg::density_tent(c.h, 10000.0, 25000.0, 40000.0), 1e-7, "density_tent", i);
    expect_close(o[6], sg::phase_rayleigh(c.cos_theta, 0.0279), 0.0, "phase_rayleigh", i);
    expect_close(o[7], sg::phase_hg(c.cos_theta, c.g), 0.0, "phase_hg", i);
    expect_close(o[8], sg::phase_cornette_shanks(c.cos_theta, c.g), 0.0, "phase_cornette_shanks", i);
    expect_close(o[9], sg::phase_double_hg(c.cos_theta, c.g, -0.3, 0.8), 0.0, "phase_double_hg", i);
    expect_close(o[10], sg::mu_along(r, mu, s, rs), 2e-6, "mu_along", i);
    expect_close(o[11], sg::tangent_radius_sq(r, mu) * 1e-12, 1e-6, "tangent_radius_sq", i);
    expect_close(o[12], sg::lut_x(s, 1000.0, 41000.0), 1e-7, "lut_x", i);
    const double p = 3.0 * (double(c.cos_theta) + 1.0) / 2.0;
    expect_close(o[13], sg::lagrange_cubic_weight(p, i % 4), 1e-6, "lagrange_cubic_weight", i);
    expect_close(o[14], sg::cos_zenith_along(r, c.g, c.cos_theta, s, rs), 2e-6, "cos_zenith_along", i);
    // The ramps' column: in float, k - r(u) carries the rounding of the radii (~0.5 m
    // at 6.4e6 m), ~1e-4 of k - r at a few km: 1e-3 of the column of |q| as the floor.
    const double ramp_r[2] = {R + 11000.0, R + 47000.0}, ramp_c[2] = {1.8e-9, -2.3e-12}, abs_c[2] = {1.8e-9, 2.3e-12};
    const double q = sg::quadratic_ramps_column(r, mu, s, ramp_r, ramp_c, 2);
    expect_close(o[15], q, 1e-3 * sg::quadratic_ramps_column(r, mu, s, ramp_r, abs_c, 2) + 1e-30,
                 "quadratic_ramps_column", i);
    ramp_cases += q != 0.0;
  }
  EXPECT_GE(ramp_cases, 10);  // rays inside the ramps, not only zeros
}

// The GLSL double build of the shared view-ray cuts (shared/view_ray.glsl.hpp,
// as assembled for the sky pass) against the C++ build: the same cut count and
// the same distances up to a few ulp of double (the bound, 1e-12 of the ray
// length, leaves room for a double sqrt that is not correctly rounded).
TEST(GpuProgram, ViewRayCutsAgreeWithTheCppBuild) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  gpu::Program prog(gpu::sky_parts("gpu/shaders/view_ray_check.comp"));
  const double R = 6371e3, T = R + 100e3;
  std::vector<double> radii;
  for (int i = 1; i < 16; ++i) radii.push_back(R + 100e3 * (i / 16.0) * (i / 16.0));
  std::vector<double> rays;
  for (double h : {0.0, 1500.0, 30e3, 100e3})
    for (double mu : {-1.0, -0.3, -0.02, -0.005, 0.0, 0.004, 0.3, 1.0})
      for (double mu_s : {0.2, -0.05, -0.2}) {
        const double r = R + h, nu = std::clamp(mu * mu_s + 0.6 * std::sqrt((1 - mu * mu) * (1 - mu_s * mu_s)), -1.0, 1.0);
        const double s_end = sg::ray_hits_ground(r, mu, R) ? sg::distance_to_ground(r, mu, R) : sg::distance_to_top(r, mu, T);
        if (!(s_end > 0)) continue;
        rays.insert(rays.end(), {r, mu, mu_s, nu, s_end});
      }
  const int n = int(rays.size() / 5), stride = sg::kMaxViewCuts + 1;
  gpu::Buffer bi(rays.size() * sizeof(double), rays.data()), br(radii.size() * sizeof(double), radii.data()),
      bo(std::size_t(n) * stride * sizeof(double));
  bi.bind(7);
  br.bind(8);
  bo.bind(9);
  prog.set("n_rays", n);
  prog.set("n_radii", int(radii.size()));
  prog.set_double("radius_R", R);
  prog.dispatch(unsigned(n + 63) / 64);
  std::vector<double> out(std::size_t(n) * stride);
  bo.download(out.data(), out.size() * sizeof(double));
  for (int i = 0; i < n; ++i) {
    const double* q = &rays[5 * std::size_t(i)];
    const sg::ViewRayCuts c = sg::view_ray_cuts(q[0], q[1], q[2], q[3], R, q[4], sg::tangent_radius_sq(q[0], q[1]),
                                                radii.data(), int(radii.size()));
    const double* g = &out[std::size_t(i) * stride];
    ASSERT_EQ(int(g[0]), c.n) << "ray " << i;
    for (int k = 0; k < c.n; ++k) EXPECT_NEAR(g[1 + k], c.s[k], 1e-12 * q[4]) << "ray " << i << " cut " << k;
  }
}

// The shared code keeps ray positions and cut radii in dynamically indexed local arrays of
// doubles (the cuts of a view ray, the sphere radii). It stores them packed, as uvec2
// (`real_array`, shared/view_ray.glsl.hpp), because a driver may not keep plain double
// arrays exact: NVIDIA's driver 580.159 (H200) rounds a dynamically indexed local double
// array and a struct member array of doubles to float (6 371 390.625 comes back as
// 6 371 390.5), while the packed form stays exact (docs/gpu.md, "On an NVIDIA GPU"). Values
// one float ulp apart (6 371 390.625 + k mm; float spacing there is 0.5 m) must come back
// bit for bit from the packed array on every driver; the two plain forms are reported, not
// required (Mesa llvmpipe keeps them exact).
TEST(GpuProgram, PackedLocalDoubleArraysKeepDoublePrecision) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  const char* src = R"(
layout(local_size_x = 1) in;
layout(std430, binding = 1) readonly buffer In { double xin[]; };
layout(std430, binding = 2) writeonly buffer Out { double o[]; };
uniform int n;
struct Cuts { double s[40]; int m; };
void main() {
  double a[64];
  Cuts c;
  uvec2 u[64];
  for (int k = 0; k < n; ++k) {
    a[k] = xin[k];
    c.s[k] = xin[k];
    u[k] = unpackDouble2x32(xin[k]);
  }
  for (int k = 0; k < n; ++k) {
    o[3 * k] = a[n - 1 - k];
    o[3 * k + 1] = c.s[n - 1 - k];
    o[3 * k + 2] = packDouble2x32(u[n - 1 - k]);
  }
}
)";
  gpu::Program prog({gpu::ShaderPart{"local_double_arrays.comp", 1, src}});
  const int n = 40;
  std::vector<double> in(n);
  for (int k = 0; k < n; ++k) in[k] = 6371390.625 + 0.001 * k;
  gpu::Buffer bi(in.size() * sizeof(double), in.data()), bo(3 * in.size() * sizeof(double));
  bi.bind(1);
  bo.bind(2);
  prog.set("n", n);
  prog.dispatch(1);
  std::vector<double> out(3 * in.size());
  bo.download(out.data(), out.size() * sizeof(double));
  const char* what[3] = {"local double array", "struct member array", "packed uvec2 array"};
  int inexact[2] = {0, 0};
  for (int k = 0; k < n; ++k) {
    for (int w = 0; w < 2; ++w) inexact[w] += out[3 * k + w] != in[n - 1 - k] ? 1 : 0;
    EXPECT_EQ(out[3 * k + 2], in[n - 1 - k]) << what[2] << ", element " << n - 1 - k << ", " << ctx->info().renderer;
  }
  std::printf("%s: %s %d of %d elements inexact, %s %d of %d (not relied on); %s exact\n", ctx->info().renderer.c_str(),
              what[0], inexact[0], n, what[1], inexact[1], n, what[2]);
}
