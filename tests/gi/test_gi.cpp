// The diffuse path tracer (atmosh::gi) against closed forms:
//  * furnace: inside a closed surface of uniform albedo a and uniform emitted radiance Le,
//    the radiance is Le / (1 - a) everywhere (the Neumann series Le sum a^k), and with at
//    most B reflections Le (1 - a^(B+1)) / (1 - a); irradiance is pi times that;
//  * irradiance below a square emitter: its configuration factor (Howell's catalogue: plane element to a parallel rectangle);
//  * a lone plane under a sun of irradiance E: radiance a E cos(theta) / pi (Lambert), also
//    for a sun disc (the cosine integral over the disc is exactly pi sin^2(r) cos(theta));
//  * an equirect environment file of two halves: pi A facing up, pi (A + B) / 2 sideways;
//  * irradiance under an SH environment: band 0 (uniform L) gives pi L, band 1 adds
//    2 pi / 3 sum c_1m Y_1m(n) (Ramamoorthi & Hanrahan 2001, "An efficient representation
//    for irradiance environment maps", eq. 8: A_0 = pi, A_1 = 2 pi / 3);
//  * determinism across thread counts.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/prt/mesh.hpp"

namespace {
using namespace atmosh;
constexpr double kPi = std::numbers::pi;

// A closed sphere of radius 1 about the origin (prt's built-in), one material.
gi::Scene furnace(const glm::dvec3& albedo, const glm::dvec3& le) {
  return gi::scene_from_mesh(prt::builtin_scene("sphere", 12), gi::Material{albedo, le, false});
}

// A square plane z = 0 of side 2 (normal +z), one material.
prt::Mesh plane(double half = 1.0, double z = 0.0) {
  prt::Mesh m;
  m.name = "plane";
  m.positions = {{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  prt::compute_normals(m);
  return m;
}

// Mean over all pixels of channel c, and its standard error (pixels independent).
std::pair<double, double> image_mean(const gi::RadianceImage& img, int c) {
  double s = 0, v = 0;
  const std::size_t n = img.mean[c].size();
  for (std::size_t i = 0; i < n; ++i) s += img.mean[c][i], v += double(img.stderr_[c][i]) * img.stderr_[c][i];
  return {s / n, std::sqrt(v) / n};
}

gi::Camera inside_camera() {
  gi::Camera cam;
  cam.eye = {0.1, -0.2, 0.05};
  cam.forward = {0.3, 1, 0.2};
  cam.up = {0, 0, 1};
  cam.vertical_fov_deg = 100;
  return cam;
}

TEST(GiFurnace, RadianceIsEmissionOverOneMinusAlbedo) {
  // Three albedos at once (one per channel), a = 0.9 included.
  const glm::dvec3 a(0.3, 0.7, 0.9), le(1.0, 0.5, 2.0);
  gi::TraceOptions opt;
  opt.samples = 128;
  opt.seed = 7;
  const auto img = gi::render(furnace(a, le), inside_camera(), 12, 12, opt);
  for (int c = 0; c < 3; ++c) {
    const double expect = le[c] / (1 - a[c]);
    const auto [m, se] = image_mean(img, c);
    EXPECT_LT(se, 0.01 * expect) << "channel " << c;
    EXPECT_NEAR(m, expect, 4 * se) << "channel " << c << " albedo " << a[c];
    // The measured error, in the test report (--gtest_output=json; docs/gi.md quotes it).
    RecordProperty("albedo_" + std::to_string(a[c]).substr(0, 4) + "_error_in_stderr", std::to_string((m - expect) / se));
    RecordProperty("albedo_" + std::to_string(a[c]).substr(0, 4) + "_relative_stderr", std::to_string(se / expect));
    // The per-pixel standard errors are calibrated: about 95 % of pixels within 2 of them.
    int within = 0;
    for (std::size_t i = 0; i < img.mean[c].size(); ++i)
      within += std::abs(img.mean[c][i] - expect) <= 2 * img.stderr_[c][i];
    EXPECT_GE(within, static_cast<int>(0.85 * img.mean[c].size())) << "channel " << c;
  }
}

TEST(GiFurnace, BlackWallsGiveTheEmissionExactly) {
  const auto img = gi::render(furnace(glm::dvec3(0.0), glm::dvec3(1.5, 2.5, 0.25)), inside_camera(), 6, 6, {});
  for (int c = 0; c < 3; ++c)
    for (float v : img.mean[c]) EXPECT_FLOAT_EQ(v, c == 0 ? 1.5f : c == 1 ? 2.5f : 0.25f);
}

TEST(GiFurnace, TruncatedBouncesGiveThePartialSum) {
  const glm::dvec3 a(0.5, 0.8, 0.9), le(1.0);
  for (int bounces : {0, 1, 3}) {
    gi::TraceOptions opt;
    opt.samples = 32;
    opt.bounces = bounces;
    const auto img = gi::render(furnace(a, le), inside_camera(), 8, 8, opt);
    for (int c = 0; c < 3; ++c) {
      const double expect = le[c] * (1 - std::pow(a[c], bounces + 1)) / (1 - a[c]);
      const auto [m, se] = image_mean(img, c);
      EXPECT_NEAR(m, expect, std::max(4 * se, 1e-6 * expect)) << "bounces " << bounces << " channel " << c;
    }
  }
}

TEST(GiFurnace, IrradianceIsPiTimesTheRadiance) {
  const glm::dvec3 a(0.2, 0.6, 0.9), le(1.0, 1.0, 0.5);
  const std::vector<glm::dvec3> pts = {{0, 0, 0}, {0.5, 0.2, -0.3}, {-0.2, 0.6, 0.1}};
  const std::vector<glm::dvec3> nrm = {{0, 0, 1}, {1, -1, 0.5}, {0, -1, 0}};
  gi::TraceOptions opt;
  opt.samples = 3000;
  const auto e = gi::irradiance(furnace(a, le), pts, nrm, opt);
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double expect = kPi * le[c] / (1 - a[c]);
      EXPECT_LT(e.stderr_[i][c], 0.02 * expect);
      EXPECT_NEAR(e.mean[i][c], expect, 4 * e.stderr_[i][c]) << "point " << i << " channel " << c;
      RecordProperty("point" + std::to_string(i) + "_albedo_" + std::to_string(a[c]).substr(0, 4) + "_rel_error",
                     std::to_string((e.mean[i][c] - expect) / expect));
    }
}

TEST(GiSun, LonePlaneFollowsLambert) {
  const glm::dvec3 a(0.2, 0.5, 0.8), E(1.0, 2.0, 3.0);
  gi::Scene s = gi::scene_from_mesh(plane(), gi::Material{a, glm::dvec3(0), false});
  const double az = 40, el = 30;
  s.sun = gi::Sun{gi::sun_direction(s, az, el), E, 0};
  EXPECT_NEAR(glm::dot(s.sun->direction, glm::dvec3(0, 0, 1)), 0.5, 1e-15);
  gi::Camera cam;  // looking straight down at the middle of the plane
  cam.eye = {0, 0, 3};
  cam.forward = {0, 0, -1};
  cam.up = {0, 1, 0};
  cam.vertical_fov_deg = 20;
  gi::TraceOptions opt;
  opt.samples = 4;
  const auto img = gi::render(s, cam, 8, 8, opt);
  const double cos_t = std::sin(el * kPi / 180);
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < img.mean[c].size(); ++i)
      EXPECT_NEAR(img.mean[c][i], a[c] * E[c] * cos_t / kPi, 1e-6 * E[c]);
  // Seen from below (the unlit side), the plane is black.
  cam.eye = {0, 0, -3};
  cam.forward = {0, 0, 1};
  const auto below = gi::render(s, cam, 4, 4, opt);
  for (int c = 0; c < 3; ++c)
    for (float v : below.mean[c]) EXPECT_EQ(v, 0.0f);
}

TEST(GiSun, SunDiscGivesTheSameIrradiance) {
  const glm::dvec3 E(1.0, 2.0, 3.0);
  gi::Scene s = gi::scene_from_mesh(plane(), gi::Material{glm::dvec3(0.5), glm::dvec3(0), false});
  s.sun = gi::Sun{gi::sun_direction(s, 120, 25), E, 0.2};
  gi::TraceOptions opt;
  opt.samples = 4000;
  const auto e = gi::irradiance(s, {{0.1, 0.2, 0.0}}, {{0, 0, 1}}, opt);
  const double cos_t = std::sin(25 * kPi / 180);
  for (int c = 0; c < 3; ++c) {
    EXPECT_GT(e.stderr_[0][c], 0);
    EXPECT_NEAR(e.mean[0][c], E[c] * cos_t, 4 * e.stderr_[0][c]) << "channel " << c;
  }
}

TEST(GiEnvironment, UniformShEnvironmentGivesPiL) {
  // A small black plane far below: nothing in the upper hemisphere.
  gi::Scene s = gi::scene_from_mesh(plane(0.5, -1000), gi::Material{glm::dvec3(0), glm::dvec3(0), false});
  const glm::dvec3 L(0.5, 1.0, 2.0);
  s.env_bands = 1;
  for (int c = 0; c < 3; ++c) s.env_sh[c] = {L[c] * 2 * std::sqrt(kPi)};  // Y_00 = 1 / (2 sqrt(pi))
  gi::TraceOptions opt;
  opt.samples = 16;
  const auto e = gi::irradiance(s, {{0, 0, 0}, {3, -2, 1}}, {{0, 0, 1}, {0, 0, 1}}, opt);
  for (int i = 0; i < 2; ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.mean[i][c], kPi * L[c], 1e-12 * L[c]);
}

TEST(GiEnvironment, LinearShEnvironmentMatchesTheIrradianceFormula) {
  gi::Scene s = gi::scene_from_mesh(plane(0.5, -1000), gi::Material{glm::dvec3(0), glm::dvec3(0), false});
  // Band 0 and band 1 (positive everywhere: |c_1| sqrt(3/(4 pi)) < c_0 / (2 sqrt(pi))).
  const double c0 = 2.0, c1[3] = {0.3, -0.4, 0.5};  // c_{1,-1}, c_{1,0}, c_{1,1}
  s.env_bands = 2;
  for (int c = 0; c < 3; ++c) s.env_sh[c] = {c0 * (c + 1), c1[0], c1[1], c1[2]};
  const std::vector<glm::dvec3> nrm = {{0, 0, 1}, glm::normalize(glm::dvec3(0.6, 0.3, 0.8))};
  gi::TraceOptions opt;
  opt.samples = 20000;
  const auto e = gi::irradiance(s, {{0, 0, 0}, {1, 1, 1}}, nrm, opt);
  const double k1 = std::sqrt(3 / (4 * kPi));
  for (std::size_t i = 0; i < nrm.size(); ++i) {
    const glm::dvec3 n = nrm[i];  // scene frame: east = x, north = y, up = z
    // Y_1-1 = -k1 y, Y_10 = k1 z, Y_11 = -k1 x (basis.hpp, Condon-Shortley phase)
    const double band1 = c1[0] * (-k1 * n.y) + c1[1] * (k1 * n.z) + c1[2] * (-k1 * n.x);
    for (int c = 0; c < 3; ++c) {
      const double expect = kPi * c0 * (c + 1) / (2 * std::sqrt(kPi)) + 2 * kPi / 3 * band1;
      EXPECT_NEAR(e.mean[i][c], expect, 4 * e.stderr_[i][c]) << "normal " << i << " channel " << c;
      EXPECT_LT(e.stderr_[i][c], 0.01 * expect);
    }
  }
}

TEST(GiDeterminism, SameImageOnAnyThreadCount) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::TraceOptions opt;
  opt.samples = 4;
  opt.seed = 11;
  opt.threads = 1;
  const auto a = gi::render(s, s.camera, 16, 12, opt);
  opt.threads = 3;
  const auto b = gi::render(s, s.camera, 16, 12, opt);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(a.mean[c], b.mean[c]);
    EXPECT_EQ(a.stderr_[c], b.stderr_[c]);
  }
  EXPECT_EQ(a.stats.rays, b.stats.rays);
  opt.seed = 12;
  const auto d = gi::render(s, s.camera, 16, 12, opt);
  EXPECT_NE(a.mean[0], d.mean[0]);
}

TEST(GiCornellBox, PublishedGeometryAndDirectLight) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  EXPECT_EQ(s.mesh.triangles.size(), 32u);  // 16 published quads
  // bounces = 0: only the light is seen, at its emitted radiance (page: 612/548/464 nm).
  gi::TraceOptions opt;
  opt.samples = 2;
  opt.bounces = 0;
  const auto img = gi::render(s, s.camera, 32, 32, opt);
  int lit = 0;
  for (std::size_t i = 0; i < img.mean[0].size(); ++i) {
    if (img.mean[0][i] > 0) ++lit;
    EXPECT_LE(img.mean[0][i], 15.936f * (1 + 1e-6f));
  }
  EXPECT_GT(lit, 0);
  EXPECT_LT(lit, 20);
  // Full transport: finite, non-negative, and the red (left) wall reddens the image's left edge.
  opt.bounces = -1;
  opt.samples = 8;
  const auto full = gi::render(s, s.camera, 16, 16, opt);
  double left_r = 0, left_g = 0;
  for (int c = 0; c < 3; ++c)
    for (float v : full.mean[c]) EXPECT_TRUE(std::isfinite(v) && v >= 0);
  for (int row = 4; row < 12; ++row) left_r += full.mean[0][row * 16], left_g += full.mean[1][row * 16];
  EXPECT_GT(left_r, 2 * left_g);
}

TEST(GiInput, BadValuesThrowInputError) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::TraceOptions opt;
  opt.samples = 1;
  EXPECT_THROW(gi::render(s, s.camera, 4, 4, opt), InputError);
  opt.samples = 4;
  opt.bounces = -2;
  EXPECT_THROW(gi::render(s, s.camera, 4, 4, opt), InputError);
  opt.bounces = 2;
  EXPECT_THROW(gi::render(s, s.camera, 0, 4, opt), InputError);
  gi::Scene bad = s;
  bad.materials[0].albedo.x = 1.5;
  EXPECT_THROW(gi::render(bad, s.camera, 4, 4, opt), InputError);
  EXPECT_THROW(gi::builtin_scene("no-such-scene"), InputError);
  EXPECT_THROW(gi::sun_direction(s, 0, 95), InputError);
  EXPECT_THROW(gi::irradiance(s, {{0, 0, 0}}, {{0, 0, 0}}, opt), InputError);
}

}  // namespace

namespace {
// Equirect environment from an EXR file: the upper half of the sphere (polar angle from the
// scene's up below 90 degrees, rows 0..1 of 4) of radiance A, the lower half B. A normal up
// sees only A: E = pi A exactly; a horizontal normal sees half of each, symmetrically in
// the cosine: E = pi (A + B) / 2.
TEST(GiEnvironment, EquirectFileHalfAndHalf) {
  const auto file = std::filesystem::temp_directory_path() / ("atmosh_gi_env_" + std::to_string(::getpid()) + ".exr");
  io::ExrImage ex(8, 4, {"R", "G", "B"});
  const glm::dvec3 A(1.0, 2.0, 0.5), B(0.25, 0.0, 3.0);
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 8; ++col) ex.data[c][row * 8 + col] = static_cast<float>(row < 2 ? A[c] : B[c]);
  io::write_exr(file, ex, io::Provenance{});
  gi::Scene s = gi::scene_from_mesh(plane(0.5, -1000), gi::Material{glm::dvec3(0), glm::dvec3(0), false});
  s.env_map = gi::read_environment_map(file);
  std::filesystem::remove(file);
  gi::TraceOptions opt;
  opt.samples = 20000;
  const auto e = gi::irradiance(s, {{0, 0, 0}, {0, 0, 0}}, {{0, 0, 1}, {1, 0, 0}}, opt);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(e.mean[0][c], kPi * A[c], 1e-12 * (1 + A[c]));
    const double side = kPi * (A[c] + B[c]) / 2;
    EXPECT_NEAR(e.mean[1][c], side, 4 * e.stderr_[1][c]) << "channel " << c;
    EXPECT_LT(e.stderr_[1][c], 0.02 * side);
  }
}
}  // namespace

namespace {
// Irradiance at a point below a square emitter of radiance L (side 2s, parallel, centred at
// height h): E = pi L F with the configuration factor of a differential element to a
// parallel rectangle with one corner above it (Howell, "A Catalog of Radiation Heat
// Transfer Configuration Factors": plane element to a parallel rectangle, the normal
// through a corner), four quadrants:
//   F = 4 / (2 pi) [X / sqrt(1 + X^2) atan(Y / sqrt(1 + X^2)) + Y / sqrt(1 + Y^2) atan(X / sqrt(1 + Y^2))],
// X = Y = s / h. Exercises the emitter sampling and its MIS with the hemisphere samples;
// the emitter is one-sided, so the same square facing up gives exactly 0.
TEST(GiEmitter, SquareLightIrradianceMatchesTheConfigurationFactor) {
  const double s = 0.7, h = 1.3;
  const glm::dvec3 L(1.0, 2.0, 4.0);
  for (bool facing_down : {true, false}) {
    prt::Mesh m = plane(s, h);
    if (facing_down) m.triangles = {{0, 2, 1}, {0, 3, 2}};
    gi::Scene sc = gi::scene_from_mesh(m, gi::Material{glm::dvec3(0), L, true});
    gi::TraceOptions opt;
    opt.samples = 4000;
    const auto e = gi::irradiance(sc, {{0, 0, 0}}, {{0, 0, 1}}, opt);
    const double X = s / h, r = std::sqrt(1 + X * X);
    const double F = 4 / (2 * kPi) * 2 * (X / r * std::atan(X / r));
    for (int c = 0; c < 3; ++c) {
      if (!facing_down) {
        EXPECT_EQ(e.mean[0][c], 0.0);
        continue;
      }
      const double expect = kPi * L[c] * F;
      EXPECT_LT(e.stderr_[0][c], 0.01 * expect);
      EXPECT_NEAR(e.mean[0][c], expect, 4 * e.stderr_[0][c]) << "channel " << c;
    }
  }
}
}  // namespace
