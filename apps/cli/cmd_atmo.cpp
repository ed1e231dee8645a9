// atmosh optical-depth, phase, stability, converge lut (placeholder).
#include "cli_common.hpp"

namespace atmosh::cli {
void register_atmo_commands(CLI::App&) {}
void demo_atmo(DemoContext&) {}
}  // namespace atmosh::cli
