// atmosh sun: exit codes and JSON contract, run through the real binary.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

namespace {
struct CliRun {
  int rc;
  std::string out;
};
CliRun run_cli(const std::string& args) {
  const std::string cmd = std::string(ATMOSH_BIN) + " " + args + " 2>/dev/null";
  std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
  std::string out;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p.get())) > 0) out.append(buf.data(), n);
  const int status = pclose(p.release());
  return {WEXITSTATUS(status), out};
}
}  // namespace

TEST(SunCli, JsonContractOnWorkedExample) {
  // Reda & Andreas 2008, Table A5.1: zenith 50.11162 (refracted), azimuth 194.34024.
  const CliRun r = run_cli("sun --lat 39.742476 --lon -105.1786 --height 1830.14 --time 2003-10-17T12:30:30-07:00 "
                    "--pressure 820 --temperature 11 --delta-t 67 --json");
  ASSERT_EQ(r.rc, 0);
  const auto j = nlohmann::json::parse(r.out);
  for (const char* k : {"zenith_deg", "azimuth_deg", "elevation_deg", "apparent_zenith_deg", "apparent_elevation_deg",
                        "declination_deg", "hour_angle_deg", "equation_of_time_min", "earth_sun_distance_au",
                        "sunrise_utc", "transit_utc", "sunset_utc", "polar"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_NEAR(j["apparent_zenith_deg"].get<double>(), 50.11162, 5e-6);
  EXPECT_NEAR(j["azimuth_deg"].get<double>(), 194.34024, 5e-6);
  EXPECT_TRUE(j["polar"].is_null());
  EXPECT_EQ(j["sunrise_utc"], "2003-10-17T13:12:43Z");  // 06:12:43 at -7 h (NREL spa_tester.c)
}

TEST(SunCli, PolarDayHasNullRiseSet) {
  const CliRun r = run_cli("sun --lat 78.2232 --lon 15.6267 --time 2024-06-21T12:00:00Z --json");
  ASSERT_EQ(r.rc, 0);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["polar"], "day");
  EXPECT_TRUE(j["sunrise_utc"].is_null());
  EXPECT_TRUE(j["sunset_utc"].is_null());
}

TEST(SunCli, BadInputExitsTwo) {
  EXPECT_EQ(run_cli("sun --lat 10 --lon 0 --time 2016-12-31T23:59:60Z").rc, 2);       // leap second
  EXPECT_EQ(run_cli("sun --lat 10 --lon 0 --time 6001-01-01T00:00:00Z").rc, 2);       // beyond SPA
  EXPECT_EQ(run_cli("sun --lat 10 --lon 0 --time -2001-06-01T00:00:00Z").rc, 2);      // before SPA
  EXPECT_EQ(run_cli("sun --lat 10 --lon 0 --time 2200-01-01T00:00Z --algorithm fast").rc, 2);  // Grena range
  EXPECT_EQ(run_cli("sun --lat 95 --lon 0 --time 2024-01-01T00:00Z").rc, 2);
  EXPECT_EQ(run_cli("sun --lat 10 --lon 0 --from 2024-01-02T00:00Z --to 2024-01-01T00:00Z").rc, 2);
}

TEST(SunCli, RangeWritesOneRowPerStep) {
  const CliRun r = run_cli("sun --lat 48.85 --lon 2.35 --from 2024-03-20T00:00Z --to 2024-03-20T01:00Z --step 10min");
  ASSERT_EQ(r.rc, 0);
  int rows = 0;
  std::size_t pos = 0;
  while ((pos = r.out.find("\n2024-03-20T", pos)) != std::string::npos) {
    ++rows;
    ++pos;
  }
  EXPECT_EQ(rows, 7);
}
