// Internal: run-time dispatch of hot kernels. With GCC on x86-64 the marked function is
// compiled twice (baseline SSE2 and x86-64-v3 = AVX2/FMA) and the loader picks the clone
// the CPU supports. Other compilers and sanitizer builds get the baseline code only.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__)
#define ATMOSH_SH_DISPATCH __attribute__((target_clones("arch=x86-64-v3", "default"), optimize("fp-contract=fast")))
#else
#define ATMOSH_SH_DISPATCH
#endif
