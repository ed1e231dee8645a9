#include "cli_common.hpp"

#include <deque>
#include <iostream>
#include <optional>

#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/io/netcdf.hpp"
#include "atmosh/io/provenance.hpp"
#include "progress.hpp"

namespace atmosh::cli {

void print_json(const nlohmann::json& j) { std::cout << j.dump(2) << std::endl; }

void print_files(const std::vector<std::filesystem::path>& files, const std::string& prefix) {
  for (const auto& f : files) std::cout << prefix << f.string() << "\n";
}

void notice(const std::string& message) { std::cerr << "atmosh: " << message << "\n"; }

void run_step(const std::string& name, const std::function<void(const ProgressCallback&)>& work) {
  ProgressStep step(name);
  work(step.callback());
}

int threads_option(int requested, const std::string& option) {
  const int n = resolve_threads(requested, option);
  io::set_threads(n);
  return n;
}

DeviceRequest check_device(const std::string& device) { return parse_device_request(device, "--device"); }

scene::Scene scene_or_default(const std::string& file) {
  return file.empty() ? scene::default_scene() : scene::load_scene(file);
}

CLI::Option* add_scene_option(CLI::App* c, std::string& file) {
  return c->add_option("--scene", file, "Scene file (default: the built-in scene)");
}

CLI::Option* add_json_flag(CLI::App* c, bool& json) { return c->add_flag("--json", json, "Print one JSON object"); }

CLI::Option* add_threads_option(CLI::App* c, int& threads) {
  return c->add_option("--threads", threads, "Worker threads (0 = the CPUs this process may use)")
      ->capture_default_str();
}

CLI::Option* add_device_option(CLI::App* c, std::string& device, const std::string& what) {
  return c->add_option("--device", device, "cpu, gpu or auto (GPU if a headless EGL device exists, else CPU): " + what)
      ->capture_default_str();
}

void add_quality_options(CLI::App* c, studies::SkySettings& q) {
  c->add_option("--shells", q.shells, "Shells of the optical-depth tables")->capture_default_str();
  c->add_option("--segments", q.segments, "Shells that cut each view ray")->capture_default_str();
  c->add_option("--samples", q.samples, "Gauss-Legendre points per view-ray piece")->capture_default_str();
  c->add_option("--max-piece-tau", q.max_piece_tau,
                "Largest extinction optical depth of one view-ray piece before it is split (accuracy vs speed: "
                "see atmosh converge sky)")
      ->capture_default_str();
  add_threads_option(c, q.threads);
  c->add_option_function<std::string>(
      "--sun-model", [&q](const std::string& v) { q.sun_model = atmo::parse_sun_model(v); },
      "disc (limb-darkened solar disc: direct beam, sun colour, the sun in images) or point; "
      "default: the scene's sun_model (disc)");
  c->add_option_function<std::string>(
      "--scattering", [&q](const std::string& v) { q.scattering = atmo::parse_scattering_method(v, "--scattering"); },
      "Scattering method: single | orders | approximate (default: the scene's [scattering] method)");
  c->add_option("--orders", q.orders, "Highest order of scattering for --scattering orders (default: the scene's)");
}

studies::SkySettings checked_quality(const studies::SkySettings& q) {
  const studies::SkySettings k = q.checked();
  io::set_threads(k.threads);
  return k;
}

void add_format_option(CLI::App* c, bool& netcdf) {
  c->add_option_function<std::string>("--format", [&netcdf](const std::string& v) { netcdf = io::parse_table_format(v); },
                                      "csv (default) | netcdf: the table also as netCDF-CF (.nc beside the .csv)");
}

void add_format_option(CLI::App* c, std::string& stem) {
  static std::deque<bool> flags;  // one per command, alive as long as the program
  bool& netcdf = flags.emplace_back(false);
  add_format_option(c, netcdf);
  c->parse_complete_callback([&netcdf, &stem] { if (netcdf && !stem.ends_with(".nc")) stem += ".nc"; });
}

}  // namespace atmosh::cli
