#include "atmosh/io/provenance.hpp"

#include <unistd.h>

#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <ctime>

#include "atmosh/format.hpp"
#include "atmosh/parallel.hpp"

namespace atmosh::io {

namespace detail {
extern const char* const kVersion;
extern const char* const kGitCommit;
}  // namespace detail

std::string version_string() { return detail::kVersion; }
std::string git_commit() { return detail::kGitCommit; }

namespace {
std::string& command_line_storage() {
  static std::string s;
  return s;
}
std::string shell_quote(const std::string& a) {
  if (!a.empty() && a.find_first_of(" \t\n'\"\\$`*?;&|<>()") == std::string::npos) return a;
  std::string q = "'";
  for (char c : a) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

void set_command_line(int argc, const char* const* argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) {
    if (i) s += ' ';
    s += shell_quote(argv[i]);
  }
  command_line_storage() = s;
}

const std::string& command_line() { return command_line_storage(); }

namespace {
std::atomic<int> g_threads{0};
}
void set_threads(int threads) { g_threads = threads; }

std::string utc_now_iso8601() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string format_double(double v) { return atmosh::format_double(v); }

Provenance Provenance::current() {
  Provenance p;
  p.add("atmosh_version", version_string());
  p.add("git_commit", git_commit());
  p.add("command_line", command_line().empty() ? std::string("(library call)") : command_line());
  p.add("run_utc", utc_now_iso8601());
  char host[256] = {0};
  if (gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  p.add("host", host[0] ? host : "unknown");
  p.add("host_cores", static_cast<double>(::sysconf(_SC_NPROCESSORS_ONLN)));
  p.add("available_cpus", static_cast<double>(available_cpus()));
  if (const int t = g_threads.load(); t > 0) p.add("threads", static_cast<double>(t));
  return p;
}

Provenance& Provenance::add(const std::string& key, const std::string& value) {
  entries.emplace_back(key, value);
  return *this;
}

Provenance& Provenance::add(const std::string& key, double value) { return add(key, format_double(value)); }

}  // namespace atmosh::io
