// CLI contract: --help/--version, exit codes, one-line errors, JSON, and the main
// job end to end (a quick version of `atmosh demo`) with the files it announces.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <vector>

#include "atmosh/io/csv.hpp"
#include "atmosh/io/exr.hpp"
#include "docs_check.hpp"
#include "run_cli.hpp"

using atmosh::test::count_lines;
using atmosh::test::run_cli;
using atmosh::test::slurp;
namespace fs = std::filesystem;

TEST(Cli, HelpAndVersion) {
  auto r = run_cli("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("spherical-harmonic"), std::string::npos);
  EXPECT_NE(r.out.find("demo"), std::string::npos);
  r = run_cli("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("git"), std::string::npos);
  for (const char* sub : {"plan --help", "scene show --help", "demo --help", "gpu info --help"}) {
    r = run_cli(sub);
    EXPECT_EQ(r.exit_code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
}

TEST(Cli, BadInputExitsTwoWithOneLine) {
  for (const char* args : {"", "no-such-command", "plan /nonexistent.toml", "plan --bogus-flag",
                           "scene check /nonexistent.toml"}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_EQ(r.err.rfind("atmosh: error: ", 0), 0u) << r.err;
  }
  const fs::path bad = fs::temp_directory_path() / "atmosh_bad_scene.toml";
  std::ofstream(bad) << "version = 1\n[mie]\nscale_height_m = \"tall\"\n";
  const auto r = run_cli("scene check '" + bad.string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("mie.scale_height_m"), std::string::npos) << r.err;
  EXPECT_EQ(count_lines(r.err), 1);
}

TEST(Cli, SceneShowIsAValidScene) {
  const auto r = run_cli("scene show");
  ASSERT_EQ(r.exit_code, 0);
  const fs::path f = fs::temp_directory_path() / "atmosh_shown_scene.toml";
  std::ofstream(f) << r.out;
  EXPECT_EQ(run_cli("scene check '" + f.string() + "'").exit_code, 0);
  EXPECT_EQ(run_cli("scene show --normalized").exit_code, 0);
}

TEST(Cli, PlanJson) {
  const auto r = run_cli("plan --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("passes"));
  EXPECT_GT(j["passes"].size(), 3u);
  for (const auto& p : j["passes"]) {
    EXPECT_TRUE(p.contains("pass") && p.contains("needed") && p.contains("reason"));
  }
}

TEST(Cli, GpuInfoAnswersWithOrWithoutDevice) {
  const auto r = run_cli("gpu info --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("available"));
  if (j["available"].get<bool>()) {
    EXPECT_NE(j["gl_version"].get<std::string>().find("4."), std::string::npos);
  }
}

// The main job, small and fast: every announced file exists and is readable.
TEST(Cli, DemoQuickEndToEnd) {
  const fs::path out = fs::temp_directory_path() / ("atmosh_demo_" + std::to_string(::getpid()));
  fs::remove_all(out);
  ::setenv("ATMOSH_PLOT_DATA", "1", 1);  // each plot also writes <name>.png.plot.json
  const auto r = run_cli("demo --quick -o '" + out.string() + "'");
  ::unsetenv("ATMOSH_PLOT_DATA");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(out.string()), std::string::npos) << "does not say where the results are";
  ASSERT_TRUE(fs::exists(out / "MANIFEST.txt"));
  std::ifstream m(out / "MANIFEST.txt");
  std::string line;
  int csv = 0, exr = 0, png = 0;
  while (std::getline(m, line)) {
    if (line.empty() || line[0] == '#') continue;
    const fs::path f = out / line;
    ASSERT_TRUE(fs::exists(f)) << f;
    EXPECT_GT(fs::file_size(f), 0u) << f;
    const auto ext = f.extension().string();
    if (ext == ".csv") {
      const auto c = atmosh::io::read_csv(f);
      EXPECT_TRUE(c.provenance.count("git_commit")) << f;
      ++csv;
    } else if (ext == ".exr") {
      const auto e = atmosh::io::read_exr(f);
      EXPECT_GT(e.width * e.height, 0) << f;
      ++exr;
    } else if (ext == ".png") {
      EXPECT_FALSE(cv::imread(f.string()).empty()) << f;
      ++png;
    }
  }
  EXPECT_GE(csv, 1);
  EXPECT_GE(exr, 1);
  EXPECT_GE(png, 1);
  // The figure notebook reads only files that the main job writes.
  {
    std::ifstream nbf(std::string(ATMOSH_SOURCE_DIR) + "/notebooks_export/figures.ipynb");
    ASSERT_TRUE(nbf.good());
    const auto nb = nlohmann::json::parse(nbf);
    std::string files_line;
    for (const auto& cell : nb["cells"])
      for (const auto& src : cell["source"]) {
        const std::string l = src.get<std::string>();
        if (l.rfind("FILES = [", 0) == 0) files_line = l.substr(8);
      }
    ASSERT_FALSE(files_line.empty());
    const auto files = nlohmann::json::parse(files_line);
    EXPECT_GT(files.size(), 5u);
    for (const auto& f : files) EXPECT_TRUE(fs::exists(out / f.get<std::string>())) << f;
  }
  // The main job's outputs read against the docs (docs/outputs.md, docs/cli.md, and
  // what docs/*.md say `atmosh demo` writes).
  atmosh::test::check_docs_against_main_job(out);
  // Tone-mapped PNGs have their side file, listed in the manifest too.
  {
    const std::string manifest = slurp(out / "MANIFEST.txt");
    for (const char* f : {"sky.png.json", "prt/relight/ao.png.json", "prt/relight/frame_0000.png.json"})
      EXPECT_NE(manifest.find(std::string("\n") + f + "\n"), std::string::npos) << f << " not in MANIFEST.txt";
  }
  // The sun-elevation study says that it varies the sun's elevation, and records the
  // scene's observer (the default scene's, 35 m).
  {
    const auto c = atmosh::io::read_csv(out / "sun_elevation_study" / "sun_elevation.csv");
    EXPECT_NE(c.provenance.at("sun_elevation_deg").find("varied"), std::string::npos)
        << c.provenance.at("sun_elevation_deg");
    EXPECT_EQ(c.provenance.at("observer_height_m"), "35");
  }
  // What the plots were handed (ATMOSH_PLOT_DATA): the zero-error reference rows are on
  // the axis floor with a note, titles name files without folders, both band-energy
  // plots use one unit convention, study points are in order of run time.
  {
    auto plot = [&](const char* f) { return nlohmann::json::parse(slurp(out / (std::string(f) + ".plot.json"))); };
    auto series = [](const nlohmann::json& p, const std::string& prefix) -> const nlohmann::json* {
      for (const auto& s : p["series"])
        if (s["label"].get<std::string>().rfind(prefix, 0) == 0) return &s;
      return nullptr;
    };
    const auto acc = plot("sun_accuracy.png");
    const auto* spa = series(acc, "spa");
    ASSERT_NE(spa, nullptr);
    EXPECT_NE((*spa)["label"].get<std::string>().find("floor"), std::string::npos) << (*spa)["label"];
    EXPECT_GE(acc["notes"].size(), 1u);
    const auto shc = plot("sh_converge.png");
    const auto* px = series(shc, "fejer-quadrature");
    ASSERT_NE(px, nullptr);
    EXPECT_NE((*px)["label"].get<std::string>().find("floor"), std::string::npos);
    const std::string title = shc["title"];
    EXPECT_NE(title.find("sh_sky_input.exr"), std::string::npos) << title;
    EXPECT_EQ(title.find('/'), std::string::npos) << title;
    const std::regex unit(R"(^energy sum_m c_lm\^2 \[\((.+) sr\)\^2\]$)");
    for (const char* f : {"sky_sh_bands.png", "sh_bands.png"}) {
      const std::string y = plot(f)["y_label"];
      EXPECT_TRUE(std::regex_match(y, unit)) << f << ": " << y;
    }
    EXPECT_EQ(plot("sky_sh_bands.png")["y_label"], "energy sum_m c_lm^2 [(cd/m^2 sr)^2]");
    for (const char* f : {"sun_accuracy.png", "sh_converge.png", "lut_convergence.png", "sky_convergence.png",
                          "ms_convergence.png", "prt/converge.png"}) {
      const auto p = plot(f);  // kept alive: the loop runs over a member of it
      for (const auto& s : p["series"]) {
        EXPECT_EQ(s["style"], "points") << f;
        std::vector<double> x;
        for (const auto& v : s["x"]) x.push_back(v.is_null() ? NAN : v.get<double>());
        EXPECT_TRUE(std::is_sorted(x.begin(), x.end())) << f << " " << s["label"];
      }
    }
  }
  // No temporaries left behind.
  for (const auto& e : fs::recursive_directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}
