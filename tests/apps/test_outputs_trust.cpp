// Outputs a reader can trust as they are: coefficient CSVs with a byte-order mark or a
// repeated column, directions near the largest double, the chromaticity of a black
// sky, the specification of plots (what is handed to the renderer: series, labels,
// notes; not pixels) and the tone-mapping side files.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/study.hpp"
#include "run_cli.hpp"

namespace fs = std::filesystem;
using atmosh::test::expect_bad_input;
using atmosh::test::run_cli;
using atmosh::test::scratch_dir;
using atmosh::test::slurp;
using namespace atmosh::io;

namespace {
// A constant-1 coefficient file with one band: c00 = sqrt(4 pi) reconstructs 1 everywhere.
std::string unit_coeffs(const std::string& header) {
  std::ostringstream os;
  os.precision(17);
  os << header << "\n0,0,0," << std::sqrt(4.0 * M_PI) << "\n";
  return os.str();
}
}  // namespace

// Spreadsheets save CSV with a UTF-8 byte-order mark: it is not part of the first
// column's name.
TEST(CsvInput, ByteOrderMarkIsSkipped) {
  const CsvData d = parse_csv("\xEF\xBB\xBF" + unit_coeffs("l,m,index,v"), "bom.csv");
  ASSERT_EQ(d.columns.size(), 4u);
  EXPECT_EQ(d.columns[0], "l");
  EXPECT_EQ(d.column("l"), 0u);
  // Also before provenance lines.
  const CsvData e = parse_csv("\xEF\xBB\xBF# a: b\nl,m\n1,2\n", "bom2.csv");
  EXPECT_EQ(e.provenance.at("a"), "b");
  EXPECT_EQ(e.columns[0], "l");
}

// A column named twice is ambiguous: refused, naming the column.
TEST(CsvInput, RepeatedColumnIsRefused) {
  try {
    parse_csv("l,m,index,r,r\n0,0,0,1,2\n", "dup.csv");
    FAIL() << "a repeated column was accepted";
  } catch (const atmosh::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'r'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("dup.csv"), std::string::npos) << e.what();
  }
}

TEST(CsvInput, ShEvalReadsBomAndRefusesRepeatedColumns) {
  const fs::path d = scratch_dir("atmosh_trust", "sh_eval");
  std::ofstream(d / "bom.csv", std::ios::binary) << "\xEF\xBB\xBF" << unit_coeffs("l,m,index,v");
  auto r = run_cli("sh eval '" + (d / "bom.csv").string() + "' --dir 0,0,1 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["values"]["v"].get<double>(), 1.0, 1e-12);
  std::ofstream(d / "dup.csv") << "l,m,index,v,v\n0,0,0,1,2\n";
  expect_bad_input("sh eval '" + (d / "dup.csv").string() + "' --dir 0,0,1 --json", "'v'");
}

// --dir 1e308,1e308,0: the squares overflow; the direction is (1, 1, 0) / sqrt(2).
TEST(CsvInput, ShEvalNormalisesHugeDirections) {
  const fs::path d = scratch_dir("atmosh_trust", "sh_dir");
  std::ofstream(d / "c.csv") << unit_coeffs("l,m,index,v");
  for (const char* dir : {"1e308,1e308,0", "1.7976931348623157e308,0,-1.7976931348623157e308", "1e-310,1e-310,0"}) {
    const auto r = run_cli("sh eval '" + (d / "c.csv").string() + "' --dir " + dir + " --json");
    ASSERT_EQ(r.exit_code, 0) << dir << ": " << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const double x = j["direction"][0], y = j["direction"][1], z = j["direction"][2];
    EXPECT_NEAR(std::hypot(x, y, z), 1.0, 1e-15) << dir;
    EXPECT_NEAR(std::fabs(x), M_SQRT1_2, 1e-15) << dir;
    EXPECT_NEAR(std::fabs(y) + std::fabs(z), M_SQRT1_2, 1e-15) << dir;
  }
}

// One rule: a black sky (sun far below the horizon, single scattering) has no
// chromaticity. `sky --json` says null where the study CSV says nan.
TEST(BlackSky, ChromaticityIsNullInJsonAndNanInCsv) {
  const fs::path d = scratch_dir("atmosh_trust", "black");
  // Single scattering, as the rule says (and no multiple-scattering table to build).
  const auto r = run_cli("sky --sun-elevation -40 --size 8x4 --scattering single -o '" + (d / "s.exr").string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["zenith_luminance_cd_m2"].get<double>(), 0.0);
  EXPECT_TRUE(j["zenith_xy"].is_null()) << j["zenith_xy"];
  EXPECT_EQ(j["sun_model"], "disc");  // the default
  EXPECT_NEAR(j["sun_angular_radius_deg"].get<double>(), std::asin(695700.0 / 149597870.7) * 180.0 / M_PI, 1e-12);
  const auto p = run_cli("sky --sun-elevation -40 --size 8x4 --scattering single --sun-model point -o '" + (d / "p.exr").string() + "' --json");
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_EQ(nlohmann::json::parse(p.out)["sun_model"], "point");
  expect_bad_input("sky --sun-elevation 5 --size 8x4 --sun-model square -o '" + (d / "q.exr").string() + "'", "square");
  const auto s = run_cli("study sun-elevation --from -40 --to -40 --step 1 --scattering single -o '" + (d / "study").string() + "'");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const CsvData c = read_csv(d / "study" / "sun_elevation.csv");
  ASSERT_EQ(c.rows.size(), 1u);
  EXPECT_EQ(c.number(0, c.column("zenith_luminance_cd_m2")), 0.0);
  EXPECT_EQ(c.rows[0][c.column("zenith_x")], "nan");
  EXPECT_EQ(c.rows[0][c.column("sun_x")], "nan");  // no direct sunlight either
}

// The scene key sun_model takes disc or point; anything else is bad input naming the key.
TEST(SunModelKey, SceneAcceptsDiscAndPointOnly) {
  const fs::path d = scratch_dir("atmosh_trust", "sun_model");
  for (const char* m : {"disc", "point"}) {
    std::ofstream(d / "s.toml") << "version = 1\nsun_model = \"" << m << "\"\n[rayleigh]\n[sun]\nelevation_deg = 10\n";
    const auto r = run_cli("scene check '" + (d / "s.toml").string() + "'");
    EXPECT_EQ(r.exit_code, 0) << m << ": " << r.err;
  }
  std::ofstream(d / "s.toml") << "version = 1\nsun_model = \"square\"\n[rayleigh]\n[sun]\nelevation_deg = 10\n";
  expect_bad_input("scene check '" + (d / "s.toml").string() + "'", "sun_model");
}

// ---- plot specifications -------------------------------------------------------------

// A series of zeros on a log axis (the reference row of a study: error 0) is drawn on
// the axis floor with a note, not silently dropped while its legend entry stays.
TEST(PlotSpec, AllZeroSeriesOnALogAxisIsDrawnOnTheFloorWithANote) {
  PlotSpec p;
  p.log_x = p.log_y = true;
  p.series.push_back({"fast", {1e-6, 1e-5}, {3e-3, 4e-4}});
  p.series.push_back({"spa", {2e-6, 3e-6}, {0.0, 0.0}});
  const PreparedPlot q = prepare_plot(p);
  ASSERT_EQ(q.spec.series.size(), 2u);
  const Series& z = q.spec.series[1];
  EXPECT_NE(z.label.find("spa"), std::string::npos);
  EXPECT_NE(z.label.find("floor"), std::string::npos) << z.label;
  EXPECT_EQ(z.style, Series::Style::Scatter);
  // The floor: the bottom of the log axis the other series set (1e-4 .. 1e-2).
  for (double y : z.y) EXPECT_DOUBLE_EQ(y, 1e-4);
  ASSERT_EQ(q.notes.size(), 1u);
  EXPECT_NE(q.notes[0].find("'spa'"), std::string::npos) << q.notes[0];
  // The untouched series is handed on as given.
  EXPECT_EQ(q.spec.series[0].y, p.series[0].y);
  // A series with some values <= 0 keeps its positive points, and a note counts the rest.
  p.series[0].y[1] = 0.0;
  const PreparedPlot r = prepare_plot(p);
  ASSERT_EQ(r.notes.size(), 2u);
  EXPECT_NE(r.notes[0].find("1 of 2"), std::string::npos) << r.notes[0];
}

// Error against run time: each method's points in order of run time (the rows come
// in the order of their settings), drawn as points.
TEST(PlotSpec, StudyPointsAreSortedByRunTime) {
  StudySpec spec;
  spec.title = "t";
  std::vector<StudyRow> rows = {{"a", "1", 1e-2, 0, 3.0, {}}, {"b", "1", 1e-3, 0, 1.0, {}},
                                {"a", "2", 1e-3, 0, 1.0, {}}, {"a", "3", 1e-4, 0, 2.0, {}}};
  const PlotSpec p = study_plot_spec(spec, rows);
  ASSERT_EQ(p.series.size(), 2u);
  EXPECT_EQ(p.series[0].label, "a");
  EXPECT_EQ(p.series[0].x, (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_EQ(p.series[0].y, (std::vector<double>{1e-3, 1e-4, 1e-2}));  // each y stays with its time
  EXPECT_EQ(p.series[0].style, Series::Style::Scatter);
  EXPECT_TRUE(p.log_x && p.log_y);
}

// Band-energy plots: one unit convention, built from the values' units.
TEST(PlotSpec, BandEnergyAxisUnitsFromTheValues) {
  const PlotSpec p = band_energy_plot_spec("e", {"r"}, {{1.0, 0.5}}, "cd/m^2");
  EXPECT_EQ(p.y_label, "energy sum_m c_lm^2 [(cd/m^2 sr)^2]");
  EXPECT_TRUE(p.log_y);
  EXPECT_EQ(p.series[0].x, (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(p.series[0].y, (std::vector<double>{1.0, 0.5}));
}

// The units of a band-energy plot come from the input: a sky image states cd/m^2, its
// coefficients carry it (# value_units), `sh bands` labels (cd/m^2 sr)^2.
TEST(PlotSpec, BandEnergyUnitsFollowTheInput) {
  const fs::path d = scratch_dir("atmosh_trust", "bands");
  auto r = run_cli("sky --sun-elevation 20 --size 32x16 --scattering single -o '" + (d / "s.exr").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("sh project '" + (d / "s.exr").string() + "' --bands 3 -o '" + (d / "c.csv").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_csv(d / "c.csv").provenance.at("value_units"), "cd/m^2");
  ::setenv("ATMOSH_PLOT_DATA", "1", 1);
  r = run_cli("sh bands '" + (d / "c.csv").string() + "' -o '" + (d / "b.csv").string() + "' --plot '" +
              (d / "b.png").string() + "'");
  ::unsetenv("ATMOSH_PLOT_DATA");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(d / "b.png.plot.json"))["y_label"], "energy sum_m c_lm^2 [(cd/m^2 sr)^2]");
}

// The plot data file (ATMOSH_PLOT_DATA=1) is the prepared plot.
TEST(PlotSpec, DataFileHoldsThePreparedPlot) {
  const fs::path d = scratch_dir("atmosh_trust", "plotdata");
  PlotSpec p;
  p.title = "T \"q\"";
  p.log_y = true;
  p.series.push_back({"zero", {1, 2}, {0, 0}});
  p.series.push_back({"one", {1, 2}, {1, 10}});
  set_plot_data_files(true);
  write_plot_png(d / "p.png", p);
  set_plot_data_files(false);
  const auto j = nlohmann::json::parse(slurp(d / "p.png.plot.json"));
  EXPECT_EQ(j["title"], "T \"q\"");
  ASSERT_EQ(j["series"].size(), 2u);
  EXPECT_EQ(j["series"][0]["y"][0].get<double>(), 1.0);  // floor of the axis 1 .. 10
  EXPECT_EQ(j["notes"].size(), 1u);
  write_plot_png(d / "q.png", p);
  EXPECT_FALSE(fs::exists(d / "q.png.plot.json"));  // off by default
}

// Every tone-mapped PNG has its side file: sky images and relit frames alike.
TEST(ToneMapSideFile, WrittenWithOperatorExposureAndSource) {
  const fs::path d = scratch_dir("atmosh_trust", "side");
  const fs::path f = write_tone_map_side_file(d / "a.png", "reinhard", 0.25, "rule", "a.exr");
  EXPECT_EQ(f, d / "a.png.json");
  const auto j = nlohmann::json::parse(slurp(f));
  EXPECT_EQ(j["tone_map"], "reinhard");
  EXPECT_EQ(j["exposure"].get<double>(), 0.25);
  EXPECT_EQ(j["exposure_rule"], "rule");
  EXPECT_EQ(j["source"], "a.exr");
}

TEST(ToneMapSideFile, PrtRelightFramesHaveOne) {
  const fs::path d = scratch_dir("atmosh_trust", "relight");
  auto r = run_cli("prt bake --scene-builtin sphere --resolution 6 --bands 2 --samples 16 --mode shadowed -o '" +
                   (d / "t.ply").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("prt relight '" + (d / "t.ply").string() + "' --light-dir 0,0,1 --size 16x16 -o '" +
              (d / "out").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int pngs = 0;
  for (const auto& e : fs::directory_iterator(d / "out"))
    if (e.path().extension() == ".png") {
      ++pngs;
      fs::path side = e.path();
      side += ".json";
      ASSERT_TRUE(fs::exists(side)) << side;
      const auto j = nlohmann::json::parse(slurp(side));
      EXPECT_GT(j["exposure"].get<double>(), 0.0) << side;
      EXPECT_FALSE(j["tone_map"].get<std::string>().empty());
    }
  EXPECT_GE(pngs, 2);  // ao and frame_0000
}
