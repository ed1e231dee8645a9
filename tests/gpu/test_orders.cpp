// The successive-orders tables built on the GPU (gpu::build_scattering_orders) against
// the CPU build (atmo::ScatteringOrders, the reference: double sums, the same set-up),
// order by order, and their stiff cases. Small tables and 4 wavelengths (llvmpipe).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/scattering_orders.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/gpu/orders.hpp"
#include "atmosh/gpu/sky.hpp"
#include "gpu_fixture.hpp"

using namespace atmosh::atmo;
namespace gpu = atmosh::gpu;

namespace {

constexpr double kPi = 3.14159265358979323846;

AtmosphereSpec earth_100km(int count) {
  AtmosphereSpec s = preset("earth-physical");
  s.planet.atmosphere_top_m = 100e3;
  s.planet.ground_albedo = 0.3;
  s.spectrum.wavelengths_nm.clear();
  s.spectrum.from_nm = 380;
  s.spectrum.to_nm = 780;
  s.spectrum.count = count;
  return s;
}

MultipleScatteringOptions small(int orders) {
  MultipleScatteringOptions o;
  o.method = ScatteringMethod::Orders;
  o.orders = orders;
  o.orders_radii = 6;
  o.orders_view_directions = 16;
  o.orders_sun_directions = 12;
  o.orders_azimuths = 5;
  o.orders_sphere_zenith = 6;
  o.orders_sphere_azimuth = 6;
  o.orders_ray_steps = 8;
  o.threads = 2;
  return o;
}

// Largest relative difference exp(g - c) - 1 over the entries of two log tables whose
// CPU value is above `rel_floor` of the table's largest (at its wavelength's table).
struct Cmp {
  double max_rel = 0;
  long compared = 0;
  bool finite = true;
};
Cmp compare_log(const std::vector<float>& g, const std::vector<float>& c, double rel_floor) {
  Cmp r;
  float peak = -1e30f;
  for (float v : c) peak = std::max(peak, v);
  const float floor = peak + static_cast<float>(std::log(rel_floor));
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!std::isfinite(g[i])) r.finite = false;
    if (c[i] < floor) continue;
    r.max_rel = std::max(r.max_rel, std::fabs(std::expm1(double(g[i]) - double(c[i]))));
    ++r.compared;
  }
  return r;
}

}  // namespace

// Orders N = 2 and 4: the sums S_2..S_N and E_1..E_{N-1} agree with the CPU's (order 2 on
// its own, then with orders 3 and 4 built from it; S_1, which the GPU computes too, enters
// both). The GPU's passes differ from the CPU's only by float rounding: single-precision
// sums, columns and sun cosines (sky_lib.glsl's sun_lookup takes floats) and GLSL's
// exp/log, where the CPU sums in double. Entries above 1e-6 of the table's largest.
// Measured on llvmpipe: 1.7e-5 (radiance), 1.1e-5 (ground); 3.8e-6 and 9.5e-7 with S_1
// from the CPU.
// Bound 1e-4: GLSL guarantees exp(x) only to 3 + 2|x| ulp (4.30, sec. 4.7.1), i.e.
// ~1e-5 relative at the logarithms these entries hold (down to ~-40), and each order
// looks up the previous one's table.
TEST(GpuOrders, TablesMatchTheCpuPerOrder) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  const Atmosphere atm(earth_100km(4));
  for (int n : {2, 4}) {
    const ScatteringOrders cpu(atm, small(n));
    gpu::OrdersGpuTimes t;
    const auto g = gpu::build_scattering_orders(*ctx, atm, small(n), &t);
    ASSERT_EQ(g->radiance_table().size(), cpu.radiance_table().size());
    const Cmp s = compare_log(g->radiance_table(), cpu.radiance_table(), 1e-6);
    const Cmp e = compare_log(g->ground_table(), cpu.ground_table(), 1e-6);
    std::printf("orders %d: radiance table max rel diff %.3g (%ld entries), ground %.3g (%ld); GPU compile %.3f s, "
                "upload and S_1 %.3f s, passes %.3f s\n", n, s.max_rel, s.compared, e.max_rel, e.compared, t.compile_s,
                t.upload_s, t.passes_s);
    EXPECT_TRUE(s.finite && e.finite) << n;
    EXPECT_GT(s.compared, static_cast<long>(cpu.radiance_table().size() / 2)) << n;
    EXPECT_LT(s.max_rel, 1e-4) << n;
    EXPECT_LT(e.max_rel, 1e-4) << n;
  }
}

// Stiff cases: every table entry finite; lookups in the Earth's deep shadow (sun at
// -18 deg, observer on the ground looking down and up), at the top of the atmosphere
// (rays straight up, grazing, straight down) and at sun -36 deg (the table's edge) are
// finite, >= 0 and agree with the CPU's where the CPU's are above 1e-30 (measured on
// llvmpipe 2.9e-5; bound as above).
TEST(GpuOrders, StiffCasesAreFiniteAndMatch) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  const Atmosphere atm(earth_100km(3));
  const ScatteringOrders cpu(atm, small(3));
  const auto g = gpu::build_scattering_orders(*ctx, atm, small(3));
  for (float v : g->radiance_table()) ASSERT_TRUE(std::isfinite(v));
  for (float v : g->ground_table()) ASSERT_TRUE(std::isfinite(v));
  const double R = atm.ground_radius(), T = atm.top_radius();
  double worst = 0;
  int compared = 0;
  for (double sun_el : {90.0, 0.0, -6.0, -12.0, -18.0, -36.0, -90.0})
    for (double r : {R, R + 1.0, R + 30e3, T - 1.0, T})
      for (double mu : {-1.0, -0.2, -0.01, 0.0, 0.01, 0.5, 1.0}) {
        const double mu_h = -std::sqrt(std::max(0.0, 1.0 - (R / r) * (R / r)));
        const bool ground = mu < mu_h;
        const double mu_s = std::sin(sun_el * kPi / 180.0);
        for (double cphi : {-1.0, 0.0, 1.0}) {
          const double nu =
              std::clamp(mu * mu_s + std::sqrt(std::max(0.0, (1 - mu * mu) * (1 - mu_s * mu_s))) * cphi, -1.0, 1.0);
          double a[3], b[3];
          g->radiance(r, mu, ground, mu_s, nu, a);
          cpu.radiance(r, mu, ground, mu_s, nu, b);
          for (int q = 0; q < 3; ++q) {
            ASSERT_TRUE(std::isfinite(a[q]) && a[q] >= 0) << sun_el << " " << r << " " << mu;
            if (b[q] > 1e-30) {
              worst = std::max(worst, std::fabs(a[q] / b[q] - 1));
              ++compared;
            }
          }
        }
        double ea[3], eb[3];
        g->ground_irradiance(mu_s, ea);
        cpu.ground_irradiance(mu_s, eb);
        for (int q = 0; q < 3; ++q) {
          ASSERT_TRUE(std::isfinite(ea[q]) && ea[q] >= 0);
          if (eb[q] > 1e-30) worst = std::max(worst, std::fabs(ea[q] / eb[q] - 1));
        }
      }
  std::printf("stiff lookups: max rel diff %.3g over %d values\n", worst, compared);
  EXPECT_GT(compared, 1000);
  EXPECT_LT(worst, 1e-4);
}

// A sky whose options name the GPU passes (MultipleScatteringOptions::orders_passes, as
// `atmosh sky --device gpu|auto --scattering orders` sets them) builds its orders tables
// there: its radiance (all orders, single scattering from the CPU integrator) equals
// the CPU-built sky's within the tables' bound, at sun 30 and -9 deg (observer at 1500 m).
TEST(GpuOrders, SkyBuildsItsTablesOnTheGpuThroughItsOptions) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  const Atmosphere atm(earth_100km(3));
  SkyOptions o;
  o.scattering = small(3);
  const SkyIntegrator cpu(atm, SolarSpectrum(3, 1.0), o);
  gpu::OrdersGpuTimes t;
  o.scattering.orders_passes = gpu::make_orders_passes(std::shared_ptr<const gpu::Context>(std::move(ctx)), &t);
  const SkyIntegrator gpu_sky(atm, SolarSpectrum(3, 1.0), o);
  EXPECT_GT(t.passes_s, 0.0);  // the passes ran on the GPU
  double worst = 0;
  for (double sun_el : {30.0, -9.0})
    for (double el : {90.0, 20.0, 2.0, -10.0}) {
      const double s = std::sin(sun_el * kPi / 180), c = std::cos(sun_el * kPi / 180);
      const double ve = el * kPi / 180;
      const glm::dvec3 sun(0.0, c, s), view(0.6 * std::cos(ve), 0.8 * std::cos(ve), std::sin(ve));
      const auto a = gpu_sky.radiance(1500.0, view, sun), b = cpu.radiance(1500.0, view, sun);
      for (int q = 0; q < 3; ++q) {
        ASSERT_GT(b[q], 0.0) << sun_el << " " << el;
        worst = std::max(worst, std::fabs(a[q] / b[q] - 1));
      }
    }
  std::printf("sky with GPU orders tables: max rel diff %.3g\n", worst);
  EXPECT_LT(worst, 1e-4);
}

TEST(GpuOrders, TooManyWavelengthsAreUnsupported) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  const Atmosphere atm(earth_100km(65));
  EXPECT_THROW(gpu::build_scattering_orders(*ctx, atm, small(2)), gpu::Unsupported);
}
