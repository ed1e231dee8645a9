#include "atmosh/io/atomic.hpp"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace atmosh::io {

namespace fs = std::filesystem;

void write_atomically(const fs::path& target, const std::function<void(const fs::path& tmp)>& writer) {
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create folder " + dir.string() + ": " + ec.message());
  static std::atomic<unsigned> counter{0};
  // Hidden temporary in the same folder; keeps the extension so format-sniffing
  // writers (OpenCV) pick the right encoder.
  const fs::path tmp = dir / ("." + target.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
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
