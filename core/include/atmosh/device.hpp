// atmosh/device.hpp — the one cpu|gpu|auto device policy of the toolkit.
//
// Every pass that has a GPU version takes a device request:
//   * cpu  — the CPU path; nothing touches EGL.
//   * gpu  — the GPU path, or an error (std::runtime_error, "<what> gpu: <why>"; the
//            CLI maps it to exit code 1) when the GPU cannot run it.
//   * auto — the GPU path where it can run, else the CPU path with a one-line notice
//            that says why and what happens instead ("no GPU (<why>); rendering on
//            the CPU"); the caller shows the notice (libraries never print).
// The caller tries its GPU path (or knows it cannot) and describes any failure as a
// GpuUnusable; resolve_device turns request + failure into the decision and the
// words. The GPU headers are not needed here: callers translate their own exceptions
// (atmosh::gpu::Unavailable, Unsupported) into a GpuUnusable.
#pragma once

#include <optional>
#include <string>

namespace atmosh {

enum class DeviceRequest { cpu, gpu, automatic };

/// "cpu", "gpu" or "auto"; InputError "<what> <text>: must be cpu, gpu or auto" otherwise.
DeviceRequest parse_device_request(const std::string& text, const std::string& what = "device");
const char* device_request_name(DeviceRequest request);  // "cpu", "gpu", "auto"

/// Why the GPU path cannot run.
struct GpuUnusable {
  enum class Why {
    no_device,    ///< no headless EGL/OpenGL context (detail: the driver's reason)
    unsupported,  ///< the GPU path does not implement this input (detail: what, e.g. "scattering method 'orders'")
    not_built,    ///< this build has no GPU library (ATMOSH_WITH_GPU=OFF)
  };
  Why why = Why::no_device;
  std::string detail;
  std::string hint;  ///< appended to the gpu-request error in parentheses, e.g. "use --device cpu"
};

struct DeviceDecision {
  bool gpu = false;    ///< run (or keep) the GPU result
  std::string notice;  ///< auto fell back to the CPU: one line for the user, without a program prefix
};

/// The policy. `unusable`: nullopt when the GPU path ran or can run (never looked at
/// for cpu). `fallback`: what the CPU path does instead, e.g. "rendering on the CPU".
/// `what`: how the request is named in the error, e.g. "--device".
///   cpu  -> {false, ""}
///   gpu  -> {true, ""}, or throws std::runtime_error("<what> gpu: " + reason)
///   auto -> {true, ""}, or {false, reason' + "; " + fallback}
/// with, by cause: no_device   reason = detail,           reason' = "no GPU (" + detail + ")"
///                 unsupported reason = reason' = detail + " is not supported on the GPU"
///                 not_built   reason = "atmosh was built without ATMOSH_WITH_GPU",
///                             reason' = "built without GPU support"
/// and " (" + hint + ")" after the gpu error's reason when a hint is given.
DeviceDecision resolve_device(DeviceRequest request, const std::optional<GpuUnusable>& unusable,
                              const std::string& fallback, const std::string& what = "--device");

}  // namespace atmosh
