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

#include "atmosh/atmo/spec.hpp"
#include "atmosh/device.hpp"
#include "atmosh/io/output_check.hpp"
#include "atmosh/memory.hpp"
#include "atmosh/work.hpp"
#include "atmosh/scene/scene.hpp"

namespace atmosh::cli {

void print_json(const nlohmann::json& j);

// "x,y,z" -> three finite doubles; InputError naming `what` otherwise.
std::array<double, 3> parse_triple(const std::string& text, const std::string& what);
// Comma-separated finite doubles.
std::vector<double> parse_list(const std::string& text, const std::string& what);
// "WxH" -> {W, H}, both in [1, 65536].
std::array<int, 2> parse_size(const std::string& text, const std::string& what);
// --device cpu|gpu|auto: InputError naming any other value. (Meaning, everywhere:
// "cpu" never touches EGL; "gpu" needs a headless EGL device, else exit 1; "auto"
// falls back to the CPU with a one-line notice on stderr: atmosh::resolve_device.)
DeviceRequest check_device(const std::string& device);
// Prints the decision's fallback notice, if any, as one "atmosh: ..." line on stderr.
void device_notice(const DeviceDecision& decision);
// --threads: the worker count for a requested one, by the toolkit's one policy
// (atmosh::resolve_threads: 0 = the CPUs this process may use, affinity and cgroup
// quota included); InputError naming the option for a negative count or one > 1024.
int threads_option(int requested, const std::string& option = "--threads");
// Throws InputError unless v is finite and lo <= v <= hi.
double require_range(double v, double lo, double hi, const std::string& what);

// ---- limits checked before work ---------------------------------------------------
// The memory budget of one command: --max-memory when given, else the memory this
// process may still take (atmosh::available_memory, atmosh/memory.hpp, which also has
// parse_memory_size, format_bytes and the saturating mul_bytes).
// Every command that sizes its work from the user's numbers estimates its memory from
// those sizes (the estimators live next to what they estimate and return bytes) and
// calls check_memory before it starts.
std::size_t memory_budget();
void set_memory_budget(std::size_t bytes);  // --max-memory
// InputError "<what> needs about 12.3 GiB (estimate), more than the memory budget of
// 7.6 GiB (MemAvailable; set with --max-memory)" when bytes exceed the budget.
void check_memory(std::size_t bytes, const std::string& what);
// The time budget of one command [s of wall time]: --max-time when given, else
// atmosh::kDefaultTimeBudgetS (24 h). Commands whose work is clear from their sizes
// estimate it (atmosh/work.hpp; the estimators live next to what they estimate) and call
// check_time before they start: InputError "<what> needs about 3.2 days of computing
// (estimate: 2.1e+13 ray nodes x wavelengths at 1.4e-08 s each on one core, 2 workers),
// more than the time budget of 24 h (set with --max-time)".
double time_budget();
void set_time_budget(double seconds);  // --max-time
// workers: the threads that share the work (0: the CPUs this process may use).
void check_time(const WorkEstimate& work, int workers, const std::string& what);
// "about 3.2 h on 2 workers (estimate: ...)" for `plan`.
std::string describe_work(const WorkEstimate& work, int workers);

// --format csv|netcdf of a table output (netCDF-CF beside the CSV, atmosh/io/netcdf.hpp),
// checked when parsed. For an output folder it sets `netcdf` (handed to the writer); for
// an output stem, `--format netcdf` is `-o STEM.nc` (the writers' io::table_output_stem).
void add_format_option(CLI::App* c, bool& netcdf);
void add_format_option(CLI::App* c, std::string& stem);

// Output paths checked before any work (atmosh/io/output_check.hpp).
using io::check_output_dir;
using io::check_output_file;
using io::check_study_stem;

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
void register_prt_commands(CLI::App& app);     // prt bake|relight|converge
void register_rt_commands(CLI::App& app);      // rt slab|sky (Monte-Carlo radiative transfer)
void register_converge_ms_command(CLI::App& app);  // converge ms (scattering methods against the MC reference)

// Computes exactly the outputs a scene lists (and the tables they need) into dir;
// sky images on `device` (cpu | gpu | auto, as render_sky_on).
void run_scene(const scene::Scene& scene, const std::filesystem::path& dir, bool quick,
               std::vector<std::filesystem::path>& written, const std::string& device = "cpu");

// Parts of the main job, run in this order by `atmosh demo`.
void demo_sun(DemoContext& ctx);
void demo_atmo(DemoContext& ctx);
void demo_sh(DemoContext& ctx);
void demo_sky(DemoContext& ctx);
void demo_ms(DemoContext& ctx);  // converge ms --quick
void demo_prt(DemoContext& ctx);

}  // namespace atmosh::cli
