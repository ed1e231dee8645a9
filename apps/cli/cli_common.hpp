// cli_common.hpp — shared helpers for the atmosh subcommands (apps/ only).
//
// Conventions every subcommand follows:
//  * bad user input -> throw atmosh::InputError("--dir: 'a,b' is not three numbers")
//    (one line, naming the option/key and the value); main() prints
//    "atmosh: error: <message>" and exits 2. Other failures exit 1.
//  * scalar queries take --json and print exactly one JSON object via print_json
//    (doubles round-trip, >= 17 significant digits).
//  * every file goes through atmosh::io writers (atomic, with provenance).
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace atmosh::cli {

void print_json(const nlohmann::json& j);

// "x,y,z" -> three finite doubles; InputError naming `what` otherwise.
std::array<double, 3> parse_triple(const std::string& text, const std::string& what);
// Comma-separated finite doubles.
std::vector<double> parse_list(const std::string& text, const std::string& what);
// "WxH" -> {W, H}, both in [1, 65536].
std::array<int, 2> parse_size(const std::string& text, const std::string& what);
// Throws InputError unless v is finite and lo <= v <= hi.
double require_range(double v, double lo, double hi, const std::string& what);

// What the main job (atmosh demo) passes to each part of the toolkit.
struct DemoContext {
  std::filesystem::path out_dir;
  bool quick = false;  // small, fast version (used by the test suite)
  std::vector<std::filesystem::path> written;  // files produced, announced at the end
};

// Subcommand registration, one function per area (each in its own .cpp).
void register_scene_commands(CLI::App& app);   // scene show, plan, demo
void register_sh_commands(CLI::App& app);      // sh project|eval|rotate|irradiance|bands|converge
void register_sun_commands(CLI::App& app);     // sun (single time, ranges, accuracy)
void register_atmo_commands(CLI::App& app);    // optical-depth, phase, stability, converge lut
void register_gpu_commands(CLI::App& app);     // gpu info
void register_sky_commands(CLI::App& app);     // sky, study, sweep, converge sky

// Parts of the main job, run in this order by `atmosh demo`.
void demo_sun(DemoContext& ctx);
void demo_atmo(DemoContext& ctx);
void demo_sh(DemoContext& ctx);
void demo_sky(DemoContext& ctx);

}  // namespace atmosh::cli
