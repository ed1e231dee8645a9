// atmosh/budget.hpp — the limits a request is checked against before any work: a memory
// budget (bytes; default: what this process may still take, atmosh/memory.hpp) and a time
// budget (seconds of wall time; default kDefaultTimeBudgetS, atmosh/work.hpp). A front end
// sets them from its options (the command line's --max-memory and --max-time); each
// request estimates its own memory and work next to what it estimates, and calls
// check_memory / check_time before it starts. Failures are one-line InputErrors naming
// the request, the estimate and the budget.
#pragma once

#include <cstddef>
#include <string>

#include "atmosh/work.hpp"

namespace atmosh {

// The memory budget [bytes]: the one set, else available_memory() now.
std::size_t memory_budget();
void set_memory_budget(std::size_t bytes);
// InputError "<what> needs about 12 GiB of memory (estimate), more than the budget of
// ... (<where the budget comes from>)" when bytes exceed the budget.
void check_memory(std::size_t bytes, const std::string& what);

// The time budget [s of wall time]: the one set, else kDefaultTimeBudgetS (24 h).
double time_budget();
void set_time_budget(double seconds);
// workers: the threads that share the work (0: the CPUs this process may use).
// InputError "<what> needs about 3.2 days of computing (estimate: 2.1e+13 ray nodes at
// 1.4e-08 s each on one core, 2 workers), more than the time budget of 24 h (...)".
void check_time(const WorkEstimate& work, int workers, const std::string& what);
// "about 3.2 h (estimate: ...)", as `atmosh plan` prints it.
std::string describe_work(const WorkEstimate& work, int workers);

}  // namespace atmosh
