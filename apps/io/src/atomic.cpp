#include "atmosh/io/atomic.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <optional>
#include <cerrno>
#include <fstream>
#include <mutex>
#include <set>
#include <stdexcept>
#include <system_error>

namespace atmosh::io {

namespace fs = std::filesystem;

std::optional<long> temporary_owner(const std::string& name) {
  // .NAME.tmp-PID-N[.ext]
  if (name.size() < 2 || name[0] != '.') return std::nullopt;
  const auto t = name.rfind(".tmp-");
  if (t == std::string::npos || t == 0) return std::nullopt;
  std::size_t i = t + 5, j = i;
  while (j < name.size() && std::isdigit(static_cast<unsigned char>(name[j]))) ++j;
  if (j == i || j - i > 9 || j >= name.size() || name[j] != '-') return std::nullopt;
  const long pid = std::stol(name.substr(i, j - i));
  std::size_t k = j + 1;
  while (k < name.size() && std::isdigit(static_cast<unsigned char>(name[k]))) ++k;
  if (k == j + 1 || (k < name.size() && name[k] != '.')) return std::nullopt;
  return pid;
}

int remove_stale_temporaries(const fs::path& dir) {
  int removed = 0;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const auto pid = temporary_owner(it->path().filename().string());
    if (!pid || *pid <= 0 || *pid == ::getpid()) continue;
    // kill(pid, 0) fails with ESRCH when no such process exists (EPERM: it exists).
    if (::kill(static_cast<pid_t>(*pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code rec;
    if (it->is_regular_file(rec) && fs::remove(it->path(), rec)) ++removed;
  }
  return removed;
}

void write_atomically(const fs::path& target, const std::function<void(const fs::path& tmp)>& writer) {
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create folder " + dir.string() + ": " + ec.message());
  {  // once per folder and process: the temporaries of killed runs
    static std::mutex mu;
    static std::set<std::string> swept;
    std::lock_guard<std::mutex> lock(mu);
    if (swept.insert(fs::absolute(dir, ec).lexically_normal().string()).second) remove_stale_temporaries(dir);
  }
  static std::atomic<unsigned> counter{0};
  // Hidden temporary in the same folder; keeps the extension so format-sniffing
  // writers (OpenCV) pick the right encoder.
  // std::string('.') first: GCC 12 warns falsely (-Wrestrict, its bug 105329) on "." + string.
  const fs::path tmp = dir / (std::string(1, '.') + target.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                              std::to_string(counter++) + target.extension().string());
  try {
    writer(tmp);
    if (!fs::exists(tmp)) throw std::runtime_error("writer produced no file for " + target.string());
    fs::rename(tmp, target);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

void write_text_atomically(const fs::path& target, const std::string& text) {
  write_atomically(target, [&](const fs::path& tmp) {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) throw std::runtime_error("cannot open " + tmp.string() + " for writing");
    f << text;
    f.flush();
    if (!f) throw std::runtime_error("write failed: " + target.string());
  });
}

}  // namespace atmosh::io
