// The before/after output comparison: the quick main job and a set of commands from
// docs/cli.md, their files and stdout reduced to normalised digests (golden_outputs.hpp
// says what is masked) and compared with the digests recorded at bb0e478, before the
// domain code moved out of apps/cli into atmosh::studies. A change of any output (a
// number, a column, a provenance entry that does not depend on the run, a pixel) fails
// it and names the first differing file and line.
//
// Bits depend on the code path: the digests were recorded on an x86-64-v3 (AVX2 + FMA)
// CPU, and the test runs the binary with ATMOSH_NO_AVX512=1 so that a CPU with AVX-512
// takes the same AVX2 kernels (atmosh/dispatch.hpp), Embree's ray traversal included (its
// device is created with max_isa=avx2 then: apps/prt/src/bake.cpp; its AVX-512 kernels
// changed the last bits of the Cornell box's LPV image on an AVX-512 CPU). A CPU without AVX2, or a build
// without function multiversioning (ATMOSH_DISPATCH_BASELINE_ONLY, sanitizer builds,
// other compilers), computes the last bits differently: there the digests must be
// recorded afresh before a refactor (ATMOSH_UPDATE_GOLDEN=1 at the old commit).
//
// When an output changes on purpose, rerun with ATMOSH_UPDATE_GOLDEN=1 to rewrite
// tests/apps/data/cli_golden/*.digest and review the diff of those files.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "golden_outputs.hpp"
#include "run_cli.hpp"
#include "../atmo/sanitizer_build.hpp"

namespace fs = std::filesystem;
using atmosh::test::run_cli;

namespace {

const fs::path kGoldenDir = fs::path(ATMOSH_TEST_DATA_DIR) / "cli_golden";

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

// `folder` (a scratch folder whose name holds the process id) is written {d}.
void compare_or_update(const std::string& name, const std::string& raw_digest, const fs::path& folder) {
  const std::string digest = replace_all(raw_digest, folder.string(), "{d}");
  const fs::path file = kGoldenDir / (name + ".digest");
  if (const char* u = std::getenv("ATMOSH_UPDATE_GOLDEN"); u != nullptr && std::string(u) == "1") {
    fs::create_directories(kGoldenDir);
    std::ofstream(file, std::ios::binary) << digest;
    GTEST_SKIP() << "rewrote " << file;
  }
  ASSERT_TRUE(fs::exists(file)) << file << " is missing (ATMOSH_UPDATE_GOLDEN=1 writes it)";
  const std::string expected = atmosh::test::slurp(file);
  const std::string diff = atmosh::test::golden::first_difference(expected, digest);
  EXPECT_TRUE(diff.empty()) << name << ": outputs differ from " << file << "\n  first difference: " << diff;
}

// The commands, run in order in one folder ({d}); each one's stdout is part of the digest.
// Representative of the areas whose code moved: sun, atmosphere queries, SH, PRT
// (per vertex and per pixel), the Monte-Carlo references.
const std::vector<std::string> kCommands = {
    "sun --lat 48.8566 --lon 2.3522 --time 2026-06-21T18:30:00Z --json",
    "sun --lat 48.8566 --lon 2.3522 --from 2026-06-21T00:00:00Z --to 2026-06-21T06:00:00Z --step 30min -o {d}/sun.csv",
    "optical-depth --preset earth-graphics --wavelength 550 --altitude 0 --zenith 89 --json",
    "optical-depth --preset earth-graphics --wavelength 550 --altitude 0 --zenith 89 --method lut --json",
    "phase --model hg --g 0.8 --cos-theta 1 --json",
    "sky --sun-elevation 5 --size 64x32 -o {d}/sky.exr",
    "sh project {d}/sky.exr --bands 4 -o {d}/sky_coeffs.csv --reconstruct {d}/sky_rec.exr",
    "sh project {d}/sky.exr --bands 3 --method jittered --samples 4096 --seed 3 -o {d}/jittered.csv",
    "sh eval {d}/sky_coeffs.csv --dir 0.3,-0.2,0.9 --json",
    "sh rotate {d}/sky_coeffs.csv --euler-zyz 10,20,30 -o {d}/rotated.csv",
    "sh irradiance {d}/sky_coeffs.csv -o {d}/irradiance.csv --reconstruct {d}/irradiance.exr",
    "sh bands {d}/sky_coeffs.csv -o {d}/bands.csv --plot {d}/bands.png",
    "sh converge {d}/sky.exr --bands 3 --quick -o {d}/sh_conv",
    "prt bake --scene-builtin sphere --resolution 12 --bands 3 --samples 256 --mode shadowed -o {d}/t.ply --json",
    "prt relight {d}/t.ply --light-dir 0,0,1 --frames 2 --size 32x24 -o {d}/frames",
    "prt relight {d}/t.ply --light {d}/jittered.csv --size 16x16 -o {d}/lit",
    "prt bake --scene-builtin sphere-on-plane --resolution 8 --samples 64 --size 24x16 -o {d}/px.exr --json",
    "prt relight {d}/px.exr --light {d}/jittered.csv -o {d}/pxlit",
    "prt converge --scene-builtin sphere-on-plane --resolution 4 --strata 2,4 --reference-samples 64 --device cpu "
    "--pixels 16x16 -o {d}/prt_conv",
    "rt slab --tau 1 --omega 0.9 --phase hg --g 0.7 --ground-albedo 0.2 --mu0 0.8 --mu 0.6 --phi-deg 30 --paths 20000 "
    "--seed 2 --json",
    "rt sky --sun-elevation 30 --view-elevation 45 --view-azimuth 90 --paths 2000 --seed 5 --json",
};

// The AVX2 kernels everywhere (see the top of this file).
void same_kernels() { ::setenv("ATMOSH_NO_AVX512", "1", 1); }

bool skip_in_sanitizer_build() {
  // ~10x slower under AddressSanitizer (the binary is built with it too); the Release
  // suite runs it.
  return atmosh::test::kSanitized;
}

}  // namespace

TEST(Cli, OutputsUnchangedByRefactor) {
  if (skip_in_sanitizer_build()) GTEST_SKIP() << "Release-only: too slow under the sanitizers";
  same_kernels();
  const fs::path out = atmosh::test::scratch_dir("atmosh_golden", "demo");
  ::setenv("ATMOSH_PLOT_DATA", "1", 1);  // the plots' data files are compared too
  const auto r = run_cli("demo --quick -o '" + out.string() + "'");
  ::unsetenv("ATMOSH_PLOT_DATA");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  compare_or_update("demo_quick", atmosh::test::golden::digest_folder(out), out);
}

TEST(Cli, CommandOutputsUnchangedByRefactor) {
  if (skip_in_sanitizer_build()) GTEST_SKIP() << "Release-only: too slow under the sanitizers";
  same_kernels();
  const fs::path d = atmosh::test::scratch_dir("atmosh_golden", "commands");
  std::string digest;
  ::setenv("ATMOSH_PLOT_DATA", "1", 1);
  for (const auto& c : kCommands) {
    const auto r = run_cli(replace_all(c, "{d}", "'" + d.string() + "'"));
    ASSERT_EQ(r.exit_code, 0) << c << "\n" << r.err;
    digest += atmosh::test::golden::digest_stdout(c, r.out, d.string());
  }
  ::unsetenv("ATMOSH_PLOT_DATA");
  digest += atmosh::test::golden::digest_folder(d);
  compare_or_update("commands", digest, d);
}
