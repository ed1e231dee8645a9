// Sweeps: point order, ranges, validation by key, resume after a kill with a torn
// journal line (no row lost or duplicated), shards + merge equal the whole sweep.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
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
      if (c != t) EXPECT_EQ(a.rows[i][c], b.rows[i][c]);
  // A missing shard, or a shard given twice, is an error.
  EXPECT_THROW(merge_sweep({parts[0], parts[1]}, d / "bad.csv"), atmosh::InputError);
  EXPECT_THROW(merge_sweep({parts[0], parts[1], parts[2], parts[2]}, d / "bad.csv"), atmosh::InputError);
  o.shard = 4;
  EXPECT_THROW(run_sweep(s, eval, o), atmosh::InputError);
}
