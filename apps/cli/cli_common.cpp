#include "cli_common.hpp"

#include <algorithm>
#include <cstdio>
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

// ---- limits checked before work ------------------------------------------------------
namespace {
std::optional<std::size_t> g_budget;  // --max-memory
}  // namespace

// The budget: --max-memory, else what this process may still take (atmosh/memory.hpp).
std::size_t memory_budget() { return g_budget ? *g_budget : available_memory().bytes; }

void set_memory_budget(std::size_t bytes) { g_budget = bytes; }

void check_memory(std::size_t bytes, const std::string& what) {
  const std::size_t budget = memory_budget();
  if (bytes > budget)
    throw InputError(what + " needs about " + format_bytes(static_cast<double>(bytes)) +
                     " of memory (estimate), more than the budget of " + format_bytes(static_cast<double>(budget)) +
                     " (" +
                     (g_budget ? std::string("--max-memory")
                      : available_memory().source == AvailableMemory::Source::cgroup
                          ? std::string("the cgroup's memory.max less its usage; set with --max-memory")
                          : std::string("MemAvailable; set with --max-memory")) +
                     ")");
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

// ---- the time budget -----------------------------------------------------------------
namespace {
std::optional<double> g_time_budget;  // --max-time
std::string estimate_detail(const WorkEstimate& w, int workers) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.3g %s at %.3g s each on one core, %d worker%s", w.units, w.unit.c_str(),
                w.seconds_per_unit, std::max(workers, 1), workers > 1 ? "s" : "");
  return buf;
}
}  // namespace

double time_budget() { return g_time_budget ? *g_time_budget : kDefaultTimeBudgetS; }

void set_time_budget(double seconds) { g_time_budget = seconds; }

std::string describe_work(const WorkEstimate& w, int workers) {
  if (workers <= 0) workers = available_cpus();
  return "about " + format_duration(w.wall_seconds(workers)) + " (estimate: " + estimate_detail(w, workers) + ")";
}

void check_time(const WorkEstimate& w, int workers, const std::string& what) {
  if (workers <= 0) workers = available_cpus();
  const double wall = w.wall_seconds(workers);
  if (!(wall <= time_budget()))
    throw InputError(what + " needs about " + format_duration(wall) + " of computing (estimate: " +
                     estimate_detail(w, workers) + "), more than the time budget of " + format_duration(time_budget()) +
                     (g_time_budget ? " (--max-time)" : " (the default; set with --max-time)"));
}

}  // namespace atmosh::cli
