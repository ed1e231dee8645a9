// atmosh/io/provenance.hpp — where a result came from.
//
// Every output file carries provenance: atmosh version, git commit, the full
// command line, the scene parameters, the UTC time of the run and the host. CSV
// files get it as leading "# key: value" lines, EXR files as string attributes.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace atmosh::io {

std::string version_string();  // e.g. "0.1.0"
std::string git_commit();      // short hash with "-dirty" suffix, or "unknown"

// Records argv once at start-up (called by the CLI's main).
void set_command_line(int argc, const char* const* argv);
const std::string& command_line();
// Records the worker-thread count a command resolved (--threads, 0 = the CPUs this
// process may use); Provenance::current() then carries it as "threads".
void set_threads(int threads);

struct Provenance {
  std::vector<std::pair<std::string, std::string>> entries;

  // Version, commit, command line, UTC time (ISO 8601), host, its cores, the CPUs
  // this process may use (available_cpus) and the resolved "threads" (if set), in that order.
  static Provenance current();
  Provenance& add(const std::string& key, const std::string& value);
  Provenance& add(const std::string& key, double value);  // full precision
};

// ISO 8601 UTC timestamp of "now", e.g. 2026-11-22T04:08:48Z.
std::string utc_now_iso8601();
// Shortest decimal form that round-trips a double: atmosh::format_double
// (atmosh/format.hpp, the toolkit's one number formatter), e.g. 8e-6 -> "8e-06".
std::string format_double(double v);

}  // namespace atmosh::io
