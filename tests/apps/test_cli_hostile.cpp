// Hostile input to the command line: numbers (threads, exposure, quality options,
// fractional time steps), outputs that would leave the output folder or overwrite
// each other, temporaries of killed runs, the sun's chromaticity of the day study,
// sweep identities end to end, and progress on stderr.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "atmosh/io/csv.hpp"
#include "run_cli.hpp"

using atmosh::test::count_lines;
using atmosh::test::run_cli;
namespace fs = std::filesystem;

namespace {
fs::path scratch(const std::string& name) { return atmosh::test::scratch_dir("atmosh_cli_hostile", name); }
void expect_bad(const std::string& args, const std::string& names) { atmosh::test::expect_bad_input(args, names); }
std::string q(const fs::path& p) { return "'" + p.string() + "'"; }
// Cheap sky settings for CLI tests: coarse tables and single scattering (no
// multiple-scattering table to build).
const std::string kCheap = " --shells 8 --segments 4 --samples 1 --scattering single";

// Runs a shell command line (with {atmosh} in it replaced by the binary); exit code.
int shell(std::string cmd, const fs::path& err_file) {
  const std::string bin = std::string("'") + ATMOSH_BIN + "'";
  for (std::size_t p; (p = cmd.find("{atmosh}")) != std::string::npos;) cmd.replace(p, 8, bin);
  const int st = std::system((cmd + " >/dev/null 2>" + q(err_file)).c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}
}  // namespace

TEST(CliHostile, ThreadCountsRefusedOrResolved) {
  const fs::path d = scratch("threads");
  expect_bad("sky --sun-elevation 10 --size 8x4 -o " + q(d / "s.exr") + " --threads -1", "--threads -1");
  expect_bad("study sun-elevation --from 0 --to 1 -o " + q(d / "st") + " --threads -3", "--threads -3");
  expect_bad("sh project in.exr --bands 2 --threads -1 -o " + q(d / "c.csv"), "--threads -1");
  // --threads 0 under `taskset -c 0`: one CPU may be used, so one worker; provenance says so.
  if (std::system("command -v taskset >/dev/null 2>&1") != 0) GTEST_SKIP() << "no taskset (util-linux)";
  const int rc = shell("taskset -c 0 {atmosh} study sun-elevation --from 0 --to 2 --step 1 --threads 0" + kCheap + " -o " +
                           q(d / "one"),
                       d / "err.txt");
  ASSERT_EQ(rc, 0) << atmosh::test::slurp(d / "err.txt");
  const auto csv = atmosh::io::read_csv(d / "one" / "sun_elevation.csv");
  EXPECT_EQ(csv.provenance.at("threads"), "1");
  EXPECT_EQ(csv.provenance.at("available_cpus"), "1");
}

TEST(CliHostile, QualityOptionsNamedAsTyped) {
  const fs::path d = scratch("quality");
  const std::string base = "sky --sun-elevation 10 --size 8x4 -o " + q(d / "s.exr");
  expect_bad(base + " --shells 0", "--shells 0");
  expect_bad(base + " --shells 8 --segments 9", "--segments 9");
  expect_bad(base + " --samples 0", "--samples 0");
  expect_bad(base + " --max-piece-tau 0", "--max-piece-tau 0");
  expect_bad("study day --lat 0 --lon 0 --date 2026-01-03 -o " + q(d / "day") + " --shells 0", "--shells 0");
  EXPECT_FALSE(fs::exists(d / "s.exr"));
}

TEST(CliHostile, RelightExposureMustBeFinite) {
  const fs::path d = scratch("exposure");
  for (const char* e : {"nan", "inf", "-1"})
    expect_bad("prt relight missing.ply --light-dir 0,0,1 --exposure " + std::string(e) + " -o " + q(d / "r"),
               "--exposure");
}

// 0.5 s steps keep their fraction in time_utc, and the --to endpoint is a row even
// where the span in Julian days rounds a hair short of a whole number of steps.
TEST(CliHostile, SunFractionalStepsKeepFractionAndEndpoint) {
  auto rows = [](const std::string& args) {
    const auto r = run_cli("sun --lat 0 --lon 0 " + args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::vector<std::string> t;
    std::istringstream in(r.out);
    std::string line;
    bool header = true;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      if (header) { header = false; continue; }
      t.push_back(line.substr(0, line.find(',')));
    }
    return t;
  };
  const auto half = rows("--from 2026-06-21T12:00:00Z --to 2026-06-21T12:00:02Z --step 0.5s");
  const std::vector<std::string> expect = {"2026-06-21T12:00:00.0Z", "2026-06-21T12:00:00.5Z", "2026-06-21T12:00:01.0Z",
                                           "2026-06-21T12:00:01.5Z", "2026-06-21T12:00:02.0Z"};
  EXPECT_EQ(half, expect);
  const auto tenth = rows("--from 2026-06-21T12:00:00Z --to 2026-06-21T12:00:03Z --step 0.1s");
  ASSERT_EQ(tenth.size(), 31u);
  EXPECT_EQ(tenth.back(), "2026-06-21T12:00:03.0Z");
  EXPECT_EQ(tenth[7], "2026-06-21T12:00:00.7Z");
  const auto third = rows("--from 2026-06-21T00:00:00Z --to 2026-06-21T00:00:03Z --step 0.3s");
  ASSERT_EQ(third.size(), 11u);
  EXPECT_EQ(third.back(), "2026-06-21T00:00:03.0Z");
  // Whole seconds keep the plain form.
  const auto whole = rows("--from 2026-06-21T12:00:00Z --to 2026-06-21T12:00:20Z --step 10s");
  EXPECT_EQ(whole, (std::vector<std::string>{"2026-06-21T12:00:00Z", "2026-06-21T12:00:10Z", "2026-06-21T12:00:20Z"}));
}

TEST(CliHostile, SceneOutputsStayInsideTheOutputFolder) {
  const fs::path d = scratch("outputs");
  auto scene = [&](const std::string& name, const std::string& outputs) {
    const fs::path p = d / name;
    std::ofstream(p) << "version = 1\n[sun]\nelevation_deg = 10.0\n" << outputs;
    return p;
  };
  const auto up = scene("up.toml", "[[output]]\nkind = \"optical-depth\"\nfile = \"../x\"\n");
  for (const std::string& cmd : std::vector<std::string>{"scene check ", "plan ", "run -o " + q(d / "out") + " "})
    expect_bad(cmd + q(up), "output[0].file");
  EXPECT_FALSE(fs::exists(d / "x.csv")) << "an output left the output folder";
  expect_bad("scene check " + q(scene("deep.toml", "[[output]]\nkind = \"optical-depth\"\nfile = \"a/../../x\"\n")),
             "output[0].file");
  expect_bad("scene check " + q(scene("abs.toml", "[[output]]\nkind = \"optical-depth\"\nfile = \"/tmp/x\"\n")),
             "absolute");
  // A sky image sky.exr writes sky.png; so does a sun track sky.exr (sky.csv, sky.png).
  const auto clash = scene("clash.toml",
                           "[[output]]\nkind = \"sky-image\"\nfile = \"sky.exr\"\nsize = [8, 4]\n"
                           "[[output]]\nkind = \"optical-depth\"\nfile = \"sky.exr\"\n");
  expect_bad("scene check " + q(clash), "sky.png");
  const auto r = run_cli("run " + q(clash) + " -o " + q(d / "clash_out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(fs::exists(d / "clash_out" / "sky.exr")) << "work started before the clash was found";
  expect_bad("scene check " + q(scene("same.toml",
                                      "[[output]]\nkind = \"optical-depth\"\nfile = \"t.csv\"\n"
                                      "[[output]]\nkind = \"lut-convergence\"\nfile = \"./t.csv\"\n")),
             "output[1].file");
  // Folders inside the output folder are fine.
  const auto ok = scene("ok.toml", "[[output]]\nkind = \"optical-depth\"\nfile = \"tables/od.csv\"\n");
  EXPECT_EQ(run_cli("scene check " + q(ok)).exit_code, 0);
}

// A killed run leaves .NAME.tmp-PID-N.ext; the next run writing into that folder
// removes it when PID is no longer a process, and leaves a live process's alone.
TEST(CliHostile, StaleTemporariesOfKilledRunsRemoved) {
  const fs::path d = scratch("stale");
  pid_t dead = 0;
  for (pid_t p = 4000000; p > 3000000; p -= 7919)
    if (::kill(p, 0) != 0 && errno == ESRCH) {
      dead = p;
      break;
    }
  ASSERT_GT(dead, 0);
  const fs::path stale = d / (".track.tmp-" + std::to_string(dead) + "-0.csv");
  const fs::path live = d / (".track.tmp-" + std::to_string(::getpid()) + "-3.png");
  const fs::path other = d / ".notes.tmp-x.txt";
  for (const auto& p : {stale, live, other}) std::ofstream(p) << "half a file";
  const auto r = run_cli("sun --lat 0 --lon 0 --from 2026-06-21T12:00:00Z --to 2026-06-21T13:00:00Z --step 1h -o " +
                         q(d / "track.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other));
  EXPECT_TRUE(fs::exists(d / "track.csv"));
}

// The transmitted sun's chromaticity does not depend on the Earth-Sun distance: the
// day study (distance of the date, 0.983 AU on 3 January) must report the same
// sun_x, sun_y as the elevation study (1 AU) at the same sun elevation, and its
// direct-normal illuminance must be the 1 AU value times (1 AU / d)^2.
TEST(CliHostile, DaySunChromaticityIsTheSpectrumsChromaticity) {
  const fs::path d = scratch("day_sun");
  const fs::path sc = d / "scene.toml";
  std::ofstream(sc) << "version = 1\n[sun]\nelevation_deg = 10.0\n";
  auto r = run_cli("study day --scene " + q(sc) + " --lat 0 --lon 0 --date 2026-01-03 --step 4h --no-frames" + kCheap +
                   " -o " + q(d / "day"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto day = atmosh::io::read_csv(d / "day" / "day.csv");
  std::size_t noon = day.rows.size();
  for (std::size_t i = 0; i < day.rows.size(); ++i)
    if (day.rows[i][0] == "2026-01-03T12:00:00Z") noon = i;
  ASSERT_LT(noon, day.rows.size());
  const std::string elev = day.rows[noon][day.column("sun_elevation_deg")];
  r = run_cli("study sun-elevation --scene " + q(sc) + " --azimuth 180 --from " + elev + " --to " + elev + " --step 1" +
              kCheap + " -o " + q(d / "elev"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto one_au = atmosh::io::read_csv(d / "elev" / "sun_elevation.csv");
  ASSERT_EQ(one_au.rows.size(), 1u);
  EXPECT_NEAR(day.number(noon, day.column("sun_x")), one_au.number(0, one_au.column("sun_x")), 1e-9);
  EXPECT_NEAR(day.number(noon, day.column("sun_y")), one_au.number(0, one_au.column("sun_y")), 1e-9);
  // Earth-Sun distance on the date from `atmosh sun` (NREL SPA).
  r = run_cli("sun --lat 0 --lon 0 --time 2026-01-03T12:00:00Z --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto k = r.out.find("\"earth_sun_distance_au\"");
  ASSERT_NE(k, std::string::npos) << r.out;
  const double au = std::strtod(r.out.c_str() + r.out.find(':', k) + 1, nullptr);
  ASSERT_NEAR(au, 0.9833, 0.001);
  const auto lux = "sun_direct_normal_illuminance_lux";
  EXPECT_NEAR(day.number(noon, day.column(lux)) / one_au.number(0, one_au.column(lux)), 1.0 / (au * au), 1e-9);
}

// End to end: a killed run of sweep A, then --resume of sweep B into the same
// folder; and a completed sweep resumed computes nothing.
TEST(CliHostile, SweepIdentityAtTheCommandLine) {
  const fs::path d = scratch("sweep");
  std::ofstream(d / "a.toml") << "version = 1\n[[parameter]]\nkey = \"sun.elevation_deg\"\nvalues = [5.0, 10.0]\n";
  std::ofstream(d / "b.toml") << "version = 1\n[[parameter]]\nkey = \"sun.elevation_deg\"\nvalues = [6.0, 11.0]\n";
  auto r = run_cli("sweep " + q(d / "a.toml") + kCheap + " -o " + q(d / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto a = atmosh::io::read_csv(d / "out" / "sweep.csv");
  for (const char* k : {"sweep_id", "lut_shells", "view_segments", "samples_per_segment", "max_piece_optical_depth"})
    EXPECT_EQ(a.provenance.count(k), 1u) << k;
  EXPECT_EQ(a.provenance.at("lut_shells"), "8");
  r = run_cli("sweep " + q(d / "a.toml") + kCheap + " --resume -o " + q(d / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2 resumed, 0 computed"), std::string::npos) << r.out;
  r = run_cli("sweep " + q(d / "b.toml") + kCheap + " --resume -o " + q(d / "out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(a.provenance.at("sweep_id")), std::string::npos) << r.err;
  // The same file with other settings is another sweep.
  r = run_cli("sweep " + q(d / "a.toml") + " --shells 12 --segments 4 --samples 1 --resume -o " + q(d / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
}

TEST(CliHostile, ProgressOnStderrUnlessQuiet) {
  const fs::path d = scratch("progress");
  const std::string study = "study sun-elevation --from 0 --to 2 --step 1" + kCheap + " -o ";
  // Shown after ATMOSH_PROGRESS_AFTER_S (2 s by default); stderr is a file here: lines.
  ASSERT_EQ(shell("ATMOSH_PROGRESS_AFTER_S=0 {atmosh} " + study + q(d / "a"), d / "err.txt"), 0);
  const std::string err = atmosh::test::slurp(d / "err.txt");
  EXPECT_NE(err.find("atmosh: study sun-elevation ..."), std::string::npos) << err;
  EXPECT_NE(err.find("atmosh: study sun-elevation: done in "), std::string::npos) << err;
  EXPECT_EQ(err.find('\r'), std::string::npos) << "a bar drawn into a file";
  for (const char* quiet : {" --quiet", " -q"}) {
    ASSERT_EQ(shell("ATMOSH_PROGRESS_AFTER_S=0 {atmosh} " + study + q(d / "b") + quiet, d / "err2.txt"), 0);
    EXPECT_EQ(atmosh::test::slurp(d / "err2.txt"), "") << quiet;
  }
  // A short step stays silent at the default threshold.
  ASSERT_EQ(shell("{atmosh} sun --lat 0 --lon 0 --time 2026-06-21T12:00:00Z", d / "err3.txt"), 0);
  EXPECT_EQ(atmosh::test::slurp(d / "err3.txt"), "");
}
