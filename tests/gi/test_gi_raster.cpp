// The rasterised passes of the GPU forms of radiosity and LPV (atmosh/gpu/gi_raster.hpp,
// apps/gi/src/raster_gpu.cpp) against independent references: the CPU's ray-cast G-buffer
// (Embree rays through the pixel centres), the CPU's shadow rays, the path tracer, the CPU's
// ray-cast VPL injection and the closed-form flux a sun brings onto a plane. Skipped where no
// EGL context can be made (ATMOSH_REQUIRE_GPU_CONTEXT=1 makes that a failure elsewhere).
#ifdef ATMOSH_GI_HAVE_GPU
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/gi/lpv.hpp"
#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/probes.hpp"
#include "atmosh/gi/radiosity.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/gi/shared/polygon.glsl.hpp"
#include "atmosh/gpu/context.hpp"
#include "atmosh/prt/bake.hpp"

namespace {
using namespace atmosh;

bool no_gpu(std::string& why) {
  try {
    gpu::Context probe;
    return false;
  } catch (const gpu::Unavailable& e) {
    why = e.what();
    return true;
  }
}

// A G-buffer spread back over its pixels.
struct Pixels {
  int w = 0, h = 0;
  std::vector<char> hit;
  std::vector<glm::dvec3> p, n, a, e, E;
};
Pixels spread(const gi::RadiosityGBuffer& g, int w, int h) {
  Pixels x;
  x.w = w, x.h = h;
  const std::size_t np = static_cast<std::size_t>(w) * h;
  x.hit.assign(np, 0);
  for (auto* v : {&x.p, &x.n, &x.a, &x.e, &x.E}) v->assign(np, glm::dvec3(0.0));
  for (std::size_t k = 0; k < g.pixel.size(); ++k) {
    const std::size_t i = g.pixel[k];
    x.hit[i] = 1;
    x.p[i] = g.receivers.position[k];
    x.n[i] = g.receivers.normal[k];
    x.a[i] = g.receivers.albedo[k];
    x.e[i] = g.receivers.emission[k];
    x.E[i] = g.receivers.direct[k];
  }
  return x;
}

double max3(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

// Same surface at pixel i: both hit, positions within `tol`, the same normal, albedo, emission.
bool same_surface(const Pixels& a, const Pixels& b, std::size_t i, double tol) {
  if (a.hit[i] != b.hit[i]) return false;
  if (!a.hit[i]) return true;
  return glm::length(a.p[i] - b.p[i]) < tol && glm::dot(a.n[i], b.n[i]) > 1 - 1e-5 && max3(a.a[i] - b.a[i]) < 1e-6 &&
         max3(a.e[i] - b.e[i]) < 1e-5 * (1 + max3(b.e[i]));
}

// Pixel i lies on an edge of the ray-cast image: one of its 8 neighbours sees another surface
// (hit or miss, another plane, another material).
bool edge_pixel(const Pixels& c, std::size_t i, double tol) {
  const int r = static_cast<int>(i) / c.w, q = static_cast<int>(i) % c.w;
  for (int dr = -1; dr <= 1; ++dr)
    for (int dq = -1; dq <= 1; ++dq) {
      const int rr = r + dr, qq = q + dq;
      if (rr < 0 || qq < 0 || rr >= c.h || qq >= c.w) continue;
      const std::size_t j = static_cast<std::size_t>(rr) * c.w + qq;
      if (c.hit[j] != c.hit[i]) return true;
      if (!c.hit[i]) continue;
      if (glm::dot(c.n[i], c.n[j]) < 1 - 1e-6 || max3(c.a[i] - c.a[j]) > 0 || max3(c.e[i] - c.e[j]) > 0 ||
          std::abs(glm::dot(c.n[i], c.p[j] - c.p[i])) > tol)
        return true;
    }
  return false;
}

gi::Scene sunlit(const char* name, double az, double el) {
  gi::Scene s = gi::builtin_scene(name);
  s.sun = gi::Sun{gi::sun_direction(s, az, el), glm::dvec3(3.0, 2.0, 1.0)};
  return s;
}

// 1. The rasterised G-buffer against the ray-cast one, pixel by pixel: the same surface
// everywhere except at edge pixels, where the rasteriser's coverage rule and Embree's ray test
// may pick different sides of an edge passing near the pixel centre.
TEST(GiRaster, GBufferAgreesWithTheRayCastGBufferExceptAtEdges) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  for (const char* name : {"cornell-box", "sphere-on-plane", "box-occluder"}) {
    gi::Scene s = gi::builtin_scene(name);
    if (!s.sun) s.sun = gi::Sun{gi::sun_direction(s, 135, 40), glm::dvec3(2.0)};
    const int W = 48, H = 40;
    const gi::RadiosityGBuffer gc = gi::radiosity_gbuffer(s, s.camera, W, H, 1, 5);
    double secs = -1;
    const gi::RadiosityGBuffer gg = gi::radiosity_gbuffer_gpu(s, s.camera, W, H, 1, 5, 0, {}, &secs);
    EXPECT_GE(secs, 0.0);
    const Pixels c = spread(gc, W, H), g = spread(gg, W, H);
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : s.mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const double tol = 1e-4 * glm::length(hi - lo);  // float positions, perspective interpolation
    std::size_t differ = 0, differ_inner = 0, hits = 0;
    double worst_p = 0;  // the largest position difference where the surfaces agree
    for (std::size_t i = 0; i < c.hit.size(); ++i) {
      hits += c.hit[i] ? 1 : 0;
      if (same_surface(g, c, i, tol)) {
        if (c.hit[i]) worst_p = std::max(worst_p, glm::length(g.p[i] - c.p[i]));
        continue;
      }
      ++differ;
      if (!edge_pixel(c, i, 1e-3 * glm::length(hi - lo))) ++differ_inner;
    }
    ASSERT_GT(hits, c.hit.size() / 6) << name;
    const double frac = static_cast<double>(differ) / static_cast<double>(c.hit.size());
    std::printf("%s: rasterised G-buffer differs from the ray-cast one at %zu of %zu pixels (%.4f), %zu off edges; "
                "elsewhere positions within %.2g of the box diagonal\n",
                name, differ, c.hit.size(), frac, differ_inner, worst_p / glm::length(hi - lo));
    EXPECT_EQ(differ_inner, 0u) << name;  // every difference is at an edge pixel
    EXPECT_LT(frac, 0.01) << name;
  }
}

// 1b. The Cornell box's direct light with the CPU's estimator at the rasterised points
// (emitter_points = 0; the same random streams): equal to the ray-cast G-buffer's where the
// surface is the same.
TEST(GiRaster, AreaLightCpuTermAtRasterisedPointsMatchesTheRayCastGBuffer) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  const gi::Scene s = gi::builtin_scene("cornell-box");
  const int W = 40, H = 40;
  gi::ShadowMapOptions so;
  so.emitter_points = 0;
  const Pixels c = spread(gi::radiosity_gbuffer(s, s.camera, W, H, 2, 9), W, H);
  const Pixels g = spread(gi::radiosity_gbuffer_gpu(s, s.camera, W, H, 2, 9, 0, so), W, H);
  double scale = 0;
  for (const auto& E : c.E) scale = std::max(scale, max3(E));
  ASSERT_GT(scale, 0);
  std::size_t n = 0, bad = 0;
  for (std::size_t i = 0; i < c.hit.size(); ++i) {
    if (!c.hit[i] || !same_surface(g, c, i, 0.05)) continue;
    ++n;
    if (max3(g.E[i] - c.E[i]) > 1e-3 * scale) ++bad;
  }
  ASSERT_GT(n, 1000u);
  std::printf("area light (CPU estimator) at rasterised points: %zu of %zu receivers differ by > 1e-3 of the largest\n",
              bad, n);
  EXPECT_LE(bad, n / 200);  // a shadow ray grazing an edge may flip for a 1e-5 shift of its origin
}

// 1c. The area light on the GPU (the shared polygon formula x the visibility of 4 fixed points
// per emitting triangle by distance cube maps) against the CPU's estimator at 64 samples
// (polygon formula x one random point's shadow ray each): equal within float rounding where
// the CPU sees the whole light (every sample visible) and zero where it sees none of it; the
// penumbra (4 points against 64 random ones) is measured.
TEST(GiRaster, AreaLightOnTheGpuAgainstTheCpuEstimator) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  const gi::Scene s = gi::builtin_scene("cornell-box");
  const int W = 40, H = 40;
  const Pixels c = spread(gi::radiosity_gbuffer(s, s.camera, W, H, 64, 9), W, H);
  double secs = -1;
  const gi::RadiosityGBuffer gb = gi::radiosity_gbuffer_gpu(s, s.camera, W, H, 64, 9, 0, {}, &secs);
  EXPECT_EQ(gb.rays, 0u) << "no light left on the CPU";
  const Pixels g = spread(gb, W, H);
  // the unoccluded irradiance at each receiver (the polygon formula in double, as the CPU's)
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : s.mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double off = 1e-4 * glm::length(hi - lo);
  std::size_t lit = 0, lit_bad = 0, umbra = 0, umbra_bad = 0, pen = 0;
  double sum_abs = 0, sum_ref = 0;
  for (std::size_t i = 0; i < c.hit.size(); ++i) {
    if (!c.hit[i] || !same_surface(g, c, i, 0.05)) continue;
    glm::dvec3 U(0.0);
    for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t) {
      const gi::Material& m = s.materials[s.material[t]];
      if (!(m.emission.x > 0)) continue;
      const auto& tv = s.mesh.triangles[t];
      const glm::dvec3 a = s.mesh.positions[tv[0]], b = s.mesh.positions[tv[1]], cc = s.mesh.positions[tv[2]];
      const glm::dvec3 nt = glm::normalize(glm::cross(b - a, cc - a));
      if (m.one_sided && glm::dot(nt, c.p[i] - a) <= 0) continue;
      U += m.emission * gi::shared::gi_polygon_irradiance(c.p[i] + 0.01 * off * c.n[i], c.n[i], a, b, cc);
    }
    if (!(U.x > 0)) continue;
    const double f = c.E[i].x / U.x;  // the CPU's visible fraction (64 samples)
    sum_abs += std::abs(g.E[i].x - c.E[i].x);
    sum_ref += c.E[i].x;
    if (f > 1 - 1e-9) {
      ++lit;
      if (std::abs(g.E[i].x - U.x) > 1e-4 * U.x) ++lit_bad;
    } else if (f < 1e-9) {
      ++umbra;
      if (g.E[i].x > 1e-3 * U.x) ++umbra_bad;
    } else {
      ++pen;
    }
  }
  ASSERT_GT(lit, 500u);
  std::printf("area light on the GPU vs CPU (64 samples): fully lit %zu (%zu differ > 1e-4), umbra %zu (%zu lit > 1e-3), "
              "penumbra %zu; mean |difference| / mean irradiance %.4f\n",
              lit, lit_bad, umbra, umbra_bad, pen, sum_abs / sum_ref);
  EXPECT_LE(lit_bad, lit / 100);
  EXPECT_LE(umbra_bad, umbra / 50 + 1);
  EXPECT_LT(sum_abs / sum_ref, 0.05);
}

// 2. The sun's direct light by the shadow map against one shadow ray per receiver (exact for a
// point sun): receivers that differ by more than 1 % of E_sun lie within the shadow map's
// footprint of a shadow edge (shadow rays from nearby points disagree), and they are few.
TEST(GiRaster, SunShadowMapAgreesWithShadowRaysAwayFromShadowEdges) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  for (const char* name : {"sphere-on-plane", "box-occluder"}) {
    const gi::Scene s = sunlit(name, 135, 40);
    const int W = 64, H = 64;
    const Pixels c = spread(gi::radiosity_gbuffer(s, s.camera, W, H, 1, 1), W, H);
    const Pixels g = spread(gi::radiosity_gbuffer_gpu(s, s.camera, W, H, 1, 1), W, H);
    const glm::dvec3 sd = glm::normalize(s.sun->direction);
    const double Es = s.sun->irradiance.x;
    // Near a shadow edge in the scene: shadow rays (Embree, independent of the rasteriser)
    // from the points of the shadow map's footprint around p do not all agree — points within
    // (pcf + 1.5) = 2.5 texels of p perpendicular to the sun, moved along the sun onto p's
    // tangent plane (the PCF kernel's half-width plus a texel's rounding), each also lifted by
    // the normal offset + bias (2 texels) along n.
    const prt::RayScene rays(s.mesh);
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : s.mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const double texel = 2 * 1.01 * 0.5 * glm::length(hi - lo) / gi::ShadowMapOptions{}.resolution;
    glm::dvec3 u = glm::normalize(glm::cross(sd, glm::dvec3(0.3, 0.5, 0.8))), w = glm::cross(sd, u);
    auto near_edge = [&](std::size_t i) {
      const glm::dvec3 p = c.p[i], n = c.n[i];
      const bool v0 = rays.unoccluded(p, sd, rays.offset());
      for (double R : {0.5, 1.0})
        for (int k = 0; k < 16; ++k) {
          const double phi = 2 * std::numbers::pi * k / 16;
          glm::dvec3 q = p + R * 2.5 * texel * (std::cos(phi) * u + std::sin(phi) * w);
          q -= sd * (glm::dot(n, q - p) / glm::dot(n, sd));
          for (double lift : {0.0, 2.0})
            if (rays.unoccluded(q + lift * texel * n, sd, rays.offset()) != v0) return true;
        }
      return false;
    };
    std::size_t n = 0, differ = 0, inner = 0;
    for (std::size_t i = 0; i < c.hit.size(); ++i) {
      if (!c.hit[i] || !same_surface(g, c, i, 1e-3)) continue;
      ++n;
      ASSERT_TRUE(std::isfinite(g.E[i].x + g.E[i].y + g.E[i].z));
      if (std::abs(g.E[i].x - c.E[i].x) <= 0.01 * Es) continue;
      ++differ;
      if (near_edge(i)) continue;
      ++inner;
      std::printf("  pixel %zu (%.3f %.3f %.3f): ray-cast %.4f shadow map %.4f\n", i, c.p[i].x, c.p[i].y, c.p[i].z,
                  c.E[i].x, g.E[i].x);
    }
    ASSERT_GT(n, 500u);
    const double frac = static_cast<double>(differ) / static_cast<double>(n);
    std::printf("%s: shadow map vs shadow rays: %zu of %zu receivers differ by > 1%% of E_sun (%.4f), %zu away from edges\n",
                name, differ, n, frac, inner);
    EXPECT_EQ(inner, 0u) << name;
    EXPECT_LT(frac, 0.03) << name;
  }
}

// 2b. The whole frame on the GPU (rasterised G-buffer with the shadow map, the walk as a
// compute pass) against the path tracer, next to the ray-cast G-buffer's frame (the same
// volume, the walk by the CPU twin): the shadow map changes the error by little.
TEST(GiRaster, SunFrameOnTheGpuAgainstThePathTracer) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  const gi::Scene s = sunlit("sphere-on-plane", 135, 40);
  const int W = 32, H = 32;
  gi::TraceOptions t;
  t.samples = 64;
  t.seed = 11;
  const gi::RadianceImage ref = gi::render(s, s.camera, W, H, t);
  gi::RadiosityOptions o;
  o.grid = 4;
  o.bands = 2;
  o.bounces = 2;
  o.samples = 1;
  gi::RadiosityVolume v = gi::build_radiosity_volume(s, o);
  gi::add_direct_volume(s, v, 16, 2);
  const gi::ImageError ec = gi::image_error(gi::render_radiosity_gbuffer(s, s.camera, W, H, v, o, false), ref);
  const gi::ImageError eg = gi::image_error(gi::render_radiosity_gbuffer(s, s.camera, W, H, v, o, true), ref);
  std::printf("sun frame vs path tracer: ray-cast G-buffer rms %.4f max %.4f mean %.4f; rasterised + shadow map rms %.4f "
              "max %.4f mean %.4f\n",
              ec.rms_rel, ec.max_rel, ec.mean_rel, eg.rms_rel, eg.max_rel, eg.mean_rel);
  EXPECT_TRUE(std::isfinite(eg.rms_rel));
  EXPECT_LT(eg.rms_rel, ec.rms_rel + 0.02);
  EXPECT_NEAR(eg.mean_rel, ec.mean_rel, 0.01);
}

// 2c. The Cornell box's frame with its area light on the GPU (distance cube maps, 4 points per
// triangle) against the path tracer, next to the ray-cast G-buffer's frame with the CPU's
// estimator (16 samples); the same volume, the walk by the CPU twin and the GPU pass.
TEST(GiRaster, CornellFrameOnTheGpuAgainstThePathTracer) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  const gi::Scene s = gi::builtin_scene("cornell-box");
  const int W = 24, H = 24;
  gi::TraceOptions t;
  t.samples = 128;
  t.seed = 11;
  const gi::RadianceImage ref = gi::render(s, s.camera, W, H, t);
  gi::TraceOptions t0;
  t0.samples = 4;
  t0.bounces = 0;
  const auto mask = gi::emitter_mask(gi::render(s, s.camera, W, H, t0), 1);
  gi::RadiosityOptions o;
  o.grid = 8;
  o.bands = 2;
  o.bounces = 2;
  o.samples = 16;
  gi::RadiosityVolume v = gi::build_radiosity_volume(s, o);
  gi::add_direct_volume(s, v);
  const gi::ImageError ec = gi::image_error(gi::render_radiosity_gbuffer(s, s.camera, W, H, v, o, false), ref, &mask);
  const gi::ImageError eg = gi::image_error(gi::render_radiosity_gbuffer(s, s.camera, W, H, v, o, true), ref, &mask);
  std::printf("Cornell frame vs path tracer: ray-cast G-buffer + CPU area light rms %.4f max %.4f mean %.4f; GPU (raster + "
              "distance maps) rms %.4f max %.4f mean %.4f\n",
              ec.rms_rel, ec.max_rel, ec.mean_rel, eg.rms_rel, eg.max_rel, eg.mean_rel);
  EXPECT_TRUE(std::isfinite(eg.rms_rel));
  EXPECT_LT(eg.rms_rel, ec.rms_rel + 0.03);
  EXPECT_NEAR(eg.mean_rel, ec.mean_rel, 0.02);
}

// 2d. A uniform sky (radiance L) on the GPU (spherical-Fibonacci directions, a depth map
// each): on an open plane E = pi L (closed form), met within the quadrature's error at the
// default 128 directions; with occluders (box-occluder) against the CPU's estimator at 256 cosine-distributed shadow
// rays per receiver, the mean difference is bounded. Then the sun + sky frame against the path
// tracer.
TEST(GiRaster, SkyOnTheGpuAgainstTheClosedFormTheCpuEstimatorAndThePathTracer) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  const double L = 0.5, E0 = std::numbers::pi * L;
  auto uniform_sky = [&](gi::Scene& s) {
    s.env_bands = 1;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = {L * std::sqrt(4 * std::numbers::pi)};  // Y_00 = 1 / sqrt(4 pi)
  };
  {  // an open plane: every receiver sees the whole sky
    // tilted (normal off the directions' polar axis, where the midpoint rule in z is exact)
    const glm::dvec3 nz = glm::normalize(glm::dvec3(0.4, 0.3, 0.866));
    const glm::dvec3 ax = glm::normalize(glm::cross(glm::dvec3(0, 0, 1), nz)), ay = glm::cross(nz, ax);
    prt::Mesh m;
    m.positions = {-ax - ay, ax - ay, ax + ay, -ax + ay};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    gi::Scene s = gi::scene_from_mesh(m, gi::Material{glm::dvec3(0.5), glm::dvec3(0.0), false});
    uniform_sky(s);
    s.camera = gi::Camera{2.5 * nz - 1.5 * ay, -(2.5 * nz - 1.5 * ay), nz, 50};
    const Pixels g = spread(gi::radiosity_gbuffer_gpu(s, s.camera, 24, 24, 1, 3), 24, 24);
    std::size_t n = 0;
    double worst = 0;
    for (std::size_t i = 0; i < g.hit.size(); ++i)
      if (g.hit[i]) ++n, worst = std::max(worst, std::abs(g.E[i].x - E0) / E0);
    ASSERT_GT(n, 100u);
    std::printf("uniform sky on the GPU over an open plane: largest error against pi L %.5f\n", worst);
    EXPECT_LT(worst, 0.01);  // 128-point spherical Fibonacci, clamped cosine: 0.66 % at most over normals
  }
  for (const char* name : {"box-occluder"}) {
    gi::Scene s = gi::builtin_scene(name);
    uniform_sky(s);
    const int W = 24, H = 24;
    const Pixels c = spread(gi::radiosity_gbuffer(s, s.camera, W, H, 256, 3), W, H);
    double gs = 0;
    const auto t0 = std::chrono::steady_clock::now();
    const gi::RadiosityGBuffer gb = gi::radiosity_gbuffer_gpu(s, s.camera, W, H, 1, 3, 0, {}, &gs);
    std::printf("%s: GPU G-buffer with 128 sky maps of 256^2: %.3f s (rasterisation %.3f s)\n", name,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), gs);
    EXPECT_EQ(gb.rays, 0u) << "no light left on the CPU";
    const Pixels g = spread(gb, W, H);
    std::size_t n = 0;
    double sum_abs = 0, sum_ref = 0;
    for (std::size_t i = 0; i < c.hit.size(); ++i) {
      if (!c.hit[i] || !same_surface(g, c, i, 1e-3)) continue;
      ++n;
      ASSERT_TRUE(std::isfinite(g.E[i].x));
      sum_abs += std::abs(g.E[i].x - c.E[i].x);
      sum_ref += c.E[i].x;
    }
    ASSERT_GT(n, 100u) << name;
    std::printf("%s: uniform sky on the GPU vs the CPU's 256 rays: mean |GPU - CPU| / mean %.4f over %zu receivers\n",
                name, sum_abs / sum_ref, n);
    EXPECT_LT(sum_abs / sum_ref, 0.04) << name;
  }
  // sun + sky frame against the path tracer (radiosity, the walk on the GPU)
  gi::Scene s = sunlit("sphere-on-plane", 135, 40);
  s.env_bands = 1;
  for (int ch = 0; ch < 3; ++ch) s.env_sh[ch] = {0.3 * std::sqrt(4 * std::numbers::pi)};
  const int W = 24, H = 24;
  gi::TraceOptions t;
  t.samples = 64;
  t.seed = 11;
  const gi::RadianceImage ref = gi::render(s, s.camera, W, H, t);
  gi::RadiosityOptions o;
  o.grid = 4;
  o.bands = 2;
  o.bounces = 2;
  o.samples = 16;
  gi::RadiosityVolume v = gi::build_radiosity_volume(s, o);
  gi::add_direct_volume(s, v, 16, 2);
  const gi::ImageError ec = gi::image_error(gi::render_radiosity_gbuffer(s, s.camera, W, H, v, o, false), ref);
  const gi::ImageError eg = gi::image_error(gi::render_radiosity_gbuffer(s, s.camera, W, H, v, o, true), ref);  // defaults
  std::printf("sun + sky frame vs path tracer: ray-cast G-buffer + CPU sky (16 samples) rms %.4f mean %.4f; GPU rms %.4f "
              "mean %.4f\n",
              ec.rms_rel, ec.mean_rel, eg.rms_rel, eg.mean_rel);
  EXPECT_LT(eg.rms_rel, ec.rms_rel + 0.02);
  EXPECT_NEAR(eg.mean_rel, ec.mean_rel, 0.02);
}

// 3. Reflective-shadow-map injection: the sun's VPLs from the RSM carry the flux of the CPU's
// ray-cast VPLs, and on sphere-on-plane (albedo 0.8 everywhere; the sphere's shadow falls on
// the plane, so the plane's cross-section seen from the sun catches every ray that hits) the
// closed form 0.8 E_sun x 16 sin(elevation).
TEST(GiRaster, RsmInjectionConservesTheFluxOfTheRayCastInjection) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  for (const char* name : {"sphere-on-plane", "box-occluder"}) {
    const double el = 40;
    const gi::Scene s = sunlit(name, 135, el);
    gi::LpvOptions o;
    o.grid = 8;
    o.sun_rays = 8;
    const gi::LpvGrid empty = gi::lpv_grid(s, o.grid);
    double secs = -1;
    const std::vector<gi::Vpl> rsm = gi::lpv_vpls_rsm(s, o, empty, &secs);
    EXPECT_GE(secs, 0.0);
    const std::vector<gi::Vpl> cpu = gi::lpv_vpls(s, o, empty);
    glm::dvec3 fr(0.0), fc(0.0);
    for (const auto& v : rsm) fr += v.flux;
    for (const auto& v : cpu) fc += v.flux;
    const double rel = max3(fr - fc) / max3(fc);
    std::printf("%s: RSM %zu VPLs, flux %.6g; ray-cast %zu VPLs, flux %.6g; relative difference %.2e\n", name,
                rsm.size(), fr.x, cpu.size(), fc.x, rel);
    EXPECT_LT(rel, 5e-3) << name;
    if (std::string(name) == "sphere-on-plane") {
      const double exact = 0.8 * 3.0 * 16 * std::sin(el * std::numbers::pi / 180);
      EXPECT_NEAR(fr.x, exact, 5e-3 * exact);
      EXPECT_NEAR(fr.z, exact / 3, 5e-3 * exact / 3);
    }
    // the injected grids (the gi_lpv_inject pass): flux conserved by the injection
    std::uint64_t rays = 1;
    const gi::LpvGrid gg = gi::lpv_inject_gpu(s, o, &rays), gcpu = gi::lpv_inject(s, o);
    EXPECT_EQ(rays, 0u) << "no emitters: no CPU rays";
    const glm::dvec3 Fg = gi::lpv_flux(gg), Fc = gi::lpv_flux(gcpu);
    EXPECT_LT(max3(Fg - fr), 1e-5 * max3(fr)) << name << ": injection conserves the RSM's flux";
    EXPECT_LT(max3(Fg - Fc), 5e-3 * max3(Fc)) << name;
    // each RSM VPL faces the sun and sits half a cell off its surface, inside the grid's box
    for (const auto& v : rsm) {
      ASSERT_GT(glm::dot(v.n, glm::normalize(s.sun->direction)), -1e-6);
      ASSERT_NEAR(glm::length(v.n), 1.0, 1e-5);
    }
  }
}

// 3b. The LPV frame on the GPU (rasterised G-buffer with the shadow map, RSM injection,
// geometry, propagation, application) against the path tracer limited to the direct light and
// one bounce (what an LPV carries), next to the CPU's LPV on the ray-cast G-buffer.
// The area emitters' reflective shadow maps (gpu::gi_emitter_rsm through gi::lpv_vpls_emitter_rsm).
// 1. Closed form: a one-sided emitting triangle (area A, radiance L, facing down) 1 unit above the
// centre of a square of half-size 1000 (albedo rho) sends the square the fraction F of its power
// pi L A, F >= 1 - 1e-6 (the inscribed disc's a^2 / (a^2 + h^2)); every texel below the horizon
// sees the square, so the VPLs' flux is rho pi L A F up to the texel-centre quadrature of
// sum c Omega = pi (midpoint rule, O(1/N^2)). 2. The Cornell box: the RSM VPLs against the
// photon VPLs of lpv_vpls (2^20 stratified photon rays, an unbiased estimate of the same
// reflected power; seeds 2..7 spread by 0.08 %). The RSM's points are point lights: where a
// wall is within the light's size of it the flux lands slightly off, a bias that shrinks with
// more points (measured on llvmpipe: +0.35 % at 4 points a triangle, +0.1 % at 16, the same at
// 64^2 and 128^2 texels a face).
TEST(GiRaster, EmitterRsmCarriesTheReflectedPowerOfTheEmitters) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  {
    prt::Mesh m;
    const double a = 1000;
    m.positions = {{-a, -a, 0}, {a, -a, 0}, {a, a, 0}, {-a, a, 0}, {-0.1, -0.05, 1}, {0.0, 0.1, 1}, {0.1, -0.05, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}};  // the emitter clockwise seen from above: facing down
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, -1}, {0, 0, -1}, {0, 0, -1}};
    gi::Material ground;
    ground.albedo = glm::dvec3(0.5, 0.6, 0.7);
    gi::Scene s = gi::scene_from_mesh(m, ground);
    gi::Material light;
    light.albedo = glm::dvec3(0.0);
    light.emission = glm::dvec3(1.0, 2.0, 3.0);
    light.one_sided = true;
    s.materials = {ground, light};
    s.material = {0, 0, 1};
    const double A = 0.5 * glm::length(glm::cross(m.positions[5] - m.positions[4], m.positions[6] - m.positions[4]));
    gi::LpvOptions o;
    o.grid = 4;
    for (const int res : {8, 32}) {
      o.emitter_rsm = res;
      double secs = -1;
      const std::vector<gi::Vpl> v = gi::lpv_vpls_emitter_rsm(s, o, gi::lpv_grid(s, o.grid), 4, &secs);
      EXPECT_GE(secs, 0.0);
      glm::dvec3 F(0.0);
      for (const auto& x : v) {
        F += x.flux;
        ASSERT_NEAR(x.n.z, 1.0, 1e-6) << "a VPL on the square, facing the light";
      }
      const glm::dvec3 exact = ground.albedo * light.emission * (std::numbers::pi * A);
      const double rel = max3((F - exact) / exact);
      std::printf("emitter RSM %d^2 a face, 4 points: %zu VPLs, flux %.6g (rho pi L A %.6g), relative difference %.2e\n",
                  res, v.size(), F.x, exact.x, rel);
      EXPECT_LT(rel, res == 8 ? 2e-2 : 2e-3) << res;
    }
  }
  {
    const gi::Scene s = gi::builtin_scene("cornell-box");
    gi::LpvOptions o;
    o.grid = 8;
    o.emitter_rsm = 32;
    const gi::LpvGrid empty = gi::lpv_grid(s, o.grid);
    o.emitter_photons = 1 << 20;
    const std::vector<gi::Vpl> rsm = gi::lpv_vpls_emitter_rsm(s, o, empty, 4), ph = gi::lpv_vpls(s, o, empty);
    glm::dvec3 fr(0.0), fp(0.0), f16(0.0);
    for (const auto& v : rsm) fr += v.flux;
    for (const auto& v : ph) fp += v.flux;
    for (const auto& v : gi::lpv_vpls_emitter_rsm(s, o, empty, 16)) f16 += v.flux;
    const double rel = max3(fr - fp) / max3(fp), rel16 = max3(f16 - fp) / max3(fp);
    std::printf("cornell-box: emitter RSM %zu VPLs, flux %.6g (16 points: %.6g); photons %zu VPLs, flux %.6g; relative "
                "difference %.2e (16 points: %.2e)\n",
                rsm.size(), fr.x, f16.x, ph.size(), fp.x, rel, rel16);
    EXPECT_LT(rel, 6e-3);  // the 4 points' bias (+0.35 %) and the photons' spread (0.08 %)
    EXPECT_LT(rel16, rel) << "the point lights' bias shrinks with more points";
    for (const auto& v : rsm) ASSERT_NEAR(glm::length(v.n), 1.0, 1e-5);
  }
}

TEST(GiRaster, LpvFrameOnTheGpuAgainstThePathTracer) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  const gi::Scene s = sunlit("box-occluder", 135, 40);
  const int W = 32, H = 32;
  gi::TraceOptions t;
  t.samples = 64;
  t.seed = 11;
  t.bounces = 2;
  const gi::RadianceImage ref = gi::render(s, s.camera, W, H, t);
  gi::LpvOptions o;
  o.grid = 8;
  o.samples = 1;
  const gi::Lpv lc = gi::build_lpv(s, o);
  gi::Lpv lg;
  lg.iterations = lc.iterations;
  lg.injected = gi::lpv_inject_gpu(s, o);
  lg.geometry = gi::lpv_geometry_gpu(s, lg.injected);
  lg.accumulated = gi::lpv_propagate_gpu(lg.injected, &lg.geometry, lg.iterations);
  const gi::ImageError ec = gi::image_error(gi::render_lpv_gbuffer(s, s.camera, W, H, lc, o, false), ref);
  const gi::ImageError eg = gi::image_error(gi::render_lpv_gbuffer(s, s.camera, W, H, lg, o, true), ref);
  std::printf("LPV frame vs path tracer (2 bounces): CPU rms %.4f max %.4f mean %.4f; GPU (raster + RSM) rms %.4f max %.4f "
              "mean %.4f\n",
              ec.rms_rel, ec.max_rel, ec.mean_rel, eg.rms_rel, eg.max_rel, eg.mean_rel);
  EXPECT_TRUE(std::isfinite(eg.rms_rel));
  EXPECT_LT(eg.rms_rel, ec.rms_rel + 0.02);
  EXPECT_NEAR(eg.mean_rel, ec.mean_rel, 0.01);
}

// Stiff lights: the sun at the zenith (the shadow map's axis along z: its other frame branch)
// gives E_sun exactly on the plane outside the sphere's shadow disc (r = 0.5 about the origin)
// and 0 inside it; a sun 0.5 degrees above the horizon and a sky of 1e15 stay finite.
TEST(GiRaster, StiffLightsStayFiniteAndTheZenithSunIsExact) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  for (double el : {90.0, 0.5}) {
    gi::Scene s = sunlit("sphere-on-plane", 135, el);
    s.env_bands = 1;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = {1e15};
    gi::ShadowMapOptions so;
    so.sky_directions = 16;
    const Pixels g = spread(gi::radiosity_gbuffer_gpu(s, s.camera, 24, 24, 1, 1, 0, so), 24, 24);
    s.env_bands = 0;
    const Pixels sun = spread(gi::radiosity_gbuffer_gpu(s, s.camera, 24, 24, 1, 1), 24, 24);
    std::size_t open = 0, shade = 0;
    for (std::size_t i = 0; i < g.hit.size(); ++i) {
      if (!g.hit[i]) continue;
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(g.E[i][c]) && g.E[i][c] >= 0) << el << " pixel " << i;
        ASSERT_TRUE(std::isfinite(sun.E[i][c]) && sun.E[i][c] >= 0) << el << " pixel " << i;
      }
      if (el != 90.0 || std::abs(sun.p[i].z) > 1e-6) continue;  // plane receivers, zenith sun
      const double r = std::hypot(sun.p[i].x, sun.p[i].y);
      if (r > 0.53) {
        ++open;
        EXPECT_NEAR(sun.E[i].x, 3.0, 3e-6) << "pixel " << i;
      } else if (r < 0.45) {
        ++shade;
        EXPECT_EQ(sun.E[i].x, 0.0) << "pixel " << i;
      }
    }
    if (el == 90.0) {
      EXPECT_GT(open, 100u);
      EXPECT_GT(shade, 3u);
    }
  }
}

// Bad input is InputError before any GPU work.
TEST(GiRaster, BadShadowOptionsAreInputErrors) {
  const gi::Scene s = sunlit("sphere-on-plane", 135, 40);
  gi::ShadowMapOptions so;
  so.resolution = 8;
  EXPECT_THROW(gi::radiosity_gbuffer_gpu(s, s.camera, 8, 8, 1, 1, 0, so), InputError);
  so = {};
  so.pcf = 9;
  EXPECT_THROW(gi::radiosity_gbuffer_gpu(s, s.camera, 8, 8, 1, 1, 0, so), InputError);
  so = {};
  so.bias = -1;
  EXPECT_THROW(gi::radiosity_gbuffer_gpu(s, s.camera, 8, 8, 1, 1, 0, so), InputError);
  so = {};
  so.emitter_points = 65;
  EXPECT_THROW(gi::radiosity_gbuffer_gpu(s, s.camera, 8, 8, 1, 1, 0, so), InputError);
  so = {};
  so.emitter_resolution = 8;
  EXPECT_THROW(gi::radiosity_gbuffer_gpu(s, s.camera, 8, 8, 1, 1, 0, so), InputError);
  so = {};
  so.sky_directions = 2000;
  EXPECT_THROW(gi::radiosity_gbuffer_gpu(s, s.camera, 8, 8, 1, 1, 0, so), InputError);
  so = {};
  so.sky_resolution = 4;
  EXPECT_THROW(gi::radiosity_gbuffer_gpu(s, s.camera, 8, 8, 1, 1, 0, so), InputError);
  EXPECT_THROW(gi::radiosity_gbuffer_gpu(s, s.camera, 0, 8, 1, 1), InputError);
}

}  // namespace
#endif  // ATMOSH_GI_HAVE_GPU
