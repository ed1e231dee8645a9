// Hostile mesh files: every fault the PLY walk finds is an InputError naming the file
// and the fault, before the mesh library sees the file. A truncated binary PLY
// aborted inside the library's triangulation (exit 134) and a binary header with no
// data read past the end of the file (exit 139).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/prt/mesh.hpp"

using namespace atmosh;
namespace fs = std::filesystem;

namespace {
fs::path dir() {
  static const fs::path d = [] {
    const fs::path p = fs::temp_directory_path() / ("atmosh_hostile_mesh_" + std::to_string(::getpid()));
    fs::create_directories(p);
    return p;
  }();
  return d;
}

template <class T>
void put(std::string& s, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}

// A binary PLY of the mesh: float x y z, uchar-count int lists.
std::string binary_ply(const prt::Mesh& m, bool big) {
  std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement vertex " + std::to_string(m.positions.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                  std::to_string(m.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : m.positions) {
    put(s, static_cast<float>(p.x), big);
    put(s, static_cast<float>(p.y), big);
    put(s, static_cast<float>(p.z), big);
  }
  for (const auto& t : m.triangles) {
    put(s, std::uint8_t{3}, big);
    for (auto v : t) put(s, static_cast<std::int32_t>(v), big);
  }
  return s;
}

fs::path write(const std::string& name, const std::string& bytes) {
  const fs::path f = dir() / name;
  std::ofstream(f, std::ios::binary) << bytes;
  return f;
}

std::string error_of(const fs::path& f) {
  try {
    prt::load_mesh(f);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(HostileMesh, ValidBinaryPlyLoadsInBothByteOrders) {
  const prt::Mesh m = prt::builtin_scene("sphere", 8);
  for (bool big : {false, true}) {
    const prt::Mesh r = prt::load_mesh(write(big ? "be.ply" : "le.ply", binary_ply(m, big)));
    ASSERT_EQ(r.positions.size(), m.positions.size());
    ASSERT_EQ(r.triangles, m.triangles);
    for (std::size_t i = 0; i < m.positions.size(); ++i)
      EXPECT_EQ(r.positions[i].z, static_cast<double>(static_cast<float>(m.positions[i].z)));
  }
}

TEST(HostileMesh, TruncatedPlyIsRefused) {
  const std::string full = binary_ply(prt::builtin_scene("sphere", 32), false);
  ASSERT_GT(full.size(), 3000u);
  const fs::path f = write("cut.ply", full.substr(0, 3000));  // `head -c 3000 mesh.ply`
  const std::string msg = error_of(f);
  EXPECT_EQ(msg.rfind(f.string() + ": PLY file ends inside vertex ", 0), 0u) << msg;
  // Cut in the faces, and a header with no data at all.
  EXPECT_NE(error_of(write("cut2.ply", full.substr(0, full.size() - 7))).find("ends inside face"), std::string::npos);
  const std::string header = full.substr(0, full.find("end_header\n") + 11);
  EXPECT_NE(error_of(write("header.ply", header)).find("ends inside vertex 0 of"), std::string::npos);
  // ASCII: a missing line and a short line.
  const std::string ascii = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_EQ(error_of(write("ok.ply", ascii)), "");
  EXPECT_NE(error_of(write("a1.ply", ascii.substr(0, ascii.size() - 8))).find("file ends at face 0 of 1"), std::string::npos);
  EXPECT_NE(error_of(write("a2.ply", ascii.substr(0, ascii.size() - 3))).find("face 0 has fewer values"), std::string::npos);
}

TEST(HostileMesh, PlyCountsIndicesAndValuesAreChecked) {
  const prt::Mesh m = prt::builtin_scene("sphere", 8);
  std::string bad = binary_ply(m, false);
  // The last face's last index -> 1e9.
  const std::int32_t big_index = 1000000000;
  std::memcpy(bad.data() + bad.size() - 4, &big_index, 4);
  EXPECT_NE(error_of(write("idx.ply", bad)).find("names vertex 1e+09 of"), std::string::npos);
  std::string nan = binary_ply(m, false);
  const float q = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan.data() + nan.find("end_header\n") + 11 + 4, &q, 4);  // vertex 0, y
  EXPECT_NE(error_of(write("nan.ply", nan)).find("vertex 0 has a non-finite y"), std::string::npos);
  std::string list = binary_ply(m, false);
  list[list.find("end_header\n") + 11 + 12 * m.positions.size()] = 0;  // face 0 lists no vertex
  EXPECT_NE(error_of(write("list.ply", list)).find("face 0 lists 0 items"), std::string::npos);
  const std::string huge = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                           "property float y\nproperty float z\nend_header\n";
  EXPECT_NE(error_of(write("huge.ply", huge)).find("has no count in 0..2147483648"), std::string::npos);
  EXPECT_NE(error_of(write("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n0\n"))
                .find("property type 'quad' is unknown"),
            std::string::npos);
  EXPECT_NE(error_of(write("magic.ply", "PLY?\n")).find("does not start with 'ply'"), std::string::npos);
}

// The mesh library's triangulation step aborted the process (exit 134, an internal
// assertion) on a triangle strip whose restarts (-1) leave segments of fewer than three
// vertices: its primitive-type flags claimed polygons that were not there. It also loses a
// strip's first triangle (a 4-vertex strip over a square came back as one triangle) and leaks
// on every strip longer than three (libFuzzer). So a file with triangle strips is refused,
// naming them; a polygon face is still cut into triangles.
TEST(HostileMesh, StripsAreRefusedAndPolygonsLoad) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string verts = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
  const std::string strip = head + "element tristrips 1\nproperty list int int vertex_indices\nend_header\n" + verts;
  for (const std::string list : {"5 0 1 -1 2 0\n", "1 -1\n", "7 0 1 2 -1 3 -1 -1\n", "4 0 1 3 2\n", "5 0 1 -2 8 1\n"}) {
    const std::string msg = error_of(write("strip.ply", strip + list));
    EXPECT_NE(msg.find("strip.ply: PLY has triangle strips"), std::string::npos) << list << msg;
  }
  // A unit square as one quad face: two triangles of total area 1, on the four file vertices.
  const prt::Mesh q = prt::load_mesh(write(
      "quad.ply", head + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + verts + "4 0 1 2 3\n"));
  ASSERT_EQ(q.triangles.size(), 2u);
  ASSERT_EQ(q.positions.size(), 4u);
  double area = 0;
  for (const auto& t : q.triangles) {
    const glm::dvec3 a = q.positions[t[0]], b = q.positions[t[1]], c = q.positions[t[2]];
    area += 0.5 * std::abs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
  }
  EXPECT_NEAR(area, 1.0, 1e-12);
}

// The mesh library reads a PLY header by words and takes its first format line; this walk
// read it by lines and let a later format line win. A file with a binary format line and
// then an ASCII one was walked as text and read by the library as binary: a list count
// of 540 024 885 from the digits "5 0 ", 6.2 GB allocated (libFuzzer;
// tests/fuzz/corpus_mesh_ply/two_formats.ply). A header now has one format line, version
// 1.0, and no words past what each line holds.
TEST(HostileMesh, PlyHeaderIsReadAsTheMeshLibraryReadsIt) {
  const std::string body = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_EQ(error_of(write("one.ply", "ply\nformat ascii 1.0\n" + body)), "");
  EXPECT_NE(error_of(write("two.ply", "ply\nformat binary_little_endian 1.0\nformat ascii 1.0\n" + body))
                .find("header has a second format line 'format ascii 1.0'"),
            std::string::npos);
  EXPECT_NE(error_of(write("ver.ply", "ply\nformat ascii 1.0 1.tle_endian\n" + body))
                .find("format line 'format ascii 1.0 1.tle_endian' is not 'format <type> 1.0'"),
            std::string::npos);
  EXPECT_NE(error_of(write("elw.ply", "ply\nformat ascii 1.0\nelement vertex 3 9\n" + body.substr(17)))
                .find("element line 'element vertex 3 9' has words after its count"),
            std::string::npos);
  EXPECT_NE(error_of(write("prw.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x y\n" + body.substr(34)))
                .find("property line 'property float x y' has words after its name"),
            std::string::npos);
  std::ifstream f(fs::path(ATMOSH_SOURCE_DIR) / "tests" / "fuzz" / "corpus_mesh_ply" / "two_formats.ply",
                  std::ios::binary);
  const std::string fuzzed((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  ASSERT_GT(fuzzed.size(), 1000u);
  EXPECT_NE(error_of(write("fuzzed.ply", fuzzed)).find("format line"), std::string::npos);
}

// A NUL byte inside an ASCII row ended the number for strtod unseen ("0\0\3..." read as 0),
// so the walk passed the file on, and the mesh library leaked memory reading it
// (libFuzzer; tests/fuzz/corpus_mesh_ply/nul_in_ascii.ply). Such a row is refused, naming
// it; a value with trailing letters still is.
TEST(HostileMesh, NulBytesInAsciiRowsAreRefused) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string rest = "\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n";
  EXPECT_EQ(error_of(write("clean.ply", head + "0 0 0" + rest)), "");
  const std::string nul = head + "0 0 0" + std::string("\0\3\0\3", 4) + rest;
  EXPECT_NE(error_of(write("nul.ply", nul)).find("vertex 0 has a NUL byte in an ASCII file"), std::string::npos);
  EXPECT_NE(error_of(write("alpha.ply", head + "0 0 0x" + rest)).find("vertex 0 has a value '0x' that is not a number"),
            std::string::npos);
}
