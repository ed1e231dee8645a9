// atmosh/dispatch.hpp — run-time dispatch of hot kernels (used inside atmosh's own
// sources; not part of the numerical API).
//
// With GCC on x86-64 Linux a function marked ATMOSH_DISPATCH is compiled twice, for
// the x86-64 baseline (SSE2: 2 doubles per vector) and for x86-64-v3 (AVX2 + FMA:
// 4 doubles per vector, fused multiply-add), and the loader picks the clone the
// running CPU supports (function multiversioning through an ifunc). The two clones
// may differ in the last bits where the compiler fuses a multiply and an add;
// results are deterministic on a given CPU. ATMOSH_DISPATCH_NO_ERRNO is the same with
// math functions that do not set errno (so that loops calling sqrt vectorise);
// ATMOSH_DISPATCH_NO_FMA builds the AVX2
// clone without FMA, for code that must round every operation as written (its two
// clones agree bit for bit). Other compilers, other targets and sanitizer builds get
// the baseline code only (the macros expand to nothing), and
// ATMOSH_DISPATCH_BASELINE_ONLY forces that.
//
// AVX-512: GCC's x86-64-v4 clones do not vectorise with 512-bit registers (it prefers
// 256 bits), so kernels that gain from them (store-bound ones, or recurrences run on
// 8 lanes at once) are written on 64-byte GCC vector types in a separate function
// marked ATMOSH_TARGET_AVX512 and called when atmosh::cpu_has_avx512() (x86-64-v4:
// AVX-512 F, VL, BW, DQ) is true. Where ATMOSH_HAS_DISPATCH is 0 neither exists.
// The environment variable ATMOSH_NO_AVX512 (any value, read once) makes
// cpu_has_avx512() false: the AVX2 path runs, e.g. to compare the two (the tests do).
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
    !defined(__SANITIZE_ADDRESS__) && !defined(ATMOSH_DISPATCH_BASELINE_ONLY)
#define ATMOSH_DISPATCH __attribute__((target_clones("arch=x86-64-v3", "default"), optimize("fp-contract=fast")))
#define ATMOSH_DISPATCH_NO_ERRNO \
  __attribute__((target_clones("arch=x86-64-v3", "default"), optimize("fp-contract=fast", "no-math-errno")))
#define ATMOSH_DISPATCH_NO_FMA __attribute__((target_clones("avx2", "default")))
#define ATMOSH_HAS_DISPATCH 1
#define ATMOSH_TARGET_AVX512 __attribute__((target("arch=x86-64-v4"), optimize("fp-contract=fast")))
#include <cstdlib>
namespace atmosh {
inline bool cpu_has_avx512() {
  static const bool yes = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                          __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
                          std::getenv("ATMOSH_NO_AVX512") == nullptr;
  return yes;
}
}  // namespace atmosh
#else
#define ATMOSH_DISPATCH
#define ATMOSH_DISPATCH_NO_ERRNO
#define ATMOSH_DISPATCH_NO_FMA
#define ATMOSH_HAS_DISPATCH 0
#endif
