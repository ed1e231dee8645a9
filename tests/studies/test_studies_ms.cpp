// The multiple-scattering convergence driver (atmosh/studies/ms.hpp): its rows are
// the study of atmo::ms_convergence_study, single scattering falls short of the
// Monte-Carlo reference (every order), and the writer puts every row in its files.
#include <gtest/gtest.h>

#include <filesystem>

#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/studies/ms.hpp"
#include "studies_test_scene.hpp"

using namespace atmosh;
namespace fs = std::filesystem;

TEST(Studies, ConvergeMsSingleScatteringFallsShortOfTheReference) {
  const auto s = test::small_scene();
  studies::ConvergeMsOptions o;
  o.quick = true;
  o.paths = 4000;
  o.seed = 7;
  const auto c = studies::converge_ms(s, o);
  EXPECT_EQ(c.paths, 4000);
  // Quick: the zenith and the horizon away from the sun, the sun at 30 and 10 deg.
  ASSERT_EQ(c.result.points.size(), 4u);
  ASSERT_EQ(c.options.settings.front().method, "single");
  double short_sum = 0;
  for (const auto& p : c.result.points) {
    ASSERT_EQ(p.luminance.size(), c.options.settings.size());
    EXPECT_GT(p.reference_luminance, 0.0);
    EXPECT_GT(p.reference_luminance_stderr, 0.0);
    // Single scattering leaves out every higher order: below the reference (within 3 sigma).
    EXPECT_LT(p.luminance[0], p.reference_luminance + 3 * p.reference_luminance_stderr)
        << p.sun_elevation_deg << " " << p.view_elevation_deg;
    short_sum += (p.reference_luminance - p.luminance[0]) / p.reference_luminance;
  }
  EXPECT_GT(short_sum / 4, 0.02);  // several per cent of the sky is light scattered more than once
  // The approximation of every order is closer to the reference than single scattering.
  double single_err = -1, approx_err = 1e9;
  for (const auto& r : c.result.rows)
    if (r.band == "all") {
      if (r.method == "single") single_err = r.error_max_rel;
      if (r.method == "approximate") approx_err = std::min(approx_err, r.error_max_rel);
    }
  EXPECT_LT(approx_err, single_err);
}

TEST(Studies, ConvergeMsWritesItsRowsAndRefusesBadPaths) {
  const auto s = test::small_scene();
  studies::ConvergeMsOptions o;
  o.quick = true;
  o.paths = 500;
  const auto c = studies::converge_ms(s, o);
  const fs::path d = fs::temp_directory_path() / ("atmosh_studies_ms_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  const auto files = studies::write_converge_ms(c, d);
  ASSERT_EQ(files.size(), 3u);
  const auto rows = io::read_csv(files[0]);
  EXPECT_EQ(rows.rows.size(), c.result.rows.size());
  const auto pts = io::read_csv(files[2]);
  ASSERT_EQ(pts.rows.size(), c.result.points.size());
  EXPECT_EQ(pts.columns.size(), 5 + c.options.settings.size());
  EXPECT_EQ(pts.number(0, pts.column("reference_luminance_cd_m2")), c.result.points[0].reference_luminance);
  o.paths = -1;
  EXPECT_THROW(studies::converge_ms(s, o), InputError);
}
