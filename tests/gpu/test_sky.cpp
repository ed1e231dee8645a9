// GPU sky images against the CPU path (SkyIntegrator / atmo::render_sky, double):
// the same spectral radiance within float precision where it is above 1e-6 of its
// maximum, finite values in the stiff cases, and a clean Unsupported for inputs
// the GPU pass does not handle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <utility>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/error.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/shared/sky_params.glsl.hpp"
#include "atmosh/gpu/program.hpp"
#include "atmosh/atmo/shared/orders.glsl.hpp"
#include "atmosh/gpu/sky.hpp"
#include "gpu_fixture.hpp"

using namespace atmosh::atmo;
namespace gpu = atmosh::gpu;

namespace {

AtmosphereSpec earth16() {
  AtmosphereSpec spec = preset("earth-physical");
  spec.spectrum.wavelengths_nm.clear();
  spec.spectrum.from_nm = 380;
  spec.spectrum.to_nm = 780;
  spec.spectrum.count = 16;
  return spec;
}

struct Diff {
  double max_rel = 0.0;  // over samples above 1e-6 of the maximum
  double max_rgb_rel = 0.0;
  long compared = 0;
  bool finite = true;
};

Diff compare(const SkyImage& g, const SkyImage& c) {
  Diff d;
  float peak = 0.0f;
  for (float v : c.spectral) peak = std::max(peak, v);
  for (std::size_t i = 0; i < c.spectral.size(); ++i) {
    if (!std::isfinite(g.spectral[i]) || g.spectral[i] < 0.0f) d.finite = false;
    if (c.spectral[i] > 1e-6f * peak) {
      d.max_rel = std::max(d.max_rel, std::fabs(double(g.spectral[i]) - c.spectral[i]) / c.spectral[i]);
      ++d.compared;
    }
  }
  float ypeak = *std::max_element(c.Y.begin(), c.Y.end());
  for (std::size_t p = 0; p < c.Y.size(); ++p)
    if (c.Y[p] > 1e-6f * ypeak) d.max_rgb_rel = std::max(d.max_rgb_rel, std::fabs(double(g.Y[p]) - c.Y[p]) / c.Y[p]);
  return d;
}

}  // namespace

// Float GPU against double CPU on the physically based Earth (Rayleigh, Mie,
// ozone tent), 16 wavelengths, sun high, low and below the horizon.
TEST(GpuSky, MatchesTheCpuImage) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  const AtmosphereSpec spec = earth16();
  const Atmosphere atm(spec);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
  ASSERT_EQ(gpu::sky_unsupported_reason(sky), "");
  double worst = 0.0;
  for (auto [proj, w, h, sun_el, alt] : {std::tuple{SkyProjection::Equirect, 64, 32, 30.0, 0.0},
                                         std::tuple{SkyProjection::Equirect, 64, 32, 2.0, 0.0},
                                         std::tuple{SkyProjection::Equirect, 48, 24, -4.0, 0.0},
                                         std::tuple{SkyProjection::Fisheye, 32, 32, 10.0, 1500.0}}) {
    const glm::dvec3 sun = enu_direction_from_zenith(90.0 - sun_el, 135.0);
    const SkyImage c = render_sky(sky, proj, w, h, alt, sun, true, 2);
    const SkyImage g = gpu::render_sky(*ctx, sky, proj, w, h, alt, sun, true);
    ASSERT_EQ(g.spectral.size(), c.spectral.size());
    EXPECT_EQ(g.valid, c.valid);
    const Diff d = compare(g, c);
    EXPECT_TRUE(d.finite);
    EXPECT_GT(d.compared, 0);
    std::printf("  sun %+5.1f deg alt %6.0f m %dx%d: max rel diff %.3g (spectral), %.3g (Y), %ld samples\n", sun_el,
                alt, w, h, d.max_rel, d.max_rgb_rel, d.compared);
    EXPECT_LT(d.max_rel, 1e-4) << "sun elevation " << sun_el;
    worst = std::max(worst, d.max_rel);
    // Everything on the GPU: tables rebuilt by the compute shader.
    const SkyImage gt = gpu::render_sky(*ctx, sky, proj, w, h, alt, sun, true, /*gpu_tables=*/true);
    const Diff dt = compare(gt, c);
    std::printf("    with GPU-built tables: max rel diff %.3g\n", dt.max_rel);
    EXPECT_TRUE(dt.finite);
    EXPECT_LT(dt.max_rel, 1e-4) << "GPU tables, sun elevation " << sun_el;
    worst = std::max(worst, dt.max_rel);
  }
  std::printf("  worst GPU/CPU relative difference: %.3g\n", worst);
}

// Stiff cases of the atmosphere tests on the GPU: finite and non-negative.
TEST(GpuSky, StiffCasesAreFinite) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  auto finite = [](const SkyImage& img) {
    for (float v : img.spectral)
      if (!std::isfinite(v) || v < 0.0f) return false;
    for (float v : img.Y)
      if (!std::isfinite(v)) return false;
    return true;
  };
  AtmosphereSpec spec = earth16();
  const Atmosphere atm(spec);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
  // Deep twilight, observer on the ground, just above it, at the top and in space.
  for (double sun_el : {-18.0, -0.5})
    for (double alt : {0.0, 1e-6, 100e3, 1000e3})
      EXPECT_TRUE(finite(gpu::render_sky(*ctx, sky, SkyProjection::Equirect, 16, 8, alt,
                                         enu_direction_from_zenith(90.0 - sun_el, 0.0), true)))
          << sun_el << " " << alt;
  // Observer in space looking past the planet: black, as on the CPU.
  {
    const SkyImage g = gpu::render_sky(*ctx, sky, SkyProjection::Equirect, 32, 16, 1000e3,
                                       enu_direction_from_zenith(90.0, 0.0), true);
    EXPECT_EQ(g.spectral[0], 0.0f);  // zenith row: the ray never enters the atmosphere
  }
  // Huge optical depth and forward-peaked phase functions.
  AtmosphereSpec thick = spec;
  thick.mie->scattering_per_m *= 1e5;
  const Atmosphere a2(thick);
  const SkyIntegrator s2(a2, solar_spectrum_for_bins(thick.spectrum));
  EXPECT_TRUE(finite(gpu::render_sky(*ctx, s2, SkyProjection::Equirect, 16, 8, 0.0, enu_direction_from_zenith(89.5, 0.0), true)));
  for (double g : {0.999, -0.999}) {
    AtmosphereSpec pk = spec;
    pk.mie->phase = PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, g);
    const Atmosphere a3(pk);
    const SkyIntegrator s3(a3, solar_spectrum_for_bins(pk.spectrum));
    EXPECT_TRUE(finite(gpu::render_sky(*ctx, s3, SkyProjection::Equirect, 16, 8, 0.0, enu_direction_from_zenith(70.0, 0.0), true)));
  }
}

TEST(GpuSky, UnsupportedInputIsReportedNotRendered) {
  AtmosphereSpec spec = earth16();
  spec.mie->phase.model = PhaseSpec::Model::Tabulated;
  spec.mie->phase.cos_theta = {-1.0, 1.0};
  spec.mie->phase.value = {1.0, 1.0};
  const Atmosphere atm(spec);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
  EXPECT_NE(gpu::sky_unsupported_reason(sky), "");
  EXPECT_THROW(gpu::render_sky(sky, SkyProjection::Equirect, 8, 4, 0.0, {0, 0, 1}, false), gpu::Unsupported);
}

// The parameter block's C++ layout (shared/sky_params.glsl.hpp) is the driver's std430
// layout of the same struct: every member's offset as the program interface query
// reports it, and the last member's end within the C++ size.
TEST(GpuSky, ParameterBlockLayoutMatches) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  namespace sg = atmosh::atmo::shared;
  // every term compiled in, as for a sky with both tables (the blocks all in use)
  gpu::Program prog(gpu::sky_pass_parts(),
                    "#define ATMOSH_SKY_TRACE 1\n#define ATMOSH_SKY_MS 1\n#define ATMOSH_SKY_ORDERS 1\n");
  const std::vector<std::pair<const char*, std::size_t>> members = {
      {"params.ground_radius_d", offsetof(sg::GpuSkyParams, ground_radius_d)},
      {"params.top_radius_d", offsetof(sg::GpuSkyParams, top_radius_d)},
      {"params.observer_radius_d", offsetof(sg::GpuSkyParams, observer_radius_d)},
      {"params.horizon_rho_d", offsetof(sg::GpuSkyParams, horizon_rho_d)},
      {"params.cut_radii[0]", offsetof(sg::GpuSkyParams, cut_radii)},
      {"params.gauss_x[0]", offsetof(sg::GpuSkyParams, gauss_x)},
      {"params.gauss_w[0]", offsetof(sg::GpuSkyParams, gauss_w)},
      {"params.part_w[0]", offsetof(sg::GpuSkyParams, part_w)},
      {"params.build_scale_height", offsetof(sg::GpuSkyParams, build_scale_height)},
      {"params.ground_radius", offsetof(sg::GpuSkyParams, ground_radius)},
      {"params.top_radius", offsetof(sg::GpuSkyParams, top_radius)},
      {"params.scale_height[0]", offsetof(sg::GpuSkyParams, scale_height)},
      {"params.ext_max[0]", offsetof(sg::GpuSkyParams, ext_max)},
      {"params.phase_p[0]", offsetof(sg::GpuSkyParams, phase_p)},
      {"params.sun_dir[0]", offsetof(sg::GpuSkyParams, sun_dir)},
      {"params.max_piece_optical_depth", offsetof(sg::GpuSkyParams, max_piece_optical_depth)},
      {"params.irradiance_scale", offsetof(sg::GpuSkyParams, irradiance_scale)},
      {"params.albedo", offsetof(sg::GpuSkyParams, albedo)},
      {"params.ozone.radius[0]", offsetof(sg::GpuSkyParams, ozone.radius)},
      {"params.ozone.value[0]", offsetof(sg::GpuSkyParams, ozone.value)},
      {"params.ozone.slope[0]", offsetof(sg::GpuSkyParams, ozone.slope)},
      {"params.ozone.n", offsetof(sg::GpuSkyParams, ozone) + offsetof(sg::GpuLinearNodes, n)},
      {"params.sub[0].radius[0]", offsetof(sg::GpuSkyParams, sub) + offsetof(sg::GpuLinearNodes, radius)},
      {"params.sub[1].radius[0]", offsetof(sg::GpuSkyParams, sub) + 1 * sizeof(sg::GpuLinearNodes) + offsetof(sg::GpuLinearNodes, radius)},
      {"params.sub[1].slope[0]", offsetof(sg::GpuSkyParams, sub) + 1 * sizeof(sg::GpuLinearNodes) + offsetof(sg::GpuLinearNodes, slope)},
      {"params.sub[1].n", offsetof(sg::GpuSkyParams, sub) + 1 * sizeof(sg::GpuLinearNodes) + offsetof(sg::GpuLinearNodes, n)},
      {"params.subq[0].radius[0]", offsetof(sg::GpuSkyParams, subq) + offsetof(sg::GpuRamps, radius)},
      {"params.subq[0].half_curv[0]", offsetof(sg::GpuSkyParams, subq) + offsetof(sg::GpuRamps, half_curv)},
      {"params.subq[1].radius[0]", offsetof(sg::GpuSkyParams, subq) + 1 * sizeof(sg::GpuRamps) + offsetof(sg::GpuRamps, radius)},
      {"params.subq[1].n", offsetof(sg::GpuSkyParams, subq) + 1 * sizeof(sg::GpuRamps) + offsetof(sg::GpuRamps, n)},
      {"params.n_items", offsetof(sg::GpuSkyParams, n_items)},
      {"params.nw", offsetof(sg::GpuSkyParams, nw)},
      {"params.n_shells", offsetof(sg::GpuSkyParams, n_shells)},
      {"params.n_sun", offsetof(sg::GpuSkyParams, n_sun)},
      {"params.off_sun", offsetof(sg::GpuSkyParams, off_sun)},
      {"params.n_cuts", offsetof(sg::GpuSkyParams, n_cuts)},
      {"params.off_nodes[0]", offsetof(sg::GpuSkyParams, off_nodes)},
      {"params.n_nodes[0]", offsetof(sg::GpuSkyParams, n_nodes)},
      {"params.n_gauss", offsetof(sg::GpuSkyParams, n_gauss)},
      {"params.has_ext[0]", offsetof(sg::GpuSkyParams, has_ext)},
      {"params.tabulated[0]", offsetof(sg::GpuSkyParams, tabulated)},
      {"params.phase_model[0]", offsetof(sg::GpuSkyParams, phase_model)},
      {"params.n_cross", offsetof(sg::GpuSkyParams, n_cross)},
      {"params.n_rule", offsetof(sg::GpuSkyParams, n_rule)},
      {"params.n_dirs", offsetof(sg::GpuSkyParams, n_dirs)},
      {"params.table_kind", offsetof(sg::GpuSkyParams, table_kind)},
      {"params.log_encoded[0]", offsetof(sg::GpuSkyParams, log_encoded)},
      {"params.build_ramps[0].radius[0]", offsetof(sg::GpuSkyParams, build_ramps) + offsetof(sg::GpuRamps, radius)},
      {"params.build_ramps[2].n", offsetof(sg::GpuSkyParams, build_ramps) + 2 * sizeof(sg::GpuRamps) + offsetof(sg::GpuRamps, n)},
      {"params.ms_altitudes", offsetof(sg::GpuSkyParams, ms_altitudes)},
      {"params.ms_suns", offsetof(sg::GpuSkyParams, ms_suns)},
      {"params.ms_zenith", offsetof(sg::GpuSkyParams, ms_zenith)},
      {"params.ms_azimuths", offsetof(sg::GpuSkyParams, ms_azimuths)},
      {"params.ms_steps", offsetof(sg::GpuSkyParams, ms_steps)},
      {"params.ms_unused", offsetof(sg::GpuSkyParams, ms_unused)},
  };
  ASSERT_EQ(members.size(), 55u);  // every member, and the ends of the nested arrays
  for (const auto& [name, offset] : members) EXPECT_EQ(prog.buffer_variable_offset(name), int(offset)) << name;
  EXPECT_EQ(offsetof(sg::GpuSkyParams, ms_unused) + sizeof(int), sizeof(sg::GpuSkyParams));
  // The orders tables' block of the same pass (sky_orders.glsl): GpuOrdersParams.
  const std::vector<std::pair<const char*, std::size_t>> orders = {
      {"op.R", offsetof(sg::GpuOrdersParams, R)},         {"op.sun_m", offsetof(sg::GpuOrdersParams, sun_m)},
      {"op.albedo", offsetof(sg::GpuOrdersParams, albedo)}, {"op.nr", offsetof(sg::GpuOrdersParams, nr)},
      {"op.nh", offsetof(sg::GpuOrdersParams, nh)},       {"op.na", offsetof(sg::GpuOrdersParams, na)},
      {"op.nw", offsetof(sg::GpuOrdersParams, nw)}};
  for (const auto& [name, offset] : orders) EXPECT_EQ(prog.buffer_variable_offset(name), int(offset)) << name;
}

// The GPU closed-form ozone column (sky_lib.glsl, float) against the CPU's
// PiecewiseLinearColumn (double) for the 10-25-40 km tent.
TEST(GpuSky, OzoneColumnMatchesTheCpu) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  namespace sg = atmosh::atmo::shared;
  gpu::Program prog(gpu::sky_parts("gpu/shaders/ozone_check.comp"));
  const double R = 6371e3, T = R + 100e3;
  const DensityProfile tent(DensityProfileSpec::tent(10e3, 25e3, 40e3));
  const PiecewiseLinearColumn cpu(tent, R);
  std::vector<glm::vec4> rays;
  std::vector<double> ref;
  for (double h : {0.0, 5e3, 12e3, 30e3, 60e3})
    for (double mu : {-1.0, -0.6, -0.2, -0.05, -0.01, 0.0, 0.01, 0.1, 0.5, 1.0}) {
      const float r = float(R + h), muf = float(mu);  // the GPU's inputs, exactly
      const bool g = sg::ray_hits_ground(r, muf, R);
      const double len = g ? sg::distance_to_ground(r, muf, R) : sg::distance_to_top(r, muf, T);
      rays.push_back(glm::vec4(r, muf, float(len), 0.f));
      ref.push_back(cpu(r, muf, double(float(len))));
    }
  gpu::Buffer bi(rays.size() * 16, rays.data()), bo(rays.size() * 4);
  bi.bind(ATMOSH_BIND_CHECK_IN);
  bo.bind(ATMOSH_BIND_CHECK_OUT);
  sg::GpuSkyParams params{};  // the parameter block (shared/sky_params.glsl.hpp): the tent's nodes
  params.ozone = {{float(R + 10e3), float(R + 25e3), float(R + 40e3)}, {0.f, 1.f, 0.f},
                  {float(1.0 / 15e3), float(-1.0 / 15e3), 0.f}, 3};
  params.n_items = int(rays.size());
  gpu::Buffer bp(sizeof params, &params);
  bp.bind(ATMOSH_BIND_PARAMS);
  prog.dispatch(unsigned(rays.size() + 63) / 64);
  std::vector<float> out(rays.size());
  bo.download(out.data(), out.size() * 4);
  // Float bound: the closed form subtracts r0 * du from the integral of r du
  // (both ~6.4e6 m * du) to get the tent's (r - r0) du (~1e4 m * du): float
  // rounding of ~6e-8 * 6.4e6 / 1e4 ~ 4e-5 per piece, a few pieces per ray.
  // Measured: 1.8e-4 on llvmpipe (the CPU uses double; the sky images stay within 1e-4).
  double worst = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const double e = std::fabs(out[i] - ref[i]) / std::max(ref[i], 1.0);
    worst = std::max(worst, e);
    EXPECT_LT(e, 5e-4) << "ray " << i << " r " << rays[i].x << " mu " << rays[i].y << ": gpu " << out[i] << " cpu " << ref[i];
  }
  std::printf("  ozone column: max rel diff %.3g\n", worst);
}

// The optical-depth tables built on the GPU against the CPU's (both: log of the
// mean relative density along each table ray), physically based Earth.
TEST(GpuTables, MatchTheCpuTables) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  const AtmosphereSpec spec = earth16();
  const Atmosphere atm(spec);
  LutOptions lo;
  lo.shells = 16;
  lo.view_directions = 32;
  lo.sun_directions = 32;
  const OpticalDepthLut lut(atm, lo);
  int cg = 0, cs = 0, gg = 0, gs = 0;
  const std::vector<float> cpu = gpu::lut_tables_from_cpu(lut, atm, cg, cs);
  double seconds = 0;
  const std::vector<float> g = gpu::build_lut_tables(*ctx, lut, atm, gg, gs, &seconds);
  ASSERT_EQ(g.size(), cpu.size());
  EXPECT_EQ(gg, cg);
  EXPECT_EQ(gs, cs);
  // Float precision of the stored log values: |log| * 6e-8 plus the float
  // densities (~1e-7 relative) summed in double -> a few 1e-7 in the mean.
  double worst = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    ASSERT_TRUE(std::isfinite(g[i])) << i;
    const double e = std::fabs(double(g[i]) - cpu[i]);
    worst = std::max(worst, e / (1.0 + std::fabs(cpu[i]) * 1e-2));
    EXPECT_LT(std::fabs(double(g[i]) - cpu[i]), 2e-6 + 1e-7 * std::fabs(cpu[i]))
        << "entry " << i << ": gpu " << g[i] << " cpu " << cpu[i];
  }
  std::printf("  GPU tables (%zu values) in %.3f s: max |log mean difference| %.3g\n", g.size(), seconds, worst);
}

// The GPU's sun-table lookups (sky_lib.glsl's sun_lookup, what the sky pass
// evaluates at each node) against OpticalDepthLut::sun in double on the same float
// inputs: earth-physical (interpolated U.S. 1976 Rayleigh with its subtracted kinks'
// linear and quadratic columns, exponential Mie, closed-form ozone tent) and
// earth-graphics, from the ground to the top, grazing rays, rays tangent beside the
// tropopause and the tent's corners, and 4000 seeded random origins.
TEST(GpuSky, SunLookupsMatchTheCpu) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  namespace sg = atmosh::atmo::shared;
  for (const char* name : {"earth-physical", "earth-graphics"}) {
    AtmosphereSpec spec = preset(name);
    const Atmosphere atm(spec);
    const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
    ASSERT_EQ(gpu::sky_unsupported_reason(sky), "") << name;
    const double R = atm.ground_radius(), top = atm.top_altitude();
    std::vector<glm::vec2> o;
    for (double h : {0.0, 1.0, 100.0, 2000.0, 10500.0, 11019.0, 11500.0, 25e3, 50e3, 0.999 * top, top}) {
      const double muh = sg::mu_horizon(R + h, R);
      for (double mu : {-1.0, -0.5, -0.1, 0.0, 0.02, 0.3, 0.7, 1.0}) o.push_back(glm::vec2(float(h), float(mu)));
      for (double e : {1e-5, 1e-4, 1e-3, 1e-2}) o.push_back(glm::vec2(float(h), float(muh + e)));
      for (double ht : {10.0, 10919.0, 11119.0, 24900.0, 39900.0})  // tangent point ht above the ground
        if (ht < h) o.push_back(glm::vec2(float(h), float(-std::sqrt(1.0 - std::pow((R + ht) / (R + h), 2.0)))));
    }
    std::mt19937_64 rng(20261123);
    auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
    for (int i = 0; i < 4000; ++i) {
      const double u = uniform(), v = uniform();
      o.push_back(glm::vec2(float(i % 2 ? u * top : top * u * u * u), float(2.0 * v - 1.0)));
    }
    const gpu::SunLookups g = gpu::sun_lookups(*ctx, sky, o);
    ASSERT_EQ(g.column.size(), o.size());
    EXPECT_EQ(g.lookups, long(o.size()));
    const Coefficients k = atm.coefficients_at(550.0);
    double worst[3] = {0, 0, 0}, worst_tau = 0.0;  // relative differences
    int compared = 0;
    for (std::size_t i = 0; i < o.size(); ++i) {
      const double r = R + double(o[i].x), mu = double(o[i].y);
      const LutColumn c = sky.lut().sun(r, mu);
      const glm::vec4 gc = g.column[i];
      ASSERT_TRUE(std::isfinite(gc.x) && std::isfinite(gc.y) && std::isfinite(gc.z) && std::isfinite(gc.w)) << i;
      if (std::fabs(mu - sg::mu_horizon(r, R)) < 1e-6) continue;  // float rounding may flip the flag
      EXPECT_EQ(gc.w == 1.0f, c.hits_ground) << name << " origin " << i << " h " << o[i].x << " mu " << o[i].y;
      if (c.hits_ground) continue;
      ++compared;
      // Rayleigh and Mie: the interpolation and the ray geometry in double, the
      // exp and the subtracted kinks' closed-form columns in float: ~1e-5 (measured
      // 3.3e-5 on llvmpipe); bound: the tables' own 1e-4 target (+ 1e-20 m: float
      // underflow). Ozone: its closed-form column in float, where each piece's
      // integral of the radius, ~6.4e6 m x its length, is rounded by ~2^-24 of that
      // before the node radius is taken off: an absolute error ~2^-24 R_top |slope|
      // per metre of the ray inside the tent (measured up to 3.5x that on llvmpipe:
      // 1.0e-2 of a 318 m limb column, 3 % of a 0.17 m one from 52 m below the
      // 40 km corner); bound 8x, + 1e-6 of the column.
      const double rt = std::sqrt(sg::tangent_radius_sq(r, mu)), Rk = R + spec.ozone->profile.top_m;
      const double a = Rk > rt ? std::sqrt((Rk - rt) * (Rk + rt)) : 0.0;
      const double len = sg::distance_to_top(r, mu, atm.top_radius());
      const double inside = std::max(0.0, std::min(len, -r * mu + a) - std::max(0.0, -r * mu - a));
      const double slope = 1.0 / std::min(spec.ozone->profile.peak_m - spec.ozone->profile.bottom_m,
                                          spec.ozone->profile.top_m - spec.ozone->profile.peak_m);
      for (int ch = 0; ch < 3; ++ch) {
        const double cc = c.column[ch], e = std::fabs(double(gc[ch]) - cc);
        if (cc > 0.0) worst[ch] = std::max(worst[ch], e / cc);
        const double bound = ch < 2 ? 1e-4 * cc + 1e-20 : 8.0 * 0x1p-24 * Rk * slope * inside + 1e-6 * cc;
        EXPECT_LE(e, bound) << name << " channel " << ch << " origin " << i << " h " << o[i].x << " mu " << o[i].y
                            << ": gpu " << gc[ch] << " cpu " << cc;
      }
      // The optical depth the sky uses, reported (its error is bounded through the
      // columns' above): the ozone term is at most a few per cent of it where the
      // ozone column's float error is largest (measured 5.7e-4).
      const double tc = optical_depth(k, c.column);
      if (tc > 0.0) worst_tau = std::max(worst_tau, std::fabs(optical_depth(k, glm::dvec3(gc)) - tc) / tc);
    }
    EXPECT_GT(compared, 2000);
    std::printf("  %s: %d sun lookups, max rel. diff Rayleigh %.3g, Mie %.3g, ozone %.3g, tau(550 nm) %.3g\n", name,
                compared, worst[0], worst[1], worst[2], worst_tau);
    // Origins outside [0, top] x [-1, 1] and repeat counts outside [1, 1000] are bad input.
    const float above = static_cast<float>(top * 1.001), nan = std::nanf("");
    for (const glm::vec2 bad : {glm::vec2(-1.0f, 0.5f), glm::vec2(above, 0.5f), glm::vec2(0.0f, 1.5f), glm::vec2(nan, 0.f)})
      EXPECT_THROW(gpu::sun_lookups(*ctx, sky, {bad}), atmosh::InputError) << bad.x << " " << bad.y;
    EXPECT_THROW(gpu::sun_lookups(*ctx, sky, {glm::vec2(0.0f, 0.5f)}, 0), atmosh::InputError);
  }
}
