// Headless EGL context: created without a display server (Mesa llvmpipe in CI,
// the NVIDIA device platform on GPU machines), or a clean Unavailable — never a crash.
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <memory>
#include <string>

#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/program.hpp"

TEST(GpuContext, CreatesOpenGL43CoreOrReportsUnavailable) {
  try {
    atmosh::gpu::Context ctx;
    const auto& i = ctx.info();
    EXPECT_FALSE(i.renderer.empty());
    EXPECT_GE(i.gl_major * 10 + i.gl_minor, 43);
    EXPECT_TRUE(i.platform == "device" || i.platform == "surfaceless") << i.platform;
    // Two contexts in sequence work (no global state left dangling).
    atmosh::gpu::Context second;
    EXPECT_EQ(second.info().renderer, i.renderer);
  } catch (const atmosh::gpu::Unavailable& e) {
    // CI installs Mesa and sets ATMOSH_REQUIRE_GPU_CONTEXT=1: there a context must exist.
    if (std::getenv("ATMOSH_REQUIRE_GPU_CONTEXT")) FAIL() << "no EGL context: " << e.what();
    GTEST_SKIP() << e.what();
  }
}

// EGL gives every context of a device the same display, and eglTerminate ends all of
// them: a context that ends must leave the others working (a frame object holding its
// own context while a study makes and drops another one). Checked by a buffer round
// trip on the first context after the second is gone.
TEST(GpuContext, EndingOneContextLeavesTheOtherWorking) {
  std::unique_ptr<atmosh::gpu::Context> first;
  try {
    first = std::make_unique<atmosh::gpu::Context>();
  } catch (const atmosh::gpu::Unavailable& e) {
    if (std::getenv("ATMOSH_REQUIRE_GPU_CONTEXT")) FAIL() << "no EGL context: " << e.what();
    GTEST_SKIP() << e.what();
  }
  { const atmosh::gpu::Context second; }  // made current, then destroyed
  ASSERT_NO_THROW(first->make_current());
  // A buffer round trip on the first context: made, filled, read back.
  const std::array<float, 4> data{1, 2, 3, 4};
  std::array<float, 4> back{};
  ASSERT_NO_THROW({
    atmosh::gpu::Buffer buffer(sizeof data, data.data());
    buffer.download(back.data(), sizeof back);
    atmosh::gpu::check_gl("buffer round trip");
  });
  EXPECT_EQ(back, data);
}
