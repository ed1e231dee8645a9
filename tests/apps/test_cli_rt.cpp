// CLI contract of `atmosh rt slab` and `atmosh rt sky`: JSON keys, full-precision
// numbers, --help, bad input (exit 2, one line naming the option).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include "run_cli.hpp"

using atmosh::test::count_lines;
using atmosh::test::run_cli;

TEST(CliRt, SlabJson) {
  // DISORT test problem 1b (van de Hulst 1980, Table 12): tau = 0.03125, omega = 1,
  // mu0 = 0.1, R(mu = 0.1) = 0.622884 (DISOTEST.f, BLOCK DATA CHEKDO).
  const auto r = run_cli(
      "rt slab --tau 0.03125 --omega 1 --phase isotropic --ground-albedo 0 --mu0 0.1 --mu 0.1 --phi-deg 0 "
      "--paths 40000 --seed 3 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* k : {"reflection", "transmission", "reflection_stderr", "transmission_stderr", "paths", "seed",
                        "time_s"})
    EXPECT_TRUE(j.contains(k)) << k;
  const double R = j["reflection"].get<double>(), se = j["reflection_stderr"].get<double>();
  EXPECT_GT(se, 0.0);
  EXPECT_LE(std::abs(R - 0.622884), 4.0 * se) << R << " +- " << se;
  EXPECT_EQ(j["paths"].get<long long>(), 40000);
  // Same seed: the same digits.
  const auto again = run_cli(
      "rt slab --tau 0.03125 --omega 1 --phase isotropic --ground-albedo 0 --mu0 0.1 --mu 0.1 --phi-deg 0 "
      "--paths 40000 --seed 3 --json --threads 1");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(nlohmann::json::parse(again.out)["reflection"].get<double>(), R);
}

TEST(CliRt, SkyJson) {
  const auto r = run_cli("rt sky --sun-elevation 30 --view-elevation 90 --view-azimuth 0 --paths 4000 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* k : {"wavelengths_nm", "radiance_w_m2_sr_nm", "radiance_stderr_w_m2_sr_nm", "luminance_cd_m2",
                        "luminance_stderr_cd_m2", "paths", "seed", "time_s", "sun_depth_rel_error"})
    EXPECT_TRUE(j.contains(k)) << k;
  const auto& L = j["radiance_w_m2_sr_nm"];
  EXPECT_EQ(L.size(), j["wavelengths_nm"].size());
  for (const auto& v : L) EXPECT_TRUE(std::isfinite(v.get<double>()) && v.get<double>() > 0);
  const double Y = j["luminance_cd_m2"].get<double>();
  EXPECT_GT(Y, 200.0);  // a daylight sky at sun 30 deg: ~1e3 cd/m^2
  EXPECT_LT(Y, 2e4);
  EXPECT_GT(j["luminance_stderr_cd_m2"].get<double>(), 0.0);
  EXPECT_LT(j["luminance_stderr_cd_m2"].get<double>(), 0.05 * Y);
}

TEST(CliRt, HelpAndBadInput) {
  for (const char* sub : {"rt --help", "rt slab --help", "rt sky --help"}) {
    const auto r = run_cli(sub);
    EXPECT_EQ(r.exit_code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
  struct Bad {
    const char* args;
    const char* names;
  };
  for (const Bad b :
       {Bad{"rt slab --tau -1 --omega 1 --phase isotropic --mu0 0.5 --mu 0.5 --json", "--tau"},
        Bad{"rt slab --tau 1 --omega 1.5 --phase isotropic --mu0 0.5 --mu 0.5", "--omega"},
        Bad{"rt slab --tau 1 --omega 1 --phase mie --mu0 0.5 --mu 0.5", "--phase"},
        Bad{"rt slab --tau 1 --omega 1 --phase hg --g 1 --mu0 0.5 --mu 0.5", "--g"},
        Bad{"rt slab --tau 1 --omega 1 --phase isotropic --mu0 0 --mu 0.5", "--mu0"},
        Bad{"rt slab --tau 1 --omega 1 --phase isotropic --mu0 0.5 --mu 0.5 --paths 0", "--paths"},
        Bad{"rt sky --sun-elevation 95 --view-elevation 90 --view-azimuth 0", "--sun-elevation"},
        Bad{"rt sky --sun-elevation 10 --view-elevation 90 --view-azimuth 0 --sun-depth foo", "--sun-depth"},
        Bad{"rt sky --sun-elevation 10 --view-elevation 90 --view-azimuth 0 --guide maybe", "--guide"},
        Bad{"rt sky --scene /nonexistent.toml --sun-elevation 10 --view-elevation 90 --view-azimuth 0", "nonexistent"}}) {
    const auto r = run_cli(b.args);
    EXPECT_EQ(r.exit_code, 2) << b.args;
    EXPECT_EQ(count_lines(r.err), 1) << b.args << ": " << r.err;
    EXPECT_NE(r.err.find(b.names), std::string::npos) << b.args << ": " << r.err;
  }
}

// `converge ms --quick`: the files, the CSV's provenance and columns, one row per
// setting and band; bad input exits 2 naming the option, before any work.
TEST(CliRt, ConvergeMsQuick) {
  const auto dir = atmosh::test::scratch_dir("atmosh_cli_rt", "converge_ms");
  const auto r = run_cli("converge ms --quick --paths 8000 --seed 5 -o '" + dir.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"ms_convergence.csv", "ms_convergence.png", "ms_convergence_points.csv"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  const std::string csv = atmosh::test::slurp(dir / "ms_convergence.csv");
  EXPECT_NE(csv.find("# reference: Monte-Carlo"), std::string::npos);
  EXPECT_NE(csv.find("8000 paths per row, seed 5"), std::string::npos);
  std::istringstream in(csv);
  std::string line, header;
  int data = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) {
      header = line;
      continue;
    }
    ++data;
    const bool single = line.rfind("single,", 0) == 0, approx = line.rfind("approximate,", 0) == 0;
    EXPECT_TRUE(single || approx) << line;
  }
  EXPECT_EQ(header,
            "method,setting,band,error_max_rel,error_rms_rel,time_s,reference_rel_stderr_max,error_max_sigma,"
            "error_max_rel_minus_3sigma,build_time_s,eval_time_s,rows,rows_skipped");
  EXPECT_EQ(data, 6);  // 3 settings x bands all, day (the quick study's suns are above the horizon)
  struct Bad {
    const char* args;
    const char* names;
  };
  for (const Bad b : {Bad{"converge ms --quick --paths 0 -o /tmp/x", "--paths"},
                      Bad{"converge ms --quick --paths abc -o /tmp/x", "--paths"},
                      Bad{"converge ms --quick --scene /nonexistent.toml -o /tmp/x", "nonexistent"},
                      Bad{"converge ms --quick", "--output"}}) {
    const auto e = run_cli(b.args);
    EXPECT_EQ(e.exit_code, 2) << b.args;
    EXPECT_EQ(count_lines(e.err), 1) << b.args << ": " << e.err;
    EXPECT_NE(e.err.find(b.names), std::string::npos) << b.args << ": " << e.err;
  }
}
