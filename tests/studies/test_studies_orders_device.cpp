// The studies' and sweeps' orders tables on a device (SkySettings::device through
// studies::make_sky_model(scene, settings, ...) and use_orders_tables_device, the policy
// of `atmosh sky`): the sun-elevation study with its tables built by the GPU's passes
// gives the rows of the CPU-built tables within the GPU tables' float tolerance (the
// tables agree to 1e-4: tests/gpu/test_orders.cpp), its provenance says where the
// tables were built, and `auto` says why in one notice when it keeps them on the CPU.
// Small tables and four wavelengths.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "atmosh/error.hpp"
#include "atmosh/studies/sky_studies.hpp"
#include "studies_test_scene.hpp"

using namespace atmosh;

namespace {

scene::Scene orders_scene() {
  scene::Scene s = test::small_scene();
  s.scattering.method = atmo::ScatteringMethod::Orders;
  s.scattering.orders = 3;
  s.scattering.orders_radii = 4;
  s.scattering.orders_view_directions = 8;
  s.scattering.orders_sun_directions = 6;
  s.scattering.orders_azimuths = 4;
  s.scattering.orders_sphere_zenith = 4;
  s.scattering.orders_sphere_azimuth = 4;
  s.scattering.orders_ray_steps = 4;
  return s;
}

std::string prov_value(const io::Provenance& p, const std::string& key) {
  for (const auto& [k, v] : p.entries)
    if (k == key) return v;
  return "<missing " + key + ">";
}

}  // namespace

TEST(StudiesOrdersDevice, SunElevationStudyWithGpuTablesMatchesTheCpu) {
  const scene::Scene s = orders_scene();
  studies::ElevationStudyOptions o;
  o.from_deg = -12;
  o.to_deg = 20;
  o.step_deg = 16;
  o.sky = test::coarse_settings();
  const auto cpu = studies::sun_elevation_study(s, o);
  EXPECT_EQ(prov_value(cpu.provenance, "orders_tables_device"), "cpu");
  studies::ElevationStudyOptions g = o;
  g.sky.device = "gpu";
  studies::ElevationStudy gpu;
  try {
    gpu = studies::sun_elevation_study(s, g);
  } catch (const std::runtime_error& e) {  // no EGL device (or a build without the GPU library)
    if (std::getenv("ATMOSH_REQUIRE_GPU_CONTEXT")) FAIL() << e.what();
    GTEST_SKIP() << e.what();
  }
  EXPECT_EQ(prov_value(gpu.provenance, "orders_tables_device"), "gpu");
  ASSERT_EQ(gpu.rows.size(), cpu.rows.size());
  double worst = 0;
  for (std::size_t i = 0; i < cpu.rows.size(); ++i)
    for (auto [a, b] : {std::pair{gpu.rows[i].zenith.xyz.Y, cpu.rows[i].zenith.xyz.Y},
                        std::pair{gpu.rows[i].horizon_toward_sun.xyz.Y, cpu.rows[i].horizon_toward_sun.xyz.Y}}) {
      ASSERT_GT(b, 0.0) << i;
      worst = std::max(worst, std::fabs(a / b - 1.0));
    }
  EXPECT_LT(worst, 1e-4);
  // auto: the GPU on a hardware device; on a software renderer the CPU, with one notice
  std::vector<std::string> notices;
  studies::ElevationStudyOptions a = o;
  a.sky.device = "auto";
  a.sky.notice = [&](const std::string& m) { notices.push_back(m); };
  const auto st = studies::sun_elevation_study(s, a);
  ASSERT_EQ(notices.size(), 1u);
  const std::string where = prov_value(st.provenance, "orders_tables_device");
  if (where == "cpu")
    EXPECT_NE(notices[0].find("orders tables: built on the CPU (the GPU is the software renderer"), std::string::npos)
        << notices[0];
  else
    EXPECT_EQ(notices[0], "orders tables: built on the GPU");
}

TEST(StudiesOrdersDevice, BadDeviceIsBadInput) {
  studies::SkySettings k = test::coarse_settings();
  k.device = "tpu";
  EXPECT_THROW(k.checked(), InputError);
}
