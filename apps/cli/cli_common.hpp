// cli_common.hpp — shared helpers for the atmosh subcommands (apps/ only).
//
// Conventions every subcommand follows:
//  * bad user input -> throw atmosh::InputError("--dir: 'a,b' is not three numbers")
//    (one line, naming the option/key and the value); main() prints
//    "atmosh: error: <message>" and exits 2. Other failures exit 1. The libraries'
//    option checks (SkySettings::checked, rt_slab, prt_bake_options, ...) name the
//    options the same way.
//  * scalar queries take --json and print exactly one JSON object via print_json
//    (doubles round-trip, >= 17 significant digits); the objects come from the
//    libraries (atmosh/studies/summaries.hpp, atmosh/gi/driver.hpp).
//  * every file goes through atmosh::io writers (atomic, with provenance).
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "atmosh/check.hpp"  // require_range, parse_list, parse_triple, parse_size
#include "atmosh/device.hpp"
#include "atmosh/io/output_check.hpp"
#include "atmosh/memory.hpp"
#include "atmosh/progress.hpp"
#include "atmosh/budget.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/studies/sky.hpp"

namespace atmosh::cli {

void print_json(const nlohmann::json& j);
// Each file on its own line of stdout, after `prefix`.
void print_files(const std::vector<std::filesystem::path>& files, const std::string& prefix = "");
// A library's one-line notice on stderr: "atmosh: <message>".
void notice(const std::string& message);
// A ProgressStep (progress.hpp) around work(its callback): the libraries' step runners.
void run_step(const std::string& name, const std::function<void(const ProgressCallback&)>& work);

// --device cpu|gpu|auto: InputError naming any other value. (Meaning, everywhere:
// "cpu" never touches EGL; "gpu" needs a headless EGL device, else exit 1; "auto"
// falls back to the CPU with a one-line notice on stderr: atmosh::resolve_device.)
DeviceRequest check_device(const std::string& device);
// --threads: the worker count for a requested one, by the toolkit's one policy
// (atmosh::resolve_threads: 0 = the CPUs this process may use, affinity and cgroup
// quota included), also recorded in the provenance; InputError naming the option for
// a negative count or one > 1024.
int threads_option(int requested, const std::string& option = "--threads");
// The scene of --scene FILE, or the built-in scene when none is given.
scene::Scene scene_or_default(const std::string& file);

// ---- option groups that several subcommands share ---------------------------------
// --scene FILE (default: the built-in scene).
CLI::Option* add_scene_option(CLI::App* c, std::string& file);
// --json: print one JSON object.
CLI::Option* add_json_flag(CLI::App* c, bool& json);
// --threads N (0 = the CPUs this process may use).
CLI::Option* add_threads_option(CLI::App* c, int& threads);
// --device cpu|gpu|auto, with what the device does for this command.
CLI::Option* add_device_option(CLI::App* c, std::string& device, const std::string& what);
// The sky integrator's quality options (--shells, --segments, --samples,
// --max-piece-tau, --threads, --sun-model, --scattering, --orders) into the studies'
// one settings struct; names are parsed as given (InputError naming the option).
void add_quality_options(CLI::App* c, studies::SkySettings& q);
// The settings checked (studies::SkySettings::checked), threads recorded in the provenance.
studies::SkySettings checked_quality(const studies::SkySettings& q);

// ---- limits checked before work: atmosh/budget.hpp (--max-memory, --max-time) ----
using atmosh::check_memory;
using atmosh::check_time;
using atmosh::describe_work;
using atmosh::memory_budget;

// --format csv|netcdf of a table output (netCDF-CF beside the CSV, atmosh/io/netcdf.hpp),
// checked when parsed. For an output folder it sets `netcdf` (handed to the writer); for
// an output stem, `--format netcdf` is `-o STEM.nc` (the writers' io::table_output_stem).
void add_format_option(CLI::App* c, bool& netcdf);
void add_format_option(CLI::App* c, std::string& stem);

// Output paths checked before any work (atmosh/io/output_check.hpp).
using io::check_output_dir;
using io::check_output_file;
using io::check_study_stem;

// Subcommand registration, one function per area (each in its own .cpp).
void register_scene_commands(CLI::App& app);   // scene show, plan, demo
void register_sh_commands(CLI::App& app);      // sh project|eval|rotate|irradiance|bands|converge
void register_sun_commands(CLI::App& app);     // sun (single time, ranges, accuracy)
void register_atmo_commands(CLI::App& app);    // optical-depth, phase, stability, converge lut
void register_gpu_commands(CLI::App& app);     // gpu info
void register_sky_commands(CLI::App& app);     // sky, study, sweep, converge sky
void register_prt_commands(CLI::App& app);     // prt bake|relight|converge
void register_rt_commands(CLI::App& app);      // rt slab|sky (Monte-Carlo radiative transfer)
void register_gi_commands(CLI::App& app);      // gi render|converge
void register_converge_ms_command(CLI::App& app);  // converge ms (scattering methods against the MC reference)

}  // namespace atmosh::cli
