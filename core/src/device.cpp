#include "atmosh/device.hpp"

#include <stdexcept>

#include "atmosh/error.hpp"

namespace atmosh {

DeviceRequest parse_device_request(const std::string& text, const std::string& what) {
  if (text == "cpu") return DeviceRequest::cpu;
  if (text == "gpu") return DeviceRequest::gpu;
  if (text == "auto") return DeviceRequest::automatic;
  throw InputError(what + " " + text + ": must be cpu, gpu or auto");
}

const char* device_request_name(DeviceRequest request) {
  switch (request) {
    case DeviceRequest::cpu: return "cpu";
    case DeviceRequest::gpu: return "gpu";
    case DeviceRequest::automatic: return "auto";
  }
  return "?";
}

DeviceDecision resolve_device(DeviceRequest request, const std::optional<GpuUnusable>& unusable,
                              const std::string& fallback, const std::string& what) {
  if (request == DeviceRequest::cpu) return {false, {}};
  if (!unusable) return {true, {}};
  std::string error, notice;
  switch (unusable->why) {
    case GpuUnusable::Why::no_device:
      error = unusable->detail;
      notice = "no GPU (" + unusable->detail + ")";
      break;
    case GpuUnusable::Why::unsupported:
      error = notice = unusable->detail + " is not supported on the GPU";
      break;
    case GpuUnusable::Why::not_built:
      error = "atmosh was built without ATMOSH_WITH_GPU";
      notice = "built without GPU support";
      break;
  }
  if (request == DeviceRequest::gpu)
    throw std::runtime_error(what + " gpu: " + error + (unusable->hint.empty() ? "" : " (" + unusable->hint + ")"));
  return {false, notice + "; " + fallback};
}

}  // namespace atmosh
