// Shared by the gi GPU tests: ATMOSH_NEED_GPU() skips a test where no EGL context can be
// made (fails instead where ATMOSH_REQUIRE_GPU_CONTEXT is set, as in CI). Include where
// ATMOSH_GI_HAVE_GPU is defined.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "atmosh/gpu/context.hpp"

namespace atmosh::test {
// A GPU context can be made; otherwise false and the reason in `why`.
inline bool gpu_or_skip(std::string& why) {
  try {
    const gpu::Context ctx;
    return true;
  } catch (const gpu::Unavailable& e) {
    why = e.what();
    return false;
  }
}
}  // namespace atmosh::test

#define ATMOSH_NEED_GPU()                                                                 \
  do {                                                                                    \
    std::string why;                                                                      \
    if (!atmosh::test::gpu_or_skip(why)) {                                                \
      if (std::getenv("ATMOSH_REQUIRE_GPU_CONTEXT")) FAIL() << "no EGL context: " << why; \
      GTEST_SKIP() << why;                                                                \
    }                                                                                     \
  } while (0)
