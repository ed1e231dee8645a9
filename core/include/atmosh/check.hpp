// atmosh/check.hpp — checks and parsing of user-given values, for every front end (the
// command line, the Python module, the libraries' option checks). `what` names the value
// as the user gave it (an option such as --lat, or a key); failures are one-line
// InputErrors naming it and the value.
#pragma once

#include <array>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <vector>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/format.hpp"

namespace atmosh {

// "<what>: <v> is out of range [lo, hi]" (numbers in the shortest round-trip form)
// unless v is finite and lo <= v <= hi.
inline double require_range(double v, double lo, double hi, const std::string& what) {
  if (!std::isfinite(v) || v < lo || v > hi)
    throw InputError(what + ": " + format_double(v) + " is out of range [" + format_double(lo) + ", " +
                     format_double(hi) + "]");
  return v;
}

// Comma-separated finite doubles ("1, 2.5,3").
inline std::vector<double> parse_list(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const char* b = item.c_str();
    char* e = nullptr;
    const double v = std::strtod(b, &e);
    while (e && *e == ' ') ++e;
    if (e == b || *e != '\0' || !std::isfinite(v))
      throw InputError(what + ": '" + text + "' is not a list of finite numbers");
    out.push_back(v);
  }
  if (out.empty()) throw InputError(what + ": '" + text + "' is empty");
  return out;
}

// Comma-separated integers, each in [lo, hi] ("4, 8,16"; "8.0" is 8): the list the
// command line takes for counts, bands, grids, orders. Fails as parse_list does for what is
// not a list of numbers, else "<what>: <item> in '<text>' is not an integer in <lo>..<hi>"
// for the first item that is not.
inline std::vector<int> parse_int_list(const std::string& text, const std::string& what, int lo, int hi) {
  std::vector<int> out;
  for (double v : parse_list(text, what)) {
    if (v != std::floor(v) || v < lo || v > hi)
      throw InputError(what + ": " + format_double(v) + " in '" + text + "' is not an integer in " + std::to_string(lo) +
                       ".." + std::to_string(hi));
    out.push_back(static_cast<int>(v));
  }
  return out;
}

// "x,y,z" -> three finite doubles.
inline std::array<double, 3> parse_triple(const std::string& text, const std::string& what) {
  const auto v = parse_list(text, what);
  if (v.size() != 3) throw InputError(what + ": '" + text + "' is not three numbers x,y,z");
  return {v[0], v[1], v[2]};
}

// "WxH" -> {W, H}, both in [1, 65536].
inline std::array<int, 2> parse_size(const std::string& text, const std::string& what) {
  const auto x = text.find_first_of("xX");
  auto bad = [&] { return InputError(what + ": '" + text + "' is not a size WxH (each 1..65536)"); };
  if (x == std::string::npos) throw bad();
  try {
    std::size_t p1 = 0, p2 = 0;
    const std::string a = text.substr(0, x), b = text.substr(x + 1);
    const long w = std::stol(a, &p1), h = std::stol(b, &p2);
    if (p1 != a.size() || p2 != b.size() || w < 1 || h < 1 || w > 65536 || h > 65536) throw bad();
    return {static_cast<int>(w), static_cast<int>(h)};
  } catch (const std::logic_error&) {
    throw bad();
  }
}

// A rendered image's size: "<what>: image size WxH is out of range (1..16384 a side)"
// unless both sides are in 1..16384 (the largest texture side GL 4.5 drivers must take
// is 16384, and the CPU renderers keep the same bound).
inline void require_image_size(int width, int height, const std::string& what) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw InputError(what + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                     " is out of range (1..16384 a side)");
}

}  // namespace atmosh
