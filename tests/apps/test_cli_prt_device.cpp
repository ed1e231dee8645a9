// `atmosh prt converge --device auto|gpu` without an EGL device (GLVND pointed at no
// vendor library, as in tests/gpu/test_fallback.cpp): the one device policy
// (atmosh::resolve_device, docs/core.md) — auto keeps the CPU rows after one notice line
// and records why the GPU rows are missing; gpu fails with exit 1 and one line naming
// --device gpu. Only "no device" falls back (gpu::Unavailable).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "atmosh/io/csv.hpp"
#include "run_cli.hpp"
#include "without_egl.hpp"

namespace fs = std::filesystem;
using atmosh::test::count_lines;
using atmosh::test::run_cli;
using atmosh::test::scratch_dir;

TEST(CliPrtDevice, WithoutAnEglDeviceAutoFallsBackAndGpuFails) {
  const fs::path d = scratch_dir("atmosh_cli_prt_device", "none");
  const std::string args = " --scene-builtin sphere-on-plane --resolution 4 --strata 2 --reference-samples 16 "
                           "--pixels 8x8 --depth-maps 64 -o ";
  atmosh::test::CliResult a, g;
  {
    const atmosh::test::WithoutEglDevice no_egl;
    a = run_cli("prt converge --device auto" + args + "'" + (d / "a").string() + "'");
    g = run_cli("prt converge --device gpu" + args + "'" + (d / "g").string() + "'");
  }
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_EQ(count_lines(a.err), 1) << a.err;
  EXPECT_NE(a.err.find("the study has no GPU rows"), std::string::npos) << a.err;
  const auto csv = atmosh::io::read_csv(d / "a.csv");
  ASSERT_EQ(csv.rows.size(), 2u);  // per vertex and per pixel, CPU only
  for (const auto& r : csv.rows) EXPECT_EQ(r[csv.column("method")].find("gpu"), std::string::npos);
  EXPECT_EQ(csv.provenance.at("gpu_method").rfind("not run (", 0), 0u) << csv.provenance.at("gpu_method");
  EXPECT_EQ(g.exit_code, 1) << g.err;
  EXPECT_EQ(count_lines(g.err), 1) << g.err;
  EXPECT_EQ(g.err.rfind("atmosh: failure: --device gpu: ", 0), 0u) << g.err;
  EXPECT_FALSE(fs::exists(d / "g.csv"));
}
