// atmosh converge ms — the sky's scattering methods (single, the all-orders
// approximation, successive orders, table sizes) against the Monte-Carlo reference:
// error against run time (the study: atmosh::studies::converge_ms).
#include <filesystem>
#include <iostream>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/studies/ms.hpp"
#include "cli_common.hpp"

namespace atmosh::cli {

namespace fs = std::filesystem;

namespace {

struct ConvergeMs {
  std::string scene_file, output;
  std::int64_t paths = 0;
  bool paths_given = false;  // else the default of the mode (quick: 16000, full: 128000)
  std::uint64_t seed = 1;
  bool quick = false, netcdf = false;
};

std::vector<fs::path> run_converge_ms(const ConvergeMs& o) {
  const std::int64_t paths = o.paths_given ? o.paths : (o.quick ? 16000 : 128000);
  if (paths < 1 || paths > (std::int64_t{1} << 40))
    throw InputError("--paths " + std::to_string(paths) + ": must be in [1, 2^40]");
  if (o.output.empty()) throw InputError("-o is required (output folder)");
  check_output_dir(o.output, "-o");
  const scene::Scene s = o.scene_file.empty() ? scene::default_scene() : scene::load_scene(o.scene_file);
  studies::ConvergeMsOptions so;
  so.paths = paths;
  so.seed = o.seed;
  so.quick = o.quick;
  return studies::write_converge_ms(studies::converge_ms(s, so), o.output, o.netcdf);
}

}  // namespace

void register_converge_ms_command(CLI::App& app) {
  static ConvergeMs o;
  auto* c = app.get_subcommand("converge")->add_subcommand(
      "ms", "Sky scattering methods (single, approximate, orders; table sizes) against the Monte-Carlo reference");
  c->add_option("--scene", o.scene_file, "Scene file (default: built-in scene)");
  auto* paths = c->add_option("--paths", o.paths, "Monte-Carlo paths per reference row (default 128000; --quick 16000)");
  c->add_option("--seed", o.seed, "Random seed of the reference")->capture_default_str();
  c->add_flag("--quick", o.quick, "4 rows (zenith and horizon, sun 30 and 10 deg), 3 settings: a few seconds");
  c->add_option("-o,--output", o.output, "Output folder (ms_convergence.csv, .png, ms_convergence_points.csv)")
      ->required();
  add_format_option(c, o.netcdf);
  c->callback([paths] {
    o.paths_given = paths->count() > 0;
    for (const auto& f : run_converge_ms(o)) std::cout << f.string() << "\n";
  });
}

void demo_ms(DemoContext& ctx) {
  for (const auto& f : studies::demo_ms(ctx.out_dir)) ctx.written.push_back(f);
}

}  // namespace atmosh::cli
