// atmosh::studies, PRT: the relight lights and exposure, the transfer error measures,
// the per-pixel transfer image's one writer and reader, per-pixel relighting and the
// sample-count study, against closed forms and the lower-level library calls.
//
// Closed forms: a directional light of irradiance E from d has SH l_i = E Y_i(d), so
// l_00 = E / (2 sqrt(pi)), l_1,-1 = -E sqrt(3 / (4 pi)) d_y, l_10 = E sqrt(3 / (4 pi)) d_z,
// l_11 = -E sqrt(3 / (4 pi)) d_x (real SH with the Condon-Shortley phase, as in Sloan,
// "Stupid Spherical Harmonics (SH) Tricks", GDC 2008, appendix); a per-pixel transfer with
// only T_00 relit by a light with only l_00 gives T_00 l_00 in every channel.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "atmosh/error.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/transfer_exr.hpp"
#include "atmosh/prt/bake.hpp"
#include "atmosh/prt/mesh.hpp"
#include "atmosh/studies/studies_prt.hpp"

namespace {

using namespace atmosh;
namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("atmosh_studies_prt_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(StudiesPrt, TurningLightsAreDirectionalLightsOfIrradiancePi) {
  const auto lights = studies::turning_lights({glm::dvec3(1, 0, 1)}, 4, 2);
  ASSERT_EQ(lights.size(), 4u);
  const double y00 = 1 / (2 * std::sqrt(kPi)), y1 = std::sqrt(3 / (4 * kPi));
  // Frame f: the direction turned by f x 90 deg about +z; normalised (1, 0, 1) / sqrt 2.
  const double s = 1 / std::sqrt(2.0);
  const glm::dvec3 dirs[4] = {{s, 0, s}, {0, s, s}, {-s, 0, s}, {0, -s, s}};
  for (int f = 0; f < 4; ++f) {
    ASSERT_EQ(lights[f].size(), 1u);
    const auto& l = lights[f][0];
    ASSERT_EQ(l.size(), 4u);
    EXPECT_NEAR(l[0], kPi * y00, 1e-14);
    EXPECT_NEAR(l[1], -kPi * y1 * dirs[f].y, 1e-14) << f;  // index 1: l = 1, m = -1 (y)
    EXPECT_NEAR(l[2], kPi * y1 * dirs[f].z, 1e-14) << f;  // m = 0 (z)
    EXPECT_NEAR(l[3], -kPi * y1 * dirs[f].x, 1e-14) << f;  // m = 1 (x)
  }
  EXPECT_THROW(studies::turning_lights({glm::dvec3(0)}, 1, 2), InputError);
  EXPECT_THROW(studies::turning_lights({glm::dvec3(1, 0, 0)}, 0, 2), InputError);
}

TEST(StudiesPrt, AutoExposureMapsThe99thPercentileToOne) {
  std::vector<float> v;
  for (int i = 100; i >= 1; --i) v.push_back(static_cast<float>(i));
  // sorted 1..100, index floor(0.99 * 99) = 98 -> 99
  EXPECT_DOUBLE_EQ(studies::auto_exposure(v), 1.0 / 99.0);
  EXPECT_EQ(studies::auto_exposure(std::vector<float>(10, 0.0f)), 1.0);
  EXPECT_EQ(studies::auto_exposure({}), 1.0);
}

TEST(StudiesPrt, TransferErrorIsRelativeToTheLargestReferenceVector) {
  prt::BakeOptions bo;
  bo.bands = 2;
  bo.strata = 3;
  const prt::Transfer ref = prt::bake(prt::builtin_scene("sphere", 6), bo);
  EXPECT_EQ(studies::transfer_error(ref, ref), std::make_pair(0.0, 0.0));
  prt::Transfer t = ref;
  const double eps = 1e-3;
  for (double& c : t.coeffs) c *= 1 + eps;
  const auto [emax, erms] = studies::transfer_error(t, ref);
  EXPECT_NEAR(emax, eps, 1e-12);  // max_v eps |T_v| / max_v |T_v|
  EXPECT_GT(erms, 0.0);
  EXPECT_LE(erms, emax + 1e-15);
}

io::TransferImage constant_transfer(int w, int h, float t00) {
  io::TransferImage t;
  t.width = w;
  t.height = h;
  t.bands = 2;
  const std::size_t np = static_cast<std::size_t>(w) * h;
  t.coefficients.assign(4, std::vector<float>(np, 0.0f));
  t.coefficients[0].assign(np, t00);
  t.coefficients[3][1] = 0.25f;  // one more value, to see it come back
  t.ao.assign(np, 0.5f);
  t.mask.assign(np, 1.0f);
  t.attributes["quantity"] = "test";
  return t;
}

TEST(StudiesPrt, TransferImageRoundTripsAndRelightsToTheClosedForm) {
  const fs::path d = scratch("pixels");
  const auto t = constant_transfer(6, 4, 0.3f);
  io::write_transfer_exr(d / "t.exr", t, io::Provenance{});
  const auto back = io::read_transfer_exr(d / "t.exr");
  EXPECT_EQ(back.bands, 2);
  EXPECT_EQ(back.coefficients, t.coefficients);
  EXPECT_EQ(back.ao, t.ao);
  EXPECT_EQ(back.mask, t.mask);
  EXPECT_EQ(back.attributes.at("quantity"), "test");
  EXPECT_EQ(back.attributes.at("sh_convention"), "real orthonormal, Condon-Shortley phase, index l(l+1)+m");
  // Relit by a light with l_00 = 2 and l_1m = 0: every pixel is 0.3 * 2 but pixel 1,
  // whose T_11 = 0.25 meets l_11 = 0 (nothing).
  const studies::ShLight light = {{2.0, 0.0, 0.0, 0.0}};
  studies::RelightImageOptions o;
  o.exposure = 1.0;
  const auto files = studies::relight_pixels_to(back, "t.exr", {light}, o, d / "lit");
  ASSERT_EQ(files.size(), 6u);  // ao and one frame, each .exr .png .png.json
  const auto frame = io::read_exr(d / "lit" / "frame_0000.exr");
  for (int c = 0; c < 3; ++c)
    for (float v : frame.data[c]) EXPECT_FLOAT_EQ(v, 0.6f);
  const auto ao = io::read_exr(d / "lit" / "ao.exr");
  for (float v : ao.data[0]) EXPECT_EQ(v, 0.5f);
  // Not a transfer image: no ao channel.
  io::ExrImage plain(2, 2, {"sh_l0_m0"});
  io::write_exr(d / "plain.exr", plain, io::Provenance{});
  EXPECT_THROW(io::read_transfer_exr(d / "plain.exr"), InputError);
}

TEST(StudiesPrt, PixelBakeBecomesTheTransferImageItWrites) {
  prt::BakeOptions bo;
  bo.bands = 2;
  bo.strata = 3;
  const prt::PixelTransfer px = prt::bake_pixels(prt::builtin_scene("sphere", 6), bo, 8, 6, {1, -1.6, 1.1});
  const io::TransferImage t = studies::transfer_image(px, bo.mode, "1,-1.6,1.1");
  ASSERT_EQ(t.coefficients.size(), 4u);
  for (std::size_t p = 0; p < px.mask.size(); ++p) {
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(t.coefficients[i][p], static_cast<float>(px.coeffs[p * 4 + i]));
    EXPECT_EQ(t.ao[p], static_cast<float>(px.ao[p]));
    EXPECT_EQ(t.mask[p], px.mask[p]);
  }
  EXPECT_EQ(t.attributes.at("device"), "cpu");
  EXPECT_EQ(t.attributes.at("samples"), std::to_string(px.samples));
  EXPECT_EQ(t.attributes.count("depth_map"), 0u);
}

TEST(StudiesPrt, ConvergenceRowsAreTheBakesErrorsAgainstTheReference) {
  const prt::Mesh mesh = prt::builtin_scene("sphere-on-plane", 4);
  studies::PrtConvergenceOptions o;
  o.bands = 2;
  o.reference_strata = 8;
  o.strata = {2, 4};
  o.threads = 1;
  o.device = "cpu";
  o.width = o.height = 12;
  const auto t = studies::prt_convergence(mesh, o);
  ASSERT_EQ(t.rows.size(), 4u);  // two per-vertex rows, two per-pixel rows
  EXPECT_EQ(t.rows[0].method, "cpu-shadowed-jittered");
  EXPECT_EQ(t.rows[2].method, "cpu-pixel-shadowed-jittered");
  // The per-vertex rows through the lower-level calls: the bake with the rows' seed
  // against the bake with the reference's.
  prt::BakeOptions bo;
  bo.bands = 2;
  bo.threads = 1;
  bo.strata = 8;
  bo.seed = 12345;
  const prt::Transfer ref = prt::bake(mesh, bo);
  bo.seed = 1;
  for (int k = 0; k < 2; ++k) {
    bo.strata = o.strata[k];
    const auto [emax, erms] = studies::transfer_error(prt::bake(mesh, bo), ref);
    EXPECT_DOUBLE_EQ(t.rows[k].error_max, emax);
    EXPECT_DOUBLE_EQ(t.rows[k].error_rms, erms);
    EXPECT_EQ(t.rows[k].extras[0], double(o.strata[k] * o.strata[k]));
  }
  // 16 samples beat 4 (per vertex and per pixel).
  EXPECT_LT(t.rows[1].error_rms, t.rows[0].error_rms);
  EXPECT_LT(t.rows[3].error_rms, t.rows[2].error_rms);
  o.device = "tpu";
  EXPECT_THROW(studies::prt_convergence(mesh, o), InputError);
}

}  // namespace
