// atmosh/io/sh_coefficients.hpp — SH coefficient CSV files as `atmosh sh project`
// writes them: columns l, m, index (= l(l+1)+m, rows in index order from 0), then
// one column per channel (real orthonormal SH, Condon-Shortley phase).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "atmosh/io/provenance.hpp"

namespace atmosh::io {

struct ShCoefficients {
  int bands = 0;                                 // rows = bands^2
  std::vector<std::string> names;                // channel column names
  std::vector<std::vector<double>> channels;     // [channel][index], finite
  std::string value_units;                       // provenance line `value_units` (of the projected values), or empty
};

// Strict reader: a square number of rows, each with the right l, m, index, and
// finite values. Throws atmosh::InputError naming the file (and row) otherwise.
ShCoefficients parse_sh_coefficients(const std::string& text, const std::string& source_name);
ShCoefficients read_sh_coefficients(const std::filesystem::path& file);

// The one writer (atomic, with provenance): columns l, m, index, then one column per
// channel named by `names`, rows in index order. add_convention appends the
// provenance lines sh_convention and sh_bands; a caller that states the convention
// in its own words passes false. Throws std::invalid_argument when the channels do
// not hold bands^2 coefficients each or the names do not match them.
void write_sh_coefficients(const std::filesystem::path& file, const ShCoefficients& coefficients,
                           Provenance provenance, bool add_convention = true);

// A light for relighting: the first (up to) three channel columns, coefficients of
// `bands` bands (missing ones are zero, rows of higher bands are ignored); the
// `index` column places each row. InputError for a bad index or a non-finite value.
std::vector<std::vector<double>> parse_sh_light(const std::string& text, const std::string& source_name, int bands);
std::vector<std::vector<double>> read_sh_light(const std::filesystem::path& file, int bands);

}  // namespace atmosh::io
