// The successive-orders tables built on the GPU (gpu::build_scattering_orders) against
// the CPU build (atmo::ScatteringOrders, the reference: double sums, the same set-up),
// order by order, and their stiff cases. Small tables and 4 wavelengths (llvmpipe).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <tuple>
#include <vector>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/scattering_orders.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/error.hpp"
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
// from the CPU; with the curvature-corrected lookup (orders_curvature) 2.0e-5 and 9.8e-6.
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
  // Built with the table kept on the GPU as well (OrdersTables::ResidentAndReadBack):
  // the CPU copy is there for the lookups below, and the kept table (the GPU's log of the
  // same sums, orders_log.comp) equals it to 1 ulp of the logs (< 4e-6 at |log| < 32).
  const auto g = gpu::build_scattering_orders(*ctx, atm, small(3), nullptr, gpu::OrdersTables::ResidentAndReadBack);
  for (float v : g->radiance_table()) ASSERT_TRUE(std::isfinite(v));
  for (float v : g->ground_table()) ASSERT_TRUE(std::isfinite(v));
  {
    const auto* kept = dynamic_cast<const gpu::OrdersResidentTable*>(g->device_table());
    ASSERT_NE(kept, nullptr);
    std::vector<float> t(g->radiance_table().size());
    ASSERT_EQ(kept->buffer().bytes(), t.size() * sizeof(float));
    kept->buffer().download(t.data(), kept->buffer().bytes());
    long same = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      same += t[i] == g->radiance_table()[i];
      ASSERT_LE(std::fabs(double(t[i]) - g->radiance_table()[i]), 4e-6) << i;
    }
    std::printf("kept and read-back log tables: %ld of %zu entries bitwise equal\n", same, t.size());
  }
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

namespace {
// Largest relative difference of the GPU image's spectral radiance from the CPU's over
// the samples above 1e-6 of the CPU image's largest; finite and >= 0 everywhere.
struct ImageCmp {
  double max_rel = 0;
  long compared = 0;
  bool finite = true;
};
ImageCmp compare_images(const SkyImage& g, const SkyImage& c) {
  ImageCmp d;
  float peak = 0.0f;
  for (float v : c.spectral) peak = std::max(peak, v);
  for (std::size_t i = 0; i < c.spectral.size(); ++i) {
    if (!std::isfinite(g.spectral[i]) || g.spectral[i] < 0.0f) d.finite = false;
    if (c.spectral[i] > 1e-6f * peak) {
      d.max_rel = std::max(d.max_rel, std::fabs(double(g.spectral[i]) - c.spectral[i]) / c.spectral[i]);
      ++d.compared;
    }
  }
  return d;
}
double image_sum(const SkyImage& img) {
  double s = 0;
  for (float v : img.spectral) s += v;
  return s;
}
}  // namespace

// The sky pass with the orders term (sky.comp: orders_lookup.glsl on shared/orders.glsl.hpp)
// against the CPU image (SkyIntegrator::shade's orders term, the reference: double) of
// the same integrator, its orders tables uploaded: by day, at sunset, in civil, nautical
// and astronomical twilight (sun -6, -12, -18 deg) from the ground with a row of views
// on the horizon (13 rows: the middle one at elevation 0, grazing), a fisheye at 1500 m,
// and from space (120 km, above the 100 km top: rays through the limb). Both sides look
// up the same float tables with the same coordinates; what differs is float arithmetic
// (the GPU's single scattering, GpuSky.MatchesTheCpuImage's 1e-4, and the lookup's
// blend in float with GLSL's exp, 3 + 2|x| ulp). Bound 1e-4 relative in spectral radiance
// above 1e-6 of the image's largest (measured on llvmpipe: 3.1e-5, sun -6 deg). The
// orders term is there: the image is 1.04 (sun -18 deg: the sunlit upper atmosphere's
// single scattering dominates it) to 8.8 (sun -12 deg) times the single-scattering
// image; asserted > 1.02.
TEST(GpuOrders, SkyMatchesTheCpuImage) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  const AtmosphereSpec spec = earth_100km(4);
  const Atmosphere atm(spec);
  SkyOptions o;
  o.scattering = small(3);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum), o);
  const SkyIntegrator single(atm, solar_spectrum_for_bins(spec.spectrum));
  ASSERT_NE(sky.orders_tables(), nullptr);
  ASSERT_EQ(gpu::sky_unsupported_reason(sky), "");
  double worst = 0;
  for (auto [proj, w, h, sun_el, alt] : {std::tuple{SkyProjection::Equirect, 24, 13, 30.0, 0.0},
                                         std::tuple{SkyProjection::Equirect, 24, 13, 0.0, 0.0},
                                         std::tuple{SkyProjection::Equirect, 24, 13, -6.0, 0.0},
                                         std::tuple{SkyProjection::Equirect, 24, 13, -12.0, 0.0},
                                         std::tuple{SkyProjection::Equirect, 24, 13, -18.0, 0.0},
                                         std::tuple{SkyProjection::Fisheye, 16, 16, 10.0, 1500.0},
                                         std::tuple{SkyProjection::Equirect, 24, 12, 20.0, 120e3},
                                         std::tuple{SkyProjection::Equirect, 24, 12, -6.0, 120e3}}) {
    const glm::dvec3 sun = enu_direction_from_zenith(90.0 - sun_el, 135.0);
    const SkyImage c = render_sky(sky, proj, w, h, alt, sun, true, 2);
    const SkyImage g = gpu::render_sky(*ctx, sky, proj, w, h, alt, sun, true);
    ASSERT_EQ(g.spectral.size(), c.spectral.size());
    EXPECT_EQ(g.valid, c.valid);
    const ImageCmp d = compare_images(g, c);
    const double ratio = image_sum(g) / image_sum(render_sky(single, proj, w, h, alt, sun, true, 2));
    std::printf("  sun %+5.1f deg alt %7.0f m %dx%d: max rel diff %.3g over %ld samples; orders/single %.3g\n", sun_el,
                alt, w, h, d.max_rel, d.compared, ratio);
    EXPECT_TRUE(d.finite) << "sun " << sun_el << " altitude " << alt;
    EXPECT_GT(d.compared, 0);
    EXPECT_GT(ratio, 1.02) << "sun " << sun_el << " altitude " << alt;
    EXPECT_LT(d.max_rel, 1e-4) << "sun " << sun_el << " altitude " << alt;
    worst = std::max(worst, d.max_rel);
  }
  std::printf("  worst GPU/CPU relative difference with orders: %.3g\n", worst);
}

// Everything on the GPU: the orders tables built by the GPU's passes (the integrator's
// options name them) and the image by the sky pass, against the CPU image with
// CPU-built tables (sun 10 and -12 deg, from the ground): within the GPU tables' bound
// (TablesMatchTheCpuPerOrder: 1e-4) plus the image's (1e-4). Stiff inputs on the same
// tables: sun -36 deg (the tables' edge) and -90, observers 1 um above the ground, at
// the top and at 1000 km: finite and >= 0.
// The same GPU build kept on the GPU (gpu::OrdersTables::Resident: the sum's log taken
// on the GPU, nothing read back, the sky pass binding the buffer): nothing on the CPU
// (radiance_table() empty, the CPU lookup throws), and its image equals the image of the
// tables read back, logged on the CPU and uploaded — the reference is the upload path,
// same passes, same sums: they differ only where the GPU's log (orders_log.comp, float
// log + a Newton step in double) rounds differently from the CPU's std::log in float.
// Bound 1e-6 relative (measured on llvmpipe: see docs/gpu.md, "The orders table kept on
// the GPU").
TEST(GpuOrders, SkyWithGpuBuiltTablesMatchesAndStiffCasesAreFinite) {
  ATMOSH_GPU_CONTEXT_OR_SKIP(ctx);
  const AtmosphereSpec spec = earth_100km(4);
  const Atmosphere atm(spec);
  SkyOptions o;
  o.scattering = small(3);
  const SkyIntegrator cpu(atm, solar_spectrum_for_bins(spec.spectrum), o);
  std::shared_ptr<const gpu::Context> shared_ctx(std::move(ctx));
  o.scattering.orders_passes = gpu::make_orders_passes(shared_ctx);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum), o);
  o.scattering.orders_passes = gpu::make_orders_passes(shared_ctx, nullptr, gpu::OrdersTables::Resident);
  const SkyIntegrator resident(atm, solar_spectrum_for_bins(spec.spectrum), o);
  ASSERT_NE(resident.orders_tables(), nullptr);
  EXPECT_TRUE(resident.orders_tables()->radiance_table().empty());
  EXPECT_NE(dynamic_cast<const gpu::OrdersResidentTable*>(resident.orders_tables()->device_table()), nullptr);
  EXPECT_EQ(sky.orders_tables()->device_table(), nullptr);
  EXPECT_EQ(resident.orders_tables()->ground_table(), sky.orders_tables()->ground_table());
  EXPECT_EQ(resident.orders_tables()->bytes(), sky.orders_tables()->bytes());
  {  // the table itself: the GPU's log against the CPU's log of the same sums
    const auto& up = sky.orders_tables()->radiance_table();
    std::vector<float> kept(up.size());
    shared_ctx->make_current();
    dynamic_cast<const gpu::OrdersResidentTable&>(*resident.orders_tables()->device_table())
        .buffer()
        .download(kept.data(), kept.size() * sizeof(float));
    long same = 0;
    double worst_log = 0;
    for (std::size_t i = 0; i < up.size(); ++i) {
      same += kept[i] == up[i];
      worst_log = std::max(worst_log, std::fabs(double(kept[i]) - up[i]));
    }
    std::printf("  resident log table: %ld of %zu entries bitwise equal to the CPU's log, max |diff| %.3g\n", same,
                up.size(), worst_log);
    EXPECT_LE(worst_log, 4e-6);  // 1 ulp at |log| in [16, 32), where the tables' logs lie
  }
  std::vector<double> v(4);
  EXPECT_THROW(resident.orders_tables()->radiance(atm.ground_radius(), 0.5, false, 0.5, 0.5, v.data()), atmosh::InputError);
  for (double sun_el : {10.0, -12.0}) {
    const glm::dvec3 sun = enu_direction_from_zenith(90.0 - sun_el, 0.0);
    const SkyImage c = render_sky(cpu, SkyProjection::Equirect, 16, 9, 0.0, sun, true, 2);
    const SkyImage g = gpu::render_sky(*shared_ctx, sky, SkyProjection::Equirect, 16, 9, 0.0, sun, true);
    const ImageCmp d = compare_images(g, c);
    const SkyImage r = gpu::render_sky(*shared_ctx, resident, SkyProjection::Equirect, 16, 9, 0.0, sun, true);
    const ImageCmp dr = compare_images(r, g);
    long bitwise = 0;
    for (std::size_t i = 0; i < g.spectral.size(); ++i) bitwise += r.spectral[i] == g.spectral[i];
    std::printf("  GPU-built tables, sun %+5.1f deg: max rel diff %.3g over %ld samples; kept on the GPU against "
                "uploaded: %.3g (%ld of %zu values bitwise equal)\n",
                sun_el, d.max_rel, d.compared, dr.max_rel, bitwise, g.spectral.size());
    EXPECT_TRUE(d.finite);
    EXPECT_GT(d.compared, 0);
    EXPECT_LT(d.max_rel, 2e-4) << "sun " << sun_el;
    EXPECT_TRUE(dr.finite);
    EXPECT_EQ(r.valid, g.valid);
    EXPECT_LE(dr.max_rel, 1e-6) << "sun " << sun_el;
  }
  EXPECT_THROW(gpu::render_sky(*shared_ctx, resident, SkyProjection::Equirect, 4, 3, 0.0, glm::dvec3(0, 0, 2), true),
               atmosh::InputError);
  for (double sun_el : {-36.0, -90.0})
    for (double alt : {1e-6, 100e3, 1000e3}) {
      const SkyImage g = gpu::render_sky(*shared_ctx, sky, SkyProjection::Equirect, 8, 5, alt,
                                         enu_direction_from_zenith(90.0 - sun_el, 0.0), true);
      for (float v : g.spectral) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << "sun " << sun_el << " alt " << alt;
      for (float v : g.Y) ASSERT_TRUE(std::isfinite(v)) << "sun " << sun_el << " alt " << alt;
    }

  // The kept table read back in part for the CPU's lookups at one observer (read_back_at:
  // what `atmosh sky --device gpu` reads for its summary and irradiance; 1500 m, sun 10
  // deg): the summary (zenith, horizon toward and away from the sun) and the irradiance
  // (8 x 16 views of the upper hemisphere) equal those of the same GPU build read back
  // in full and logged on the CPU (`sky`) within the two logs' rounding (1e-6, as the
  // images above), and those of the CPU-built tables within the GPU tables' bound (2e-4,
  // as above); a lookup outside the part (sun -30 deg) throws; read_back_all then reads
  // the rest.
  {
    const ScatteringOrders& kept = *resident.orders_tables();
    const double h = 1500.0;
    const glm::dvec3 sun = enu_direction_from_zenith(80.0, 30.0);
    const std::size_t all = kept.texels() * kept.wavelengths() * sizeof(float);
    EXPECT_EQ(kept.bytes_on_cpu(), 0u);
    const std::size_t part = kept.read_back_at(atm.ground_radius() + h, sun.z);
    std::printf("  read back for the lookups at one observer: %zu of %zu bytes\n", part, all);
    EXPECT_GT(part, 0u);
    EXPECT_LT(part, all / 2);
    EXPECT_EQ(kept.bytes_on_cpu(), part);
    const SkySummary a = summarize_sky(resident, h, sun), b = summarize_sky(sky, h, sun), c = summarize_sky(cpu, h, sun);
    const SkyIrradiance ia = sky_irradiance(resident, h, sun, 8, 16), ib = sky_irradiance(sky, h, sun, 8, 16),
                        ic = sky_irradiance(cpu, h, sun, 8, 16);
    double to_read_back = 0, to_cpu = 0;
    auto cmp = [&](double x, double y, double z) {
      ASSERT_TRUE(std::isfinite(x) && x > 0);
      to_read_back = std::max(to_read_back, std::fabs(x / y - 1));
      to_cpu = std::max(to_cpu, std::fabs(x / z - 1));
    };
    cmp(a.zenith.xyz.Y, b.zenith.xyz.Y, c.zenith.xyz.Y);
    cmp(a.horizon_toward_sun.xyz.Y, b.horizon_toward_sun.xyz.Y, c.horizon_toward_sun.xyz.Y);
    cmp(a.horizon_away.xyz.Y, b.horizon_away.xyz.Y, c.horizon_away.xyz.Y);
    cmp(ia.diffuse_lux, ib.diffuse_lux, ic.diffuse_lux);
    for (std::size_t q = 0; q < ia.diffuse.size(); ++q) cmp(ia.diffuse[q], ib.diffuse[q], ic.diffuse[q]);
    EXPECT_EQ(ia.direct, ib.direct);
    std::printf("  summary and irradiance from the part: max rel diff %.3g to the full read-back, %.3g to the CPU "
                "tables\n", to_read_back, to_cpu);
    EXPECT_LE(to_read_back, 1e-6);
    EXPECT_LT(to_cpu, 2e-4);
    const glm::dvec3 low = enu_direction_from_zenith(120.0, 30.0);
    EXPECT_THROW(summarize_sky(resident, h, low), atmosh::InputError);
    EXPECT_EQ(kept.read_back_all(), all);
    EXPECT_EQ(kept.read_back_all(), 0u);  // already here
    EXPECT_LE(std::fabs(summarize_sky(resident, h, low).zenith.xyz.Y / summarize_sky(sky, h, low).zenith.xyz.Y - 1),
              1e-6);
  }
}
