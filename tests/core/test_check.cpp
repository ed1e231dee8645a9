// The parsing of user-given lists (atmosh/check.hpp): one integer-list parser for every
// option that takes counts, bands, grids or orders, its one-line messages naming the
// option, the bad item and the list as given.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "atmosh/check.hpp"
#include "atmosh/error.hpp"

namespace {

std::string message_of(const std::string& text, int lo, int hi) {
  try {
    atmosh::parse_int_list(text, "--grids", lo, hi);
  } catch (const atmosh::InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(ParseIntList, AcceptsIntegersInRangeAsWritten) {
  EXPECT_EQ(atmosh::parse_int_list("4, 8,16", "--grids", 1, 64), (std::vector<int>{4, 8, 16}));
  EXPECT_EQ(atmosh::parse_int_list("8.0,1e1", "--grids", 1, 64), (std::vector<int>{8, 10}));
  EXPECT_EQ(atmosh::parse_int_list("1,64", "--grids", 1, 64), (std::vector<int>{1, 64}));  // both ends
  EXPECT_EQ(atmosh::parse_int_list("0", "--bounces", 0, 16), (std::vector<int>{0}));
  EXPECT_EQ(atmosh::parse_int_list("3,3,1", "--grids", 1, 64), (std::vector<int>{3, 3, 1}));  // order kept
}

TEST(ParseIntList, NamesTheOptionTheItemAndTheList) {
  EXPECT_EQ(message_of("2,0", 1, 64), "--grids: 0 in '2,0' is not an integer in 1..64");
  EXPECT_EQ(message_of("8,65", 1, 64), "--grids: 65 in '8,65' is not an integer in 1..64");
  EXPECT_EQ(message_of("2.5", 1, 64), "--grids: 2.5 in '2.5' is not an integer in 1..64");
  EXPECT_EQ(message_of("-3,4", 1, 64), "--grids: -3 in '-3,4' is not an integer in 1..64");
  EXPECT_EQ(message_of("1e12", 1, 64), "--grids: 1e+12 in '1e12' is not an integer in 1..64");
  // not numbers at all: parse_list's message, the same shape
  EXPECT_EQ(message_of("1,x", 1, 64), "--grids: '1,x' is not a list of finite numbers");
  EXPECT_EQ(message_of("1,,2", 1, 64), "--grids: '1,,2' is not a list of finite numbers");
  EXPECT_EQ(message_of("nan", 1, 64), "--grids: 'nan' is not a list of finite numbers");
  EXPECT_EQ(message_of("", 1, 64), "--grids: '' is empty");
  for (const char* bad : {"2,0", "1,x", "", "2.5"})
    EXPECT_EQ(message_of(bad, 1, 64).find('\n'), std::string::npos) << bad;  // one line
}

}  // namespace
