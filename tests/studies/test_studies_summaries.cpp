// atmosh::studies (and atmosh::gi's driver, atmosh::io's image writer): the option checks
// and JSON summaries that front ends share, against closed forms, independent
// computations in the test, and the lower-level library calls they wrap.
//
// Henyey-Greenstein phase function (Henyey & Greenstein, ApJ 93, 70 (1941)):
//   p(mu) = (1 - g^2) / (4 pi (1 + g^2 - 2 g mu)^(3/2)), mean cosine g;
// Rayleigh with depolarisation 0 (Chandrasekhar 1960): p(mu) = 3 (1 + mu^2) / (16 pi).
// The real SH Y_00 = 1 / (2 sqrt(pi)): a uniform radiance L has the coefficient
// 2 sqrt(pi) L; the Gaunt coefficient of (1, 0), (1, 0), (0, 0) is the integral of
// Y_10^2 Y_00 = Y_00 = 1 / (2 sqrt(pi)); Y_10(z) = sqrt(3 / (4 pi)) z. The unit vector towards the sun has ENU up component sin(elevation).
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/gi/driver.hpp"
#include "atmosh/io/rgb_image.hpp"
#include "atmosh/studies/studies_prt.hpp"
#include "atmosh/studies/studies_sh.hpp"
#include "atmosh/studies/studies_sun.hpp"
#include "atmosh/studies/summaries.hpp"
#include "studies_test_scene.hpp"

namespace {

using namespace atmosh;
constexpr double kPi = std::numbers::pi;

// The InputError's message of f(), or "" when it throws none.
template <class F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(StudiesSummaries, SkySettingsCheckNamesTheOptions) {
  studies::SkySettings k = test::coarse_settings();
  EXPECT_EQ(k.checked().shells, 16);
  k.shells = 3;
  EXPECT_EQ(input_error_of([&] { k.checked(); }), "--shells 3 is outside [4, 4096]");
  k = test::coarse_settings();
  k.segments = 16;  // at most shells - 1
  EXPECT_NE(input_error_of([&] { k.checked(); }).find("--segments 16 is outside [1, 15]"), std::string::npos);
  k = test::coarse_settings();
  k.max_piece_tau = 0;
  EXPECT_EQ(input_error_of([&] { k.checked(); }), "--max-piece-tau 0 must be finite and > 0");
  k = test::coarse_settings();
  k.orders = 65;
  EXPECT_EQ(input_error_of([&] { k.checked(); }), "--orders 65 is outside [1, 64]");
  k = test::coarse_settings();
  k.threads = -1;
  EXPECT_NE(input_error_of([&] { k.checked(); }).find("--threads"), std::string::npos);
  k.threads = 0;  // resolved to the CPUs this process may use
  EXPECT_GE(k.checked().threads, 1);
}

TEST(StudiesSummaries, SweepSettingsNameEveryOverrideOrTheScene) {
  studies::SkySettings k = test::coarse_settings();
  const auto plain = k.sweep_settings();
  ASSERT_EQ(plain.size(), 7u);
  EXPECT_EQ(plain[0], (std::pair<std::string, std::string>{"lut_shells", "16"}));
  EXPECT_EQ(plain[3].second, "0.5") << "max_piece_optical_depth in the shortest round-trip form";
  for (std::size_t i = 4; i < 7; ++i) EXPECT_EQ(plain[i].second, "scene") << plain[i].first;
  k.sun_model = atmo::SunModel::Point;
  k.scattering = atmo::ScatteringMethod::Orders;
  k.orders = 5;
  const auto s = k.sweep_settings();
  EXPECT_EQ(s[4].second, "point");
  EXPECT_EQ(s[5].second, "orders");
  EXPECT_EQ(s[6].second, "5");
}

TEST(StudiesSummaries, PlaceSunTakesOneWayAndChecksItsRanges) {
  const auto scene = test::small_scene();
  studies::SunRequest r;
  const auto from_scene = studies::place_sun(scene, r);  // neither: the scene's [sun]
  EXPECT_EQ(from_scene.elevation_deg, 20.0);
  EXPECT_EQ(from_scene.azimuth_deg, 150.0);
  r.elevation_deg = 10.0;
  r.azimuth_deg = 90.0;
  const auto given = studies::place_sun(scene, r);
  EXPECT_NEAR(given.direction().z, std::sin(10.0 * kPi / 180), 1e-15);
  EXPECT_NEAR(given.direction().x, std::cos(10.0 * kPi / 180), 1e-15) << "azimuth 90 deg: east";
  r.lat_deg = 48.0;
  EXPECT_EQ(input_error_of([&] { studies::place_sun(scene, r); }),
            "give either --lat/--lon/--time or --sun-elevation, not both");
  r.elevation_deg.reset();
  EXPECT_EQ(input_error_of([&] { studies::place_sun(scene, r); }), "--lat, --lon and --time go together");
  r.lon_deg = 2.0;
  r.time_utc = "2026-06-21T12:00:00Z";
  const auto spa = studies::place_sun(scene, r);
  const auto direct = studies::sun_from_place(48.0, 2.0, 0.0, "2026-06-21T12:00:00Z");
  EXPECT_EQ(spa.elevation_deg, direct.elevation_deg);
  r.lat_deg = 91.0;
  EXPECT_EQ(input_error_of([&] { studies::place_sun(scene, r); }), "--lat: 91 is out of range [-90, 90]");
}

TEST(StudiesSummaries, SkyJsonReportsTheSkyOfItsModel) {
  const auto scene = test::small_scene();
  const auto k = test::coarse_settings();
  const auto sun = studies::sun_of_scene(scene);
  const auto model = studies::make_sky_model(scene, k.sky(scene), sun.distance_au);
  std::string used;
  const auto img = studies::render_sky_on("cpu", *model->sky, atmo::SkyProjection::Equirect, 16, 8, 0.0,
                                          sun.direction(), false, 2, used);
  const auto j = studies::sky_json(*model, sun, img, 0.5, used, {"a.exr", "", ""});
  // An integrator of its own, built here, gives the same zenith.
  const atmo::Atmosphere atm(scene.atmosphere);
  atmo::SkyOptions o = k.sky(scene);
  o.scattering = scene.scattering;
  const atmo::SkyIntegrator sky(atm, atmo::solar_spectrum_for_bins(scene.atmosphere.spectrum), o);
  const auto sm = atmo::summarize_sky(sky, 0.0, sun.direction());
  EXPECT_EQ(j["zenith_luminance_cd_m2"].get<double>(), sm.zenith.xyz.Y);
  EXPECT_GT(sm.zenith.xyz.Y, 0.0);
  EXPECT_EQ(j["exr"], "a.exr");
  EXPECT_TRUE(j["png"].is_null());
  EXPECT_FALSE(j.contains("netcdf"));
  EXPECT_EQ(j["device"], "cpu");
  EXPECT_EQ(j["scattering"], "single");
  EXPECT_EQ(j["wavelengths_nm"].size(), 4u);
  EXPECT_DOUBLE_EQ(j["rays_per_s"].get<double>(), img.rays / img.seconds);
  // The sun's angular radius at 1 AU: 6.957e8 m / 1.495978707e11 m (IAU 2015 B3 nominal
  // solar radius; IAU 2012 B2 au), in degrees.
  EXPECT_NEAR(j["sun_angular_radius_deg"].get<double>(), std::asin(6.957e8 / 1.495978707e11) * 180 / kPi, 1e-4);
  EXPECT_GT(j["irradiance_diffuse_lux"].get<double>(), 0.0);
}

TEST(StudiesSummaries, SunQueryChecksAndSunJsonPointsAtTheSun) {
  studies::SunPlaceRequest r;
  EXPECT_EQ(input_error_of([&] { studies::sun_query(r); }), "--lat is required");
  r.lat_deg = 48.8566;
  EXPECT_EQ(input_error_of([&] { studies::sun_query(r); }), "--lon is required");
  r.lon_deg = 2.3522;
  r.algorithm = "nope";
  EXPECT_FALSE(input_error_of([&] { studies::sun_query(r); }).empty());
  r.algorithm = "spa";
  r.pressure_hpa = -1;
  EXPECT_EQ(input_error_of([&] { studies::sun_query(r); }), "--pressure: -1 is out of range [0, 5000]");
  r.pressure_hpa = 1013.25;
  atmo::SunQuery q = studies::sun_query(r);
  q.jd_utc = atmo::parse_iso8601("2026-06-21T12:00:00Z").jd_utc;
  const atmo::SunPosition s = atmo::sun_position(q);
  const auto j = studies::sun_position_json(q, s);
  EXPECT_EQ(j["time_utc"], "2026-06-21T12:00:00.000Z");
  const auto d = j["sun_direction_enu"];
  EXPECT_NEAR(d[2].get<double>(), std::sin(s.elevation_deg * kPi / 180), 1e-12);
  EXPECT_NEAR(std::hypot(d[0].get<double>(), d[1].get<double>(), d[2].get<double>()), 1.0, 1e-12);
  EXPECT_TRUE(j["polar"].is_null());
  EXPECT_TRUE(j["sunrise_utc"].is_string());
}

TEST(StudiesSummaries, PhaseSpecMatchesTheClosedFormsAndRefusesUnusedParameters) {
  studies::PhaseRequest r;
  r.model = "hg";
  EXPECT_EQ(input_error_of([&] { studies::phase_spec(r); }), "--g: required for --model hg");
  r.g_given = true;
  r.g = 0.6;
  const atmo::PhaseFunction hg(studies::phase_spec(r), "hg");
  const double mu = 0.3, g = 0.6;
  EXPECT_NEAR(hg.value(mu), (1 - g * g) / (4 * kPi * std::pow(1 + g * g - 2 * g * mu, 1.5)), 1e-12);
  const auto j = studies::phase_json(hg, "hg", mu);
  EXPECT_NEAR(j["mean_cosine"].get<double>(), g, 1e-6);
  r.weight_given = true;
  EXPECT_EQ(input_error_of([&] { studies::phase_spec(r); }), "--weight: not a parameter of --model hg");
  studies::PhaseRequest ray;
  ray.model = "rayleigh";
  ray.depolarization = 0;
  const atmo::PhaseFunction p(studies::phase_spec(ray), "r");
  EXPECT_NEAR(p.value(0.5), 3 * (1 + 0.25) / (16 * kPi), 1e-12);
  ray.depolarization = 0.5;
  EXPECT_EQ(input_error_of([&] { studies::phase_spec(ray); }), "--depolarization = 0.5: must be in [0, 0.5)");
  ray.model = "mie";
  EXPECT_EQ(input_error_of([&] { studies::phase_spec(ray); }),
            "--model: 'mie' is not rayleigh, hg, cornette-shanks or double-hg");
}

TEST(StudiesSummaries, OpticalDepthAtIsTheQueryAtOneWavelength) {
  const atmo::AtmosphereSpec spec = atmo::preset("earth-graphics");
  const studies::OpticalDepthQuery q{1000.0, 60.0, false, 40, 64};
  const auto a = studies::optical_depth_at(spec, 550.0, q);
  atmo::AtmosphereSpec one = spec;
  one.spectrum.wavelengths_nm = {550.0};
  const auto b = studies::optical_depth_query(atmo::Atmosphere(one), q);
  EXPECT_EQ(a.total, b.total);
  const auto j = studies::optical_depth_json(a, "reference", 550.0, spec.name);
  EXPECT_DOUBLE_EQ(j["transmittance"].get<double>(), std::exp(-a.total));
  EXPECT_EQ(j["hits_ground"], false);
  EXPECT_EQ(input_error_of([&] { studies::optical_depth_at(spec, 300.0, q); }),
            "--wavelength 300: outside the ozone table (360-830 nm)");
  EXPECT_EQ(input_error_of([&] { studies::optical_depth_at(spec, 550.0, {-10.0, 60.0, false, 40, 64}); }),
            "--altitude -10: below the ground");
  EXPECT_EQ(input_error_of([&] { studies::optical_depth_at(spec, 550.0, {0.0, 181.0, false, 40, 64}); }),
            "--zenith: 181 is out of range [0, 180]");
}

TEST(StudiesSummaries, RtRequestsCheckThenRunTheDrivers) {
  studies::RtSlabRequest r;
  r.tau = 0.5;
  r.omega = 0.8;
  r.mu0 = 0.8;
  r.mu = 0.5;
  r.phi_deg = 30;
  r.orders = 1;
  r.run.paths = 4000;
  r.run.seed = 3;
  r.run.threads = 1;
  const atmo::SlabResult a = studies::rt_slab(r);
  atmo::SlabSpec s;
  s.tau = 0.5;
  s.omega = 0.8;
  atmo::RtOptions run = r.run;
  run.max_orders = 1;
  const atmo::SlabResult b = studies::rt_slab(s, 0.8, 0.5, 30.0, run);
  EXPECT_EQ(a.reflection, b.reflection);
  EXPECT_EQ(a.transmission, b.transmission);
  const auto j = studies::rt_slab_json(r, a);
  EXPECT_EQ(j["orders"], 1);
  EXPECT_EQ(j["threads"], 1);
  EXPECT_EQ(j["reflection"].get<double>(), a.reflection);
  r.phase = "mie";
  EXPECT_EQ(input_error_of([&] { studies::rt_slab(r); }), "--phase: 'mie' is not isotropic, hg or rayleigh");
  r.phase = "hg";
  r.run.paths = 0;
  EXPECT_EQ(input_error_of([&] { studies::rt_slab(r); }), "--paths 0: must be in [1, 2^40]");
  studies::RtSkyRequest k;
  k.sun_depth = "fast";
  EXPECT_EQ(input_error_of([&] { studies::rt_sky_view(atmo::preset("test-planet"), k); }),
            "--sun-depth: 'fast' is not table or exact");
}

TEST(StudiesSummaries, PrtBakeOptionsCheckEveryOptionAndTheOutput) {
  studies::PrtBakeRequest r;
  r.output = "t.ply";
  const prt::BakeOptions bo = studies::prt_bake_options(r);
  EXPECT_EQ(bo.strata, 45);  // 2025 = 45 x 45
  EXPECT_GE(bo.threads, 1);
  r.samples = 2024;
  EXPECT_NE(input_error_of([&] { studies::prt_bake_options(r); }).find("--samples: 2024 is not a square count"),
            std::string::npos);
  r.samples = 64;
  r.output = "t.exr";
  r.mode = "interreflected";
  EXPECT_EQ(input_error_of([&] { studies::prt_bake_options(r); }),
            "--mode interreflected: per-pixel transfer is unshadowed or shadowed");
  r.mode = "shadowed";
  r.output = "t.txt";
  EXPECT_EQ(input_error_of([&] { studies::prt_bake_options(r); }),
            "-o: 't.txt' must end in .ply (per-vertex) or .exr (per-pixel)");
  EXPECT_EQ(input_error_of([&] { studies::prt_input_mesh("", "", 8); }),
            "no mesh: give MESH (.obj, .ply) or --scene-builtin NAME");
}

TEST(StudiesSummaries, PercentileExposureAndTheRgbImageWriter) {
  std::vector<float> v;
  for (int i = 100; i >= 1; --i) v.push_back(static_cast<float>(i));
  // 0.99 (n - 1) = 98.01: the 99th of the sorted values, 99.
  EXPECT_DOUBLE_EQ(io::percentile_exposure(v), 1.0 / 99.0);
  EXPECT_EQ(io::percentile_exposure({}), 1.0);
  EXPECT_EQ(io::percentile_exposure({0.0f, 0.0f}), 1.0);
  const auto dir = std::filesystem::temp_directory_path() / ("atmosh_rgb_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  io::ExrImage ex(2, 1, {"R", "G", "B", "extra"});
  for (auto& c : ex.data) c = {0.5f, 1.0f};
  const auto files = io::write_rgb_image(dir / "a.exr", ex, dir / "a.png", 1.0, "rule", io::Provenance::current());
  ASSERT_EQ(files.size(), 3u);
  for (const auto& f : files) EXPECT_TRUE(std::filesystem::exists(f)) << f;
  EXPECT_EQ(io::read_exr(dir / "a.exr").channels.size(), 4u);
  EXPECT_EQ(io::write_rgb_image(dir / "b.exr", ex, "", 1.0, "rule", io::Provenance::current()).size(), 1u);
  std::filesystem::remove_all(dir);
}

TEST(StudiesSummaries, GiDriverDispatchesToTheRenderersAndLightsTheScene) {
  gi::SceneRequest req;
  req.builtin = "sphere-on-plane";
  req.resolution = 6;
  req.sky_radiance = "0.5,1,2";
  const gi::Scene s = gi::scene_from_request(req);
  ASSERT_EQ(s.env_bands, 1);
  EXPECT_NEAR(s.env_sh[2][0], 2.0 * 2 * std::sqrt(kPi), 1e-12);  // Y_00 = 1 / (2 sqrt(pi))
  gi::RenderOptions m;
  m.samples = 2;
  m.threads = 1;
  gi::check_render_request(req, m);
  const gi::MethodImage a = gi::render_request(s, 8, 6, m);
  gi::TraceOptions t;
  t.samples = 2;
  t.threads = 1;
  const gi::RadianceImage b = gi::render(s, s.camera, 8, 6, t);
  EXPECT_EQ(a.image.mean[1], b.mean[1]) << "path: the path tracer, bit for bit";
  const auto j = gi::render_json(s, m, a, "x.exr");
  EXPECT_EQ(j["width"], 8);
  EXPECT_FALSE(j.contains("grid"));
  m.method = "probes";
  m.grid = 2;
  m.cube_size = 2;
  m.pixel_samples = 1;
  const gi::MethodImage p = gi::render_request(s, 8, 6, m);
  EXPECT_GT(p.probe_seconds, 0.0);
  EXPECT_EQ(gi::render_json(s, m, p, "x.exr")["grid"], 2);
  m.method = "splat";
  EXPECT_EQ(input_error_of([&] { gi::check_render_request(req, m); }),
            "--method: unknown method 'splat' (path, probes, radiosity, lpv)");
  m.method = "path";
  m.samples = 1;
  EXPECT_EQ(input_error_of([&] { gi::check_render_request(req, m); }), "--samples: must be in 2..10000000, got 1");
  req.light = "moon:1,2";
  EXPECT_EQ(input_error_of([&] { gi::scene_from_request(req); }), "--light: 'moon:1,2' is not sun:AZ,EL (degrees)");
}

TEST(StudiesSummaries, GiConvergeHasARowPerSettingAndWritesItsImages) {
  gi::SceneRequest req;
  req.builtin = "cornell-box";
  const gi::Scene s = gi::scene_from_request(req);
  gi::ConvergeOptions c;
  c.method.samples = 2;
  c.method.threads = 1;
  c.method.cube_size = 2;
  c.method.pixel_samples = 1;
  c.bands = {1, 2};
  c.grids = {2};
  c.path_samples = {2};
  c.reference_samples = 4;
  c.study.radiosity_grids.clear();  // probes and the path tracer only: radiosity and lpv have their own tests
  c.study.lpv_grids.clear();
  const auto dir = std::filesystem::temp_directory_path() / ("atmosh_giconv_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::vector<std::string> steps;
  const auto st = gi::converge_methods(s, 6, 6, c, dir, [&](const std::string& name, const auto& work) {
    steps.push_back(name);
    work({});
  });
  ASSERT_EQ(st.rows.size(), 1u + 2 * 2);  // path spp=2; probes and probes-visibility at bands 1, 2
  EXPECT_EQ(st.rows[0].method, "path");
  EXPECT_EQ(st.rows[4].setting, "bands=2 grid=2");
  for (const auto& r : st.rows) EXPECT_TRUE(std::isfinite(r.error_rms)) << r.setting;
  EXPECT_EQ(steps, (std::vector<std::string>{"gi converge: reference", "gi converge: probes"}));
  for (const char* f : {"reference.exr", "reference.png", "probes_b1_g2.exr", "probes-visibility_b2_g2.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  std::filesystem::remove_all(dir);
}

TEST(StudiesSummaries, ShEvalAndGauntAgainstTheClosedForms) {
  const auto j = studies::gaunt_json({1, 0, 1, 0, 0, 0});
  EXPECT_NEAR(j["value"].get<double>(), 1 / (2 * std::sqrt(kPi)), 1e-14);
  EXPECT_EQ(input_error_of([] { studies::gaunt_json({1, 2, 1, 0, 0, 0}); }), "M1 must satisfy |M1| <= L1, got 2");
  const glm::dvec3 u = studies::sh_eval_direction("0,0,2");
  EXPECT_EQ(u, glm::dvec3(0, 0, 1));
  EXPECT_EQ(input_error_of([] { studies::sh_eval_direction("0,0,0"); }), "--dir: '0,0,0' has zero length");
  io::ShCoefficients c{2, {"g"}, {{0.0, 0.0, 1.0, 0.0}}, ""};  // Y_10 alone (index l(l+1)+m = 2)
  const auto e = studies::sh_eval_json(c, u);
  EXPECT_NEAR(e["values"]["g"].get<double>(), std::sqrt(3 / (4 * kPi)), 1e-14);
  EXPECT_EQ(e["bands"], 2);
}

}  // namespace
