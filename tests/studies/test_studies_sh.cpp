// atmosh::studies, spherical harmonics: the image loader and projection, the error
// measure, the projection study, the coefficient file's one writer and reader, the band
// table and the window study, against closed forms.
//
// Closed forms (real orthonormal SH, Y_00 = 1 / (2 sqrt(pi)), Y_10 = sqrt(3 / (4 pi)) z):
// f = a + b z has c_00 = 2 sqrt(pi) a and c_10 = 2 sqrt(pi / 3) b, every other
// coefficient 0; the band energy of band l is sum_m c_lm^2.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/studies/studies_sh.hpp"

namespace {

using namespace atmosh;
namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("atmosh_studies_sh_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// An equirect image of f = a + b z (row 0 at +z), as the projection reads images.
fs::path linear_image(const fs::path& dir, double a, double b, int w = 64) {
  const int h = w / 2;
  io::ExrImage img(w, h, {"R", "G", "B"});
  for (int r = 0; r < h; ++r)
    for (int q = 0; q < w; ++q) {
      const double z = std::cos(kPi * (r + 0.5) / h);
      for (int c = 0; c < 3; ++c) img.data[c][static_cast<std::size_t>(r) * w + q] = static_cast<float>((c + 1) * a + b * z);
    }
  const fs::path f = dir / "linear.exr";
  io::write_exr(f, img, io::Provenance{});
  return f;
}

TEST(StudiesSh, QuadratureProjectionOfALinearImageIsTheClosedForm) {
  const fs::path d = scratch("linear");
  const double a = 0.7, b = 0.25;
  const auto img = studies::load_sh_image(linear_image(d, a, b), "auto", std::size_t{1} << 30);
  EXPECT_FALSE(img.cross);
  ASSERT_EQ(img.names, (std::vector<std::string>{"r", "g", "b"}));
  const auto c = studies::project_sh_image(img, 4, sh::ProjectOptions{});
  for (int ch = 0; ch < 3; ++ch) {
    // float pixels: ~1e-7 relative
    EXPECT_NEAR(c[ch][0], 2 * std::sqrt(kPi) * (ch + 1) * a, 1e-6);
    EXPECT_NEAR(c[ch][2], 2 * std::sqrt(kPi / 3) * b, 1e-6);
    for (int i : {1, 3, 4, 5, 6, 7, 8}) EXPECT_NEAR(c[ch][i], 0.0, 1e-6) << i;
  }
}

TEST(StudiesSh, LoaderRefusesAShapeWithoutALayoutAndNamesTheFile) {
  const fs::path d = scratch("shape");
  io::ExrImage img(30, 20, {"R", "G", "B"});
  io::write_exr(d / "odd.exr", img, io::Provenance{});
  try {
    studies::load_sh_image(d / "odd.exr", "auto", std::size_t{1} << 30);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("odd.exr"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << "names an option: " << e.what();
  }
  EXPECT_THROW(studies::load_sh_image(d / "odd.exr", "spiral", std::size_t{1} << 30), InputError);
}

TEST(StudiesSh, CompareIsTheRelativeMaxAndL2Error) {
  const sh::Channels ref = {{1.0, -2.0, 0.5}, {0.0, 4.0, 1.0}};
  sh::Channels c = ref;
  const double eps = 1e-3;
  for (auto& ch : c)
    for (auto& v : ch) v *= 1 + eps;
  const auto e = studies::compare_sh(c, ref);
  EXPECT_NEAR(e.max_rel, eps, 1e-15);  // max |c - ref| = eps * 4, max |ref| = 4
  EXPECT_NEAR(e.rms_rel, eps, 1e-15);
  EXPECT_EQ(studies::compare_sh(ref, ref).max_rel, 0.0);
}

TEST(StudiesSh, ConvergeShRowsMeasureEachMethodAgainstTheQuadrature) {
  const fs::path d = scratch("converge");
  const auto img = studies::load_sh_image(linear_image(d, 0.7, 0.25), "equirect", std::size_t{1} << 30);
  const auto t = studies::converge_sh(img, 3, /*quick=*/true, 7, "linear.exr");
  ASSERT_EQ(t.rows.size(), 1u + 3 + 3 + 2);  // reference, jittered x3, uniform x3, gauss grid x2
  EXPECT_EQ(t.rows[0].method, "fejer-quadrature");
  EXPECT_EQ(t.rows[0].error_max, 0.0);
  EXPECT_EQ(t.rows[0].extras[0], 64.0 * 32.0);
  for (const auto& r : t.rows) {
    EXPECT_TRUE(std::isfinite(r.error_max) && std::isfinite(r.error_rms)) << r.method << " " << r.setting;
    EXPECT_GE(r.time_s, 0.0);
  }
  // A jittered row is the jittered projection with the study's seed, measured against
  // the quadrature: recomputed here through the projection itself.
  const auto ref = studies::project_sh_image(img, 3, sh::ProjectOptions{});
  const auto j45 = studies::project_sh_image(img, 3, sh::ProjectOptions{sh::Method::jittered, 45, 7, 1});
  EXPECT_DOUBLE_EQ(t.rows[3].error_max, studies::compare_sh(j45, ref).max_rel);
  // More samples, smaller error: 45 x 45 strata against 8 x 8 (n^-3/2 for smooth f:
  // ~ 20x smaller), 8192 uniform samples against 256.
  EXPECT_LT(t.rows[3].error_max, t.rows[1].error_max);
  EXPECT_LT(t.rows[6].error_max, t.rows[4].error_max);
  // The Gauss grid resampled bilinearly from a linear function in z: near exact.
  EXPECT_LT(t.rows[8].error_max, 1e-2);
}

TEST(StudiesSh, CoefficientFileRoundTripsAtFullPrecision) {
  const fs::path d = scratch("csv");
  io::ShCoefficients c;
  c.bands = 3;
  c.names = {"r", "g"};
  c.channels = {std::vector<double>(9), std::vector<double>(9)};
  for (int i = 0; i < 9; ++i) {
    c.channels[0][i] = std::sqrt(2.0) * (i + 1) / 3.0;
    c.channels[1][i] = -1e-300 * (i + 1);
  }
  io::Provenance p;
  p.add("value_units", "cd/m^2");
  io::write_sh_coefficients(d / "c.csv", c, p);
  const auto back = io::read_sh_coefficients(d / "c.csv");
  EXPECT_EQ(back.bands, 3);
  EXPECT_EQ(back.names, c.names);
  EXPECT_EQ(back.channels, c.channels);  // bit for bit
  EXPECT_EQ(back.value_units, "cd/m^2");
  const auto csv = io::read_csv(d / "c.csv");
  EXPECT_TRUE(csv.provenance.count("sh_convention"));
  EXPECT_EQ(csv.provenance.at("sh_bands"), "3");
  for (std::size_t r = 0; r < csv.rows.size(); ++r) {  // l, m, index of every row
    const double l = csv.number(r, 0), m = csv.number(r, 1);
    EXPECT_EQ(l * (l + 1) + m, csv.number(r, 2));
    EXPECT_EQ(csv.number(r, 2), double(r));
  }
  io::write_sh_coefficients(d / "plain.csv", c, p, /*add_convention=*/false);
  EXPECT_FALSE(io::read_csv(d / "plain.csv").provenance.count("sh_convention"));
  c.channels[1].resize(4);
  EXPECT_THROW(io::write_sh_coefficients(d / "bad.csv", c, p), std::invalid_argument);
}

TEST(StudiesSh, BandTableHoldsTheBandEnergies) {
  const fs::path d = scratch("bands");
  io::ShCoefficients c;
  c.bands = 2;
  c.names = {"g"};
  c.channels = {{3.0, 1.0, -2.0, 2.0}};
  studies::write_sh_bands(c, d / "b.csv", {}, io::Provenance{});
  const auto csv = io::read_csv(d / "b.csv");
  ASSERT_EQ(csv.rows.size(), 2u);
  EXPECT_EQ(csv.number(0, csv.column("energy_g")), 9.0);
  EXPECT_EQ(csv.number(1, csv.column("energy_g")), 1.0 + 4.0 + 4.0);
  EXPECT_DOUBLE_EQ(csv.number(0, csv.column("fraction_g")), 0.5);
  EXPECT_DOUBLE_EQ(csv.number(1, csv.column("fraction_g")), 1.0);
  EXPECT_FALSE(fs::exists(d / "b.png"));
}

TEST(StudiesSh, SyntheticSkyPeaksAtItsSunAndTheUnwindowedRowChangesNothing) {
  const io::ExrImage img = studies::synthetic_sky(128);
  ASSERT_EQ(img.width, 128);
  ASSERT_EQ(img.height, 64);
  std::size_t best = 0;
  for (std::size_t p = 0; p < img.data[1].size(); ++p) {
    ASSERT_TRUE(std::isfinite(img.data[1][p]));
    if (img.data[1][p] > img.data[1][best]) best = p;
  }
  // The sun: elevation 30 deg (polar 60 deg), azimuth 40 deg from +x.
  const double polar = 180.0 * (static_cast<double>(best / 128) + 0.5) / 64, azimuth = 360.0 * (best % 128 + 0.5) / 128;
  EXPECT_NEAR(polar, 60.0, 2.9);
  EXPECT_NEAR(azimuth, 40.0, 2.9);
  const auto rows = studies::sh_window_study(std::vector<double>{1.0, 0.2, 0.3, -0.1, 0.05, 0, 0.02, 0, 0.01}, 3);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0].window, "none");
  EXPECT_EQ(rows[0].l2_change_rel, 0.0);
  EXPECT_EQ(rows[0].irradiance_max_change_rel, 0.0);
  for (const auto& r : rows) EXPECT_TRUE(std::isfinite(r.delta_min_rel) && std::isfinite(r.l2_change_rel)) << r.window;
  EXPECT_GT(rows[1].l2_change_rel, 0.0);  // a window changes the coefficients
}

}  // namespace
