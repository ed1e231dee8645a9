// The scene runner at the library level (atmosh/studies/scene_run.hpp): it writes
// the files the table of output kinds lists, shares one sky between outputs, agrees
// with `plan` on what it builds, and refuses before any work.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/sun_position.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/scene/outputs.hpp"
#include "atmosh/studies/scene_run.hpp"
#include "atmosh/studies/sky_studies.hpp"
#include "studies_test_scene.hpp"

using namespace atmosh;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("atmosh_studies_scene_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

scene::Output output(const std::string& kind, const std::string& file) {
  scene::Output o;
  o.kind = kind;
  o.file = file;
  o.size = {16, 8};
  return o;
}

bool plan_needs(const scene::Scene& s, const std::string& pass) {
  for (const auto& p : scene::plan(s))
    if (p.name == pass) return p.needed;
  if (pass == "sun-position:spa")  // planned as "sun-position" (skipped) when SPA is not needed
    for (const auto& p : scene::plan(s))
      if (p.name == "sun-position") return false;
  ADD_FAILURE() << "no pass " << pass;
  return false;
}

studies::SceneRunOptions quick_options() {
  studies::SceneRunOptions o;
  o.quick = true;
  return o;
}

}  // namespace

TEST(Studies, EveryOutputKindHasOneRunner) {
  std::set<std::string> kinds;
  for (const auto& k : scene::output_kinds()) kinds.insert(std::string(k.name));
  std::set<std::string> here;
  for (const auto& [name, run] : studies::scene_output_runners()) {
    EXPECT_TRUE(kinds.count(std::string(name))) << name << " has a runner but is not in scene::output_kinds()";
    EXPECT_TRUE(static_cast<bool>(run)) << name;
    here.insert(std::string(name));
  }
  for (const auto& k : kinds) EXPECT_EQ(here.count(k), 1u) << k << " has no runner in this library";
}

TEST(Studies, RunSceneWritesTheFilesOfTheTableAndSharesOneSky) {
  auto s = test::small_scene();
  s.outputs = {output("sky-image", "img/sky.exr"), output("sh-coefficients", "sky_sh.csv"),
               output("sun-elevation-study", "elev")};
  s.outputs[1].bands = 2;
  const fs::path d = scratch("tiny");
  const auto r = studies::run_scene(s, d, quick_options());
  // Exactly the files output_files lists (the study's folder aside), in output order.
  std::vector<fs::path> listed;
  for (const auto& o : s.outputs)
    for (const auto& f : scene::output_files(o))
      if (!fs::is_directory(d / f)) listed.push_back(d / f);
  EXPECT_EQ(r.written, listed);
  for (const auto& f : r.written) EXPECT_TRUE(fs::is_regular_file(f)) << f;
  // The image and the SH share one sky; the study builds its own (its own suns).
  EXPECT_EQ(r.skies_built, 2);
  EXPECT_FALSE(r.spa_computed);  // [sun] given
  // The SH file holds the projection of the scene's sky at the scene's sun.
  const auto sun = studies::sun_of_scene(s);
  const auto m = studies::make_sky_model(s, studies::SkySettings{}.sky(s), sun.distance_au);
  const auto sh = studies::project_sky_sh(*m, sun, 2);
  const auto csv = io::read_csv(d / "sky_sh.csv");
  ASSERT_EQ(csv.rows.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(csv.number(i, csv.column("r")), sh.coeffs[0][i]);
  // The study's rows at the quick step (12 deg from -18 to 90).
  EXPECT_EQ(io::read_csv(d / "elev" / "sun_elevation.csv").rows.size(), 10u);
}

// `plan` and `run` read one table: for a scene of each single kind, plan says the sky is
// needed exactly when run builds one, and the sun is placed by SPA exactly when run
// places it so. (An sh-coefficients-only scene needs the sky: its coefficients are the
// sky's projection; plan says so, and run builds it.)
TEST(Studies, PlanAndRunAgreeOnEveryKind) {
  for (const auto& kind : scene::output_kinds()) {
    auto s = test::small_scene(test::kParisObserver);
    s.outputs = {output(std::string(kind.name), "x/out.csv")};
    s.outputs[0].file = kind.image ? "x/out.exr" : "x/out.csv";
    const fs::path d = scratch("agree_" + std::string(kind.name));
    auto o = quick_options();
    // The LUT study builds no sky and places no sun (SunAndAtmosphereKindsRunHere runs
    // it); a stand-in keeps this test short.
    o.runners["lut-convergence"] = [](studies::SceneRunContext&, const scene::Output&, const fs::path&,
                                      const fs::path&) { return std::vector<fs::path>{}; };
    const auto r = studies::run_scene(s, d, o);
    EXPECT_EQ(plan_needs(s, "sky-radiance:single-scattering"), r.skies_built > 0) << kind.name;
    EXPECT_EQ(plan_needs(s, "optical-depth-lut:sun"), r.skies_built > 0) << kind.name;
    EXPECT_EQ(plan_needs(s, "sun-position:spa"), r.spa_computed) << kind.name;
    EXPECT_EQ(plan_needs(s, "sh-projection"), kind.bands) << kind.name;
  }
}

TEST(Studies, RunSceneRefusesBeforeAnyWork) {
  const fs::path d = scratch("refuse");
  auto s = test::small_scene();
  s.outputs = {output("sky-image", "a.exr"), output("sun-track", "t.csv")};
  // sun-track needs an [observer]: scene::check_outputs refuses it.
  EXPECT_THROW(studies::run_scene(s, d, quick_options()), InputError);
  s = test::small_scene(test::kParisObserver);
  s.outputs = {output("sky-image", "a.exr"), output("sun-track", "t.csv")};
  // A kind without a runner: refused, naming the kind, before the sky image.
  s.outputs[1].kind = "sun-trail";
  try {
    studies::run_scene(s, d, studies::SceneRunOptions{});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sun-trail"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(d / "a.exr"));
  s.outputs[1].kind = "sun-track";
  auto o = quick_options();
  o.device = "tpu";
  EXPECT_THROW(studies::run_scene(s, d, o), InputError);
  EXPECT_FALSE(fs::exists(d / "a.exr"));
  // The peak memory names the largest output.
  s.outputs = {output("sky-image", "small.exr"), output("sky-image", "large.exr")};
  s.outputs[1].size = {4096, 2048};
  const auto peak = studies::scene_peak_memory(s, studies::SceneRunOptions{});
  EXPECT_NE(peak.what.find("large.exr"), std::string::npos);
  EXPECT_GT(peak.bytes, std::size_t{4096} * 2048 * 6 * sizeof(float));  // at least the EXR's six channels
  EXPECT_LT(studies::scene_peak_memory(s, quick_options()).bytes, peak.bytes);  // quick: at most 64 x 32
}

TEST(Studies, PlanCsvAndManifestHoldThePlanAndTheFiles) {
  const fs::path d = scratch("plan");
  auto s = test::small_scene(test::kParisObserver);
  s.outputs = {output("sh-coefficients", "sh.csv"), output("lut-convergence", "lut.csv")};
  const auto csv = io::read_csv(studies::write_plan_csv(s, d / "plan.csv"));
  const auto passes = scene::plan(s);
  ASSERT_EQ(csv.rows.size(), passes.size());
  for (std::size_t i = 0; i < passes.size(); ++i) {
    EXPECT_EQ(csv.rows[i][csv.column("pass")], passes[i].name);
    EXPECT_EQ(csv.number(i, csv.column("needed")), passes[i].needed ? 1.0 : 0.0);
  }
  EXPECT_EQ(csv.provenance.at("scene"), "small.toml");
  // The lut-convergence kind lists a pass of its own (OutputKind::plan_pass).
  EXPECT_TRUE(plan_needs(s, "lut-convergence-study"));
  const auto m = studies::write_manifest(d, "files", {d / "plan.csv", d / "a" / "b.csv"});
  std::ifstream in(m);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "# files\nplan.csv\na/b.csv\n");
}

// The sun and atmosphere kinds (sun-track, lut-convergence, optical-depth) run in this
// library like the others: their rows against the libatmo calls they are made of,
// called here independently (NREL SPA at a row's time; the exact optical-depth reference
// at a row's zenith angle, 1 km above the ground).
TEST(Studies, SunAndAtmosphereKindsRunHere) {
  auto s = test::small_scene(test::kParisObserver);
  s.outputs = {output("sun-track", "track.csv"), output("optical-depth", "od.csv"),
               output("lut-convergence", "lut.csv")};
  const fs::path d = scratch("sun_atmo");
  const auto r = studies::run_scene(s, d, quick_options());
  for (const auto& f : r.written) EXPECT_TRUE(fs::is_regular_file(f)) << f;
  EXPECT_TRUE(r.spa_computed);  // the track's suns are SPA's
  EXPECT_EQ(r.skies_built, 0);  // none of the three needs a sky
  // sun-track: the UTC day of the observer's time every 30 min (quick).
  const auto track = io::read_csv(d / "track.csv");
  ASSERT_EQ(track.rows.size(), 49u);  // 00:00 .. 24:00
  for (std::size_t i : {std::size_t{0}, std::size_t{37}}) {
    atmo::SunQuery q;
    q.latitude_deg = 48.8566;
    q.longitude_deg = 2.3522;
    q.height_m = 35.0;
    q.rise_transit_set = false;
    q.jd_utc = atmo::parse_iso8601("2026-06-21T00:00:00Z").jd_utc + static_cast<double>(i) * 1800.0 / 86400.0;
    const auto p = atmo::sun_position(q);
    EXPECT_NEAR(track.number(i, track.column("zenith_deg")), p.zenith_deg, 1e-6) << i;  // deg; the row time rounds to ~1e-10 d
    EXPECT_NEAR(track.number(i, track.column("azimuth_deg")), p.azimuth_deg, 1e-6) << i;
  }
  // optical-depth: 0..180 deg in 0.5 deg steps, the reference column against the
  // reference integrated here.
  const auto od = io::read_csv(d / "od.csv");
  ASSERT_EQ(od.rows.size(), 361u);
  const atmo::Atmosphere atm(s.atmosphere);
  const atmo::OpticalDepthReference ref(atm);
  const auto k = atm.coefficients_at(550.0);
  for (std::size_t i : {std::size_t{0}, std::size_t{120}, std::size_t{178}, std::size_t{200}}) {
    const double z = od.number(i, od.column("zenith_deg"));
    EXPECT_EQ(z, 0.5 * static_cast<double>(i));
    const auto c = ref.column(atm.ground_radius() + 1000.0, std::cos(z * 3.14159265358979323846 / 180.0));
    EXPECT_NEAR(od.number(i, od.column("tau_reference")), atmo::optical_depth(k, c.column),
                1e-12 * atmo::optical_depth(k, c.column))
        << z;
  }
  // lut-convergence: the reference row, then the quick pair of settings on the CPU.
  const auto lut = io::read_csv(d / "lut.csv");
  ASSERT_GE(lut.rows.size(), 3u);
  EXPECT_EQ(lut.rows[0][lut.column("method")], "reference");
  EXPECT_EQ(lut.rows[1][lut.column("method")], "lut");
  EXPECT_EQ(lut.provenance.at("device"), "cpu");
  // The finer table has the smaller error, both well under 1 %.
  std::vector<double> errors;
  for (std::size_t i = 0; i < lut.rows.size(); ++i)
    if (lut.rows[i][lut.column("method")] == "lut") errors.push_back(lut.number(i, lut.column("error_max_rel")));
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[0], 1e-2);
}
