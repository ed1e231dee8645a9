// `atmosh converge lut --device cpu|gpu|auto`: with a GPU every setting gets a
// second row, lut_gpu (the same tables built by the GPU table pass,
// gpu/shaders/lut_build.comp), whose error against the exact reference must
// match the CPU row's to the float precision of the stored tables; a bad
// --device value is bad input (exit 2); without an EGL device `auto` falls back
// to the CPU rows with a one-line notice and `gpu` fails (exit 1).
#include <cstdio>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/presets.hpp"
#include "run_cli.hpp"
#include "without_egl.hpp"

namespace fs = std::filesystem;
using atmosh::test::count_lines;
using atmosh::test::expect_bad_input;
using atmosh::test::run_cli;
using atmosh::test::scratch_dir;
using atmosh::test::slurp;

namespace {

// Rows of a study CSV (comment lines '#' skipped) as column name -> text.
std::vector<std::map<std::string, std::string>> csv_rows(const fs::path& file) {
  std::istringstream in(slurp(file));
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    if (header.empty()) {
      header = cells;
      continue;
    }
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

const std::map<std::string, std::string>* find_row(const std::vector<std::map<std::string, std::string>>& rows,
                                                   const std::string& method, const std::string& setting) {
  for (const auto& r : rows)
    if (r.at("method") == method && r.at("setting") == setting) return &r;
  return nullptr;
}

double num(const std::map<std::string, std::string>& row, const std::string& col) { return std::stod(row.at(col)); }

// `converge lut --device cpu ARGS` into the scratch directory `name`: the rows of its
// CSV (none, and a test failure, if it did not exit 0).
std::vector<std::map<std::string, std::string>> cpu_study(const std::string& name, const std::string& args) {
  const fs::path d = scratch_dir("atmosh_cli_lut_gpu", name);
  const auto r = run_cli("converge lut --device cpu " + args + " -o '" + (d / "lut").string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) return {};
  return csv_rows(d / "lut.csv");
}

const std::string kSmall = " --shells 16 --directions 32";

}  // namespace

TEST(CliConvergeLutGpu, GpuRowsMatchTheCpuRowsToFloatPrecision) {
  const fs::path d = scratch_dir("atmosh_cli_lut_gpu", "gpu");
  const auto r = run_cli("converge lut --device gpu" + kSmall + " -o '" + (d / "lut").string() + "'");
  if (r.exit_code == 1 && r.err.find("--device gpu") != std::string::npos && !std::getenv("ATMOSH_REQUIRE_GPU_CONTEXT"))
    GTEST_SKIP() << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(d / "lut.csv"));
  EXPECT_NE(slurp(d / "lut.csv").find("# device: gpu"), std::string::npos);
  const auto rows = csv_rows(d / "lut.csv");
  const auto* cpu = find_row(rows, "lut", "16x32");
  const auto* gpu = find_row(rows, "lut_gpu", "16x32");
  ASSERT_NE(cpu, nullptr);
  ASSERT_NE(gpu, nullptr);
  for (const char* col : {"error_max_rel", "error_rms_rel", "error_max_rel_rayleigh_mie", "time_s", "build_time_s"}) {
    EXPECT_TRUE(std::isfinite(num(*gpu, col))) << col;
    EXPECT_GT(num(*gpu, col), 0.0) << col;
  }
  // Same shells, directions and lookup: the GPU tables differ from the CPU's by
  // the float rounding of the stored log-means (a few 1e-6 relative in a column,
  // docs/gpu.md), so the relative errors against the same exact columns differ
  // by at most ~1e-5 (absolute, in relative-error units).
  EXPECT_NEAR(num(*gpu, "error_max_rel"), num(*cpu, "error_max_rel"), 1e-5);
  EXPECT_NEAR(num(*gpu, "error_rms_rel"), num(*cpu, "error_rms_rel"), 1e-5);
  EXPECT_NEAR(num(*gpu, "error_max_rel_rayleigh_mie"), num(*cpu, "error_max_rel_rayleigh_mie"), 1e-5);
  EXPECT_NEAR(num(*gpu, "error_estimate_rel"), num(*cpu, "error_estimate_rel"), 1e-5);
  EXPECT_EQ(num(*gpu, "flag_mismatches"), num(*cpu, "flag_mismatches"));
  EXPECT_EQ(num(*gpu, "rays"), num(*cpu, "rays"));
  EXPECT_EQ(num(*gpu, "table_bytes"), num(*cpu, "table_bytes"));
}

// error_estimate_rel, the tables' own a-posteriori estimate (samples midway between
// shells and directions, every interval of both, and the kink probe rays, against fresh
// integrals), calibrated on rays the estimate does not visit: 600 random rays of another
// seed and, beside every node of earth-physical's 206-node table, horizontal rays 30 m
// off it and rays tangent 10 m and 30 m off it. Here, earth-physical and test-planet at
// 16-32 shells x 32-64 directions, it was 0.92-1.19 times their maximum (0.52-1.81
// when it sampled every other shell interval and every third direction); it must stay
// within 0.7-3 times. The study's CSV carries the same estimate at 550 nm.
TEST(CliConvergeLut, ErrorEstimateTracksTheMeasuredError) {
  using namespace atmosh::atmo;
  for (const char* name : {"earth-physical", "test-planet"}) {
    const Atmosphere atm(preset(name));
    const OpticalDepthReference exact(atm);
    const auto k = atm.coefficients_at(550.0);
    const double R = atm.ground_radius(), top = atm.top_altitude(), r_top = R + 0.99999 * top;
    std::vector<std::pair<double, double>> rays;
    std::mt19937_64 rng(7);
    auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
    for (int i = 0; i < 600; ++i) {
      const double u = uniform(), v = uniform();
      rays.push_back({R + ((i % 2 != 0) ? u * top : top * u * u * u), (i % 3 == 0) ? 0.05 * (v - 0.5) : 2 * v - 1});
    }
    for (int c = 0; c < 3; ++c)
      if (atm.has(c))
        for (double hk : atm.profile(c).kinks()) {
          if (!(hk > 0.0 && hk < top)) continue;
          for (double dh : {-30.0, 30.0}) rays.push_back({R + hk + dh, 0.0});
          for (double dt : {-30.0, -10.0, 10.0, 30.0}) {
            const double rt = R + hk + dt;
            if (rt > R && rt < r_top) rays.push_back({r_top, -std::sqrt((r_top - rt) * (r_top + rt)) / r_top});
          }
        }
    std::vector<double> tau(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i)
      tau[i] = optical_depth(k, exact.column(rays[i].first, rays[i].second).column);
    for (int shells : {16, 32})
      for (int dirs : {32, 64}) {
        LutOptions o;
        o.shells = shells;
        o.view_directions = o.sun_directions = dirs;
        const OpticalDepthLut lut(atm, o);
        double measured = 0.0;
        for (std::size_t i = 0; i < rays.size(); ++i)
          if (tau[i] > 0.0)
            measured = std::max(measured,
                                std::abs(optical_depth(k, lut.view(rays[i].first, rays[i].second).column) - tau[i]) / tau[i]);
        const double estimate = lut.estimate_max_rel_error(550.0);
        EXPECT_GT(measured, 0.0) << name << " " << shells << "x" << dirs;
        EXPECT_GE(estimate, 0.7 * measured) << name << " " << shells << "x" << dirs;
        EXPECT_LE(estimate, 3.0 * measured) << name << " " << shells << "x" << dirs;
      }
  }
  // The study reports the same estimate; its reference row, the quadrature's own.
  const auto rows = cpu_study("estimate", "--preset test-planet --shells 16 --directions 32");
  const auto* row = find_row(rows, "lut", "16x32");
  ASSERT_NE(row, nullptr);
  LutOptions o;
  o.shells = 16;
  o.view_directions = o.sun_directions = 32;
  const Atmosphere tp(preset("test-planet"));
  EXPECT_NEAR(num(*row, "error_estimate_rel"), OpticalDepthLut(tp, o).estimate_max_rel_error(550.0), 1e-12);
  // No long tabulated profile: no kinks subtracted, no lut_plain rows.
  EXPECT_EQ(num(*row, "subtracted_kinks"), 0.0);
  EXPECT_EQ(find_row(rows, "lut_plain", "16x32"), nullptr);
  const auto* ref = find_row(rows, "reference", "adaptive G7-K15 (estimated error)");
  ASSERT_NE(ref, nullptr);
  // The reference's row reports its estimated error: below the reference's tolerance
  // (ReferenceOptions::rel_tol 1e-12, with room for the estimate's own looseness), an
  // rms below the maximum.
  EXPECT_GT(num(*ref, "error_max_rel"), 0.0);
  EXPECT_LT(num(*ref, "error_max_rel"), 1e-9);
  EXPECT_LT(num(*ref, "error_rms_rel"), num(*ref, "error_max_rel"));
  // What that estimate stands for, measured: the reference's optical depth against an
  // independent quadrature written here (composite 8-point Gauss-Legendre, 3000 panels,
  // split where the ray crosses a kink of a profile) on test-planet rays of every kind,
  // grazing ones included. Its error stays within its own estimate (plus 1e-13 of
  // rounding in the comparison) and within the row's reported maximum's order.
  const auto k = tp.coefficients_at(550.0);
  const OpticalDepthReference exact(tp);
  const double R = tp.ground_radius(), T = tp.top_radius();
  static const double gx[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                               0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
  static const double gw[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                               0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
  auto independent_tau = [&](double r, double mu) {
    // Length inside the atmosphere (to the top or to the ground).
    const double disc_top = r * r * (mu * mu - 1.0) + T * T, disc_g = r * r * (mu * mu - 1.0) + R * R;
    double s_end = -r * mu + std::sqrt(std::max(0.0, disc_top));
    if (mu < 0.0 && disc_g >= 0.0) s_end = -r * mu - std::sqrt(disc_g);
    std::vector<double> cuts = {0.0, s_end};
    for (int c = 0; c < 3; ++c)
      if (tp.has(c))
        for (double hk : tp.profile(c).kinks()) {
          const double rk = R + hk, d = r * r * (mu * mu - 1.0) + rk * rk;
          if (d < 0.0) continue;
          for (double sk : {-r * mu - std::sqrt(d), -r * mu + std::sqrt(d)})
            if (sk > 0.0 && sk < s_end) cuts.push_back(sk);
        }
    std::sort(cuts.begin(), cuts.end());
    double tau = 0.0;
    for (std::size_t p = 0; p + 1 < cuts.size(); ++p) {
      const int panels = 3000;
      const double a = cuts[p], h = (cuts[p + 1] - cuts[p]) / panels;
      for (int q = 0; q < panels; ++q)
        for (int g = 0; g < 8; ++g) {
          const double sn = a + h * (q + 0.5 + 0.5 * gx[g]);
          const double alt = std::sqrt(r * r + sn * sn + 2.0 * r * mu * sn) - R;
          double ext = 0.0;
          for (int c = 0; c < 3; ++c)
            if (tp.has(c)) ext += k.extinction[c] * tp.profile(c)(alt);
          tau += 0.5 * h * gw[g] * ext;
        }
    }
    return tau;
  };
  std::mt19937_64 rng(11);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
  double worst = 0.0;
  for (int i = 0; i < 40; ++i) {
    const double r = R + (T - R) * uniform() * uniform();
    const double mu = i % 4 == 0 ? 0.02 * (uniform() - 0.5) : 2.0 * uniform() - 1.0;
    const auto col = exact.column(r, mu);
    const double a = optical_depth(k, col.column), b = independent_tau(r, mu);
    ASSERT_GT(b, 0.0);
    const double err = std::fabs(a - b) / b;
    EXPECT_LE(err, optical_depth(k, col.error) / b + 1e-13) << "r " << r << " mu " << mu;
    worst = std::max(worst, err);
  }
  EXPECT_LT(worst, 1e-11);
}

// The study's maximum covers the rays where the tables do worst: those near the kinks
// of an interpolated profile. Here the tropopause node of earth-physical's U.S. 1976
// Rayleigh table (geometric 11019.07 m, where d ln rho / dh jumps by ~0.03 per km):
// rays from just below it, horizontal and grazing, and rays tangent just below it from
// the top. Their largest error at 32 x 64, computed here with the library, must not
// exceed the reported maximum. Without the subtracted kinks (LutOptions::
// subtracted_kinks = 0) these rays reach ~4e-3 (before they were part of the study it
// reported 2.3e-3); with them (the default) they must be at least 3x better.
TEST(CliConvergeLut, StudyCoversTheRaysBesideKinks) {
  const auto rows = cpu_study("kinks", "--preset earth-physical --shells 32 --directions 64");
  const auto* d32 = find_row(rows, "lut", "32x64");
  ASSERT_NE(d32, nullptr);
  using namespace atmosh::atmo;
  const Atmosphere atm(preset("earth-physical"));
  const OpticalDepthReference exact(atm);
  const auto k = atm.coefficients_at(550.0);
  const double R = atm.ground_radius(), r_top = R + 0.99999 * atm.top_altitude(), h_trop = 11019.07;
  auto worst_of = [&](int subtracted) {
    LutOptions o;
    o.shells = 32;
    o.subtracted_kinks = subtracted;
    const OpticalDepthLut lut(atm, o);
    double worst = 0.0;
    auto probe = [&](double r0, double mu) {
      const double te = optical_depth(k, exact.column(r0, mu).column);
      worst = std::max(worst, std::abs(optical_depth(k, lut.view(r0, mu).column) - te) / te);
    };
    for (double mu : {0.0, 1e-3, -1e-3, 1e-2, -1e-2}) probe(R + h_trop - 100.0, mu);
    for (double dt : {-100.0, -1.0}) {
      const double rt = R + h_trop + dt;
      probe(r_top, -std::sqrt((r_top - rt) * (r_top + rt)) / r_top);
    }
    return worst;
  };
  const double plain = worst_of(0), worst = worst_of(LutOptions{}.subtracted_kinks);
  std::printf("  rays below the tropopause, 32 x 64: max rel. error %.3g plain, %.3g with subtracted kinks\n", plain,
              worst);
  EXPECT_GT(plain, 2.5e-3);  // these rays are the hard ones
  EXPECT_LT(worst, plain / 3.0);
  EXPECT_GE(num(*d32, "error_max_rel"), worst * (1.0 - 1e-9));
  // The study shows the trade: the seven U.S. 1976 layer boundaries subtracted, and a
  // lut_plain row with the same tables interpolated across them, worse and reported
  // no lower than these rays.
  EXPECT_EQ(num(*d32, "subtracted_kinks"), 7.0);
  const auto* p32 = find_row(rows, "lut_plain", "32x64");
  ASSERT_NE(p32, nullptr);
  EXPECT_EQ(num(*p32, "subtracted_kinks"), 0.0);
  EXPECT_GE(num(*p32, "error_max_rel"), plain * (1.0 - 1e-9));
  EXPECT_GT(num(*p32, "error_max_rel"), 2.0 * num(*d32, "error_max_rel"));
}

// The 1e-4 target reached for U.S. 1976 (docs/atmosphere.md, "Curvature jumps subtracted
// too"): the shipped scene docs/scenes/earth-physical-us1976-100m.toml (earth-physical
// with the standard tabulated every 100 m, whose linear pieces stay within 2.6e-5 of it)
// at 80 x 128, over the study's 2500+ rays against the exact reference, with the kinks'
// slope and curvature jumps subtracted: <= 1e-4 (5.8e-5 when measured); interpolated
// across the seven layer boundaries instead (the lut_plain row) 1.1e-3.
TEST(CliConvergeLut, FineUsStandard1976MeetsTheTarget) {
  const std::string scene = std::string(ATMOSH_SOURCE_DIR) + "/docs/scenes/earth-physical-us1976-100m.toml";
  const auto rows = cpu_study("fine", "--scene '" + scene + "' --shells 80 --directions 128");
  const auto* lut = find_row(rows, "lut", "80x128");
  const auto* plain = find_row(rows, "lut_plain", "80x128");
  ASSERT_NE(lut, nullptr);
  ASSERT_NE(plain, nullptr);
  std::printf("  U.S. 1976 every 100 m, 80 x 128: max rel. error %.3g (plain %.3g)\n", num(*lut, "error_max_rel"),
              num(*plain, "error_max_rel"));
  EXPECT_EQ(num(*lut, "subtracted_kinks"), 7.0);
  EXPECT_LE(num(*lut, "error_max_rel"), 1e-4);
  EXPECT_GT(num(*plain, "error_max_rel"), 5e-4);
  EXPECT_GE(num(*lut, "error_estimate_rel"), 0.5 * num(*lut, "error_max_rel"));
}

TEST(CliConvergeLutGpu, BadDeviceIsBadInput) {
  const fs::path d = scratch_dir("atmosh_cli_lut_gpu", "bad");
  expect_bad_input("converge lut --device tpu" + kSmall + " -o '" + (d / "lut").string() + "'", "--device");
  EXPECT_FALSE(fs::exists(d / "lut.csv"));
  // --quick has its own settings: combined with explicit ones it is ambiguous.
  expect_bad_input("converge lut --quick --shells 8 -o '" + (d / "lut").string() + "'", "--quick");
  EXPECT_FALSE(fs::exists(d / "lut.csv"));
}

// No EGL device: GLVND pointed at no vendor library (as in
// tests/gpu/test_fallback.cpp); atmosh inherits the variable from this process.
TEST(CliConvergeLutGpu, WithoutAnEglDeviceAutoFallsBackAndGpuFails) {
  const fs::path d = scratch_dir("atmosh_cli_lut_gpu", "none");
  atmosh::test::CliResult a, g;
  {
    const atmosh::test::WithoutEglDevice no_egl;
    a = run_cli("converge lut --device auto" + kSmall + " -o '" + (d / "lut").string() + "'");
    g = run_cli("converge lut --device gpu" + kSmall + " -o '" + (d / "lut_g").string() + "'");
  }
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_EQ(count_lines(a.err), 1) << a.err;
  const auto rows = csv_rows(d / "lut.csv");
  EXPECT_NE(find_row(rows, "lut", "16x32"), nullptr);
  EXPECT_EQ(find_row(rows, "lut_gpu", "16x32"), nullptr);
  EXPECT_NE(slurp(d / "lut.csv").find("# device: cpu"), std::string::npos);
  EXPECT_EQ(g.exit_code, 1) << g.err;
  EXPECT_EQ(count_lines(g.err), 1) << g.err;
  EXPECT_NE(g.err.find("--device gpu"), std::string::npos) << g.err;
}

// The 1e-4 target, measured: the largest relative error of the total optical depth
// over the study's rays (grazing, tangent, beside the ozone tent's corners, 1000 seeded
// random rays) against the exact reference. earth-graphics meets it at the default
// 32 x 64 (2.9e-5, docs/atmosphere.md); the built-in default scene (the same with the
// top at 100 km) does at 48 x 64 (3.6e-5) but not quite at 32 x 64 (1.03e-4, on rays
// looking up from ~97 km, where the direction coordinate has one sample for all
// upward rays).
TEST(CliConvergeLut, TablesMeetTheTargetOnSmoothProfiles) {
  const fs::path d = scratch_dir("atmosh_cli_lut_gpu", "target");
  const auto show = run_cli("scene show");
  ASSERT_EQ(show.exit_code, 0) << show.err;
  {
    std::ofstream f(d / "default.toml");
    f << show.out;
  }
  struct Case {
    std::string source, setting;
    int shells;
  };
  for (const Case& c : {Case{"--preset earth-graphics", "32x64", 32},
                        Case{"--scene '" + (d / "default.toml").string() + "'", "48x64", 48}}) {
    const auto rows = cpu_study("targets", c.source + " --shells " + std::to_string(c.shells) + " --directions 64");
    const auto* row = find_row(rows, "lut", c.setting);
    ASSERT_NE(row, nullptr) << c.source;
    EXPECT_LE(num(*row, "error_max_rel"), 1e-4) << c.source;
    EXPECT_GT(num(*row, "error_max_rel"), 0.0) << c.source;
    EXPECT_GT(num(*row, "rays"), 2000.0) << c.source;
  }
}
