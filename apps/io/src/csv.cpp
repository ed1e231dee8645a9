#include "atmosh/io/csv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string_view>
#include <stdexcept>

#include "atmosh/error.hpp"
#include "atmosh/io/atomic.hpp"

namespace atmosh::io {

namespace {
std::string quote_if_needed(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}
std::string one_line(const std::string& s) {
  std::string r = s;
  for (char& c : r)
    if (c == '\n' || c == '\r') c = ' ';
  return r;
}
}  // namespace

CsvTable::CsvTable(std::vector<std::string> columns) : columns_(std::move(columns)) {
  if (columns_.empty()) throw std::invalid_argument("CsvTable needs at least one column");
}

void CsvTable::add_row(std::vector<CsvCell> row) {
  if (row.size() != columns_.size())
    throw std::invalid_argument("CSV row has " + std::to_string(row.size()) + " cells, expected " +
                                std::to_string(columns_.size()));
  rows_.push_back(std::move(row));
}

std::string CsvTable::to_string(const Provenance& provenance) const {
  std::ostringstream os;
  for (const auto& [k, v] : provenance.entries) os << "# " << k << ": " << one_line(v) << '\n';
  for (std::size_t i = 0; i < columns_.size(); ++i) os << (i ? "," : "") << quote_if_needed(columns_[i]);
  os << '\n';
  for (const auto& row : rows_) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i) os << ',';
      std::visit(
          [&](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, double>) os << format_double(v);
            else if constexpr (std::is_same_v<T, std::int64_t>) os << v;
            else os << quote_if_needed(v);
          },
          row[i]);
    }
    os << '\n';
  }
  return os.str();
}

void CsvTable::write(const std::filesystem::path& file, const Provenance& provenance) const {
  write_text_atomically(file, to_string(provenance));
}

std::size_t CsvData::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return i;
  throw InputError(source + ": no column '" + name + "'");
}

double CsvData::number(std::size_t row, std::size_t col) const {
  const std::string& s = rows.at(row).at(col);
  const char* begin = s.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0' || !std::isfinite(v))
    throw InputError(source + ": row " + std::to_string(row + 1) + ", column '" + columns.at(col) +
                     "': '" + s + "' is not a finite number");
  return v;
}

namespace {
std::vector<std::string> split_csv_line(const std::string& line, bool& open_quote_out) {
  std::vector<std::string> cells;
  std::string cur;
  bool q = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (q) {
      if (c == '"') {
        if (i + 1 < line.size() && line[i + 1] == '"') {
          cur += '"';
          ++i;
        } else {
          q = false;
        }
      } else {
        cur += c;
      }
    } else if (c == '"') {
      q = true;
    } else if (c == ',') {
      cells.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  cells.push_back(cur);
  open_quote_out = q;
  return cells;
}
}  // namespace

CsvData parse_csv(const std::string& text, const std::string& source_name) {
  CsvData d;
  d.source = source_name;
  // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first cell.
  const bool bom = text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0;
  std::istringstream is(bom ? text.substr(3) : text);
  std::string line;
  std::size_t lineno = 0;
  while (std::getline(is, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line[0] == '#') {
      const auto colon = line.find(':');
      if (colon != std::string::npos) {
        std::string key = line.substr(1, colon - 1);
        std::string val = line.substr(colon + 1);
        auto trim = [](std::string& s) {
          s.erase(0, s.find_first_not_of(' '));
          s.erase(s.find_last_not_of(' ') + 1);
        };
        trim(key);
        trim(val);
        d.provenance[key] = val;
      }
      continue;
    }
    bool open = false;
    auto cells = split_csv_line(line, open);
    if (open) throw InputError(source_name + ": line " + std::to_string(lineno) + ": unterminated quote");
    if (d.columns.empty()) {
      std::set<std::string_view> seen;
      for (const auto& c : cells)
        if (!seen.insert(c).second)
          throw InputError(source_name + ": line " + std::to_string(lineno) + ": column '" + c +
                           "' appears twice in the header");
      d.columns = std::move(cells);
    } else {
      if (cells.size() != d.columns.size())
        throw InputError(source_name + ": line " + std::to_string(lineno) + " has " +
                         std::to_string(cells.size()) + " cells, header has " + std::to_string(d.columns.size()));
      d.rows.push_back(std::move(cells));
    }
  }
  if (d.columns.empty()) throw InputError(source_name + ": no CSV header found");
  return d;
}

CsvData read_csv(const std::filesystem::path& file) {
  std::ifstream f(file, std::ios::binary);
  if (!f) throw InputError("cannot read CSV file '" + file.string() + "'");
  std::ostringstream ss;
  ss << f.rdbuf();
  return parse_csv(ss.str(), file.string());
}

}  // namespace atmosh::io
