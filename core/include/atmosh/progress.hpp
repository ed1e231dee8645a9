// atmosh/progress.hpp — how long work says how far it has got.
//
// Libraries never print. A computation that can run for seconds takes a
// ProgressCallback and calls it with the fraction done, in [0, 1], non-decreasing,
// from any thread (the callee synchronises) and as often as it likes (the callee
// throttles). An empty callback means nobody listens. The command line turns the
// calls into a line per step or a bar with an ETA on stderr (apps/cli/progress.hpp).
#pragma once

#include <functional>

namespace atmosh {

using ProgressCallback = std::function<void(double fraction_done)>;

}  // namespace atmosh
