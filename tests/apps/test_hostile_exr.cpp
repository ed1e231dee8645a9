// Hostile EXR files: the header is walked before OpenEXR allocates by it. A string
// attribute declaring 2 GB made OpenEXR allocate it whole (out of memory under the
// fuzzer's 2 GB limit); a data window of 2^30 pixels a side made read_exr allocate by it;
// a channel list whose records did not fill its declared length made OpenEXR, which reads
// a channel list up to its empty name, read the rest of the header from elsewhere than
// the walk, and allocate a 1.86 GB string (libFuzzer; tests/fuzz/corpus_exr/chlist_desync.exr).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/io/exr.hpp"

namespace fs = std::filesystem;

namespace {
std::string corpus_file(const char* name) {
  std::ifstream f(fs::path(ATMOSH_SOURCE_DIR) / "tests" / "fuzz" / "corpus_exr" / name, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
std::string seed() { return corpus_file("equirect.exr"); }  // an 8 x 4 sky image written by `atmosh sky --size 8x4`
std::string error_of(const std::string& bytes) {
  const fs::path f = fs::temp_directory_path() / ("atmosh_hostile_" + std::to_string(::getpid()) + ".exr");
  std::ofstream(f, std::ios::binary) << bytes;
  std::string msg;
  try {
    (void)atmosh::io::read_exr(f, std::size_t{64} << 20);
  } catch (const atmosh::InputError& e) {
    msg = e.what();
  }
  fs::remove(f);
  return msg;
}
void put32(std::string& s, std::size_t at, std::int32_t v) { std::memcpy(s.data() + at, &v, 4); }
}  // namespace

TEST(HostileExr, HeaderIsCheckedBeforeOpenExrAllocatesByIt) {
  const std::string ok = seed();
  ASSERT_GT(ok.size(), 100u);
  EXPECT_EQ(error_of(ok), "");
  std::string big = ok;
  const std::size_t p = big.find(std::string("projection\0string\0", 18));
  ASSERT_NE(p, std::string::npos);
  put32(big, p + 18, 2000000000);
  EXPECT_NE(error_of(big).find("attribute 'projection' declares 2000000000 bytes"), std::string::npos) << error_of(big);
  std::string wide = ok;
  const std::size_t d = wide.find(std::string("dataWindow\0box2i\0", 17));
  ASSERT_NE(d, std::string::npos);
  put32(wide, d + 17 + 4 + 8, 1 << 30);  // max.x
  EXPECT_NE(error_of(wide).find("data window 1073741825 x 4"), std::string::npos) << error_of(wide);
  const std::string cut = error_of(ok.substr(0, 200));  // inside the header
  EXPECT_TRUE(cut.find("header ends") != std::string::npos || cut.find("more than the file holds") != std::string::npos)
      << cut;
  EXPECT_NE(error_of("not an exr").find("no EXR magic"), std::string::npos);
}

// Every attribute type OpenEXR reads by its own layout must have that layout exactly: a
// channel list with bytes after its end, a box2i of 12 bytes, and the fuzzer's file (a
// channel list cut inside a record) are refused with the attribute named; OpenEXR never
// sees them.
TEST(HostileExr, KnownAttributeTypesMustFillTheirLengthExactly) {
  const std::string ok = seed();
  const std::string tag("channels\0chlist\0", 16);
  const std::size_t c = ok.find(tag);
  ASSERT_NE(c, std::string::npos);
  std::int32_t len = 0;
  std::memcpy(&len, ok.data() + c + tag.size(), 4);
  std::string padded = ok;
  put32(padded, c + tag.size(), len + 16);
  padded.insert(c + tag.size() + 4 + static_cast<std::size_t>(len), std::string(16, 'x'));
  EXPECT_NE(error_of(padded).find("attribute 'channels' of type chlist holds bytes after the channel list's end"),
            std::string::npos)
      << error_of(padded);
  std::string box = ok;
  const std::size_t d = box.find(std::string("dataWindow\0box2i\0", 17));
  ASSERT_NE(d, std::string::npos);
  put32(box, d + 17, 12);
  EXPECT_NE(error_of(box).find("attribute 'dataWindow' of type box2i holds 12 bytes, not 16"), std::string::npos)
      << error_of(box);
  const std::string fuzzed = error_of(corpus_file("chlist_desync.exr"));
  EXPECT_NE(fuzzed.find("attribute 'channels' of type chlist holds"), std::string::npos) << fuzzed;
}
