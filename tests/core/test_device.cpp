// atmosh/device.hpp: the cpu|gpu|auto policy. The table it must follow is the one the
// command line documents (docs/gpu.md, "`--device cpu|gpu|auto`"; docs/cli.md):
// cpu never uses the GPU; gpu uses it or fails (exit 1, the message starts with
// "--device gpu:"); auto uses it or falls back with one line that says why.
#include <gtest/gtest.h>

#include <optional>
#include <stdexcept>
#include <string>

#include "atmosh/device.hpp"
#include "atmosh/error.hpp"

namespace {

using atmosh::DeviceRequest;
using atmosh::GpuUnusable;
using Why = atmosh::GpuUnusable::Why;

TEST(Device, ParsesTheThreeRequestsAndNamesABadOne) {
  EXPECT_EQ(atmosh::parse_device_request("cpu"), DeviceRequest::cpu);
  EXPECT_EQ(atmosh::parse_device_request("gpu"), DeviceRequest::gpu);
  EXPECT_EQ(atmosh::parse_device_request("auto"), DeviceRequest::automatic);
  for (const char* r : {"cpu", "gpu", "auto"})
    EXPECT_STREQ(atmosh::device_request_name(atmosh::parse_device_request(r)), r);
  for (const char* bad : {"", "GPU", "cuda", "auto "}) {
    try {
      atmosh::parse_device_request(bad, "--device");
      ADD_FAILURE() << "'" << bad << "' accepted";
    } catch (const atmosh::InputError& e) {
      EXPECT_EQ(std::string(e.what()), std::string("--device ") + bad + ": must be cpu, gpu or auto");
    }
  }
}

TEST(Device, CpuNeverUsesTheGpuAndSaysNothing) {
  for (const std::optional<GpuUnusable>& u :
       {std::optional<GpuUnusable>{}, std::optional<GpuUnusable>{GpuUnusable{Why::no_device, "no EGL", {}}}}) {
    const auto d = atmosh::resolve_device(DeviceRequest::cpu, u, "rendering on the CPU");
    EXPECT_FALSE(d.gpu);
    EXPECT_TRUE(d.notice.empty());
  }
}

TEST(Device, UsableGpuIsUsedForGpuAndAuto) {
  for (DeviceRequest r : {DeviceRequest::gpu, DeviceRequest::automatic}) {
    const auto d = atmosh::resolve_device(r, std::nullopt, "rendering on the CPU");
    EXPECT_TRUE(d.gpu);
    EXPECT_TRUE(d.notice.empty());
  }
}

TEST(Device, AutoFallsBackWithOneLineSayingWhy) {
  const auto no = atmosh::resolve_device(DeviceRequest::automatic, GpuUnusable{Why::no_device, "no EGL device", {}},
                                         "rendering on the CPU");
  EXPECT_FALSE(no.gpu);
  EXPECT_EQ(no.notice, "no GPU (no EGL device); rendering on the CPU");
  const auto un = atmosh::resolve_device(DeviceRequest::automatic,
                                         GpuUnusable{Why::unsupported, "scattering method 'orders'", "use --device cpu"},
                                         "rendering on the CPU");
  EXPECT_FALSE(un.gpu);
  EXPECT_EQ(un.notice, "scattering method 'orders' is not supported on the GPU; rendering on the CPU");
  const auto nb = atmosh::resolve_device(DeviceRequest::automatic, GpuUnusable{Why::not_built, {}, {}},
                                         "building the tables on the CPU only");
  EXPECT_FALSE(nb.gpu);
  EXPECT_EQ(nb.notice, "built without GPU support; building the tables on the CPU only");
}

TEST(Device, GpuRequestFailsNamingTheRequestAndTheCause) {
  auto message = [](const GpuUnusable& u) {
    try {
      atmosh::resolve_device(DeviceRequest::gpu, u, "rendering on the CPU", "--device");
    } catch (const atmosh::InputError&) {
      return std::string("InputError");  // must not be an input error: exit code 1, not 2
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({Why::no_device, "no EGL device", {}}), "--device gpu: no EGL device");
  EXPECT_EQ(message({Why::unsupported, "scattering method 'orders'", "use --scattering single or --device cpu"}),
            "--device gpu: scattering method 'orders' is not supported on the GPU (use --scattering single or "
            "--device cpu)");
  EXPECT_EQ(message({Why::not_built, {}, {}}), "--device gpu: atmosh was built without ATMOSH_WITH_GPU");
}

}  // namespace
