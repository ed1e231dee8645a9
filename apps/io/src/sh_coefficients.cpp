// SH coefficient CSV readers (see sh_coefficients.hpp).
#include "atmosh/io/sh_coefficients.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/provenance.hpp"

namespace atmosh::io {

ShCoefficients parse_sh_coefficients(const std::string& text, const std::string& source) {
  const CsvData d = parse_csv(text, source);
  const std::size_t cl = d.column("l"), cm = d.column("m"), ci = d.column("index");
  ShCoefficients cf;
  std::vector<std::size_t> chan;
  for (std::size_t c = 0; c < d.columns.size(); ++c)
    if (c != cl && c != cm && c != ci) {
      cf.names.push_back(d.columns[c]);
      chan.push_back(c);
    }
  if (chan.empty()) throw InputError(source + ": no coefficient columns besides l, m, index");
  if (auto u = d.provenance.find("value_units"); u != d.provenance.end()) cf.value_units = u->second;
  const std::size_t n = d.rows.size();
  const auto L = static_cast<std::size_t>(std::llround(std::sqrt(static_cast<double>(n))));
  if (n == 0 || L * L != n)
    throw InputError(source + ": " + std::to_string(n) + " rows is not a square number of coefficients");
  cf.bands = static_cast<int>(L);
  cf.channels.assign(chan.size(), std::vector<double>(n));
  for (std::size_t r = 0; r < n; ++r) {
    const double l = d.number(r, cl), m = d.number(r, cm), idx = d.number(r, ci);
    if (idx != static_cast<double>(r) || l * (l + 1) + m != idx || std::abs(m) > l)
      throw InputError(source + ": row " + std::to_string(r + 1) + " has l, m, index = " + format_double(l) + ", " +
                       format_double(m) + ", " + format_double(idx) + " (expected index " + std::to_string(r) +
                       " = l(l+1)+m)");
    for (std::size_t k = 0; k < chan.size(); ++k) cf.channels[k][r] = d.number(r, chan[k]);  // finite or InputError
  }
  return cf;
}

void write_sh_coefficients(const std::filesystem::path& file, const ShCoefficients& cf, Provenance prov,
                           bool add_convention) {
  const std::size_t n = static_cast<std::size_t>(cf.bands) * static_cast<std::size_t>(cf.bands);
  if (cf.names.size() != cf.channels.size()) throw std::invalid_argument("write_sh_coefficients: names and channels differ in count");
  for (const auto& c : cf.channels)
    if (c.size() < n) throw std::invalid_argument("write_sh_coefficients: a channel has fewer than bands^2 coefficients");
  std::vector<std::string> cols = {"l", "m", "index"};
  for (const auto& name : cf.names) cols.push_back(name);
  CsvTable t(cols);
  for (int l = 0; l < cf.bands; ++l)
    for (int m = -l; m <= l; ++m) {
      const int i = l * (l + 1) + m;
      std::vector<CsvCell> row = {std::int64_t{l}, std::int64_t{m}, std::int64_t{i}};
      for (const auto& c : cf.channels) row.emplace_back(c[static_cast<std::size_t>(i)]);
      t.add_row(std::move(row));
    }
  if (add_convention) {
    prov.add("sh_convention", "real orthonormal, Condon-Shortley phase, index l(l+1)+m, t from +z, p from +x to +y");
    prov.add("sh_bands", std::to_string(cf.bands));
  }
  t.write(file, prov);
}

namespace {
std::string slurp(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw InputError("cannot read CSV file '" + file.string() + "'");
  std::ifstream f(file, std::ios::binary);
  if (!f) throw InputError("cannot read CSV file '" + file.string() + "'");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
}  // namespace

ShCoefficients read_sh_coefficients(const std::filesystem::path& file) {
  return parse_sh_coefficients(slurp(file), file.string());
}

std::vector<std::vector<double>> parse_sh_light(const std::string& text, const std::string& source, int bands) {
  if (bands < 1 || bands > 4096) throw InputError(source + ": light of " + std::to_string(bands) + " bands");
  const CsvData d = parse_csv(text, source);
  const std::size_t ci = d.column("index");
  std::vector<std::size_t> chan;
  for (std::size_t c = 0; c < d.columns.size(); ++c)
    if (d.columns[c] != "l" && d.columns[c] != "m" && c != ci && chan.size() < 3) chan.push_back(c);
  if (chan.empty()) throw InputError(source + ": no coefficient columns besides l, m, index");
  const std::size_t K = static_cast<std::size_t>(bands) * static_cast<std::size_t>(bands);
  std::vector<std::vector<double>> light(chan.size(), std::vector<double>(K, 0.0));
  for (std::size_t r = 0; r < d.rows.size(); ++r) {
    const double idx = d.number(r, ci);
    if (!(idx >= 0) || idx != std::floor(idx))
      throw InputError(source + ": row " + std::to_string(r + 1) + " has index " + format_double(idx));
    if (idx >= static_cast<double>(K)) continue;
    for (std::size_t k = 0; k < chan.size(); ++k) light[k][static_cast<std::size_t>(idx)] = d.number(r, chan[k]);
  }
  return light;
}

std::vector<std::vector<double>> read_sh_light(const std::filesystem::path& file, int bands) {
  return parse_sh_light(slurp(file), file.string(), bands);
}

}  // namespace atmosh::io
