// The GPU depth-map method of per-pixel transfer (atmosh/gpu/prt.hpp) against the CPU
// ray-casting reference (prt::bake_pixels with the same camera and sample set): the
// two estimators differ only in the visibility test, so their difference must shrink
// as the depth map grows. Runs on Mesa llvmpipe in CI (skips only where no EGL
// context exists and ATMOSH_REQUIRE_GPU_CONTEXT is unset).
#if ATMOSH_HAVE_GPU
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../gpu/gpu_fixture.hpp"
#include "atmosh/error.hpp"
#include "atmosh/prt/bake.hpp"

namespace {
using namespace atmosh;

struct Diff {
  double rms = 0, max = 0, ao_mean = 0;  // transfer errors relative to max |T_ref|_2; mean |AO - AO_ref|
  double mask_mismatch = 0;              // fraction of pixels where exactly one sees a surface
};

Diff compare(const prt::PixelTransfer& a, const prt::PixelTransfer& ref) {
  const std::size_t K = static_cast<std::size_t>(ref.bands) * ref.bands, np = ref.mask.size();
  double scale = 0;
  for (std::size_t p = 0; p < np; ++p) {
    double s = 0;
    for (std::size_t i = 0; i < K; ++i) s += ref.coeffs[p * K + i] * ref.coeffs[p * K + i];
    scale = std::max(scale, std::sqrt(s));
  }
  Diff d;
  double n = 0, mismatch = 0, sum = 0, ao = 0;
  for (std::size_t p = 0; p < np; ++p) {
    if ((a.mask[p] != 0) != (ref.mask[p] != 0)) mismatch += 1;
    if (a.mask[p] == 0 || ref.mask[p] == 0) continue;
    double e = 0;
    for (std::size_t i = 0; i < K; ++i) e += std::pow(a.coeffs[p * K + i] - ref.coeffs[p * K + i], 2);
    d.max = std::max(d.max, std::sqrt(e) / scale);
    sum += e;
    ao += std::abs(a.ao[p] - ref.ao[p]);
    n += 1;
  }
  d.rms = std::sqrt(sum / n) / scale;
  d.ao_mean = ao / n;
  d.mask_mismatch = mismatch / static_cast<double>(np);
  return d;
}

TEST(GpuPrt, AgreesWithTheRayCastReferenceBetterWithLargerDepthMaps) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  ctx.reset();  // bake_pixels makes its own context
  const prt::Mesh m = prt::builtin_scene("sphere-on-plane", 24);
  prt::BakeOptions o;
  o.bands = 3;
  o.strata = 16;  // 256 directions
  o.threads = 2;
  const int W = 96;
  const glm::dvec3 view(1, -1.6, 1.1);
  const prt::PixelTransfer ref = prt::bake_pixels(m, o, W, W, view);
  o.device = prt::Device::gpu;
  double previous = 1e30;
  for (int D : {64, 256, 1024}) {
    o.depth_resolution = D;
    const prt::PixelTransfer g = prt::bake_pixels(m, o, W, W, view);
    ASSERT_EQ(g.device, prt::Device::gpu);
    EXPECT_EQ(g.depth_resolution, D);
    EXPECT_EQ(g.samples, ref.samples);
    for (double v : g.coeffs) ASSERT_TRUE(std::isfinite(v));
    const Diff d = compare(g, ref);
    std::printf("depth map %4d: transfer rms %.3e max %.3e, mean |dAO| %.3e, mask mismatch %.2e\n", D, d.rms, d.max,
                d.ao_mean, d.mask_mismatch);
    // Rasterised pixel centres and primary rays see the same surface points.
    EXPECT_LT(d.mask_mismatch, 2e-3);
    EXPECT_LT(d.rms, previous);
    previous = d.rms;
    if (D == 1024) {
      EXPECT_LT(d.rms, 5e-3);
      EXPECT_LT(d.ao_mean, 3e-3);
    }
  }
}

TEST(GpuPrt, ConvexObjectCastsNoShadowOnItself) {
  // A lone convex sphere: shadowed = unshadowed transfer; the depth-map biases must
  // not shadow a surface by itself (acne), even at grazing sample directions.
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  ctx.reset();
  const prt::Mesh m = prt::builtin_scene("sphere", 32);
  prt::BakeOptions o;
  o.bands = 3;
  o.strata = 12;
  o.device = prt::Device::gpu;
  o.depth_resolution = 512;
  const prt::PixelTransfer sh = prt::bake_pixels(m, o, 64, 64, {0.2, -1, 0.4});
  o.mode = sh::prt::TransferMode::unshadowed;
  const prt::PixelTransfer un = prt::bake_pixels(m, o, 64, 64, {0.2, -1, 0.4});
  double worst = 0, covered = 0;
  for (std::size_t p = 0; p < sh.mask.size(); ++p) {
    ASSERT_EQ(sh.mask[p], un.mask[p]);
    if (sh.mask[p] == 0) continue;
    covered += 1;
    worst = std::max(worst, std::abs(sh.ao[p] - un.ao[p]));
  }
  EXPECT_GT(covered, 500);
  // One lost sample direction at the horizon costs (4 pi / N) cos / pi < 4/144 cos;
  // grazing directions (cos < 0.05) may flip: bound 0.05 * 4/144 * (a few).
  EXPECT_LT(worst, 5e-3);
}

TEST(GpuPrt, MoreBandsThanOnePassHoldsAgreeWithTheCpu) {
  // L = 6: 36 coefficients + the AO sum exceed 8 targets x 4 channels, so every
  // direction takes two accumulation passes.
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  ctx.reset();
  prt::Mesh m = prt::builtin_scene("box-occluder", 8);
  m.albedo.assign(m.positions.size(), 0.8);  // one albedo, so that band 0 gives AO directly
  prt::BakeOptions o;
  o.bands = 6;
  o.strata = 8;
  o.threads = 2;
  const glm::dvec3 view(0.7, -1.2, 1.5);
  const prt::PixelTransfer ref = prt::bake_pixels(m, o, 48, 48, view);
  o.device = prt::Device::gpu;
  o.depth_resolution = 1024;
  const prt::PixelTransfer g = prt::bake_pixels(m, o, 48, 48, view);
  const Diff d = compare(g, ref);
  std::printf("L = 6, box-occluder: transfer rms %.3e max %.3e, mean |dAO| %.3e\n", d.rms, d.max, d.ao_mean);
  // 64 directions: one direction flipped at a shadow edge moves T by (4 pi / 64) of a term.
  EXPECT_LT(d.rms, 2e-2);
  EXPECT_LT(d.ao_mean, 2e-3);
  // Band 0 is ambient occlusion (sh/prt.hpp): both outputs agree with each other.
  for (std::size_t p = 0; p < g.mask.size(); ++p)
    if (g.mask[p] != 0) {
      ASSERT_NEAR(sh::prt::ambient_occlusion(g.coeffs[p * 36], 0.8), g.ao[p], 1e-5);
    }
}

}  // namespace
#endif
