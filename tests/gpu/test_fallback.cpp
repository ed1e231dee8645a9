// Without an EGL device (simulated by pointing GLVND at no vendor library) the
// context, the GPU sky and `auto` selection report Unavailable cleanly — no crash.
// Runs in a fresh child process (death-test machinery), since EGL reads the
// environment once per process.
#include <gtest/gtest.h>

#include <cstdlib>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/sky.hpp"

namespace {
int try_without_device() {
  setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/atmosh_no_egl_vendor.json", 1);
  try {
    atmosh::gpu::Context ctx;
    return 3;  // a context appeared: the simulation did not work
  } catch (const atmosh::gpu::Unavailable&) {
  }
  using namespace atmosh::atmo;
  AtmosphereSpec spec = preset("earth-graphics");
  const Atmosphere atm(spec);
  const SkyIntegrator sky(atm, solar_spectrum_for_bins(spec.spectrum));
  try {
    (void)atmosh::gpu::render_sky(sky, SkyProjection::Equirect, 8, 4, 0.0, enu_direction_from_zenith(45.0, 0.0), false);
    return 4;
  } catch (const atmosh::gpu::Unavailable&) {
    return 0;
  }
}
}  // namespace

TEST(GpuFallback, NoEglDeviceThrowsUnavailableNotACrash) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(std::exit(try_without_device()), ::testing::ExitedWithCode(0), "");
}
