// Shared by the GPU tests: one headless context per test, or a skip when no EGL
// device exists (a failure when ATMOSH_REQUIRE_GPU_CONTEXT is set, as in CI).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>

#include "atmosh/gpu/context.hpp"

#define ATMOSH_GPU_CONTEXT_OR_SKIP(ctx)                                                        \
  std::unique_ptr<atmosh::gpu::Context> ctx;                                                   \
  try {                                                                                        \
    ctx = std::make_unique<atmosh::gpu::Context>();                                            \
  } catch (const atmosh::gpu::Unavailable& e) {                                                \
    if (std::getenv("ATMOSH_REQUIRE_GPU_CONTEXT")) FAIL() << "no EGL context: " << e.what();   \
    GTEST_SKIP() << e.what();                                                                  \
  }
