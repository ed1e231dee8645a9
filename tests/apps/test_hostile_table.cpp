// The table of hostile inputs in docs/hostile-input.md, run: every row with a command
// in backticks must exit 2 with one line on stderr naming the row's key word.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "run_cli.hpp"

namespace fs = std::filesystem;
using atmosh::test::run_cli;

namespace {
struct Row {
  std::string command, exit, names;
};

// Rows of the "Tried inputs" table: | Subcommand | Hostile input | `command` | exit | names |
std::vector<Row> documented_rows() {
  std::ifstream f(fs::path(ATMOSH_SOURCE_DIR) / "docs" / "hostile-input.md");
  std::vector<Row> rows;
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("| ", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    for (std::string c; std::getline(ss, c, '|');) {
      c.erase(0, c.find_first_not_of(' '));
      c.erase(c.find_last_not_of(' ') + 1);
      cells.push_back(c);
    }
    if (cells.size() < 5 || cells[2].size() < 9 || cells[2].rfind("`atmosh ", 0) != 0 || cells[2].back() != '`') continue;
    rows.push_back({cells[2].substr(8, cells[2].size() - 9), cells[3], cells[4]});
  }
  return rows;
}

std::string repeat(const std::string& s, int n, const std::string& sep) {
  std::string out;
  for (int i = 0; i < n; ++i) out += (i ? sep : "") + s;
  return out;
}

template <class T>
void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}

// A binary little-endian PLY of an n x n grid (z = 0), two triangles per cell.
std::string grid_ply(int n, std::int32_t last_index_override = -1) {
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n * n) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                  std::to_string(2 * (n - 1) * (n - 1)) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) put(s, float(i)), put(s, float(j)), put(s, 0.0f);
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const std::int32_t a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      for (auto t : {std::array<std::int32_t, 3>{a, b, c}, std::array<std::int32_t, 3>{a, c, d}}) {
        put(s, std::uint8_t{3});
        for (auto v : t) put(s, v);
      }
    }
  if (last_index_override >= 0) std::memcpy(s.data() + s.size() - 4, &last_index_override, 4);
  return s;
}

void make_fixtures(const fs::path& d) {
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(d / name, std::ios::binary) << text;
  };
  const std::string deep = repeat("a", 40000, ".");
  write("deep_key.toml", "version = 1\n" + deep + " = 1\n");
  write("deep_header.toml", "version = 1\n[" + deep + "]\n");
  write("deep_sweep.toml", "version = 1\n[" + repeat("p", 40000, ".") + "]\n");
  const std::string obs = "version = 1\n[observer]\nlatitude_deg = 48\nlongitude_deg = 2\n";
  const std::string sky = "[[output]]\nkind = \"sky-image\"\nfile = \"sky.exr\"\n";
  write("bad_date.toml", obs + "time_utc = \"2026-02-30T18:30:00Z\"\n" + sky);
  write("year99999.toml", obs + "time_utc = \"99999-06-21T18:30:00Z\"\n" + sky);
  write("no_sun.toml", "version = 1\n" + sky);
  write("sh_no_sun.toml", "version = 1\n[[output]]\nkind = \"sh-coefficients\"\nfile = \"sh.csv\"\n");
  write("wl_desc.toml", "version = 1\n[spectrum]\nwavelengths_nm = [500.0, 400.0]\n");
  write("huge_image.toml", "version = 1\n[sun]\nelevation_deg = 10\n" + sky + "size = [65536, 65536]\n");
  const std::string ply = grid_ply(30);
  write("cut.ply", ply.substr(0, 3000));
  write("header.ply", ply.substr(0, ply.find("end_header\n") + 11));
  write("bad_index.ply", grid_ply(30, 1000000000));
  write("big_image.toml", "version = 1\n[sun]\nelevation_deg = 10\n" + sky + "size = [8192, 4096]\n");
  write("file.txt", "a file\n");
  fs::create_directories(d / "folder");
  fs::create_directories(d / "stem.png");   // STEM.png of a study is a folder
  fs::create_directories(d / "folder.ply"); // a folder with a file's name
}
}  // namespace

TEST(HostileInput, DocumentedRowsExitTwoNamingTheFault) {
  const auto rows = documented_rows();
  ASSERT_GE(rows.size(), 20u) << "docs/hostile-input.md: table not found";
  const fs::path d = atmosh::test::scratch_dir("atmosh_hostile", "table");
  make_fixtures(d);
  const fs::path here = fs::current_path();
  fs::current_path(d);
  for (const auto& r : rows) {
    const auto res = run_cli(r.command);
    EXPECT_EQ(std::to_string(res.exit_code), r.exit) << r.command << "\n" << res.err;
    EXPECT_EQ(atmosh::test::count_lines(res.err), 1) << r.command << "\n" << res.err;
    EXPECT_NE(res.err.find(r.names), std::string::npos) << r.command << ": '" << res.err << "' does not name '" << r.names << "'";
    // Refused before any work: nothing written.
    for (const char* out : {"out", "sky.exr", "st", "day", "c.csv", "t.ply", "stem.csv", "track.txt", "track.csv",
                            "folder.csv", "folder.png"})
      EXPECT_FALSE(fs::exists(d / out)) << r.command << " wrote " << out;
  }
  fs::current_path(here);
}

// `plan` and `run` read one table of output kinds: an sh-coefficients scene is planned
// with the sky it needs, and run writes exactly the files the table lists for it.
TEST(HostileInput, PlanAndRunAgreeOnAnShCoefficientsScene) {
  const fs::path d = atmosh::test::scratch_dir("atmosh_hostile", "sh_only");
  std::ofstream(d / "sh.toml") << "version = 1\n[sun]\nelevation_deg = 20\n[spectrum]\nwavelengths_nm = [400.0, 500.0, 600.0]\n"
                                  "[[output]]\nkind = \"sh-coefficients\"\nfile = \"sky_sh.csv\"\nbands = 2\n";
  const auto p = run_cli("plan '" + (d / "sh.toml").string() + "'");
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_NE(p.out.find("run   sky-radiance:single-scattering"), std::string::npos) << p.out;
  EXPECT_NE(p.out.find("run   sh-projection"), std::string::npos) << p.out;
  EXPECT_NE(p.out.find("3 wavelengths 400\u2013600 nm"), std::string::npos) << p.out;
  const auto r = run_cli("run '" + (d / "sh.toml").string() + "' -o '" + (d / "out").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("ran   sky-radiance:single-scattering"), std::string::npos) << r.out;
  for (const char* f : {"sky_sh.csv", "sky_sh_bands.csv", "sky_sh_bands.png"})
    EXPECT_TRUE(fs::exists(d / "out" / f)) << f;
}

// `scene check`, `plan` and `run` hold a scene to what its outputs need; `sky --scene`
// uses only its atmosphere (the sun comes from the command line).
TEST(HostileInput, SkySceneUsesTheAtmosphereNotTheOutputs) {
  const fs::path d = atmosh::test::scratch_dir("atmosh_hostile", "sky_scene");
  std::ofstream(d / "no_sun.toml") << "version = 1\n[rayleigh]\n[[output]]\nkind = \"sky-image\"\nfile = \"sky.exr\"\n";
  const std::string scene = "'" + (d / "no_sun.toml").string() + "'";
  EXPECT_EQ(run_cli("scene check " + scene).exit_code, 2);
  const auto r = run_cli("sky --scene " + scene + " --sun-elevation 10 --size 8x4 -o '" + (d / "sky.exr").string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "sky.exr"));
}

// `plan` reports the estimates `run` checks against its budgets: for one 8192 x 4096 sky
// image, rays x view-ray nodes = 8192 x 4096 x (16 segments x 2 samples, the defaults of
// atmo::SkyOptions) steps, and at least the image's six float channels in memory.
TEST(HostileInput, PlanReportsTheEstimates) {
  const fs::path d = atmosh::test::scratch_dir("atmosh_hostile", "plan_estimate");
  std::ofstream(d / "big.toml") << "version = 1\n[sun]\nelevation_deg = 10\n[[output]]\nkind = \"sky-image\"\n"
                                   "file = \"sky.exr\"\nsize = [8192, 4096]\n";
  const auto j = run_cli("plan --json '" + (d / "big.toml").string() + "'");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto p = nlohmann::json::parse(j.out);
  EXPECT_DOUBLE_EQ(p["estimate"]["units"].get<double>(), 8192.0 * 4096 * 16 * 2);
  EXPECT_EQ(p["estimate"]["unit"], "view-ray nodes");
  EXPECT_GT(p["estimate"]["cpu_seconds"].get<double>(), 10.0);  // ~1e9 nodes at > 10 ns each
  EXPECT_LE(p["estimate"]["wall_seconds"].get<double>(), p["estimate"]["cpu_seconds"].get<double>());
  EXPECT_GE(p["estimate"]["peak_memory_bytes"].get<double>(), 8192.0 * 4096 * 6 * 4);
  const auto t = run_cli("plan '" + (d / "big.toml").string() + "'");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_NE(t.out.find("estimate: memory"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("computing about"), std::string::npos) << t.out;
  // The run is refused by the same estimate under a small budget, before any work.
  const auto r = run_cli("--max-time 1m run '" + (d / "big.toml").string() + "' -o '" + (d / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("of computing"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "out" / "sky.exr"));
}
