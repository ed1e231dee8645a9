// atmosh converge ms — the sky's scattering methods (single, the all-orders
// approximation, successive orders, table sizes) against the Monte-Carlo reference:
// error against run time (the study: atmosh::studies::converge_ms).
#include "atmosh/error.hpp"
#include "atmosh/studies/ms.hpp"
#include "cli_common.hpp"

namespace atmosh::cli {

void register_converge_ms_command(CLI::App& app) {
  static std::string scene_file, output;
  static studies::ConvergeMsOptions o;
  static bool netcdf = false;
  auto* c = app.get_subcommand("converge")->add_subcommand(
      "ms", "Sky scattering methods (single, approximate, orders; table sizes) against the Monte-Carlo reference");
  add_scene_option(c, scene_file);
  auto* paths = c->add_option("--paths", o.paths, "Monte-Carlo paths per reference row (default 128000; --quick 16000)");
  c->add_option("--seed", o.seed, "Random seed of the reference")->capture_default_str();
  c->add_flag("--quick", o.quick, "4 rows (zenith and horizon, sun 30 and 10 deg), 3 settings: a few seconds");
  c->add_option("-o,--output", output, "Output folder (ms_convergence.csv, .png, ms_convergence_points.csv)")
      ->required();
  add_format_option(c, netcdf);
  c->callback([paths] {
    studies::ConvergeMsOptions so = o;
    if (paths->count() == 0) so.paths = o.quick ? 16000 : 128000;
    if (so.paths < 1 || so.paths > (std::int64_t{1} << 40))
      throw InputError("--paths " + std::to_string(so.paths) + ": must be in [1, 2^40]");
    if (output.empty()) throw InputError("-o is required (output folder)");
    check_output_dir(output, "-o");
    print_files(studies::write_converge_ms(studies::converge_ms(scene_or_default(scene_file), so), output, netcdf));
  });
}

}  // namespace atmosh::cli
