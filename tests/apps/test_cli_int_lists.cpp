// The command line's lists of integers (counts, bands, grids: atmosh::parse_int_list) fail
// alike in every subcommand: exit 2 before any work, one line naming the option, the bad
// item and the list as given, and the option's range.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "run_cli.hpp"

using atmosh::test::expect_bad_input;
using atmosh::test::scratch_dir;
namespace fs = std::filesystem;

TEST(CliIntLists, EverySubcommandNamesTheOptionTheItemAndTheRange) {
  const fs::path d = scratch_dir("atmosh_cli_int_lists", "bad");
  const std::string o = " -o '" + (d / "x").string() + "'";
  expect_bad_input("converge lut --shells 8,2" + o, "--shells: 2 in '8,2' is not an integer in 4..4096");
  expect_bad_input("converge lut --directions 16,4.5" + o, "--directions: 4.5 in '16,4.5' is not an integer in 4..4096");
  expect_bad_input("prt converge --depth-maps 256,9" + o, "--depth-maps: 9 in '256,9' is not an integer in 16..16384");
  expect_bad_input("prt converge --strata 0,4" + o, "--strata: 0 in '0,4' is not an integer in 1..2000");
  const std::string gi = "gi converge --scene-builtin sphere-on-plane";
  expect_bad_input(gi + " --grids 2,0" + o, "--grids: 0 in '2,0' is not an integer in 1..64");
  expect_bad_input(gi + " --radiosity-bands 1,4" + o, "--radiosity-bands: 4 in '1,4' is not an integer in 1..3");
  expect_bad_input(gi + " --lpv-grids x" + o, "--lpv-grids: 'x' is not a list of finite numbers");
  // "none" leaves out the rows of a study list that says so; the probe rows' lists need
  // numbers (with none, the probe grid's band count was read from an empty list)
  expect_bad_input(gi + " --grids none" + o, "--grids: 'none'");
  expect_bad_input(gi + " --bands-list none" + o, "--bands-list: 'none'");
  EXPECT_FALSE(fs::exists(d / "x"));
}
