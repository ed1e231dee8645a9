// For the CLI tests of `--device`: the command line run as on a machine without an EGL
// device.
#pragma once

#include <cstdlib>
#include <optional>
#include <string>

namespace atmosh::test {

// While one lives, glvnd reads its EGL vendor list from a file that does not exist
// (__EGL_VENDOR_LIBRARY_FILENAMES), so that no EGL display opens in the processes started
// meanwhile; the variable as it was comes back afterwards.
class WithoutEglDevice {
 public:
  WithoutEglDevice() {
    if (const char* old = std::getenv(kVar)) saved_ = old;
    ::setenv(kVar, "/nonexistent/atmosh_no_egl_vendor.json", 1);
  }
  ~WithoutEglDevice() {
    if (saved_)
      ::setenv(kVar, saved_->c_str(), 1);
    else
      ::unsetenv(kVar);
  }
  WithoutEglDevice(const WithoutEglDevice&) = delete;
  WithoutEglDevice& operator=(const WithoutEglDevice&) = delete;

 private:
  static constexpr const char* kVar = "__EGL_VENDOR_LIBRARY_FILENAMES";
  std::optional<std::string> saved_;
};

}  // namespace atmosh::test
