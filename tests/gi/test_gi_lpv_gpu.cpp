// The GPU-resident LPV frame (gi::LpvFrameGpu over gpu::GiLpvFrame: G-buffer, shadow map, RSM,
// injection, geometry volume, propagation and application in one context, only the image read
// back) against the CPU LPV (double) on the same inputs: the RSM's VPLs read back
// (lpv_vpls_rsm: the same rasterisation) and the frame's emitter VPLs injected by lpv_add_vpl,
// lpv_geometry, lpv_propagate, and shade_lpv_receivers_cpu on the rasterised G-buffer
// (radiosity_gbuffer_gpu: the same direct light). Both use the shared block
// atmosh/gi/shared/lpv.glsl.hpp (compiled as C++ in double and as GLSL in float), so they must
// agree within float rounding; the LPV's own closed forms (flux conservation, a VPL's falloff,
// the face solid angles) are tested on the CPU in test_gi_lpv.cpp. Mesa llvmpipe or any EGL
// device; skipped without a context (ATMOSH_REQUIRE_GPU_CONTEXT=1 makes that a failure).
#ifdef ATMOSH_GI_HAVE_GPU
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "atmosh/error.hpp"
#include "atmosh/gi/lpv.hpp"
#include "atmosh/gi/radiosity.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/gi/shared/lpv.glsl.hpp"
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/gi_raster.hpp"

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

struct Case {
  const char* name;
  gi::Scene scene;
};

// The largest coefficient of the CPU grid `acc` (scale) and the largest difference of `gpu` from it.
void grid_difference(const gi::LpvGrid& acc, const gi::LpvGrid& gpu, double& scale, double& worst) {
  for (std::size_t c = 0; c < acc.cells.size(); ++c)
    for (int q = 0; q < 12; ++q) {
      scale = std::max(scale, std::abs(acc.cells[c][q]));
      worst = std::max(worst, std::abs(acc.cells[c][q] - gpu.cells[c][q]));
    }
}

// The 2-level nested cascade in the resident frame (LpvFrameGpu with cascades = 2: the RSM at
// the fine level's density, the VPLs split by the fine box, three grids propagated and blended, on
// the GPU with one read-back) against the CPU cascade in double on the same VPLs
// (lpv_cascade_from_vpls: the RSM's VPLs of lpv_vpls_rsm at the fine cell edge and the frame's
// emitter VPLs; its own geometry volumes and propagation; lpv_cascade_irradiance at the
// rasterised G-buffer, applied as L = L_e + a / pi max(0, E_direct + E_lpv)). The same shared
// functions on both sides (gi_lpv_in_box, gi_lpv_cascade_weight, gi_lpv_cascade_blend and the
// one-level LPV's), so agreement within float rounding. Run inside the one-level test: the same
// scene, lights, map options and G-buffer (the same GL state, so llvmpipe's shader cache serves
// this frame's programs), a smaller grid. The cascade runs with Kaplanyan & Dachsbacher 2010's
// re-emission (LpvReemission::face_lobe, the propagation shader's uniform) on both sides, so the
// published variant is checked in the resident frame without another frame or compilation; the
// one-level frame above keeps the default.
gi::LpvOptions cascade_options() {
  gi::LpvOptions o;
  o.reemission = gi::LpvReemission::face_lobe;
  o.grid = 6;
  o.iterations = 8;
  o.sun_rays = 2;
  o.emitter_photons = 4096;
  return o;
}

void expect_cascade_agrees(const gi::Scene& s, const gi::ShadowMapOptions& so, int W, int H,
                           const gi::RadiosityGBuffer& gb, const gi::LpvCascadeLayout& layout,
                           std::vector<gi::Vpl> vpls) {
  const gi::LpvOptions o = cascade_options();
  const std::size_t n_rsm = vpls.size();
  gi::LpvFrameGpu frame(s, o, so, 2);
  ASSERT_NE(frame.cascade(), nullptr);
  gi::LpvGrid outer_gpu, inner_gpu, fine_gpu;
  const gi::RadianceImage img = frame.render(s.camera, W, H, &outer_gpu, &inner_gpu, &fine_gpu);
  vpls.insert(vpls.end(), frame.emitter_vpls().begin(), frame.emitter_vpls().end());
  const gi::LpvCascade c = gi::lpv_cascade_from_vpls(s, o, layout, vpls);
  // every level's accumulated grid, against the largest coefficient of the three
  const std::pair<const gi::LpvGrid*, const gi::LpvGrid*> levels[3] = {
      {&c.outer.accumulated, &outer_gpu}, {&c.inner.accumulated, &inner_gpu}, {&c.fine.accumulated, &fine_gpu}};
  double scale = 0, worst = 0;
  for (const auto& [cpu, gpu] : levels) {
    ASSERT_EQ(cpu->cells.size(), gpu->cells.size());
    for (std::size_t k = 0; k < cpu->cells.size(); ++k)
      for (int q = 0; q < 12; ++q) scale = std::max(scale, std::abs(cpu->cells[k][q]));
  }
  ASSERT_GT(scale, 0);
  const double f_outer = gi::lpv_flux(c.outer.injected).x, f_inner = gi::lpv_flux(c.inner.injected).x;
  ASSERT_GT(f_outer, 0) << "cascade: VPLs outside the fine box";
  ASSERT_GT(f_inner, 0) << "cascade: VPLs inside the fine box";
  for (const auto& [cpu, gpu] : levels)
    for (std::size_t k = 0; k < cpu->cells.size(); ++k)
      for (int q = 0; q < 12; ++q) worst = std::max(worst, std::abs(cpu->cells[k][q] - gpu->cells[k][q]));
  EXPECT_LT(worst, 1e-4 * scale) << "cascade: accumulated grids";
  const gi::LpvGrid& g = c.outer.accumulated;
  const glm::dvec3 hi = g.lo + g.h * glm::dvec3(g.nx, g.ny, g.nz);
  double lmax = 0, lworst = 0, ind = 0, wsum = 0;
  for (std::size_t r = 0; r < gb.receivers.size(); ++r) {
    const glm::dvec3 x = gb.receivers.position[r], n = gb.receivers.normal[r];
    const glm::dvec3 E = gi::lpv_cascade_irradiance(c, x, n);
    const glm::dvec3 L = gb.receivers.emission[r] + gb.receivers.albedo[r] / 3.14159265358979324 *
                                                        glm::max(gb.receivers.direct[r] + E, glm::dvec3(0.0));
    wsum += gi::shared::gi_lpv_cascade_weight(x, c.fine_lo, c.fine_hi, g.lo, hi, g.h);
    const std::size_t px = gb.pixel[r];
    for (int ch = 0; ch < 3; ++ch) {
      ASSERT_TRUE(std::isfinite(img.mean[ch][px])) << "cascade";
      lmax = std::max(lmax, L[ch]);
      lworst = std::max(lworst, std::abs(img.mean[ch][px] - L[ch]));
      ind = std::max(ind, gb.receivers.albedo[r][ch] / 3.14159265358979324 * E[ch]);
    }
  }
  ASSERT_GT(ind, 0) << "cascade: the cascade adds light";
  ASSERT_GT(wsum, 0) << "cascade: some receivers read the fine level";
  EXPECT_LT(lworst, 1e-4 * lmax) << "cascade: image";
  EXPECT_LT(lworst, 3e-4 * ind) << "cascade: image against the LPV's part";
  std::printf("cascade (grid 6): %zu RSM + %zu emitter VPLs (flux outer %.4g, inner %.4g); resident cascade vs CPU "
              "cascade: grids %.3g of the largest coefficient, image %.3g of the largest radiance, %.3g of the largest "
              "LPV part; mean fine weight %.3f; frame %.3f s\n",
              n_rsm, frame.emitter_vpls().size(), f_outer, f_inner, worst / scale, lworst / lmax, lworst / ind,
              wsum / static_cast<double>(gb.receivers.size()), img.stats.seconds);
}

TEST(GiLpvGpu, ResidentFrameAgreesWithTheCpuLpv) {
  std::string why;
  if (no_gpu(why)) {
    if (std::getenv("ATMOSH_REQUIRE_GPU_CONTEXT")) FAIL() << why;
    GTEST_SKIP() << why;
  }
  // One scene with every light (a frame compiles its programs once, so one frame keeps the
  // test short): the Cornell box's area light (emitter distance maps, emitter VPLs), a sun
  // through its open front (shadow map, RSM VPLs) and a uniform sky (depth maps).
  std::vector<Case> cases;
  {
    gi::Scene s = gi::builtin_scene("cornell-box");
    s.sun = gi::Sun{gi::sun_direction(s, 200, 30), glm::dvec3(1.0, 0.8, 0.6)};
    s.env_bands = 1;
    for (int c = 0; c < 3; ++c) s.env_sh[c] = {0.3 * 2 * std::sqrt(3.14159265358979324)};
    cases.push_back({"cornell-box + sun + sky", s});
  }
  const int W = 48, H = 40;
  for (const Case& k : cases) {
    const gi::Scene& s = k.scene;
    gi::LpvOptions o;
    o.grid = 8;
    o.iterations = 12;
    o.sun_rays = 4;
    o.emitter_photons = 4096;
    gi::ShadowMapOptions so;
    so.sky_directions = 16;
    so.sky_resolution = 128;
    so.emitter_resolution = 128;
    // The CPU side's rasterised inputs first: every gpu::Context that ends terminates the EGL
    // display it shares with the frame's (gpu/context.cpp), so none may end while the frame lives.
    gi::LpvGrid inj = gi::lpv_grid(s, o.grid);
    std::vector<gi::Vpl> vpls = gi::lpv_vpls_rsm(s, o, inj);
    const std::size_t n_rsm = vpls.size();
    const gi::RadiosityGBuffer gb = gi::radiosity_gbuffer_gpu(s, s.camera, W, H, 1, 1, 0, so);
    const gi::LpvCascadeLayout layout = gi::lpv_cascade_layout(s, cascade_options());
    const std::vector<gi::Vpl> vpls_fine = gi::lpv_vpls_rsm(s, cascade_options(), layout.fine);
    {  // the one-level frame (ended before the cascade's)
      gi::LpvFrameGpu frame(s, o, so);
      gi::LpvGrid acc_gpu;
      const gi::RadianceImage img = frame.render(s.camera, W, H, &acc_gpu);
      // the CPU LPV on the same VPLs
      vpls.insert(vpls.end(), frame.emitter_vpls().begin(), frame.emitter_vpls().end());
      ASSERT_GT(vpls.size(), 100u) << k.name;
      for (const gi::Vpl& v : vpls) gi::lpv_add_vpl(inj, v.p, v.n, v.flux);
      const gi::GeometryVolume gv = gi::lpv_geometry(s, inj);
      const gi::LpvGrid acc = gi::lpv_propagate(inj, &gv, o.iterations);
      double scale = 0, worst = 0;
      grid_difference(acc, acc_gpu, scale, worst);
      ASSERT_GT(scale, 0) << k.name;
      EXPECT_LT(worst, 1e-4 * scale) << k.name << ": accumulated grid";
      // the image: the CPU application on the rasterised G-buffer
      const std::vector<glm::dvec3> L = gi::shade_lpv_receivers_cpu(acc, gb.receivers);
      std::vector<char> hit(static_cast<std::size_t>(W) * H, 0);
      double lmax = 0, lworst = 0, ind = 0;
      for (std::size_t r = 0; r < L.size(); ++r) {
        const std::size_t px = gb.pixel[r];
        hit[px] = 1;
        for (int c = 0; c < 3; ++c) {
          lmax = std::max(lmax, L[r][c]);
          ASSERT_TRUE(std::isfinite(img.mean[c][px])) << k.name;
          lworst = std::max(lworst, std::abs(img.mean[c][px] - L[r][c]));
          // the LPV's part of the CPU's radiance
          ind = std::max(ind, L[r][c] - gb.receivers.emission[r][c] -
                                  gb.receivers.albedo[r][c] / 3.14159265358979324 * gb.receivers.direct[r][c]);
        }
      }
      ASSERT_GT(ind, 0) << k.name << ": the LPV adds light";
      EXPECT_LT(lworst, 1e-4 * lmax) << k.name << ": image";
      EXPECT_LT(lworst, 3e-4 * ind) << k.name << ": image against the LPV's part";
      // misses: the environment (box-occluder's sky), exactly as the CPU's background
      for (std::size_t i = 0; i < hit.size(); ++i)
        if (!hit[i])
          for (int c = 0; c < 3; ++c) ASSERT_NEAR(img.mean[c][i], gb.background[i][c], 1e-6) << k.name;
      std::printf("%s: %zu RSM + %zu emitter VPLs; resident frame vs CPU LPV: grid %.3g of the largest coefficient, "
                  "image %.3g of the largest radiance, %.3g of the largest LPV part; frame %.3f s\n",
                  k.name, n_rsm, frame.emitter_vpls().size(), worst / scale, lworst / lmax, lworst / ind,
                  img.stats.seconds);
    }
    expect_cascade_agrees(s, so, W, H, gb, layout, vpls_fine);
  }
}

// The resident frame keeps the lights' maps (the sun's shadow map, the emitters' distance maps,
// the sky's depth maps) between frames and remakes a map only when its inputs change
// (gpu/src/gi_raster.cpp, LightMaps). Checked at gpu::GiLpvFrame, where the lights are given per
// frame: one frame object rendered again after each change — the sun moved, the sky's radiance
// doubled (its depth maps kept, its buffer new), its directions turned, the shadow map's
// resolution changed — must give the image of a fresh frame object for the same lights, and the
// same image again when nothing changed. No VPLs and no propagation (iterations 0): the image is
// the direct light alone, L = L_e + a / pi max(0, E_sun + E_sky), whose every part comes from
// the maps under test. Same programs and inputs in one context, so the images agree to float
// rounding (bound 1e-6 of the largest radiance; measured 0 on Mesa llvmpipe).
TEST(GiLpvGpu, ResidentFrameRemakesALightMapWhenItsLightChanges) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  const gi::Scene s = gi::builtin_scene("box-occluder");
  const std::size_t nt = s.mesh.triangles.size();
  std::vector<glm::dvec3> normal(nt), albedo(nt), emission(nt);
  std::vector<std::uint8_t> one_sided(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tv = s.mesh.triangles[t];
    const auto& P = s.mesh.positions;
    normal[t] = glm::normalize(glm::cross(P[tv[1]] - P[tv[0]], P[tv[2]] - P[tv[0]]));
    const gi::Material& m = s.materials[s.material[t]];
    albedo[t] = m.albedo, emission[t] = m.emission, one_sided[t] = m.one_sided ? 1 : 0;
  }
  gpu::GiMeshView mv;
  mv.positions = &s.mesh.positions, mv.triangles = &s.mesh.triangles, mv.normal = &normal;
  mv.albedo = &albedo, mv.emission = &emission, mv.one_sided = &one_sided;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : s.mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  gpu::GiLpvGrid grid;
  grid.h = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) / 4 * 1.001;
  grid.lo = lo - 0.0005 * grid.h;
  grid.nx = grid.ny = grid.nz = 4;
  gpu::PrtCamera cam;
  const glm::dvec3 f = glm::normalize(s.camera.forward), right = glm::normalize(glm::cross(f, s.camera.up));
  cam.eye = s.camera.eye, cam.right = right, cam.up = glm::cross(right, f), cam.back = -f;
  cam.tan_half_fov = std::tan(0.5 * s.camera.vertical_fov_deg * std::numbers::pi / 180);
  cam.width = 48, cam.height = 40;
  // 24 spherical-Fibonacci directions over the sphere, turned about z by `turn` radians.
  auto sky = [](double scale, double turn) {
    gpu::GiSkyOptions k;
    k.resolution = 64;
    const int n = 24;
    for (int i = 0; i < n; ++i) {
      const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z);
      const double phi = i * std::numbers::pi * (3 - std::sqrt(5.0)) + turn;
      k.directions.push_back({r * std::cos(phi), r * std::sin(phi), z});
      k.radiance.push_back(scale * glm::dvec3(0.1, 0.2, 0.3) * (4 * std::numbers::pi / n));
    }
    return k;
  };
  gpu::GiSun sun1, sun2;
  sun1.direction = glm::normalize(glm::dvec3(0.3, 0.4, 0.87));
  sun2.direction = glm::normalize(glm::dvec3(-0.5, 0.2, 0.84));
  auto options = [](const gpu::GiSun* sun, const gpu::GiSkyOptions* k, int shadow_res) {
    gpu::GiLpvFrameOptions o;
    o.iterations = 0;
    o.blocking = false;
    o.sun = sun;
    o.sun_irradiance = glm::dvec3(3.0, 2.0, 1.0);
    o.shadow.resolution = shadow_res;
    o.sky = k;
    return o;
  };
  const gpu::Context ctx;
  gpu::GiLpvFrame frame(ctx, mv, grid, {}, {});
  auto differs = [&](const gpu::GiLpvFrameResult& a, const gpu::GiLpvFrameResult& b) {
    double worst = 0, top = 0;
    for (std::size_t i = 0; i < a.radiance.size(); ++i) {
      worst = std::max(worst, static_cast<double>(std::abs(a.radiance[i] - b.radiance[i])));
      top = std::max(top, static_cast<double>(std::abs(b.radiance[i])));
    }
    return worst / std::max(top, 1e-30);
  };
  auto fresh = [&](const gpu::GiLpvFrameOptions& o) {
    gpu::GiLpvFrame f2(ctx, mv, grid, {}, {});
    return f2.render(cam, o);
  };
  const gpu::GiSkyOptions k1 = sky(1, 0), k2 = sky(2, 0), k3 = sky(2, 0.4);
  const gpu::GiLpvFrameResult r1 = frame.render(cam, options(&sun1, &k1, 256));
  EXPECT_EQ(differs(frame.render(cam, options(&sun1, &k1, 256)), r1), 0.0) << "the same lights again";
  EXPECT_LE(differs(r1, fresh(options(&sun1, &k1, 256))), 1e-6) << "first frame";
  struct Step {
    const char* what;
    gpu::GiLpvFrameOptions o;
  };
  for (const Step& st : {Step{"sun moved", options(&sun2, &k1, 256)}, Step{"sky radiance doubled", options(&sun2, &k2, 256)},
                         Step{"sky directions turned", options(&sun2, &k3, 256)},
                         Step{"shadow map resolution", options(&sun2, &k3, 512)}, Step{"sun removed", options(nullptr, &k3, 512)},
                         Step{"sky removed", options(&sun1, nullptr, 512)}}) {
    const gpu::GiLpvFrameResult kept = frame.render(cam, st.o), made = fresh(st.o);
    const double d = differs(kept, made);
    std::printf("%s: kept-map frame vs a fresh frame %.3g of the largest radiance\n", st.what, d);
    EXPECT_LE(d, 1e-6) << st.what;
  }
  // Each change above alters the image (so that a map wrongly kept would show).
  EXPECT_GT(differs(fresh(options(&sun2, &k1, 256)), r1), 1e-3);
  EXPECT_GT(differs(fresh(options(&sun2, &k2, 256)), fresh(options(&sun2, &k1, 256))), 1e-3);
  EXPECT_GT(differs(fresh(options(&sun2, &k3, 256)), fresh(options(&sun2, &k2, 256))), 1e-4);
}

// The resident frame with the area emitters' RSMs instead of their photon VPLs (LpvOptions::
// emitter_rsm): its accumulated grid against the CPU LPV (double) fed the same VPLs, read back
// from the same rasterisation (lpv_vpls_emitter_rsm). Agreement within float rounding, as
// ResidentFrameAgreesWithTheCpuLpv; the RSM's own flux is checked against a closed form and the
// photons in test_gi_raster.cpp.
TEST(GiLpvGpu, ResidentFrameWithTheEmittersRsmAgreesWithTheCpuLpv) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::LpvOptions o;
  o.grid = 8;
  o.iterations = 12;
  o.emitter_rsm = 16;
  gi::ShadowMapOptions so;
  so.emitter_resolution = 64;
  gi::LpvGrid inj = gi::lpv_grid(s, o.grid);
  // the CPU side's rasterised input first (no context may end while the frame's lives)
  const std::vector<gi::Vpl> vpls = gi::lpv_vpls_emitter_rsm(s, o, inj, so.emitter_points);
  ASSERT_GT(vpls.size(), 1000u);
  gi::LpvFrameGpu frame(s, o, so);
  EXPECT_TRUE(frame.emitter_vpls().empty()) << "no photon VPLs with the emitters' RSM";
  EXPECT_EQ(frame.rays(), 0u);
  gi::LpvGrid acc_gpu;
  const gi::RadianceImage img = frame.render(s.camera, 32, 32, &acc_gpu);
  for (const gi::Vpl& v : vpls) gi::lpv_add_vpl(inj, v.p, v.n, v.flux);
  const gi::GeometryVolume gv = gi::lpv_geometry(s, inj);
  const gi::LpvGrid acc = gi::lpv_propagate(inj, &gv, o.iterations);
  double scale = 0, worst = 0;
  grid_difference(acc, acc_gpu, scale, worst);
  ASSERT_GT(scale, 0);
  std::printf("cornell-box, emitters' RSM 16^2 a face: %zu VPLs; resident frame vs CPU LPV: grid %.3g of the largest "
              "coefficient\n",
              vpls.size(), worst / scale);
  EXPECT_LT(worst, 1e-4 * scale);
  for (int c = 0; c < 3; ++c)
    for (const float x : img.mean[c]) ASSERT_TRUE(std::isfinite(x));
  o.emitter_rsm = 1;
  EXPECT_THROW(gi::LpvFrameGpu(s, o, so), InputError);
  o.emitter_rsm = 1025;
  EXPECT_THROW(gi::lpv_vpls_emitter_rsm(s, o, inj), InputError);
}

TEST(GiLpvGpu, BadOptionsThrowInputError) {
  std::string why;
  if (no_gpu(why)) GTEST_SKIP() << why;
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::LpvOptions o;
  o.grid = 4;
  o.iterations = 1025;
  EXPECT_THROW(gi::LpvFrameGpu(s, o), InputError);
  o.iterations = 2;
  o.grid = 0;
  EXPECT_THROW(gi::LpvFrameGpu(s, o), InputError);
  o.grid = 4;
  gi::ShadowMapOptions so;
  so.emitter_points = 0;  // the area light would need the CPU's estimator
  EXPECT_THROW(gi::LpvFrameGpu(s, o, so), InputError);
  EXPECT_THROW(gi::LpvFrameGpu(s, o, {}, 3), InputError);  // cascades 1 or 2
  o.grid = 1;
  EXPECT_THROW(gi::LpvFrameGpu(s, o, {}, 2), InputError);  // a cascade needs grid >= 2
}

}  // namespace
#endif  // ATMOSH_GI_HAVE_GPU
