// The sky's studies at the library level (atmosh/studies/sky_studies.hpp): each
// study's rows against the lower-level libatmo calls they are made of (an integrator
// built here, NREL SPA called here), and physical properties of the rows.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sun_position.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/transform.hpp"
#include "atmosh/studies/sky_studies.hpp"
#include "studies_test_scene.hpp"

using namespace atmosh;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("atmosh_studies_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string prov_value(const io::Provenance& p, const std::string& key) {
  for (const auto& [k, v] : p.entries)
    if (k == key) return v;
  return "<missing " + key + ">";
}

// An integrator built here from the scene, independently of make_sky_model.
struct Direct {
  atmo::Atmosphere atm;
  atmo::SkyIntegrator sky;
  Direct(const scene::Scene& s, const studies::SkySettings& k, double d_au = 1.0)
      : atm(s.atmosphere), sky(atm, atmo::solar_spectrum_for_bins(s.atmosphere.spectrum), [&] {
          atmo::SkyOptions o;
          o.lut.shells = k.shells;
          o.segments = k.segments;
          o.samples_per_segment = k.samples;
          o.max_piece_optical_depth = k.max_piece_tau;
          o.sun_model = atmo::parse_sun_model(s.sun_model);
          o.scattering = s.scattering;
          o.sun_distance_au = d_au;
          return o;
        }()) {}
};

}  // namespace

// -------------------------------------------------------- sun-elevation study
TEST(Studies, SunElevationStudyRowsAreTheSkySummaryAtEachElevation) {
  const auto s = test::small_scene();
  studies::ElevationStudyOptions o;
  o.from_deg = -4;
  o.to_deg = 60;
  o.step_deg = 16;
  o.azimuth_deg = 150;
  o.sky = test::coarse_settings();
  const auto st = studies::sun_elevation_study(s, o);
  ASSERT_EQ(st.elevations_deg, (std::vector<double>{-4, 12, 28, 44, 60}));
  ASSERT_EQ(st.rows.size(), 5u);
  const Direct d(s, o.sky);
  for (std::size_t i = 0; i < st.rows.size(); ++i) {
    const auto ref = atmo::summarize_sky(d.sky, 0.0, atmo::enu_direction_from_zenith(90.0 - st.elevations_deg[i], 150.0));
    EXPECT_EQ(st.rows[i].zenith.xyz.Y, ref.zenith.xyz.Y) << i;
    EXPECT_EQ(st.rows[i].horizon_toward_sun.xyz.Y, ref.horizon_toward_sun.xyz.Y) << i;
    EXPECT_EQ(st.rows[i].sun_transmitted.Y, ref.sun_transmitted.Y) << i;
  }
  // Physics: the zenith brightens and the direct sun strengthens as the sun rises; the
  // sun below the horizon sends no direct light.
  for (std::size_t i = 1; i < st.rows.size(); ++i) {
    EXPECT_GT(st.rows[i].zenith.xyz.Y, st.rows[i - 1].zenith.xyz.Y) << st.elevations_deg[i];
    if (st.elevations_deg[i - 1] > 0) {
      EXPECT_GT(st.rows[i].sun_transmitted.Y, st.rows[i - 1].sun_transmitted.Y);
    }
  }
  EXPECT_EQ(st.rows[0].sun_transmitted.Y, 0.0);
  // The varied elevation is recorded as a column, the fixed azimuth as a value.
  EXPECT_NE(prov_value(st.provenance, "sun_elevation_deg").find("varied"), std::string::npos);
  EXPECT_EQ(prov_value(st.provenance, "sun_azimuth_deg"), "150");
}

TEST(Studies, SunElevationStudyWritesItsRows) {
  const auto s = test::small_scene();
  studies::ElevationStudyOptions o;
  o.from_deg = 0;
  o.to_deg = 10;
  o.step_deg = 5;
  o.sky = test::coarse_settings();
  const auto st = studies::sun_elevation_study(s, o);
  const fs::path d = scratch("elevation");
  const auto files = studies::write_elevation_study(st, d);
  ASSERT_EQ(files.size(), 5u);
  for (const auto& f : files) EXPECT_TRUE(fs::exists(f)) << f;
  const auto csv = io::read_csv(files[0]);
  ASSERT_EQ(csv.rows.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(csv.number(i, csv.column("sun_elevation_deg")), st.elevations_deg[i]);
    EXPECT_EQ(csv.number(i, csv.column("zenith_luminance_cd_m2")), st.rows[i].zenith.xyz.Y);
  }
}

TEST(Studies, SunElevationStudyRefusesBadRanges) {
  const auto s = test::small_scene();
  studies::ElevationStudyOptions o;
  o.step_deg = 0;
  EXPECT_THROW(studies::sun_elevation_study(s, o), InputError);
  o.step_deg = 1;
  o.from_deg = 10;
  o.to_deg = 5;
  EXPECT_THROW(studies::sun_elevation_study(s, o), InputError);
  o.to_deg = 95;
  EXPECT_THROW(studies::sun_elevation_study(s, o), InputError);
}

// ------------------------------------------------------------------ day study
TEST(Studies, DayStudyFollowsTheSunFromSpa) {
  const auto s = test::small_scene();
  studies::DayStudyOptions o;
  o.latitude_deg = 48.8566;
  o.longitude_deg = 2.3522;
  o.height_m = 35;
  o.date = "2026-06-21";
  o.step_s = 4 * 3600.0;
  o.frame_width = 8;
  o.frame_height = 4;
  o.sky = test::coarse_settings();
  std::vector<studies::DayFrame> frames;
  const auto st = studies::day_study(s, o, [&](studies::DayFrame&& f) { frames.push_back(std::move(f)); });
  // 00:00, 04:00, ..., 20:00 UTC: the times of [00:00, 24:00) of the date.
  ASSERT_EQ(st.rows.size(), 6u);
  ASSERT_EQ(frames.size(), st.rows.size());
  const double jd0 = atmo::parse_iso8601("2026-06-21T00:00:00Z").jd_utc;
  const Direct d(s, o.sky);
  std::size_t noon = 0, night = 0;
  for (std::size_t i = 0; i < st.rows.size(); ++i) {
    const auto& r = st.rows[i];
    EXPECT_NEAR(r.hours, 4.0 * i, 1e-6);
    // The row's sun against NREL SPA called here at the row's time.
    atmo::SunQuery q;
    q.jd_utc = jd0 + r.hours / 24.0;
    q.latitude_deg = o.latitude_deg;
    q.longitude_deg = o.longitude_deg;
    q.height_m = o.height_m;
    q.rise_transit_set = false;
    const auto spa = atmo::sun_position(q);
    EXPECT_NEAR(r.sun.elevation_deg, spa.elevation_deg, 1e-6) << r.time_utc;
    EXPECT_NEAR(r.sun.azimuth_deg, spa.azimuth_deg, 1e-6) << r.time_utc;
    EXPECT_EQ(atmo::parse_iso8601(r.time_utc).jd_utc, atmo::parse_iso8601(frames[i].time_utc).jd_utc);
    // The summary is the sky at the day's Earth-Sun distance (tables for 1 AU, scaled).
    const auto ref = atmo::summarize_sky(d.sky, 35.0, atmo::enu_direction_from_zenith(90.0 - spa.elevation_deg, spa.azimuth_deg),
                                         1.0, spa.earth_sun_distance_au);
    EXPECT_NEAR(r.summary.zenith.xyz.Y, ref.zenith.xyz.Y, 1e-9 * ref.zenith.xyz.Y + 1e-300) << r.time_utc;
    if (r.sun.elevation_deg > st.rows[noon].sun.elevation_deg) noon = i;
    if (r.sun.elevation_deg < st.rows[night].sun.elevation_deg) night = i;
  }
  // Midsummer in Paris: the sun is high at 12:00 UTC and below the horizon at 00:00.
  EXPECT_EQ(st.rows[noon].time_utc.substr(11, 5), "12:00");
  EXPECT_GT(st.rows[noon].sun.elevation_deg, 60.0);
  EXPECT_LT(st.rows[0].sun.elevation_deg, 0.0);
  EXPECT_GT(st.rows[noon].summary.zenith.xyz.Y, 100.0 * st.rows[night].summary.zenith.xyz.Y);
  // Frames: the sky's image, radiance scaled to the day's distance (1.016 AU in June).
  EXPECT_EQ(frames[noon].image.width, 8);
  EXPECT_EQ(frames[noon].image.height, 4);
  EXPECT_GT(frames[noon].sun.distance_au, 1.01);
}

// A step that divides the day gives 24 h / step rows, the last one step before the
// next midnight; never the next day's 00:00, whose frame would carry the same file
// name (sky_0000Z.exr) as this day's first.
TEST(Studies, DayStudyStopsBeforeTheNextMidnight) {
  const auto s = test::small_scene();
  for (double step_h : {3.0, 1.0, 0.25}) {
    studies::DayStudyOptions o;
    o.latitude_deg = 48.8566;
    o.longitude_deg = 2.3522;
    o.date = "2026-03-20";
    o.step_s = step_h * 3600.0;
    o.frames = false;
    o.sky = test::coarse_settings();
    const auto st = studies::day_study(s, o, {});
    const std::size_t n = static_cast<std::size_t>(std::lround(24.0 / step_h));
    ASSERT_EQ(st.rows.size(), n) << "step " << step_h << " h";
    EXPECT_EQ(st.rows.front().time_utc.substr(0, 10), "2026-03-20");
    EXPECT_EQ(st.rows.back().time_utc.substr(0, 10), "2026-03-20") << st.rows.back().time_utc;
    EXPECT_NEAR(st.rows.back().hours, 24.0 - step_h, 1e-6);
  }
}

TEST(Studies, DayStudyWritesCsvAndFrames) {
  const auto s = test::small_scene();
  studies::DayStudyOptions o;
  o.latitude_deg = -33.9;
  o.longitude_deg = 151.2;
  o.date = "2026-12-21";
  o.step_s = 8 * 3600.0;
  o.frame_width = 8;
  o.frame_height = 4;
  o.sky = test::coarse_settings();
  const fs::path d = scratch("day");
  std::vector<fs::path> frames;
  const auto st = studies::day_study(s, o, [&](studies::DayFrame&& f) { frames.push_back(studies::write_day_frame(f, d)); });
  const auto files = studies::write_day_study(st, d);
  ASSERT_EQ(frames.size(), 3u);  // 00:00, 08:00, 16:00
  EXPECT_EQ(frames[1], d / "frames" / "sky_0800Z.exr");
  for (const auto& f : frames) EXPECT_TRUE(fs::exists(f)) << f;
  const auto csv = io::read_csv(files.at(0));
  ASSERT_EQ(csv.rows.size(), st.rows.size());
  for (std::size_t i = 0; i < st.rows.size(); ++i)
    EXPECT_EQ(csv.number(i, csv.column("sun_elevation_deg")), st.rows[i].sun.elevation_deg);
}

// ------------------------------------------------------------------ sweep point
TEST(Studies, SweepPointIsTheSkySummaryOfTheScenesSun) {
  const auto s = test::small_scene(test::kParisObserver);
  const auto k = test::coarse_settings();
  const auto out = studies::sweep_point(s, k);
  auto value = [&](const std::string& key) {
    for (const auto& [n, v] : out)
      if (n == key) return v;
    ADD_FAILURE() << key;
    return std::nan("");
  };
  atmo::SunQuery q;
  q.jd_utc = atmo::parse_iso8601(s.observer->time_utc).jd_utc;
  q.latitude_deg = s.observer->latitude_deg;
  q.longitude_deg = s.observer->longitude_deg;
  q.height_m = s.observer->height_m;
  q.rise_transit_set = false;
  const auto spa = atmo::sun_position(q);
  EXPECT_NEAR(value("sun_elevation_deg"), spa.elevation_deg, 1e-9);
  EXPECT_NEAR(value("sun_azimuth_deg"), spa.azimuth_deg, 1e-9);
  const Direct d(s, k, spa.earth_sun_distance_au);
  const auto ref = atmo::summarize_sky(d.sky, 35.0, atmo::enu_direction_from_zenith(90.0 - spa.elevation_deg, spa.azimuth_deg));
  EXPECT_EQ(value("zenith_luminance_cd_m2"), ref.zenith.xyz.Y);
  EXPECT_EQ(value("horizon_away_luminance_cd_m2"), ref.horizon_away.xyz.Y);
  EXPECT_EQ(value("sun_direct_normal_illuminance_lux"), ref.sun_transmitted.Y);
  EXPECT_GE(value("table_build_time_s"), 0.0);
  // Every summary column, in the order the sun-elevation study writes them.
  ASSERT_EQ(out.size(), 2 + studies::sky_summary_columns().size() + 1);
  for (std::size_t i = 0; i < studies::sky_summary_columns().size(); ++i)
    EXPECT_EQ(out[2 + i].first, studies::sky_summary_columns()[i]);
  // A scene that places no sun has no sweep point.
  auto no_sun = s;
  no_sun.observer.reset();
  EXPECT_THROW(studies::sweep_point(no_sun, k), InputError);
}

// ------------------------------------------------------------------ converge sky
TEST(Studies, ConvergeSkyErrorFallsWithFinerSettings) {
  const auto s = test::small_scene();
  studies::ConvergeSkyOptions o;
  o.quick = true;
  o.threads = 2;
  const auto c = studies::converge_sky(s, o);
  // Three settings, each with a day and a twilight row.
  ASSERT_EQ(c.rows.size(), 6u);
  for (const auto& r : c.rows) {
    EXPECT_TRUE(std::isfinite(r.error_max) && r.error_max >= 0) << r.setting;
    EXPECT_LE(r.error_rms, r.error_max) << r.setting;
    EXPECT_GT(r.time_s, 0.0);
    ASSERT_EQ(r.extras.size(), c.spec.extra_columns.size());
  }
  // Rows 0/1: 16 shells, 4 segments, 1 sample; rows 4/5: 32 shells, 16 segments, 2 samples.
  EXPECT_EQ(c.rows[0].extras[0], 16);
  EXPECT_EQ(c.rows[4].extras[1], 16);
  EXPECT_LT(c.rows[4].error_max, c.rows[0].error_max);  // day
  EXPECT_LT(c.rows[5].error_max, c.rows[1].error_max);  // twilight
  // The toolkit's default (32 shells, 16 segments, 2 samples) is within 1 % by day
  // (docs/sky.md reports its error against the same reference).
  EXPECT_LT(c.rows[4].error_max, 1e-2);
}

// ---------------------------------------------------------------- sky -> SH
TEST(Studies, SkyShMeanIsTheSkysMeanRadiance) {
  // c_00 = Y_00 * integral of L over the sphere (Y_00 = 1 / (2 sqrt(pi))): the
  // integral computed here by the midpoint rule in cos(theta) and phi, independently
  // of the Gauss-Legendre grid of project_sky_sh.
  const auto s = test::small_scene();
  const auto k = test::coarse_settings();
  const auto sun = studies::sun_of_scene(s);
  const auto m = studies::make_sky_model(s, k.sky(s), sun.distance_au);
  const auto sh = studies::project_sky_sh(*m, sun, 3);
  ASSERT_EQ(sh.coeffs[1].size(), 9u);
  const atmo::SpectralToXyz cmf(m->atmosphere->wavelengths_nm());
  const int nu = 200, nphi = 100;
  double sum = 0;
  for (int i = 0; i < nu; ++i) {
    const double u = -1.0 + (i + 0.5) * 2.0 / nu, r = std::sqrt(1 - u * u);
    for (int j = 0; j < nphi; ++j) {
      const double ph = (j + 0.5) * 2 * std::numbers::pi / nphi;
      sum += atmo::sky_colour(*m->sky, cmf, 0.0, glm::dvec3(r * std::cos(ph), r * std::sin(ph), u), sun.direction()).srgb.g;
    }
  }
  const double integral = sum * (2.0 / nu) * (2 * std::numbers::pi / nphi);
  const double y00 = 0.5 / std::sqrt(std::numbers::pi);
  EXPECT_NEAR(sh.coeffs[1][0], y00 * integral, 2e-3 * y00 * integral);
}

TEST(Studies, SkyShBandEnergyDoesNotChangeWhenTheSunTurnsAboutTheZenith) {
  // Turning the sun by 90 deg in azimuth rotates the sky about z; the energy in each
  // band is invariant under rotation (and the grid's phi spacing divides 90 deg).
  const auto s = test::small_scene();
  const auto k = test::coarse_settings();
  auto sun = studies::sun_of_scene(s);
  const auto m = studies::make_sky_model(s, k.sky(s), sun.distance_au);
  const auto a = studies::project_sky_sh(*m, sun, 4);
  sun.azimuth_deg += 90;
  const auto b = studies::project_sky_sh(*m, sun, 4);
  for (std::size_t c = 0; c < 3; ++c) {
    for (int l = 0; l < 4; ++l) {
      double ea = 0, eb = 0;
      for (int mm = -l; mm <= l; ++mm) {
        const auto i = static_cast<std::size_t>(l * (l + 1) + mm);
        ea += a.coeffs[c][i] * a.coeffs[c][i];
        eb += b.coeffs[c][i] * b.coeffs[c][i];
      }
      EXPECT_NEAR(ea, eb, 1e-9 * ea) << "channel " << c << " band " << l;
    }
    // m = 0 terms depend on the polar angle only.
    for (int l = 0; l < 4; ++l) {
      const auto i = static_cast<std::size_t>(l * (l + 1));
      EXPECT_NEAR(a.coeffs[c][i], b.coeffs[c][i], 1e-9 * std::fabs(a.coeffs[c][0]));
    }
  }
  // The sun's side is brighter: the band-limited sky (bands 0-1) on the horizon toward
  // the sun exceeds the one away from it (basis evaluated by libsh).
  const glm::dvec3 toward(std::sin(150 * std::numbers::pi / 180), std::cos(150 * std::numbers::pi / 180), 0);
  auto low = [&](const glm::dvec3& v) {
    const auto y = sh::evaluate(2, v);
    double f = 0;
    for (std::size_t i = 0; i < 4; ++i) f += a.coeffs[1][i] * y[i];
    return f;
  };
  EXPECT_GT(low(toward), low(-toward));
  EXPECT_THROW(studies::project_sky_sh(*m, sun, 0), InputError);
}

TEST(Studies, SkyShWriterWritesCoefficientsAndBands) {
  const auto s = test::small_scene();
  const auto k = test::coarse_settings();
  const auto sun = studies::sun_of_scene(s);
  const auto m = studies::make_sky_model(s, k.sky(s), sun.distance_au);
  const auto sh = studies::project_sky_sh(*m, sun, 3);
  const fs::path d = scratch("sh");
  const auto files = studies::write_sky_sh(sh, d / "sky.csv");
  ASSERT_EQ(files, (std::vector<fs::path>{d / "sky.csv", d / "sky_bands.csv", d / "sky_bands.png"}));
  const auto csv = io::read_csv(files[0]);
  ASSERT_EQ(csv.rows.size(), 9u);
  for (std::size_t i = 0; i < 9; ++i) EXPECT_EQ(csv.number(i, csv.column("g")), sh.coeffs[1][i]);
  const auto bands = io::read_csv(files[1]);
  ASSERT_EQ(bands.rows.size(), 3u);
  EXPECT_NEAR(bands.number(0, bands.column("energy_g")), sh.coeffs[1][0] * sh.coeffs[1][0], 1e-12 * sh.coeffs[1][0] * sh.coeffs[1][0]);
  EXPECT_NEAR(bands.number(2, bands.column("cumulative_fraction_g")), 1.0, 1e-12);
}
