// The CLI contract of `atmosh gi render`: bad input exits 2 with one line naming the bad
// value, before any work; a small render writes an EXR with radiance and standard errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "../apps/run_cli.hpp"
#include "atmosh/io/exr.hpp"

namespace {
using atmosh::test::count_lines;
using atmosh::test::run_cli;

void expect_bad(const std::string& args, const std::string& named) {
  const auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
  EXPECT_NE(r.err.find(named), std::string::npos) << args << "\n" << r.err;
}

TEST(GiCli, BadInputExitsTwoNamingTheValue) {
  const auto dir = atmosh::test::scratch_dir("atmosh_gi_cli", "bad");
  const std::string out = " -o '" + (dir / "x.exr").string() + "'";
  expect_bad("gi render --scene-builtin no-such-box" + out, "no-such-box");
  expect_bad("gi render --scene-builtin cornell-box --method radiosity --bands 4" + out, "--bands");
  expect_bad("gi render --scene-builtin cornell-box --method lpv --iterations -2" + out, "--iterations");
  expect_bad("gi render --scene-builtin cornell-box --method lpv --device tpu" + out, "tpu");
  expect_bad("gi render --scene-builtin cornell-box --method lpv --cascades 3" + out, "--cascades");
  expect_bad("gi render --scene-builtin cornell-box --method lpv --lpv-reemission lambert" + out, "lambert");
  expect_bad("gi render --scene-builtin cornell-box --method probes --bands 0" + out, "--bands");
  expect_bad("gi render --scene-builtin cornell-box --method probes --device gpu --bands 17" + out, "17");  // above 16
  expect_bad("gi render --scene-builtin cornell-box --method probes --grid 65" + out, "--grid");
  expect_bad("gi render --scene-builtin cornell-box --method probes --cube-size 0" + out, "--cube-size");
  expect_bad("gi render --scene-builtin cornell-box --method probes --window boxcar" + out, "boxcar");
  expect_bad("gi render --scene-builtin cornell-box --method probes --pixel-samples 0" + out, "--pixel-samples");
  const std::string od = " -o '" + (dir / "conv").string() + "'";
  expect_bad("gi converge --scene-builtin sphere-on-plane --grids 2,0" + od, "2,0");
  expect_bad("gi converge --scene-builtin sphere-on-plane --bands-list 1,x" + od, "1,x");
  expect_bad("gi converge --scene-builtin sphere-on-plane --reference-samples 1" + od, "--reference-samples");
  expect_bad("gi converge --scene-builtin no-such-box" + od, "no-such-box");
  expect_bad("gi converge --scene-builtin sphere-on-plane --window boxcar" + od, "boxcar");
  expect_bad("gi converge --scene-builtin sphere-on-plane --radiosity-bands 1,4" + od, "1,4");
  expect_bad("gi converge --scene-builtin sphere-on-plane --lpv-cascade-max-grid 300" + od, "--lpv-cascade-max-grid");
  expect_bad("gi converge --scene-builtin sphere-on-plane --lpv-paper-max-grid -1" + od, "--lpv-paper-max-grid");
  expect_bad("gi render --scene-builtin cornell-box --method magic" + out, "magic");
  expect_bad("gi render --scene-builtin cornell-box --samples 1" + out, "--samples");
  expect_bad("gi render --scene-builtin cornell-box --bounces -5" + out, "-5");
  expect_bad("gi render --scene-builtin cornell-box --size 0x10" + out, "0x10");
  expect_bad("gi render --scene-builtin cornell-box --light moon:1,2" + out, "moon:1,2");
  expect_bad("gi render --scene-builtin cornell-box --light sun:10,95" + out, "sun:10,95");
  expect_bad("gi render --scene-builtin cornell-box --sun-irradiance 1,x,1 --light sun:0,45" + out, "1,x,1");
  expect_bad("gi render --mesh '" + (dir / "missing.obj").string() + "'" + out, "missing.obj");
  expect_bad("gi render --scene-builtin cornell-box -o '" + (dir / "x.png").string() + "'", "x.png");
  expect_bad("gi render" + out, "--scene-builtin");
  EXPECT_FALSE(std::filesystem::exists(dir / "x.exr"));
  EXPECT_FALSE(std::filesystem::exists(dir / "conv" / "reference.exr"));
}

TEST(GiCli, ProbesRenderAndConvergeWriteTheirFiles) {
  const auto dir = atmosh::test::scratch_dir("atmosh_gi_cli", "probes");
  const auto exr = dir / "p.exr";
  auto r = run_cli("gi render --scene-builtin sphere-on-plane --resolution 8 --light sun:30,40 --method probes "
                   "--bands 2 --grid 2 --cube-size 4 --samples 2 --size 12x8 -o '" + exr.string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"probe_seconds\""), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(exr));
  r = run_cli("gi converge --scene-builtin sphere-on-plane --resolution 8 --light sun:30,40 --bands-list 1,2 "
              "--grids 1,2 --cube-size 4 --samples 2 --path-samples 2 --reference-samples 8 --size 12x8 "
              "--radiosity-grids 2 --radiosity-bands 1,2 --radiosity-bounces 0,2 --lpv-grids 2 -o '" +
              (dir / "conv").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "conv" / "reference.exr"));
  EXPECT_TRUE(std::filesystem::exists(dir / "conv" / "probes_b2_g2.exr"));
  EXPECT_TRUE(std::filesystem::exists(dir / "conv" / "radiosity_bands-2_grid-2_bounces-2.exr"));
  EXPECT_TRUE(std::filesystem::exists(dir / "conv" / "lpv_grid-2_iterations-4.exr"));
  std::ifstream csv(dir / "conv" / "gi_converge.csv");
  std::string line;
  int rows = 0, rows_radiosity = 0, rows_lpv = 0, rows_lpv_paper = 0;
  bool header = false;
  while (std::getline(csv, line)) {
    if (line.rfind("method,setting,error_max_rel,error_rms_rel,time_s,leak_rel,build_s,shade_s,mean_rel", 0) == 0)
      header = true;
    if (line.rfind("radiosity,", 0) == 0) ++rows_radiosity;
    if (line.rfind("lpv,", 0) == 0 || line.rfind("lpv-noblock,", 0) == 0) ++rows_lpv;
    if (line.rfind("lpv-paper,grid=2 iterations=4,", 0) == 0) ++rows_lpv_paper;
    if (line.rfind("probes,", 0) == 0 || line.rfind("probes-visibility,", 0) == 0 || line.rfind("path,", 0) == 0) ++rows;
  }
  EXPECT_TRUE(header);
  EXPECT_EQ(rows, 9);  // path spp=2, probes 2 bands x 2 grids x plain / visibility
  EXPECT_EQ(rows_radiosity, 4);  // 2 bands x 2 bounce counts
  EXPECT_EQ(rows_lpv, 3);        // with and without the geometry volume, and the 2-level cascade
  EXPECT_EQ(rows_lpv_paper, 1);  // the published re-emission beside them (grid 2 <= 16)
  EXPECT_TRUE(std::filesystem::exists(dir / "conv" / "lpv-paper_grid-2_iterations-4.exr"));
}

TEST(GiCli, RadiosityAndLpvRender) {
  const auto dir = atmosh::test::scratch_dir("atmosh_gi_cli", "methods");
  for (const char* m : {"radiosity", "lpv"}) {
    const auto exr = dir / (std::string(m) + ".exr");
    const auto r = run_cli(std::string("gi render --scene-builtin cornell-box --method ") + m +
                           " --grid 4 --bands 2 --bounces 2 --cube-size 4 --pixel-samples 2 --size 12x8 -o '" +
                           exr.string() + "' --json");
    ASSERT_EQ(r.exit_code, 0) << m << r.err;
    EXPECT_NE(r.out.find("\"build_seconds\""), std::string::npos) << m;
    const auto img = atmosh::io::read_exr(exr);
    double sum = 0;
    for (float v : img.channel("G")) sum += v;
    EXPECT_GT(sum, 0) << m;
    EXPECT_TRUE(std::isfinite(sum)) << m;
  }
  // --device auto: the LPV propagates on the GPU where an EGL context can be made, else on
  // the CPU with a one-line notice; either way an image. gpu for a CPU-only method (probes): exit 1.
  const auto exr = dir / "lpv_auto.exr";
  // (with the published re-emission: named in the JSON and the EXR's provenance)
  auto r = run_cli("gi render --scene-builtin cornell-box --method lpv --grid 4 --device auto --pixel-samples 2 "
                   "--lpv-reemission paper --size 12x8 -o '" + exr.string() + "' --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"lpv_reemission\": \"paper\""), std::string::npos) << r.out;
  ASSERT_TRUE(std::filesystem::exists(exr));
  {
    const auto img = atmosh::io::read_exr(exr);
    const auto it = img.string_attributes.find("atmosh:lpv_reemission");
    ASSERT_NE(it, img.string_attributes.end());
    EXPECT_EQ(it->second, "paper");
  }
  // radiosity's walk runs as a GPU pass too (auto: on the CPU where no context is made)
  const auto exr_r = dir / "radiosity_auto.exr";
  r = run_cli("gi render --scene-builtin cornell-box --method radiosity --grid 4 --cube-size 4 --device auto "
              "--pixel-samples 1 --size 12x8 -o '" + exr_r.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(exr_r));
  // probes: cube maps of a baked surface radiance, rasterised (auto: ray cast where no context is made);
  // with a context the GPU-resident frame at 5 bands (pixel centres: stderr 0)
  const auto exr_p = dir / "probes_auto.exr";
  r = run_cli("gi render --scene-builtin cornell-box --method probes --grid 2 --cube-size 4 --bands 5 --device auto "
              "--pixel-samples 1 --size 12x8 -o '" + exr_p.string() + "' --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"device\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"bands\": 5"), std::string::npos) << r.out;
  if (r.out.find("\"device\": \"gpu\"") != std::string::npos)
    EXPECT_NE(r.out.find("\"stderr_max\": 0.0"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(exr_p));
  // the path tracer is CPU only: --device gpu is exit 1 naming it
  r = run_cli("gi render --scene-builtin cornell-box --method path --device gpu --size 12x8 -o '" +
              (dir / "no.exr").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("path"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "no.exr"));
}

TEST(GiCli, RenderWritesRadianceAndStandardError) {
  const auto dir = atmosh::test::scratch_dir("atmosh_gi_cli", "ok");
  const auto exr = dir / "box.exr", png = dir / "box.png";
  const auto r = run_cli("gi render --scene-builtin sphere-on-plane --resolution 8 --light sun:30,40 --samples 2 "
                         "--size 12x8 --bounces 2 -o '" + exr.string() + "' --png '" + png.string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"rays_per_second\""), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(png));
  const auto img = atmosh::io::read_exr(exr);
  EXPECT_EQ(img.width, 12);
  EXPECT_EQ(img.height, 8);
  for (const char* ch : {"R", "G", "B", "stderr.R", "stderr.G", "stderr.B"}) EXPECT_GE(img.find_channel(ch), 0) << ch;
  EXPECT_EQ(img.string_attributes.count("atmosh:method"), 1u);
  double sum = 0;
  for (float v : img.channel("G")) sum += v;
  EXPECT_GT(sum, 0);
}

// An SH environment from a CSV file (the layout `atmosh sh project` writes), no reflections:
// the background shows its radiance L exactly, the scene is black.
TEST(GiCli, ShEnvironmentFileIsTheBackground) {
  const auto dir = atmosh::test::scratch_dir("atmosh_gi_cli", "env");
  const double y00 = 0.5 / std::sqrt(3.14159265358979323846);  // Y_00 = 1 / (2 sqrt(pi))
  {
    std::ofstream f(dir / "sky.csv");
    f.precision(17);
    f << "l,m,index,R,G,B\n0,0,0," << 0.5 / y00 << "," << 1.0 / y00 << "," << 2.0 / y00 << "\n";
  }
  const auto exr = dir / "bg.exr";
  const auto r = run_cli("gi render --scene-builtin box-occluder --resolution 8 --env-sh '" + (dir / "sky.csv").string() +
                         "' --bounces 0 --samples 2 --size 16x12 -o '" + exr.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto img = atmosh::io::read_exr(exr);
  const double L[3] = {0.5, 1.0, 2.0};
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    const auto& v = img.channel(names[c]);
    EXPECT_NEAR(*std::max_element(v.begin(), v.end()), L[c], 1e-6 * L[c]) << c;
    EXPECT_EQ(*std::min_element(v.begin(), v.end()), 0.0f) << c;
  }
}

TEST(GiCli, ConvergeWithDeviceAddsGpuRowsAndSplitsRinging) {
  const auto dir = atmosh::test::scratch_dir("atmosh_gi_cli", "converge_device");
  auto r = run_cli("gi converge --scene-builtin cornell-box --device sometimes -o '" + (dir / "bad").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("sometimes"), std::string::npos) << r.err;
  r = run_cli("gi converge --scene-builtin sphere-on-plane --resolution 8 --bands-list 1,3 --grids 2 --cube-size 4 --samples 2 "
              "--path-samples 2 --reference-samples 4 --size 12x8 --radiosity-grids 2 --radiosity-bands 2 "
              "--radiosity-bounces 1 --lpv-grids 2 --device auto -o '" + (dir / "conv").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream csv(dir / "conv" / "gi_converge.csv");
  std::string line;
  int gpu_rows = 0, probe_rows = 0, resident_rows = 0, cascade_gpu_rows = 0;
  double paper_rms = -1, paper_gpu_rms = -1;
  bool header = false;
  // ringing_rel and leak_ringfree_rel (the last two columns) of a probe row: finite and >= 0;
  // band 1 holds only the mean, its ringing (what it differs from 8 bands) is not 0 under a
  // sky over a plane
  auto check_ringing = [](const std::string& line) {
    const auto c2 = line.rfind(','), c1 = line.rfind(',', c2 - 1);
    const double ring = std::stod(line.substr(c1 + 1, c2 - c1 - 1)), leak = std::stod(line.substr(c2 + 1));
    EXPECT_TRUE(ring >= 0 && std::isfinite(ring)) << line;
    EXPECT_TRUE(leak >= 0 && std::isfinite(leak)) << line;
    if (line.find("bands=1 ") != std::string::npos) {
      EXPECT_GT(ring, 0) << line;
    }
  };
  while (std::getline(csv, line)) {
    if (line.rfind("method,setting,error_max_rel,error_rms_rel,time_s,leak_rel,build_s,shade_s,mean_rel,ringing_rel,"
                   "leak_ringfree_rel", 0) == 0)
      header = true;
    if (line.rfind("#", 0) == 0) continue;  // provenance
    if (line.rfind("probes-resident-gpu,", 0) == 0) {  // the GPU-resident probe frame: errors and frame time
      ++resident_rows;
      std::vector<double> v;
      for (std::size_t a = line.find(',', line.find(',') + 1), b; a != std::string::npos && v.size() < 3; a = b) {
        b = line.find(',', a + 1);
        v.push_back(std::stod(line.substr(a + 1, b == std::string::npos ? b : b - a - 1)));
      }
      ASSERT_EQ(v.size(), 3u) << line;
      for (double x : v) EXPECT_TRUE(std::isfinite(x) && x > 0) << line;  // error_max_rel, error_rms_rel, time_s
      check_ringing(line);  // against the 8-band resident frame of the same grid
      continue;
    }
    if (line.find("-gpu") != std::string::npos) ++gpu_rows;
    // the published re-emission on the CPU and on the GPU: error_rms_rel (column 4)
    for (auto [prefix, out] : {std::pair{"lpv-paper,", &paper_rms}, std::pair{"lpv-paper-gpu,", &paper_gpu_rms}})
      if (line.rfind(prefix, 0) == 0) {
        std::size_t a = 0;
        for (int k = 0; k < 3; ++k) a = line.find(',', a) + 1;
        *out = std::stod(line.substr(a, line.find(',', a) - a));
      }
    if (line.rfind("lpv-cascade-gpu,grid=2 iterations=4 cascades=2,", 0) == 0) ++cascade_gpu_rows;
    if (line.rfind("probes", 0) == 0) {
      ++probe_rows;
      check_ringing(line);
    }
  }
  EXPECT_TRUE(header);
  // a GPU context: probes-gpu[-visibility] 2 bands each, radiosity-gpu 1, lpv[-noblock]-gpu 2,
  // lpv-cascade-gpu 1 (the 2-level cascade in the resident frame), lpv-paper-gpu 1; none: a notice
  if (std::getenv("ATMOSH_REQUIRE_GPU_CONTEXT") || r.err.find("CPU forms") == std::string::npos) {
    EXPECT_EQ(gpu_rows, 9) << r.err;
    EXPECT_EQ(cascade_gpu_rows, 1) << r.err;
    // lpv-paper-gpu: the same propagation as lpv-paper on the GPU (its grids match the CPU's
    // to 2e-5, GiLpvGpu), so the same error against the reference up to the shading's
    ASSERT_GT(paper_rms, 0);
    ASSERT_GT(paper_gpu_rms, 0);
    std::printf("[ measured ] lpv-paper rms %.4f, lpv-paper-gpu rms %.4f\n", paper_rms, paper_gpu_rms);
    EXPECT_NEAR(paper_gpu_rms, paper_rms, 0.05);
    EXPECT_EQ(probe_rows, 8);
  } else {
    EXPECT_EQ(gpu_rows, 0);
  }

  // probes-resident-gpu: one row per grid and band count (bands 1 and 3 at grid 2) with a GPU
  EXPECT_EQ(resident_rows, gpu_rows > 0 ? 2 : 0);
}

// The emitters' reflective shadow maps from the command line: `gi render --lpv-emitter-rsm N`
// (named in the JSON), a bad N (exit 2 naming it), and the converge study's lpv-rsm-gpu row of a
// scene with an area light beside its lpv-gpu row (the same frame with photon VPLs; the two
// estimate the same reflected power, docs/gi.md "The area emitters' reflective shadow maps").
TEST(GiCli, LpvEmitterRsmRenderAndConvergeRow) {
  const auto dir = atmosh::test::scratch_dir("atmosh_gi_cli", "emitter_rsm");
  auto r = run_cli("gi render --scene-builtin cornell-box --method lpv --lpv-emitter-rsm 1 -o '" +
                   (dir / "bad.exr").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--lpv-emitter-rsm"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" 1"), std::string::npos) << r.err;
  r = run_cli("gi converge --scene-builtin cornell-box --lpv-emitter-rsm 2000 -o '" + (dir / "badc").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("2000"), std::string::npos) << r.err;
  // an atlas over kMaxEmitterRsmTexels (the Cornell box's 2 emitting triangles x 4 points x 6
  // faces x 1024^2 = 50 M texels): refused before any work, by render and by converge
  r = run_cli("gi render --scene-builtin cornell-box --method lpv --device gpu --lpv-emitter-rsm 1024 -o '" +
              (dir / "big.exr").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("1024"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "big.exr"));
  r = run_cli("gi converge --scene-builtin cornell-box --device auto --lpv-emitter-rsm 1024 -o '" +
              (dir / "bigc").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("lower --lpv-emitter-rsm"), std::string::npos) << r.err;
  const auto exr = dir / "rsm.exr";
  r = run_cli("gi render --scene-builtin cornell-box --method lpv --grid 4 --device auto --pixel-samples 1 "
              "--lpv-emitter-rsm 8 --size 12x8 -o '" + exr.string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"lpv_emitter_rsm\": 8"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(exr));
  r = run_cli("gi converge --scene-builtin cornell-box --bands-list 1 --grids 1 --cube-size 2 --samples 2 "
              "--path-samples 2 --reference-samples 2 --size 8x6 --radiosity-grids none --lpv-grids 2 "
              "--lpv-paper-max-grid 0 --lpv-cascade-max-grid 0 --lpv-emitter-rsm 8 --device auto -o '" +
              (dir / "conv").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream csv(dir / "conv" / "gi_converge.csv");
  std::string line;
  double rms_photons = -1, rms_rsm = -1;
  auto rms_of = [](const std::string& l) {
    std::size_t a = 0;
    for (int k = 0; k < 3; ++k) a = l.find(',', a) + 1;
    return std::stod(l.substr(a, l.find(',', a) - a));
  };
  while (std::getline(csv, line)) {
    if (line.rfind("lpv-gpu,", 0) == 0) rms_photons = rms_of(line);
    if (line.rfind("lpv-rsm-gpu,grid=2 iterations=4 emitter_rsm=8,", 0) == 0) rms_rsm = rms_of(line);
  }
  if (std::getenv("ATMOSH_REQUIRE_GPU_CONTEXT") || r.err.find("CPU forms") == std::string::npos) {
    ASSERT_GT(rms_photons, 0) << r.err;
    ASSERT_GT(rms_rsm, 0) << r.err;
    std::printf("[ measured ] Cornell box, grid 2, 8x6: lpv-gpu rms %.4f, lpv-rsm-gpu rms %.4f\n", rms_photons, rms_rsm);
    EXPECT_NEAR(rms_rsm, rms_photons, 0.05);
  } else {
    EXPECT_LT(rms_rsm, 0) << "no GPU: no lpv-rsm-gpu row";
  }
}

}  // namespace
