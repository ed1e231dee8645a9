#include "progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace atmosh::cli {

namespace {
std::atomic<bool> g_quiet{false};
// A step is shown once it has run this long: 2 s, or ATMOSH_PROGRESS_AFTER_S (tests).
double show_after_s() {
  const char* e = std::getenv("ATMOSH_PROGRESS_AFTER_S");
  if (e && *e) {
    char* end = nullptr;
    const double v = std::strtod(e, &end);
    if (end && *end == '\0' && std::isfinite(v) && v >= 0) return v;
  }
  return 2.0;
}

std::string seconds(double s) {
  char b[32];
  if (s < 60) std::snprintf(b, sizeof b, "%.1f s", s);
  else std::snprintf(b, sizeof b, "%d min %02d s", static_cast<int>(s / 60), static_cast<int>(s) % 60);
  return b;
}
}  // namespace

void set_progress_quiet(bool quiet) { g_quiet = quiet; }
bool progress_quiet() {
  if (g_quiet) return true;
  const char* e = std::getenv("ATMOSH_QUIET");
  return e && *e && std::string(e) != "0";
}

ProgressStep::ProgressStep(std::string name) : name_(std::move(name)), t0_(std::chrono::steady_clock::now()) {
  if (progress_quiet()) return;
  tty_ = ::isatty(STDERR_FILENO) == 1;
  thread_ = std::thread([this] { run(); });
}

ProgressStep::~ProgressStep() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mu_);
    done_ = true;
  }
  cv_.notify_all();
  thread_.join();
  std::lock_guard<std::mutex> lock(mu_);
  if (shown_) draw(true);
}

void ProgressStep::set_fraction(double f) {
  if (!std::isfinite(f)) return;
  std::lock_guard<std::mutex> lock(mu_);
  fraction_ = std::clamp(f, 0.0, 1.0);
}

ProgressCallback ProgressStep::callback() {
  return [this](double f) { set_fraction(f); };
}

void ProgressStep::run() {
  std::unique_lock<std::mutex> lock(mu_);
  if (cv_.wait_for(lock, std::chrono::duration<double>(show_after_s()), [this] { return done_; })) return;
  shown_ = true;
  draw(false);
  if (!tty_) return;  // one line; the closing line comes from the destructor
  while (!cv_.wait_for(lock, std::chrono::milliseconds(250), [this] { return done_; })) draw(false);
}

void ProgressStep::draw(bool final) {  // under mu_
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  if (!tty_) {
    if (final) std::fprintf(stderr, "atmosh: %s: done in %s\n", name_.c_str(), seconds(t).c_str());
    else std::fprintf(stderr, "atmosh: %s ...\n", name_.c_str());
    std::fflush(stderr);
    return;
  }
  std::string line = "atmosh: " + name_;
  if (final) {
    line += ": done in " + seconds(t);
  } else if (fraction_ >= 0) {
    const int width = 24, fill = static_cast<int>(std::lround(fraction_ * width));
    line += " [" + std::string(static_cast<std::size_t>(fill), '#') + std::string(static_cast<std::size_t>(width - fill), '-') + "] ";
    char pct[16];
    std::snprintf(pct, sizeof pct, "%3d%%", static_cast<int>(fraction_ * 100));
    line += pct;
    if (fraction_ > 0.01) line += ", ETA " + seconds(t * (1 - fraction_) / fraction_);
  } else {
    line += " ... " + seconds(t);
  }
  std::fprintf(stderr, "\r%s\033[K%s", line.c_str(), final ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace atmosh::cli
