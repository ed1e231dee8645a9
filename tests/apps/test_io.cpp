// Output writers: CSV with provenance, EXR round trip with named channels and
// attributes, atomic writes under a simulated failure, PNG plots.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "atmosh/error.hpp"
#include "atmosh/io/atomic.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/study.hpp"

namespace fs = std::filesystem;
using namespace atmosh::io;

namespace {
fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("atmosh_io_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
std::size_t count_files(const fs::path& d) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++n;
  return n;
}
}  // namespace

TEST(Csv, ProvenanceHeaderAndFullPrecisionRoundTrip) {
  const fs::path d = scratch("csv");
  CsvTable t({"sun_elevation_deg", "zenith_luminance_cd_m2", "label"});
  const double third = 1.0 / 3.0, tiny = 4.9406564584124654e-324, big = 1.7976931348623157e308;
  t.add_row({third, tiny, std::string("a,b \"quoted\"")});
  t.add_row({big, std::int64_t{-7}, std::string("plain")});
  Provenance p = Provenance::current();
  p.add("scene_turbidity", 2.5);
  t.write(d / "t.csv", p);
  const CsvData r = read_csv(d / "t.csv");
  for (const char* key : {"atmosh_version", "git_commit", "command_line", "run_utc", "host"})
    EXPECT_TRUE(r.provenance.count(key)) << key;
  EXPECT_EQ(r.provenance.at("scene_turbidity"), "2.5");
  // The run time is ISO 8601 UTC.
  EXPECT_EQ(r.provenance.at("run_utc").size(), 20u);
  EXPECT_EQ(r.provenance.at("run_utc").back(), 'Z');
  ASSERT_EQ(r.columns.size(), 3u);
  EXPECT_EQ(r.columns[1], "zenith_luminance_cd_m2");
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.number(0, 0), third);  // bit-exact round trip
  EXPECT_EQ(r.number(0, 1), tiny);
  EXPECT_EQ(r.number(1, 0), big);
  EXPECT_EQ(r.rows[0][2], "a,b \"quoted\"");
  EXPECT_EQ(r.number(1, 1), -7.0);
}

TEST(Csv, RaggedRowsAndBadNumbersAreInputErrors) {
  EXPECT_THROW(parse_csv("a,b\n1,2\n3\n", "x.csv"), atmosh::InputError);
  EXPECT_THROW(parse_csv("# only: comments\n", "x.csv"), atmosh::InputError);
  const CsvData d = parse_csv("a,b\n1,zz\n", "x.csv");
  EXPECT_THROW(d.number(0, 1), atmosh::InputError);
  EXPECT_THROW(d.column("c"), atmosh::InputError);
  EXPECT_THROW(read_csv("/nonexistent/file.csv"), atmosh::InputError);
  CsvTable t({"a"});
  EXPECT_THROW(t.add_row({1.0, 2.0}), std::invalid_argument);
}

TEST(Exr, RoundTripNamedChannelsAndAttributes) {
  const fs::path d = scratch("exr");
  ExrImage img(7, 5, {"R", "G", "B", "L_550nm", "sh_l2_m-1"});
  for (std::size_t c = 0; c < img.channels.size(); ++c)
    for (std::size_t i = 0; i < img.data[c].size(); ++i)
      img.data[c][i] = static_cast<float>(std::sin(0.37 * i + c) * std::pow(10.0, static_cast<double>(c) - 2));
  img.data[0][0] = std::numeric_limits<float>::denorm_min();
  img.string_attributes["units"] = "W m^-2 sr^-1 nm^-1";
  img.float_attributes["exposure"] = 0.125f;
  Provenance p;
  p.add("scene", "test");
  write_exr(d / "a.exr", img, p);
  const ExrImage back = read_exr(d / "a.exr");
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  for (const auto& name : img.channels) {
    ASSERT_GE(back.find_channel(name), 0) << name;
    EXPECT_EQ(back.channel(name), img.channel(name)) << name;  // float32, lossless
  }
  EXPECT_EQ(back.string_attributes.at("units"), "W m^-2 sr^-1 nm^-1");
  EXPECT_EQ(back.string_attributes.at("atmosh:scene"), "test");
  EXPECT_FLOAT_EQ(back.float_attributes.at("exposure"), 0.125f);
  EXPECT_EQ(count_files(d), 1u);  // no temporary left behind
}

TEST(Exr, UnreadableFileIsInputError) {
  const fs::path d = scratch("exr_bad");
  std::ofstream(d / "junk.exr") << "not an exr";
  EXPECT_THROW(read_exr(d / "junk.exr"), atmosh::InputError);
  EXPECT_THROW(read_exr(d / "missing.exr"), atmosh::InputError);
}

TEST(Atomic, FailingWriterLeavesOldFileAndNoTemporary) {
  const fs::path d = scratch("atomic");
  write_text_atomically(d / "out.csv", "old contents\n");
  // The writer starts writing, then fails half-way (as a killed run would).
  EXPECT_THROW(write_atomically(d / "out.csv",
                                [](const fs::path& tmp) {
                                  std::ofstream(tmp) << "half of the new";
                                  throw std::runtime_error("simulated failure");
                                }),
               std::runtime_error);
  std::ifstream f(d / "out.csv");
  std::string s((std::istreambuf_iterator<char>(f)), {});
  EXPECT_EQ(s, "old contents\n");
  EXPECT_EQ(count_files(d), 1u);
  // A failing first write leaves nothing at all.
  EXPECT_THROW(write_atomically(d / "new.exr", [](const fs::path&) { throw std::runtime_error("x"); }),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(d / "new.exr"));
  EXPECT_EQ(count_files(d), 1u);
}

TEST(Plot, LogLogStudyWritesCsvAndReadablePng) {
  const fs::path d = scratch("study");
  std::vector<StudyRow> rows;
  for (int i = 1; i <= 5; ++i) {
    rows.push_back({"jittered", "n=" + std::to_string(i * i), 1.0 / i, 0.5 / i, 1e-3 * i, {double(i)}});
    rows.push_back({"uniform", "n=" + std::to_string(i * i), 2.0 / i, 1.0 / i, 1e-3 * i, {double(i)}});
  }
  rows.push_back({"broken", "nan", std::nan(""), 0.0, -1.0, {0.0}});  // skipped on the plot, kept in CSV
  StudySpec spec;
  spec.title = "test study";
  spec.extra_columns = {"samples"};
  const auto files = write_study(d / "study", spec, rows, Provenance::current());
  ASSERT_EQ(files.size(), 2u);
  const CsvData c = read_csv(files[0]);
  EXPECT_EQ(c.columns, (std::vector<std::string>{"method", "setting", "error_max_rel", "error_rms_rel", "time_s",
                                                 "samples"}));
  EXPECT_EQ(c.rows.size(), rows.size());
  const cv::Mat png = cv::imread(files[1].string());
  ASSERT_FALSE(png.empty());
  EXPECT_EQ(png.cols, 1200);
  EXPECT_EQ(png.rows, 800);
  // Something other than white was drawn inside the plot frame.
  EXPECT_LT(cv::mean(png)[0], 254.0);
}

TEST(Plot, SwatchesAndToneMap) {
  const fs::path d = scratch("swatch");
  write_swatch_png(d / "s.png", "colours", {{{1, 0, 0}, "red"}, {{0, 0, 1}, "blue"}});
  const cv::Mat s = cv::imread((d / "s.png").string());
  ASSERT_FALSE(s.empty());
  // First patch is pure red (BGR order in OpenCV).
  const cv::Vec3b px = s.at<cv::Vec3b>(60, 30);
  EXPECT_EQ(px[2], 255);
  EXPECT_EQ(px[0], 0);
  std::vector<float> r = {0.0f, 1.0f, 1e9f, -1.0f}, g = r, b = r;
  b[3] = std::nanf("");
  write_tonemapped_png(d / "t.png", 2, 2, r, g, b, 1.0, "clamp");
  const cv::Mat t = cv::imread((d / "t.png").string());
  ASSERT_FALSE(t.empty());
  EXPECT_EQ(t.at<cv::Vec3b>(0, 0)[0], 0);    // 0 -> black
  EXPECT_EQ(t.at<cv::Vec3b>(0, 1)[0], 255);  // 1 -> white (sRGB(1) = 1)
  EXPECT_EQ(t.at<cv::Vec3b>(1, 0)[0], 255);  // clamped
  EXPECT_EQ(t.at<cv::Vec3b>(1, 1)[0], 0);    // NaN/negative -> black, never garbage
}
