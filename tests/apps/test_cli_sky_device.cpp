// `--device cpu|gpu|auto` for sky images, in `atmosh sky` and in `atmosh run` (a scene's
// sky-image outputs): the GPU image agrees with the CPU image (within the GPU pass's
// documented float tolerance, 1e-4 relative where the radiance exceeds 1e-6 of its
// maximum; gpu/sky.hpp), the device is recorded in the EXR, a bad name exits 2, and with
// no EGL device `auto` falls back with one notice line while `gpu` exits 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

#include "atmosh/io/exr.hpp"
#include "atmosh/scene/scene.hpp"
#include "run_cli.hpp"
#include "without_egl.hpp"

using atmosh::test::count_lines;
using atmosh::test::expect_bad_input;
using atmosh::test::run_cli;
using atmosh::test::scratch_dir;
namespace fs = std::filesystem;

namespace {

// Max relative difference of channel Y where the CPU image exceeds 1e-6 of its maximum.
double max_rel_y(const atmosh::io::ExrImage& a, const atmosh::io::ExrImage& b) {
  const auto y = [](const atmosh::io::ExrImage& e) {
    return static_cast<std::size_t>(std::find(e.channels.begin(), e.channels.end(), "Y") - e.channels.begin());
  };
  const auto& ya = a.data[y(a)];
  const auto& yb = b.data[y(b)];
  const float peak = *std::max_element(yb.begin(), yb.end());
  double worst = 0;
  for (std::size_t i = 0; i < yb.size(); ++i)
    if (yb[i] > 1e-6f * peak) worst = std::max(worst, std::abs(double(ya[i]) - yb[i]) / yb[i]);
  return worst;
}

bool no_egl_and_optional(const atmosh::test::CliResult& r) {
  return r.exit_code == 1 && r.err.find("--device gpu") != std::string::npos && !std::getenv("ATMOSH_REQUIRE_GPU_CONTEXT");
}

}  // namespace

TEST(CliSkyDevice, SkyAndRunRenderOnTheGpuLikeTheCpu) {
  const fs::path d = scratch_dir("atmosh_cli_sky_device", "gpu");
  // The GPU pass computes single scattering: compare it with the CPU's single scattering.
  const auto g = run_cli("sky --sun-elevation 20 --size 48x24 --scattering single --device gpu -o '" +
                         (d / "g.exr").string() + "'");
  if (no_egl_and_optional(g)) GTEST_SKIP() << g.err;
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const auto c = run_cli("sky --sun-elevation 20 --size 48x24 --scattering single --device cpu -o '" +
                         (d / "c.exr").string() + "'");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const auto eg = atmosh::io::read_exr(d / "g.exr"), ec = atmosh::io::read_exr(d / "c.exr");
  EXPECT_EQ(eg.string_attributes.at("atmosh:device"), "gpu");
  EXPECT_EQ(ec.string_attributes.at("atmosh:device"), "cpu");
  EXPECT_LT(max_rel_y(eg, ec), 1e-4);

  // The built-in scene's sky-image output with single scattering, quick, on the GPU and
  // on the CPU (orders: OrdersTablesFollowTheDevicePolicy). Its other
  // outputs (studies, SH, sun track) are left out: --device changes only sky images.
  atmosh::scene::Scene single = atmosh::scene::default_scene();
  single.scattering.method = atmosh::atmo::ScatteringMethod::Single;
  std::erase_if(single.outputs, [](const atmosh::scene::Output& o) { return o.kind != "sky-image"; });
  ASSERT_EQ(single.outputs.size(), 1u);
  const fs::path scene_file = d / "single.toml";
  std::ofstream(scene_file) << atmosh::scene::to_toml(single);
  const auto rg = run_cli("run '" + scene_file.string() + "' --quick --device gpu -o '" + (d / "run_gpu").string() + "'");
  ASSERT_EQ(rg.exit_code, 0) << rg.err;
  const auto rc = run_cli("run '" + scene_file.string() + "' --quick -o '" + (d / "run_cpu").string() + "'");
  ASSERT_EQ(rc.exit_code, 0) << rc.err;
  int images = 0;
  for (const auto& e : fs::directory_iterator(d / "run_gpu")) {
    if (e.path().extension() != ".exr") continue;
    const auto a = atmosh::io::read_exr(e.path());
    if (!a.string_attributes.count("atmosh:device")) continue;  // not a sky image
    ++images;
    EXPECT_EQ(a.string_attributes.at("atmosh:device"), "gpu") << e.path();
    const auto b = atmosh::io::read_exr(d / "run_cpu" / e.path().filename());
    EXPECT_EQ(b.string_attributes.at("atmosh:device"), "cpu");
    EXPECT_LT(max_rel_y(a, b), 1e-4) << e.path();
  }
  EXPECT_GE(images, 1);
}

// The all-orders approximation (the default scene's method) renders on the GPU: the
// same image as the CPU's within the GPU pass's float tolerance (1e-4 relative in Y where
// it exceeds 1e-6 of its maximum; measured in tests/gpu/test_ms.cpp), by day and in
// twilight, and `auto` renders it on the GPU without a notice.
TEST(CliSkyDevice, ApproximateScatteringRendersOnTheGpuLikeTheCpu) {
  const fs::path d = scratch_dir("atmosh_cli_sky_device", "approximate");
  const std::string small = " --size 32x16 --scattering approximate --json";
  // --device gpu at one sun, auto (which must take the GPU for this method) at the other:
  // each GPU run is a process compiling the sky pass (~25 s of CPU on llvmpipe).
  for (const char* sun : {"20", "-9"}) {
    const std::string tag = std::string("s") + sun, device = sun[0] == '-' ? "auto" : "gpu";
    const auto g = run_cli(std::string("sky --sun-elevation ") + sun + small + " --device " + device + " -o '" +
                           (d / (tag + "g.exr")).string() + "'");
    if (no_egl_and_optional(g)) GTEST_SKIP() << g.err;
    ASSERT_EQ(g.exit_code, 0) << g.err;
    if (device == "auto") EXPECT_EQ(g.err, "");
    EXPECT_NE(g.out.find("\"scattering\": \"approximate\""), std::string::npos) << g.out;
    EXPECT_NE(g.out.find("\"device\": \"gpu\""), std::string::npos) << g.out;
    const auto c = run_cli(std::string("sky --sun-elevation ") + sun + small + " --device cpu -o '" +
                           (d / (tag + "c.exr")).string() + "'");
    ASSERT_EQ(c.exit_code, 0) << c.err;
    const auto eg = atmosh::io::read_exr(d / (tag + "g.exr")), ec = atmosh::io::read_exr(d / (tag + "c.exr"));
    EXPECT_EQ(eg.string_attributes.at("atmosh:device"), "gpu");
    EXPECT_LT(max_rel_y(eg, ec), 1e-4) << "sun " << sun;
  }
}

// Orders (studies::use_orders_tables_device, the one policy of `sky` and `run`):
// --device gpu builds the tables with the GPU's passes and renders the image with the sky
// pass's orders term, on any renderer: the same image as --device cpu within the GPU
// tables' and the sky pass's float tolerances (1e-4 each; tests/gpu/test_orders.cpp:
// measured 1.2e-5 together), its provenance naming the GPU for both. --device auto does
// the same on a hardware GPU; on a software renderer (the CI's llvmpipe, which builds the
// tables ~11x and renders the image ~18x slower than the CPU, docs/gpu.md) it keeps both
// on the CPU with one notice for each; with no EGL device the CPU, saying so. `run` with a
// sky-image output follows the same policy. Small tables: the property is the device
// decision and the image's agreement, not the tables' accuracy.
TEST(CliSkyDevice, OrdersTablesFollowTheDevicePolicy) {
  const fs::path d = scratch_dir("atmosh_cli_sky_device", "orders");
  atmosh::scene::Scene sc = atmosh::scene::default_scene();
  sc.scattering.method = atmosh::atmo::ScatteringMethod::Orders;
  sc.scattering.orders = 2;
  sc.scattering.orders_radii = 4;
  sc.scattering.orders_view_directions = 8;
  sc.scattering.orders_sun_directions = 4;
  sc.scattering.orders_azimuths = 4;
  sc.scattering.orders_sphere_zenith = 4;
  sc.scattering.orders_sphere_azimuth = 4;
  sc.scattering.orders_ray_steps = 4;
  std::erase_if(sc.outputs, [](const atmosh::scene::Output& o) { return o.kind != "sky-image"; });
  ASSERT_EQ(sc.outputs.size(), 1u);
  const fs::path scene_file = d / "orders.toml";
  std::ofstream(scene_file) << atmosh::scene::to_toml(sc);
  const std::string base = "sky --scene '" + scene_file.string() + "' --sun-elevation -6 --size 16x8 --json";
  const auto a = run_cli(base + " --device auto -o '" + (d / "a.exr").string() + "'");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto attrs = atmosh::io::read_exr(d / "a.exr").string_attributes;
  ASSERT_TRUE(attrs.count("atmosh:orders_tables_device"));
  const std::string where = attrs.at("atmosh:orders_tables_device");
  if (where == "gpu") {  // a hardware GPU: tables and image there
    EXPECT_NE(a.err.find("orders tables: built on the GPU"), std::string::npos) << a.err;
    EXPECT_EQ(attrs.at("atmosh:device"), "gpu");
  } else {
    ASSERT_EQ(where, "cpu");
    EXPECT_NE(a.err.find("orders tables: built on the CPU ("), std::string::npos) << a.err;
    EXPECT_EQ(attrs.at("atmosh:device"), "cpu");
    // with an EGL context, the reason is the software renderer (the CI's llvmpipe), for
    // the tables and for the image
    if (a.err.find("no GPU") == std::string::npos) {
      EXPECT_NE(a.err.find("software renderer"), std::string::npos) << a.err;
      EXPECT_NE(a.err.find("sky image with orders: rendered on the CPU (the software renderer"), std::string::npos)
          << a.err;
    }
  }
  // gpu: tables and image on the GPU, the CPU's image
  const auto g = run_cli(base + " --device gpu -o '" + (d / "g.exr").string() + "'");
  if (no_egl_and_optional(g)) GTEST_SKIP() << g.err;
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_NE(g.out.find("\"device\": \"gpu\""), std::string::npos) << g.out;
  EXPECT_NE(g.out.find("\"scattering\": \"orders\""), std::string::npos) << g.out;
  const auto c = run_cli(base + " --device cpu -o '" + (d / "c.exr").string() + "'");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const auto eg = atmosh::io::read_exr(d / "g.exr"), ec = atmosh::io::read_exr(d / "c.exr");
  EXPECT_EQ(eg.string_attributes.at("atmosh:device"), "gpu");
  EXPECT_EQ(eg.string_attributes.at("atmosh:orders_tables_device"), "gpu");
  EXPECT_EQ(ec.string_attributes.at("atmosh:orders_tables_device"), "cpu");
  // the tables kept on the GPU; the summary and the irradiance read back their part only
  EXPECT_NE(g.err.find("orders tables: built on the GPU and kept there"), std::string::npos) << g.err;
  EXPECT_EQ(eg.string_attributes.at("atmosh:orders_tables_read_back").rfind("part: ", 0), 0u)
      << eg.string_attributes.at("atmosh:orders_tables_read_back");
  EXPECT_EQ(ec.string_attributes.at("atmosh:orders_tables_read_back"), "all");
  EXPECT_LT(max_rel_y(eg, ec), 2e-4);
  // run: the scene's sky image on the GPU, its tables too
  const auto rg = run_cli("run '" + scene_file.string() + "' --quick --device gpu -o '" + (d / "run_gpu").string() + "'");
  ASSERT_EQ(rg.exit_code, 0) << rg.err;
  int images = 0;
  for (const auto& e : fs::directory_iterator(d / "run_gpu")) {
    if (e.path().extension() != ".exr") continue;
    const auto x = atmosh::io::read_exr(e.path()).string_attributes;
    if (!x.count("atmosh:device")) continue;
    ++images;
    EXPECT_EQ(x.at("atmosh:device"), "gpu");
    EXPECT_EQ(x.at("atmosh:orders_tables_device"), "gpu");
    EXPECT_EQ(x.at("atmosh:orders_tables_read_back"), "none (kept on the GPU)");  // an image only
  }
  EXPECT_EQ(images, 1);
}

TEST(CliSkyDevice, BadDeviceIsBadInput) {
  const fs::path d = scratch_dir("atmosh_cli_sky_device", "bad");
  expect_bad_input("sky --sun-elevation 20 --size 8x4 --device tpu -o '" + (d / "x.exr").string() + "'", "tpu");
  // checked with the other options, before the scene is read (and its tables built)
  expect_bad_input("sky --sun-elevation 20 --size 8x4 --scene '" + (d / "missing.toml").string() + "' --device tpu -o '" +
                       (d / "x.exr").string() + "'",
                   "tpu");
  expect_bad_input("run --quick --device tpu -o '" + (d / "r").string() + "'", "tpu");
}

TEST(CliSkyDevice, WithoutAnEglDeviceAutoFallsBackAndGpuFails) {
  const fs::path d = scratch_dir("atmosh_cli_sky_device", "none");
  // Single scattering, which the GPU pass computes: auto falls back and gpu fails for want
  // of an EGL device, not for the method. The scene's sky-image output only (what
  // --device changes).
  atmosh::scene::Scene single = atmosh::scene::default_scene();
  single.scattering.method = atmosh::atmo::ScatteringMethod::Single;
  std::erase_if(single.outputs, [](const atmosh::scene::Output& o) { return o.kind != "sky-image"; });
  const fs::path scene_file = d / "single.toml";
  std::ofstream(scene_file) << atmosh::scene::to_toml(single);
  atmosh::test::CliResult a, g, o;
  {
    const atmosh::test::WithoutEglDevice no_egl;
    a = run_cli("run '" + scene_file.string() + "' --quick --device auto -o '" + (d / "a").string() + "'");
    g = run_cli("sky --sun-elevation 20 --size 8x4 --scattering single --device gpu -o '" + (d / "g.exr").string() + "'");
    // orders: refused before its tables are built (the default size: minutes if it were not)
    o = run_cli("sky --sun-elevation 20 --size 8x4 --scattering orders --orders 2 --device gpu -o '" +
                (d / "o.exr").string() + "'");
  }
  EXPECT_EQ(o.exit_code, 1) << o.err;
  EXPECT_EQ(count_lines(o.err), 1) << o.err;
  EXPECT_FALSE(fs::exists(d / "o.exr"));
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NE(a.err.find("rendering on the CPU"), std::string::npos) << a.err;
  EXPECT_EQ(g.exit_code, 1) << g.err;
  EXPECT_EQ(count_lines(g.err), 1) << g.err;
  EXPECT_EQ(g.err.find("scattering"), std::string::npos) << g.err;  // the device failed, not the method
  EXPECT_FALSE(fs::exists(d / "g.exr"));
}
