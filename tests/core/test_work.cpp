// The work policy (atmosh/work.hpp): time budgets as people write them, durations for
// messages, and step counts that cannot wrap.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "atmosh/error.hpp"
#include "atmosh/work.hpp"

namespace {

TEST(Work, TimeBudgetsAsWritten) {
  EXPECT_DOUBLE_EQ(atmosh::parse_time_budget("24h"), 86400.0);
  EXPECT_DOUBLE_EQ(atmosh::parse_time_budget("90m"), 5400.0);
  EXPECT_DOUBLE_EQ(atmosh::parse_time_budget("90min"), 5400.0);
  EXPECT_DOUBLE_EQ(atmosh::parse_time_budget("45s"), 45.0);
  EXPECT_DOUBLE_EQ(atmosh::parse_time_budget("2d"), 172800.0);
  EXPECT_DOUBLE_EQ(atmosh::parse_time_budget("1.5H"), 5400.0);
  EXPECT_DOUBLE_EQ(atmosh::parse_time_budget("3600"), 3600.0);
  EXPECT_DOUBLE_EQ(atmosh::kDefaultTimeBudgetS, 24 * 3600.0);
}

TEST(Work, BadTimeBudgetsNameTheOption) {
  for (const char* bad : {"", "lots", "0", "-1h", "1y", "nan", "inf", "1e13", "5 h", "h"}) {
    try {
      atmosh::parse_time_budget(bad);
      ADD_FAILURE() << "'" << bad << "' was accepted";
    } catch (const atmosh::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--max-time: '" + std::string(bad) + "'"), std::string::npos) << e.what();
    }
  }
}

TEST(Work, DurationsForMessages) {
  EXPECT_EQ(atmosh::format_duration(42), "42 s");
  EXPECT_EQ(atmosh::format_duration(600), "10 min");
  EXPECT_EQ(atmosh::format_duration(3 * 3600), "3 h");
  EXPECT_EQ(atmosh::format_duration(5 * 86400), "5 days");
  EXPECT_EQ(atmosh::format_duration(1e10), "317 years");  // 1e10 / (365.25 x 86400) = 316.9
  EXPECT_EQ(atmosh::format_duration(std::numeric_limits<double>::infinity()), "forever");
}

TEST(Work, EstimatesAddAndSaturate) {
  const atmosh::WorkEstimate a{1e9, 2e-9, "rays"}, b{1e6, 1e-6, "samples"};
  EXPECT_DOUBLE_EQ(a.cpu_seconds(), 2.0);
  EXPECT_DOUBLE_EQ(a.wall_seconds(4), 0.5);
  EXPECT_DOUBLE_EQ(a.wall_seconds(0), 2.0);  // no workers: counted as one
  const auto s = a + b;
  EXPECT_DOUBLE_EQ(s.cpu_seconds(), 3.0);
  EXPECT_EQ(s.unit, "rays");  // the larger piece names the unit
  EXPECT_DOUBLE_EQ(atmosh::mul_units(65536.0, 65536.0, 1e300), std::numeric_limits<double>::infinity());
  EXPECT_DOUBLE_EQ(atmosh::mul_units(-3.0, 5.0), 0.0);
}

}  // namespace
