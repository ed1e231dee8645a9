// Sweeps: point order, ranges, validation by key, resume after a kill with a torn
// journal line (no row lost or duplicated), shards + merge equal the whole sweep.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/hash.hpp"
#include "atmosh/scene/sweep.hpp"

using namespace atmosh::scene;
namespace fs = std::filesystem;

namespace {
const char* kSweep = R"(version = 1
mode = "grid"
[[parameter]]
key = "sun.elevation_deg"
from = 0
to = 10
step = 2.5
[[parameter]]
key = "mie.scattering_per_m"
values = [1e-6, 2e-6, 4e-6]
)";

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("atmosh_sweep_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// A cheap evaluator whose outputs are closed-form functions of the point's scene.
SweepOutputs eval(const Scene& s) {
  return {{"sin_elevation", std::sin(s.sun->elevation_deg * M_PI / 180.0)},
          {"mie_km", s.atmosphere.mie->scattering_per_m * 1e3}};
}
}  // namespace

TEST(Sweep, GridOrderLastParameterFastest) {
  const SweepSpec s = parse_sweep(kSweep, "s.toml", ".");
  ASSERT_EQ(s.points.size(), 5u * 3u);
  EXPECT_EQ(std::get<double>(s.points[0][0].value), 0.0);
  EXPECT_EQ(std::get<double>(s.points[1][1].value), 2e-6);
  EXPECT_EQ(std::get<double>(s.points[3][0].value), 2.5);
  EXPECT_EQ(std::get<double>(s.points[14][0].value), 10.0);
}

TEST(Sweep, BadValuesNamedByKey) {
  const fs::path d = scratch("bad");
  const SweepSpec s = parse_sweep("version = 1\n[[parameter]]\nkey = \"mie.scale_height_m\"\nvalues = [\"tall\"]\n",
                                  "s.toml", ".");
  SweepOptions o;
  o.out_dir = d;
  try {
    run_sweep(s, eval, o);
    FAIL() << "accepted a string scale height";
  } catch (const atmosh::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mie.scale_height_m"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_sweep("version = 1\n", "s.toml", "."), atmosh::InputError);
  EXPECT_THROW(parse_sweep("version = 1\nmode=\"zip\"\n[[parameter]]\nkey=\"a.b\"\nvalues=[1,2]\n[[parameter]]\nkey=\"c.d\"\nvalues=[1]\n",
                           "s.toml", "."),
               atmosh::InputError);
}

TEST(Sweep, ResumeAfterKillLosesAndDuplicatesNothing) {
  const fs::path d = scratch("resume");
  const SweepSpec s = parse_sweep(kSweep, "s.toml", ".");
  SweepOptions o;
  o.out_dir = d;
  // First run dies at point 7 (single thread: points 0..6 are journaled).
  std::atomic<int> calls{0};
  auto dying = [&](const Scene& sc) {
    if (calls++ == 7) throw std::runtime_error("killed");
    return eval(sc);
  };
  EXPECT_THROW(run_sweep(s, dying, o), std::runtime_error);
  EXPECT_FALSE(fs::exists(d / "sweep.csv"));
  const fs::path journal = d / ".sweep.journal";
  ASSERT_TRUE(fs::exists(journal));
  std::ofstream(journal, std::ios::app) << "7,5,2e-06,0.08";  // torn line: killed mid-write
  std::atomic<int> second{0};
  o.resume = true;
  o.threads = 2;
  const auto r = run_sweep(s, [&](const Scene& sc) { ++second; return eval(sc); }, o);
  EXPECT_EQ(r.points_resumed, 7);
  EXPECT_EQ(r.points_computed, 8);
  EXPECT_EQ(second.load(), 8);
  const auto csv = atmosh::io::read_csv(d / "sweep.csv");
  ASSERT_EQ(csv.rows.size(), 15u);
  for (std::size_t i = 0; i < 15; ++i) {
    EXPECT_EQ(csv.number(i, 0), static_cast<double>(i));
    const double elev = csv.number(i, csv.column("sun.elevation_deg"));
    EXPECT_NEAR(csv.number(i, csv.column("sin_elevation")), std::sin(elev * M_PI / 180.0), 1e-15);
  }
  EXPECT_FALSE(fs::exists(journal));
}

TEST(Sweep, ShardsMergeToTheWholeSweep) {
  const fs::path d = scratch("shards");
  const SweepSpec s = parse_sweep(kSweep, "s.toml", ".");
  SweepOptions o;
  o.out_dir = d;
  const auto whole = run_sweep(s, eval, o);
  std::vector<fs::path> parts;
  for (int k = 1; k <= 3; ++k) {
    o.shard = k;
    o.shards = 3;
    parts.push_back(run_sweep(s, eval, o).csv);
  }
  merge_sweep(parts, d / "merged.csv");
  const auto a = atmosh::io::read_csv(whole.csv), b = atmosh::io::read_csv(d / "merged.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  const auto t = a.column("time_s");
  for (std::size_t i = 0; i < a.rows.size(); ++i)
    for (std::size_t c = 0; c < a.columns.size(); ++c)
      if (c != t) {
        EXPECT_EQ(a.rows[i][c], b.rows[i][c]);
      }
  // A missing shard, or a shard given twice, is an error.
  EXPECT_THROW(merge_sweep({parts[0], parts[1]}, d / "bad.csv"), atmosh::InputError);
  EXPECT_THROW(merge_sweep({parts[0], parts[1], parts[2], parts[2]}, d / "bad.csv"), atmosh::InputError);
  o.shard = 4;
  EXPECT_THROW(run_sweep(s, eval, o), atmosh::InputError);
}

namespace {
std::string slurp_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
// Sweep B: the same keys and grid size as kSweep, other values.
const char* kOtherSweep = R"(version = 1
[[parameter]]
key = "sun.elevation_deg"
values = [1.0, 3.0, 5.0, 7.0, 9.0]
[[parameter]]
key = "mie.scattering_per_m"
values = [1e-6, 2e-6, 4e-6]
)";
const SweepSettings kSettings = {{"lut_shells", "32"}, {"view_segments", "16"}};
}  // namespace

// 64-bit FNV-1a test vectors published with the algorithm (isthe.com/chongo/tech/comp/fnv).
TEST(Sweep, ContentHashIsFnv1a64) {
  EXPECT_EQ(atmosh::io::ContentHash().hex(), "cbf29ce484222325");
  EXPECT_EQ(atmosh::io::ContentHash().add("a").hex(), "af63dc4c8601ec8c");
  EXPECT_EQ(atmosh::io::ContentHash().add("foobar").hex(), "85944171f73967e8");
}

// The identity depends on what changes results, not on how the file is written.
TEST(Sweep, IdentityIsTheNormalizedContentAndSettings) {
  const SweepSpec a = parse_sweep(kSweep, "s.toml", ".");
  const SweepSpec same = parse_sweep(std::string("# a comment\n") +
                                         "version = 1\n[[parameter]]\nkey = \"sun.elevation_deg\"\n"
                                         "values = [0.0, 2.5, 5.0, 7.5, 10.0]\n[[parameter]]\n"
                                         "key = \"mie.scattering_per_m\"\nvalues = [1e-6, 2e-6, 4e-6]\n",
                                     "other-name.toml", ".");
  EXPECT_EQ(sweep_identity(a, kSettings), sweep_identity(same, kSettings));
  const SweepSpec b = parse_sweep(kOtherSweep, "s.toml", ".");
  EXPECT_NE(sweep_identity(a, kSettings), sweep_identity(b, kSettings));
  EXPECT_NE(sweep_identity(a, kSettings), sweep_identity(a, {{"lut_shells", "64"}, {"view_segments", "16"}}));
  SweepSpec other_scene = a;
  other_scene.base_scene_text += "\n[sun]\nelevation_deg = 3.0\n";
  EXPECT_NE(sweep_identity(a, kSettings), sweep_identity(other_scene, kSettings));
  EXPECT_EQ(sweep_identity(a, kSettings).size(), 16u);
}

// A killed run of sweep A, then `--resume` of sweep B (same grid size, other values)
// into the same folder: refused, naming both identities; nothing of A is mixed in.
TEST(Sweep, ResumeOfAnotherSweepIsRefused) {
  const fs::path d = scratch("resume_other");
  const SweepSpec a = parse_sweep(kSweep, "a.toml", "."), b = parse_sweep(kOtherSweep, "b.toml", ".");
  SweepOptions o;
  o.out_dir = d;
  o.settings = kSettings;
  int calls = 0;
  EXPECT_THROW(run_sweep(a, [&](const Scene& sc) {
                 if (calls++ == 4) throw std::runtime_error("killed");
                 return eval(sc);
               }, o),
               std::runtime_error);
  ASSERT_TRUE(fs::exists(d / ".sweep.journal"));
  o.resume = true;
  try {
    run_sweep(b, eval, o);
    FAIL() << "resumed sweep b from sweep a's journal";
  } catch (const atmosh::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(sweep_identity(a, kSettings)), std::string::npos) << m;
    EXPECT_NE(m.find(sweep_identity(b, kSettings)), std::string::npos) << m;
    EXPECT_NE(m.find(".sweep.journal"), std::string::npos) << m;
  }
  // Other settings are another sweep too.
  SweepOptions o2 = o;
  o2.settings = {{"lut_shells", "64"}, {"view_segments", "16"}};
  EXPECT_THROW(run_sweep(a, eval, o2), atmosh::InputError);
  // The same sweep resumes; then a completed CSV of A refuses B as well.
  const auto r = run_sweep(a, eval, o);
  EXPECT_EQ(r.points_resumed, 4);
  EXPECT_THROW(run_sweep(b, eval, o), atmosh::InputError);
}

TEST(Sweep, ResumeOfACompletedSweepRecomputesNothing) {
  const fs::path d = scratch("resume_done");
  const SweepSpec s = parse_sweep(kSweep, "s.toml", ".");
  SweepOptions o;
  o.out_dir = d;
  o.settings = kSettings;
  run_sweep(s, eval, o);
  const std::string before = slurp_file(d / "sweep.csv");
  const auto mtime = fs::last_write_time(d / "sweep.csv");
  o.resume = true;
  int calls = 0;
  const auto r = run_sweep(s, [&](const Scene& sc) { ++calls; return eval(sc); }, o);
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(r.points_computed, 0);
  EXPECT_EQ(r.points_resumed, 15);
  EXPECT_EQ(slurp_file(d / "sweep.csv"), before);
  EXPECT_EQ(fs::last_write_time(d / "sweep.csv"), mtime);
}

TEST(Sweep, CsvRecordsIdentityAndSettings) {
  const fs::path d = scratch("settings");
  const SweepSpec s = parse_sweep(kSweep, "s.toml", ".");
  SweepOptions o;
  o.out_dir = d;
  o.settings = kSettings;
  const auto r = run_sweep(s, eval, o);
  const auto csv = atmosh::io::read_csv(r.csv);
  EXPECT_EQ(csv.provenance.at("sweep_id"), sweep_identity(s, kSettings));
  EXPECT_EQ(csv.provenance.at("lut_shells"), "32");
  EXPECT_EQ(csv.provenance.at("view_segments"), "16");
  EXPECT_EQ(csv.provenance.at("sweep"), "s.toml");
  EXPECT_EQ(csv.provenance.at("base_scene"), "<built-in default scene>");
}

// Range values are the decimal numbers a user wrote, printed in shortest form:
// from = 2e-6, step = 2e-6 gives 8e-6 (pandas: df[df.col == 8e-6] matches).
TEST(Sweep, RangeValuesAreShortestAndExact) {
  const fs::path d = scratch("shortest");
  const SweepSpec s = parse_sweep(
      "version = 1\n[[parameter]]\nkey = \"mie.scattering_per_m\"\nfrom = 2e-6\nto = 8e-6\nstep = 2e-6\n", "s.toml", ".");
  ASSERT_EQ(s.points.size(), 4u);
  EXPECT_EQ(std::get<double>(s.points[3][0].value), 8e-6);
  EXPECT_EQ(std::get<double>(s.points[2][0].value), 6e-6);
  SweepOptions o;
  o.out_dir = d;
  const auto csv = atmosh::io::read_csv(run_sweep(s, eval, o).csv);
  const auto c = csv.column("mie.scattering_per_m");
  EXPECT_EQ(csv.rows[0][c], "2e-06");
  EXPECT_EQ(csv.rows[3][c], "8e-06");
  EXPECT_EQ(csv.number(3, c), 8e-6);
  // count = 5 from 0 to 1: 0, 0.25, 0.5, 0.75, 1 exactly.
  const SweepSpec n = parse_sweep("version = 1\n[[parameter]]\nkey = \"sun.elevation_deg\"\nfrom = 0.1\nto = 0.7\ncount = 7\n",
                                  "s.toml", ".");
  EXPECT_EQ(std::get<double>(n.points[2][0].value), 0.3);
  EXPECT_EQ(std::get<double>(n.points[6][0].value), 0.7);
}

TEST(Sweep, MergeRefusesShardsOfDifferentSweepsAndKeepsProvenance) {
  const fs::path d = scratch("merge_other");
  const SweepSpec a = parse_sweep(kSweep, "a.toml", "."), b = parse_sweep(kOtherSweep, "b.toml", ".");
  SweepOptions o;
  o.settings = kSettings;
  o.shards = 2;
  std::vector<fs::path> pa, pb;
  for (int k = 1; k <= 2; ++k) {
    o.shard = k;
    o.out_dir = d / "a";
    pa.push_back(run_sweep(a, eval, o).csv);
    o.out_dir = d / "b";
    pb.push_back(run_sweep(b, eval, o).csv);
  }
  try {
    merge_sweep({pa[0], pb[1]}, d / "mixed.csv");
    FAIL() << "merged shards of two sweeps";
  } catch (const atmosh::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(sweep_identity(a, kSettings)), std::string::npos) << m;
    EXPECT_NE(m.find(sweep_identity(b, kSettings)), std::string::npos) << m;
  }
  EXPECT_FALSE(fs::exists(d / "mixed.csv"));
  merge_sweep(pa, d / "merged.csv");
  const auto m = atmosh::io::read_csv(d / "merged.csv");
  EXPECT_EQ(m.rows.size(), 15u);
  EXPECT_EQ(m.provenance.at("sweep"), "a.toml");
  EXPECT_EQ(m.provenance.at("base_scene"), "<built-in default scene>");
  EXPECT_EQ(m.provenance.at("sweep_id"), sweep_identity(a, kSettings));
  EXPECT_EQ(m.provenance.at("lut_shells"), "32");
  EXPECT_EQ(m.provenance.count("shard"), 0u);
}

// The library reports progress through a callback (it never prints): fractions of the
// shard's points, non-decreasing, ending at 1 — resumed points included.
TEST(Sweep, ReportsProgressThroughTheCallback) {
  const fs::path d = scratch("progress");
  const SweepSpec s = parse_sweep(kSweep, "s.toml", ".");
  SweepOptions o;
  o.out_dir = d;
  o.threads = 3;
  std::vector<double> seen;
  o.progress = [&](double f) { seen.push_back(f); };
  run_sweep(s, eval, o);
  ASSERT_EQ(seen.size(), 15u);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i], seen[i - 1]);
  EXPECT_DOUBLE_EQ(seen.front(), 1.0 / 15.0);
  EXPECT_EQ(seen.back(), 1.0);
  seen.clear();
  o.resume = true;
  run_sweep(s, eval, o);
  EXPECT_EQ(seen, std::vector<double>{1.0});
}
