// progress.hpp — progress of long work on stderr (apps/ only; libraries report
// through atmosh::ProgressCallback, atmosh/progress.hpp).
//
// A ProgressStep names one step of a command (a study, a sweep, a part of the main
// job). Nothing is shown for a step that ends within 2 s (ATMOSH_PROGRESS_AFTER_S
// changes the 2 s). Past 2 s:
//  * stderr is not a terminal (logs, CI, batch jobs): one line when the step passes
//    2 s, "atmosh: <name> ...", and one when it ends, "atmosh: <name>: done in 12.3 s";
//  * stderr is a terminal: one line redrawn in place, with a bar, the percentage and
//    an ETA when the step reports fractions (else the elapsed time), ending with the
//    time the step took.
// `--quiet` (any subcommand) or ATMOSH_QUIET=1 silences all of it.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "atmosh/progress.hpp"

namespace atmosh::cli {

void set_progress_quiet(bool quiet);
bool progress_quiet();

class ProgressStep {
 public:
  explicit ProgressStep(std::string name);
  ~ProgressStep();
  ProgressStep(const ProgressStep&) = delete;
  ProgressStep& operator=(const ProgressStep&) = delete;

  void set_fraction(double fraction_done);  // thread-safe
  ProgressCallback callback();              // calls set_fraction; valid while the step lives

 private:
  void run();
  void draw(bool final);
  std::string name_;
  std::chrono::steady_clock::time_point t0_;
  std::mutex mu_;
  std::condition_variable cv_;
  double fraction_ = -1;  // < 0: not reported
  bool done_ = false, shown_ = false, tty_ = false;
  std::thread thread_;
};

}  // namespace atmosh::cli
