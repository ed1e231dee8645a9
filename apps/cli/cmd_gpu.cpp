// atmosh gpu info — which headless OpenGL device and driver atmosh would use.
#include <iostream>

#include "cli_common.hpp"
#ifdef ATMOSH_HAVE_GPU
#include "atmosh/gpu/context.hpp"
#endif

namespace atmosh::cli {

void register_gpu_commands(CLI::App& app) {
  auto* g = app.add_subcommand("gpu", "Headless OpenGL (EGL) device information")->require_subcommand(1);
  auto* info = g->add_subcommand("info", "Create a headless EGL context and report vendor, renderer, GL version");
  static bool json = false;
  add_json_flag(info, json);
  info->callback([] {
    nlohmann::json j;
#ifdef ATMOSH_HAVE_GPU
    try {
      gpu::Context ctx;
      const auto& i = ctx.info();
      j = {{"available", true},      {"platform", i.platform}, {"vendor", i.vendor},
           {"renderer", i.renderer}, {"gl_version", i.version}, {"egl_vendor", i.egl_vendor},
           {"software", i.software}};
    } catch (const gpu::Unavailable& e) {
      j = {{"available", false}, {"reason", e.what()}};
    }
#else
    j = {{"available", false}, {"reason", "atmosh was built without ATMOSH_WITH_GPU"}};
#endif
    if (json) return print_json(j);
    if (!j["available"].get<bool>()) {
      std::cout << "no headless OpenGL device: " << j["reason"].get<std::string>() << "\n";
      return;
    }
    std::cout << "platform:   " << j["platform"].get<std::string>() << "\nvendor:     " << j["vendor"].get<std::string>()
              << "\nrenderer:   " << j["renderer"].get<std::string>()
              << "\nGL version: " << j["gl_version"].get<std::string>() << "\n";
  });
}

}  // namespace atmosh::cli
