// atmosh sun — solar position subcommands (placeholder).
#include "cli_common.hpp"

namespace atmosh::cli {
void register_sun_commands(CLI::App&) {}
void demo_sun(DemoContext&) {}
}  // namespace atmosh::cli
