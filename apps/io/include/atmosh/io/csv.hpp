// atmosh/io/csv.hpp — tidy CSV tables with provenance.
//
// Layout of a written file:
//   # atmosh_version: 0.1.0
//   # git_commit: abc1234
//   # ... (one "# key: value" line per provenance entry)
//   col_a_unit,col_b_unit,...        (snake_case with unit suffix)
//   1.0000000000000002,2,...          (one row per sample, doubles round-trip)
// Strings containing a comma, quote or newline are quoted RFC 4180 style.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "atmosh/io/provenance.hpp"

namespace atmosh::io {

using CsvCell = std::variant<double, std::int64_t, std::string>;

class CsvTable {
 public:
  explicit CsvTable(std::vector<std::string> columns);
  // Throws std::invalid_argument when the row's size differs from the columns'.
  void add_row(std::vector<CsvCell> row);
  const std::vector<std::string>& columns() const { return columns_; }
  const std::vector<std::vector<CsvCell>>& rows() const { return rows_; }
  std::string to_string(const Provenance& provenance) const;
  // Atomic write (temp file + rename).
  void write(const std::filesystem::path& file, const Provenance& provenance) const;

 private:
  std::vector<std::string> columns_;
  std::vector<std::vector<CsvCell>> rows_;
};

// A CSV read back: provenance comments, header, and cells as strings.
struct CsvData {
  std::map<std::string, std::string> provenance;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;

  // Index of a column; throws atmosh::InputError naming the file and column.
  std::size_t column(const std::string& name) const;
  // Cell as a number; throws atmosh::InputError naming row, column and value.
  double number(std::size_t row, std::size_t col) const;
  std::string source;  // file name, for messages
};

// Throws atmosh::InputError (unreadable file, ragged rows, no header, a column name
// that appears twice). A leading UTF-8 byte-order mark is skipped.
CsvData read_csv(const std::filesystem::path& file);
CsvData parse_csv(const std::string& text, const std::string& source_name);

}  // namespace atmosh::io
