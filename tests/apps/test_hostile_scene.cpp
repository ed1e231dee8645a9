// Hostile scene and sweep files: bounded TOML nesting (no stack overflow inside the
// TOML parser), `scene check` refusing what `run` refuses, the plan's spectrum, and
// the one table of output kinds that check, plan and run read.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/scene/outputs.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/scene/sweep.hpp"
#include "atmosh/scene/toml_limits.hpp"

using namespace atmosh::scene;
namespace fs = std::filesystem;

namespace {
std::string repeat(const std::string& s, int n, const std::string& sep = "") {
  std::string out;
  for (int i = 0; i < n; ++i) out += (i ? sep : "") + s;
  return out;
}
// The message of the InputError f throws ("" if it throws none).
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const atmosh::InputError& e) {
    return e.what();
  }
  return "";
}
const Pass& find_pass(const std::vector<Pass>& ps, const std::string& name) {
  auto it = std::find_if(ps.begin(), ps.end(), [&](const Pass& p) { return p.name == name; });
  if (it == ps.end()) throw std::runtime_error("no pass " + name);
  return *it;
}
}  // namespace

// 40 000 parts (80 KB) overflowed the stack inside the TOML parser (exit 139) in
// `scene check`, `plan`, `run` and `sky --scene`; now refused before parsing.
TEST(HostileToml, DeepKeyPathsAndHeadersAreRefusedBeforeParsing) {
  const std::string key = "version = 1\n" + repeat("a", 40000, ".") + " = 1\n";
  const std::string header = "version = 1\n[" + repeat("a", 40000, ".") + "]\n";
  for (const auto& text : {key, header}) {
    const std::string msg = error_of([&] { parse_scene(text, "deep.toml"); });
    EXPECT_EQ(msg.rfind("deep.toml:2: ", 0), 0u) << msg;
    EXPECT_NE(msg.find("limit is 64"), std::string::npos) << msg;
  }
  // The sweep reader goes through the same bound.
  const std::string sweep = "version = 1\n[" + repeat("p", 40000, ".") + "]\n";
  EXPECT_NE(error_of([&] { parse_sweep(sweep, "s.toml", "."); }).find("limit is 64"), std::string::npos);
  // A sweep parameter key is a key path too (one nested table per part).
  const std::string deep_override = repeat("a", 40000, ".");
  EXPECT_NE(error_of([&] { parse_scene(default_scene_toml(), "base", {Override{deep_override, 1.0}}); })
                .find("limit is 64"),
            std::string::npos);
}

TEST(HostileToml, NestingDepthAndKeyLengthAreBounded) {
  EXPECT_NE(error_of([] { check_toml_limits("x = " + repeat("[", 65) + repeat("]", 65) + "\n", "n.toml"); })
                .find("nest 65 deep"),
            std::string::npos);
  // Inline tables: each level is its key and the table (depth 2 per level).
  EXPECT_NE(error_of([] { check_toml_limits("x = " + repeat("{a = ", 65) + "1" + repeat("}", 65) + "\n", "n.toml"); })
                .find("limit is 128"),
            std::string::npos);
  EXPECT_EQ(error_of([] { check_toml_limits("x = " + repeat("{a = ", 60) + "1" + repeat("}", 60) + "\n", "n.toml"); }), "");
  // Depth adds up: a header of 64 parts and a dotted key of 64 parts under it.
  EXPECT_EQ(error_of([] { check_toml_limits("[" + repeat("t", 64, ".") + "]\n" + repeat("k", 63, ".") + " = 1\n", "d.toml"); }), "");
  EXPECT_NE(error_of([] { check_toml_limits("[" + repeat("t", 64, ".") + "]\n" + repeat("k", 64, ".") + " = 1\n", "d.toml"); })
                .find("limit is 128"),
            std::string::npos);
  EXPECT_NE(error_of([] { check_toml_limits(std::string(2000, 'k') + " = 1\n", "l.toml"); }).find("1024 bytes"),
            std::string::npos);
  TomlLimits small;
  small.max_bytes = 10;
  EXPECT_NE(error_of([&] { check_toml_limits("version = 1\n", "b.toml", small); }).find("12 bytes"), std::string::npos);
}

TEST(HostileToml, StringsAndCommentsDoNotCount) {
  // Dots, brackets and braces inside strings (every kind) and comments are not structure.
  const std::string dots = repeat("a", 5000, ".");
  const std::string text = "version = 1\n"
                           "name = \"" + dots + "[[[{{{\"\n"
                           "# " + dots + " [[[[[[\n"
                           "k1 = '" + dots + "'\n"
                           "k2 = \"\"\"\n" + dots + "\n\\\"\"\" ]]]\n\"\"\"\n"
                           "k3 = '''" + dots + "'''\n"
                           "\"quoted.key.with.dots\" = 1\n"
                           "arr = [ \"" + dots + "\", { a.b = 1 }, [1, [2, [3]]] ]\n";
  EXPECT_EQ(error_of([&] { check_toml_limits(text, "ok.toml"); }), "");
  // Real scenes pass untouched.
  EXPECT_EQ(error_of([] { check_toml_limits(default_scene_toml(), "default"); }), "");
}

TEST(HostileToml, OversizedFilesAreRefusedBeforeReading) {
  const fs::path d = fs::temp_directory_path() / ("atmosh_hostile_toml_" + std::to_string(::getpid()));
  fs::create_directories(d);
  const fs::path big = d / "big.toml";
  { std::ofstream(big) << "version = 1\n"; }
  fs::resize_file(big, (16u << 20) + 1);
  EXPECT_NE(error_of([&] { load_scene(big); }).find("limit is 16777216"), std::string::npos);
  // Not a regular file (a sweep naming /dev/zero as its scene would read forever).
  EXPECT_NE(error_of([&] { load_scene(d); }).find("not a regular file"), std::string::npos);
  EXPECT_NE(error_of([] { load_scene("/dev/zero"); }).find("not a regular file"), std::string::npos);
  fs::remove_all(d);
}

// `scene check` (load_scene) refuses everything `run` would refuse, naming the file and key.
TEST(HostileScene, CheckRefusesWhatRunRefuses) {
  const std::string obs = "version = 1\n[observer]\nlatitude_deg = 48\nlongitude_deg = 2\n";
  const std::string out = "[[output]]\nkind = \"sky-image\"\nfile = \"sky.exr\"\n";
  auto msg = error_of([&] { parse_scene(obs + "time_utc = \"2026-02-30T18:30:00Z\"\n" + out, "t.toml"); });
  EXPECT_EQ(msg.rfind("t.toml: observer.time_utc: ", 0), 0u) << msg;
  msg = error_of([&] { parse_scene(obs + "time_utc = \"99999-06-21T18:30:00Z\"\n" + out, "t.toml"); });
  EXPECT_EQ(msg.rfind("t.toml: observer.time_utc: ", 0), 0u) << msg;
  msg = error_of([&] { check_outputs(parse_scene("version = 1\n" + out, "t.toml")); });
  EXPECT_EQ(msg.rfind("t.toml: output[0] (sky-image", 0), 0u) << msg;
  EXPECT_NE(msg.find("needs the sun"), std::string::npos) << msg;
  msg = error_of([&] { check_outputs(parse_scene("version = 1\n[sun]\nelevation_deg = 5\n[[output]]\nkind = \"sun-track\"\nfile = \"t\"\n", "t.toml")); });
  EXPECT_NE(msg.find("needs an [observer]"), std::string::npos) << msg;
  msg = error_of([&] { parse_scene("version = 1\n[spectrum]\nwavelengths_nm = [500.0, 400.0]\n", "t.toml"); });
  EXPECT_EQ(msg.rfind("t.toml: spectrum.wavelengths_nm[1]", 0), 0u) << msg;
  // Outputs that need no sun run without one.
  EXPECT_EQ(error_of([] { check_outputs(parse_scene("version = 1\n[[output]]\nkind = \"optical-depth\"\nfile = \"od\"\n", "t.toml")); }), "");
}

TEST(HostileScene, PlanReportsTheSpectrumTheRunUses) {
  const Scene s = parse_scene("version = 1\n[sun]\nelevation_deg = 10\n[spectrum]\nwavelengths_nm = [400.0, 500.0, 600.0]\n"
                              "[[output]]\nkind = \"sky-image\"\nfile = \"sky.exr\"\n", "t.toml");
  const auto passes = plan(s);
  const auto& sp = find_pass(passes, "spectrum");
  EXPECT_TRUE(sp.needed);
  EXPECT_NE(sp.reason.find("3 wavelengths 400\u2013600 nm"), std::string::npos) << sp.reason;
  const Scene g = parse_scene("version = 1\n[sun]\nelevation_deg = 10\n[spectrum]\nfrom_nm = 380\nto_nm = 780\ncount = 8\n"
                              "[[output]]\nkind = \"sky-image\"\nfile = \"sky.exr\"\n", "t.toml");
  const auto gpasses = plan(g);
  const auto& gp = find_pass(gpasses, "spectrum");
  EXPECT_NE(gp.reason.find("8 wavelengths in 8 bins 380\u2013780 nm (centres 405\u2013755 nm)"), std::string::npos) << gp.reason;
}

// An sh-coefficients output is the SH of the sky: the plan says so, and without a sun
// the scene is refused up front (it ran the sky, then failed, before).
TEST(HostileScene, ShCoefficientsNeedTheSkyAndTheSun) {
  const std::string sh = "[[output]]\nkind = \"sh-coefficients\"\nfile = \"sky_sh.csv\"\nbands = 4\n";
  const Scene s = parse_scene("version = 1\n[rayleigh]\n[sun]\nelevation_deg = 10\n" + sh, "t.toml");
  const auto passes = plan(s);
  EXPECT_TRUE(find_pass(passes, "sky-radiance:single-scattering").needed);
  EXPECT_TRUE(find_pass(passes, "optical-depth-lut:sun").needed);
  EXPECT_NE(find_pass(passes, "sh-projection").reason.find("4 bands"), std::string::npos);
  EXPECT_NE(error_of([&] { check_outputs(parse_scene("version = 1\n" + sh, "t.toml")); }).find("needs the sun"), std::string::npos);
}

TEST(HostileScene, OneTableOfOutputKinds) {
  // Every kind the reader accepts is in the table, with the files it writes; an unknown
  // kind is refused with the table's list.
  for (const auto& k : output_kinds()) {
    Output o;
    o.kind = std::string(k.name);
    o.file = "x.ext";
    EXPECT_FALSE(output_files(o).empty()) << k.name;
    EXPECT_TRUE(k.sky || k.sun || k.observer || k.atmosphere) << k.name << " needs nothing";
  }
  Output sky;
  sky.kind = "sky-image";
  sky.file = "img/sky.exr";
  EXPECT_EQ(output_files(sky), (std::vector<std::string>{"img/sky.exr", "img/sky.png", "img/sky.png.json"}));
  const auto msg = error_of([] { parse_scene("version = 1\n[[output]]\nkind = \"hologram\"\nfile = \"h\"\n", "t.toml"); });
  EXPECT_NE(msg.find(output_kind_names()), std::string::npos) << msg;
}
