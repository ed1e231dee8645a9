// atmosh — command line entry point. Maps errors to exit codes:
// 0 success, 2 bad input (one line naming the value), 1 other failure.
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace {
std::string first_line(std::string s) {
  if (auto p = s.find('\n'); p != std::string::npos) s.resize(p);
  return s;
}
}  // namespace

int main(int argc, char** argv) {
  atmosh::io::set_command_line(argc, argv);
  // ATMOSH_PLOT_DATA=1: every plot also writes <name>.png.plot.json (docs/outputs.md).
  if (const char* v = std::getenv("ATMOSH_PLOT_DATA"); v != nullptr && std::strcmp(v, "1") == 0)
    atmosh::io::set_plot_data_files(true);
  CLI::App app{
      "atmosh — physically based sky colour and spherical-harmonic analysis, with error bars and run times.\n"
      "Single and multiple scattering (Nishita 1993; Hillaire 2020; successive orders after Bruneton 2017) against a\n"
      "Monte-Carlo reference, NREL SPA sun positions, SH of any band.\n"
      "Every approximate method reports its error against an exact reference and its run time (CSV + plot).",
      "atmosh"};
  app.set_version_flag("--version",
                       "atmosh " + atmosh::io::version_string() + " (git " + atmosh::io::git_commit() + ")");
  app.require_subcommand(1);
  app.fallthrough();  // global options (--max-memory) also after the subcommand; inherited by subcommands
  app.add_option_function<std::string>(
         "--max-memory",
         [](const std::string& v) { atmosh::set_memory_budget(atmosh::parse_memory_size(v)); },
         "Memory budget of the command, e.g. 2G or 512M (default: the memory still available, from "
         "/proc/meminfo MemAvailable and the cgroup's limit). Requests estimated above it are refused "
         "(exit 2) before any work")
      ->trigger_on_parse();
  app.add_option_function<std::string>(
         "--max-time", [](const std::string& v) { atmosh::set_time_budget(atmosh::parse_time_budget(v)); },
         "Time budget of the command, e.g. 24h, 90m, 45s (default 24h). Requests whose computing is estimated "
         "from their sizes above it (sky images, studies, optical-depth tables, sh project sampling) are "
         "refused (exit 2) before any work")
      ->trigger_on_parse();
  app.add_flag_callback("-q,--quiet", [] { atmosh::cli::set_progress_quiet(true); },
                        "No progress lines or bars on stderr (also ATMOSH_QUIET=1)");
  app.footer(
      "Run `atmosh demo -o results` for the main job on the built-in default scene;\n"
      "`atmosh SUBCOMMAND --help` for details. Units: SI inside, degrees and nanometres at the\n"
      "command line, times in UTC (ISO 8601). Exit codes: 0 ok, 2 bad input, 1 other failure.");
  app.add_subcommand("converge", "Error against run time of an approximate method versus its exact reference")
      ->require_subcommand(1);

  atmosh::cli::register_scene_commands(app);
  atmosh::cli::register_sun_commands(app);
  atmosh::cli::register_atmo_commands(app);
  atmosh::cli::register_sh_commands(app);
  atmosh::cli::register_gpu_commands(app);
  atmosh::cli::register_sky_commands(app);
  atmosh::cli::register_prt_commands(app);
  atmosh::cli::register_rt_commands(app);
  atmosh::cli::register_gi_commands(app);
  atmosh::cli::register_converge_ms_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {  // a command's own failure status (e.g. stability: 1)
    return e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::cerr << "atmosh: error: " << first_line(e.what()) << " (see --help)\n";
    return 2;
  } catch (const atmosh::InputError& e) {
    std::cerr << "atmosh: error: " << first_line(e.what()) << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "atmosh: failure: " << first_line(e.what()) << '\n';
    return 1;
  }
  return 0;
}
