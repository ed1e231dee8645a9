// atmosh sh ... — spherical-harmonic subcommands (placeholder until libsh lands).
#include "cli_common.hpp"

namespace atmosh::cli {
void register_sh_commands(CLI::App&) {}
void demo_sh(DemoContext&) {}
}  // namespace atmosh::cli
