// The scene runner at the library level (atmosh/studies/scene_run.hpp): it writes
// the files the table of output kinds lists, shares one sky between outputs, agrees
// with `plan` on what it builds, and refuses before any work.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

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

// The kinds whose runners live with the sun and atmosphere commands (not this library
// yet): the runner takes them from SceneRunOptions::runners.
const std::set<std::string> kElsewhere = {"sun-track", "lut-convergence", "optical-depth"};

studies::SceneRunOptions quick_options() {
  studies::SceneRunOptions o;
  o.quick = true;
  for (const auto& k : kElsewhere)  // stand-ins: these kinds' own tests are the CLI's
    o.runners[k] = [](studies::SceneRunContext&, const scene::Output&, const fs::path&, const fs::path&) {
      return std::vector<fs::path>{};
    };
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
  for (const auto& k : kinds) EXPECT_NE(here.count(k) + kElsewhere.count(k), 0u) << k << " has no runner";
  for (const auto& k : kElsewhere) EXPECT_EQ(here.count(k), 0u) << k << " has two runners";
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
    const auto r = studies::run_scene(s, d, quick_options());
    EXPECT_EQ(plan_needs(s, "sky-radiance:single-scattering"), r.skies_built > 0) << kind.name;
    EXPECT_EQ(plan_needs(s, "optical-depth-lut:sun"), r.skies_built > 0) << kind.name;
    if (!kElsewhere.count(std::string(kind.name)))
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
  // No runner for sun-track given: refused, naming the kind, before the sky image.
  try {
    studies::run_scene(s, d, studies::SceneRunOptions{});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'sun-track' has no runner"), std::string::npos) << e.what();
  }
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
