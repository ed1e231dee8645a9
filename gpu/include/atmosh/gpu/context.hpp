// atmosh/gpu/context.hpp — a headless OpenGL context through EGL.
//
// No display server is needed. The constructor tries, in order:
//   1. the EGL device platform (EGL_EXT_platform_device): hardware devices first
//      (NVIDIA's driver exposes its GPUs this way);
//   2. Mesa's surfaceless platform (EGL_MESA_platform_surfaceless; llvmpipe in CI).
// It requests desktop OpenGL 4.5 core, then 4.3 core (compute shaders, SSBOs, float
// textures). If none works it throws atmosh::gpu::Unavailable, which callers use
// to fall back to the CPU path. The context is current on the constructing thread.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

namespace atmosh::gpu {

class Unavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ContextInfo {
  std::string platform;     // "device" or "surfaceless"
  std::string vendor;       // GL_VENDOR
  std::string renderer;     // GL_RENDERER
  std::string version;      // GL_VERSION
  std::string egl_vendor;   // EGL_VENDOR
  int gl_major = 0, gl_minor = 0;
  bool software = false;    // llvmpipe / softpipe / swrast
};

class Context {
 public:
  Context();
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  const ContextInfo& info() const;
  void make_current() const;

  struct Impl;  // EGL handles (opaque)

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace atmosh::gpu
