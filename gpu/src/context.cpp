#include "atmosh/gpu/context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>

#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define ATMOSH_GPU_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ATMOSH_GPU_ASAN 1
#endif
#endif
#ifdef ATMOSH_GPU_ASAN
#include <dlfcn.h>
#include <link.h>
#endif

#ifndef EGL_PLATFORM_SURFACELESS_MESA
#define EGL_PLATFORM_SURFACELESS_MESA 0x31DD
#endif

namespace atmosh::gpu {

struct Context::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  ContextInfo info;
};

namespace {

bool has_ext(const char* list, const char* ext) {
  if (!list) return false;
  const std::size_t n = std::strlen(ext);
  for (const char* p = list; (p = std::strstr(p, ext)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

// EGL hands every Context of a device the same display, and eglTerminate ends every
// context on it at once: a display is terminated only when no Context holds it (the
// count of the Contexts made on it and not yet destroyed).
std::mutex& display_mutex() {
  static std::mutex m;
  return m;
}
std::map<EGLDisplay, int>& display_users() {
  static std::map<EGLDisplay, int> users;
  return users;
}
// Terminates `dpy` unless a living Context uses it (display_mutex held).
void release_display(EGLDisplay dpy) {
  const auto it = display_users().find(dpy);
  if (it == display_users().end() || it->second == 0) eglTerminate(dpy);
}

bool try_display(EGLDisplay dpy, const char* platform, Context::Impl& out) {
  if (dpy == EGL_NO_DISPLAY) return false;
  const std::lock_guard<std::mutex> lock(display_mutex());
  EGLint major = 0, minor = 0;
  if (!eglInitialize(dpy, &major, &minor)) return false;
  if (!eglBindAPI(EGL_OPENGL_API)) {
    release_display(dpy);
    return false;
  }
  const EGLint cfg_attr[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig cfg = nullptr;
  EGLint ncfg = 0;
  const bool no_config = has_ext(eglQueryString(dpy, EGL_EXTENSIONS), "EGL_KHR_no_config_context");
  if (!eglChooseConfig(dpy, cfg_attr, &cfg, 1, &ncfg) || ncfg < 1) {
    if (!no_config) {
      release_display(dpy);
      return false;
    }
    cfg = nullptr;  // EGL_NO_CONFIG_KHR
  }
  for (int minor_v : {5, 3}) {
    const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, minor_v,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, cfg, EGL_NO_CONTEXT, ctx_attr);
    if (ctx == EGL_NO_CONTEXT) continue;
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
      eglDestroyContext(dpy, ctx);
      continue;
    }
    out.display = dpy;
    out.context = ctx;
    ++display_users()[dpy];
    auto str = [](GLenum e) {
      const auto* s = reinterpret_cast<const char*>(glGetString(e));
      return std::string(s ? s : "");
    };
    out.info.platform = platform;
    out.info.vendor = str(GL_VENDOR);
    out.info.renderer = str(GL_RENDERER);
    out.info.version = str(GL_VERSION);
    const char* ev = eglQueryString(dpy, EGL_VENDOR);
    out.info.egl_vendor = ev ? ev : "";
    out.info.gl_major = 4;
    out.info.gl_minor = minor_v;
    const std::string r = out.info.renderer;
    out.info.software = r.find("llvmpipe") != std::string::npos || r.find("softpipe") != std::string::npos ||
                        r.find("swrast") != std::string::npos;
    return true;
  }
  release_display(dpy);
  return false;
}

// Under AddressSanitizer only: keeps the loaded OpenGL driver modules mapped until
// the process exits. eglTerminate of the last display unloads the driver; blocks the
// driver leaked are then reported with no module name, and tests/lsan.supp (which
// suppresses leaks inside the system's drivers by module) cannot match them.
void pin_driver_modules() {
#ifdef ATMOSH_GPU_ASAN
  std::vector<std::string> names;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* out) {
        const char* n = info->dlpi_name;
        if (n && (std::strstr(n, "_dri.so") || std::strstr(n, "libgallium") || std::strstr(n, "libLLVM") ||
                  std::strstr(n, "libEGL_mesa") || std::strstr(n, "libglapi")))
          static_cast<std::vector<std::string>*>(out)->emplace_back(n);
        return 0;
      },
      &names);
  for (const auto& n : names) dlopen(n.c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);
#endif
}

}  // namespace

Context::Context() : impl_(std::make_unique<Impl>()) {
  const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) throw Unavailable("EGL: eglGetPlatformDisplayEXT is not available");

  // 1. Device platform, hardware devices before software ones.
  if (has_ext(client_ext, "EGL_EXT_platform_device")) {
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_device_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLint n = 0;
    if (query_devices && query_devices(0, nullptr, &n) && n > 0) {
      std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(n));
      query_devices(n, devices.data(), &n);
      for (int pass = 0; pass < 2; ++pass)
        for (EGLDeviceEXT d : devices) {
          const char* dext = query_device_string ? query_device_string(d, EGL_EXTENSIONS) : nullptr;
          const bool software = has_ext(dext, "EGL_MESA_device_software");
          if ((pass == 0) == software) continue;
          if (try_display(get_platform_display(EGL_PLATFORM_DEVICE_EXT, d, nullptr), "device", *impl_)) {
            pin_driver_modules();
            return;
          }
        }
    }
  }
  // 2. Mesa surfaceless.
  if (has_ext(client_ext, "EGL_MESA_platform_surfaceless") &&
      try_display(get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr), "surfaceless",
                  *impl_)) {
    pin_driver_modules();
    return;
  }
  throw Unavailable("no EGL device offers a headless OpenGL 4.3+ core context");
}

Context::~Context() {
  if (impl_ && impl_->display != EGL_NO_DISPLAY) {
    if (eglGetCurrentContext() == impl_->context)  // another Context current here stays so
      eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (impl_->context != EGL_NO_CONTEXT) eglDestroyContext(impl_->display, impl_->context);
    const std::lock_guard<std::mutex> lock(display_mutex());
    if (--display_users()[impl_->display] == 0) eglTerminate(impl_->display);
  }
}

const ContextInfo& Context::info() const { return impl_->info; }

void Context::make_current() const {
  if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
    throw std::runtime_error("eglMakeCurrent failed");
}

}  // namespace atmosh::gpu
