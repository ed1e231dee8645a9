// The work estimates (atmosh/work.hpp) count what the loops they estimate run, from the
// request's sizes alone, before any work: closed-form counts of rays, view-ray nodes,
// wavelengths, table entries and samples; absurd sizes give absurd (finite or +inf),
// never wrapped, estimates.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/sh/projection.hpp"

namespace {

using atmosh::atmo::SkyOptions;

// render_sky traces one view ray per pixel; each ray is cut into `segments` pieces of
// `samples_per_segment` Gauss-Legendre nodes (sky.hpp), each node summed over every
// wavelength.
TEST(WorkEstimates, SkyImageCountsRaysAndNodes) {
  SkyOptions o;
  o.segments = 12;
  o.samples_per_segment = 3;
  const auto w = atmosh::atmo::sky_image_work(640, 320, 16, o);
  EXPECT_DOUBLE_EQ(w.units, 640.0 * 320 * 12 * 3);
  EXPECT_GT(w.seconds_per_unit, 0);
  EXPECT_DOUBLE_EQ(atmosh::atmo::sky_rays_work(640.0 * 320, 16, o).units, w.units);
  // More wavelengths cost more per node; the approximate method's lookups cost more per node.
  EXPECT_GT(atmosh::atmo::sky_image_work(640, 320, 47, o).seconds_per_unit, w.seconds_per_unit);
  o.scattering.method = atmosh::atmo::ScatteringMethod::Approximate;
  EXPECT_GT(atmosh::atmo::sky_image_work(640, 320, 16, o).cpu_seconds(), w.cpu_seconds());
  // The largest image and settings stay finite; an empty one is no work.
  o.segments = 64;
  o.samples_per_segment = 8;
  const auto big = atmosh::atmo::sky_image_work(65536, 65536, 4096, o);
  EXPECT_DOUBLE_EQ(big.units, 65536.0 * 65536 * 512);
  EXPECT_TRUE(std::isfinite(big.cpu_seconds()));
  EXPECT_EQ(atmosh::atmo::sky_image_work(0, 100, 16, o).units, 0.0);
}

// OpticalDepthLut builds shells x directions entries per table: two view tables (sky and
// ground branches) and one sun table (optical_depth.hpp).
TEST(WorkEstimates, LutBuildCountsTableEntries) {
  atmosh::atmo::LutOptions o;
  o.shells = 4096;
  o.view_directions = 65536;
  o.sun_directions = 1024;
  const auto w = atmosh::atmo::OpticalDepthLut::estimate_build_work(o);
  EXPECT_DOUBLE_EQ(w.units, 4096.0 * (2 * 65536.0 + 1024));
  o.view_tables = false;
  EXPECT_DOUBLE_EQ(atmosh::atmo::OpticalDepthLut::estimate_build_work(o).units, 4096.0 * 1024);
  EXPECT_GT(w.seconds_per_unit, 0);
  // An entry's ray crosses more shells in a finer table: more work per entry.
  atmosh::atmo::LutOptions small = o;
  small.shells = 40;
  EXPECT_LT(atmosh::atmo::OpticalDepthLut::estimate_build_work(small).seconds_per_unit, w.seconds_per_unit);
}

// A Monte Carlo projection evaluates bands^2 basis functions per sample and adds them to
// each channel: n^2 samples for jittered (n strata per side), n for uniform.
TEST(WorkEstimates, ShSamplerCountsSamplesCoefficientsAndChannels) {
  namespace sh = atmosh::sh;
  sh::ProjectOptions u{sh::Method::uniform, 2000000000, 1, 1};
  EXPECT_DOUBLE_EQ(sh::sampler_work(u, 16, 3).units, 2e9 * 256 * 3);
  sh::ProjectOptions j{sh::Method::jittered, 100, 1, 1};
  EXPECT_DOUBLE_EQ(sh::sampler_work(j, 3, 3).units, 1e4 * 9 * 3);
  sh::ProjectOptions q{sh::Method::quadrature, 0, 1, 1};
  EXPECT_EQ(sh::sampler_work(q, 8, 3).units, 0.0);
}

}  // namespace
