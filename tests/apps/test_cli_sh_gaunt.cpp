// `atmosh sh gaunt`: the JSON contract (key `value`, full precision) against a closed form,
// and bad input (exit 2, the bad value named).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>

#include "run_cli.hpp"

using atmosh::test::run_cli;

TEST(CliSh, GauntJsonAndBadInput) {
  // Y_10 Y_10 Y_20: (3/4pi) sqrt(5/4pi) int z^2 (3z^2-1)/2 dOmega = (2/5) sqrt(5/4pi)
  auto r = run_cli("sh gaunt 1 0 1 0 2 0 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["value"].get<double>(), 0.4 * std::sqrt(5 / (4 * std::numbers::pi)), 1e-14);
  // negative orders are positional values; Y_1-1^2 Y_22 = -(2/5) sqrt(15/16pi)
  r = run_cli("sh gaunt 1 -1 1 -1 2 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["value"].get<double>(), -0.4 * std::sqrt(15 / (16 * std::numbers::pi)),
              1e-14);
  atmosh::test::expect_bad_input("sh gaunt 1 2 1 0 2 0 --json", "M1");
  atmosh::test::expect_bad_input("sh gaunt -1 0 1 0 2 0 --json", "L1");
}
