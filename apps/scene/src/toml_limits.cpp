// Bounds on TOML text checked before parsing (see toml_limits.hpp), and the one
// parse entry point of scene and sweep files.
#include "atmosh/scene/toml_limits.hpp"

#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include "atmosh/error.hpp"
#include "toml_read.hpp"

namespace atmosh::scene {

namespace {

bool bare_key_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

// A single pass over the text with an explicit stack: no recursion, linear time.
class Scanner {
 public:
  Scanner(std::string_view s, const std::string& src, const TomlLimits& lim) : s_(s), src_(src), lim_(lim) {}

  void run() {
    if (s_.size() > lim_.max_bytes)
      fail("file has " + std::to_string(s_.size()) + " bytes (this reader's limit is " +
           std::to_string(lim_.max_bytes) + ")");
    bool expect_key = true, line_start = true;
    std::size_t pending_key_parts = 0;  // parts of the key whose value comes next
    while (i_ < s_.size()) {
      const char c = s_[i_];
      if (c == '\n') {
        ++line_;
        ++i_;
        if (stack_.empty()) {
          expect_key = line_start = true;
          pending_key_parts = 0;
        }
        continue;
      }
      if (c == ' ' || c == '\t' || c == '\r') {
        ++i_;
        continue;
      }
      if (c == '#') {
        while (i_ < s_.size() && s_[i_] != '\n') ++i_;
        continue;
      }
      if (expect_key && c != '}') {
        if (stack_.empty() && line_start && c == '[') {  // [table] or [[array of tables]]
          ++i_;
          if (i_ < s_.size() && s_[i_] == '[') ++i_;
          header_parts_ = scan_key("table header");
          check_depth(header_parts_);
        } else {
          const std::size_t before = i_;
          pending_key_parts = scan_key("key path");
          check_depth(pending_key_parts + 1);
          if (i_ < s_.size() && s_[i_] == '=') ++i_;
          else if (i_ == before) ++i_;  // not a key: let the parser report it
        }
        expect_key = line_start = false;
        continue;
      }
      line_start = false;
      if (c == '"' || c == '\'') {
        skip_string();
      } else if (c == '[' || c == '{') {
        stack_.push_back(c);
        opened_parts_.push_back(pending_key_parts);
        open_depth_ += pending_key_parts + 1;
        pending_key_parts = 0;
        if (stack_.size() > lim_.max_nesting)
          fail("arrays and inline tables nest " + std::to_string(stack_.size()) +
               " deep (this reader's limit is " + std::to_string(lim_.max_nesting) + ")");
        check_depth(0);
        expect_key = c == '{';
        ++i_;
      } else if (c == ']' || c == '}') {
        if (!stack_.empty()) {
          open_depth_ -= opened_parts_.back() + 1;
          stack_.pop_back();
          opened_parts_.pop_back();
        }
        ++i_;
      } else if (c == ',') {
        expect_key = !stack_.empty() && stack_.back() == '{';
        pending_key_parts = 0;
        ++i_;
      } else {
        ++i_;
      }
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(src_ + ":" + std::to_string(line_) + ": " + what);
  }

  void check_depth(std::size_t extra) const {
    const std::size_t depth = header_parts_ + open_depth_ + extra;
    if (depth > lim_.max_depth)
      fail("values nest " + std::to_string(depth) + " tables and arrays deep (this reader's limit is " +
           std::to_string(lim_.max_depth) + ")");
  }

  // A dotted key (bare and quoted parts); returns its number of parts.
  std::size_t scan_key(const char* what) {
    const std::size_t start = i_;
    std::size_t parts = 0;
    bool in_part = false;
    while (i_ < s_.size()) {
      const char c = s_[i_];
      if (c == ' ' || c == '\t') {
        ++i_;
      } else if (c == '"' || c == '\'') {
        if (!in_part) ++parts;
        in_part = true;
        skip_string();
      } else if (bare_key_char(c)) {
        if (!in_part) ++parts;
        in_part = true;
        ++i_;
      } else if (c == '.') {
        in_part = false;
        ++i_;
      } else {
        break;
      }
      if (parts > lim_.max_key_parts)
        fail(std::string(what) + " has more than " + std::to_string(lim_.max_key_parts) +
             " parts (this reader's limit is " + std::to_string(lim_.max_key_parts) + ")");
      if (i_ - start > lim_.max_key_bytes)
        fail(std::string(what) + " is longer than " + std::to_string(lim_.max_key_bytes) +
             " bytes (this reader's limit is " + std::to_string(lim_.max_key_bytes) + ")");
    }
    return parts;
  }

  // Skips a basic, literal or multi-line string starting at s_[i_] (a quote).
  void skip_string() {
    const char q = s_[i_];
    const bool multi = i_ + 2 < s_.size() && s_[i_ + 1] == q && s_[i_ + 2] == q;
    if (multi) {
      i_ += 3;
      while (i_ < s_.size()) {
        const char c = s_[i_];
        if (c == '\n') ++line_;
        if (q == '"' && c == '\\') {
          if (i_ + 1 < s_.size() && s_[i_ + 1] == '\n') ++line_;
          i_ += 2;
          continue;
        }
        if (c == q && i_ + 2 < s_.size() && s_[i_ + 1] == q && s_[i_ + 2] == q) {
          i_ += 3;
          for (int k = 0; k < 2 && i_ < s_.size() && s_[i_] == q; ++k) ++i_;  // """" ends with a quote
          return;
        }
        ++i_;
      }
      return;
    }
    ++i_;
    while (i_ < s_.size() && s_[i_] != q && s_[i_] != '\n') i_ += (q == '"' && s_[i_] == '\\') ? 2 : 1;
    if (i_ < s_.size() && s_[i_] == q) ++i_;
  }

  std::string_view s_;
  const std::string& src_;
  const TomlLimits& lim_;
  std::size_t i_ = 0, line_ = 1;
  std::vector<char> stack_;                // '[' or '{' of each open array / inline table
  std::vector<std::size_t> opened_parts_;  // key parts of the key that opened each
  std::size_t open_depth_ = 0;             // sum over open levels of (key parts + 1)
  std::size_t header_parts_ = 0;           // parts of the current table header
};

}  // namespace

void check_toml_limits(std::string_view text, const std::string& source_name, const TomlLimits& limits) {
  Scanner(text, source_name, limits).run();
}

std::string read_toml_file(const std::filesystem::path& file, const std::string& what, const TomlLimits& limits) {
  std::error_code ec;
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec))
    throw InputError(file.string() + ": " + what + " is not a regular file");
  const auto size = std::filesystem::file_size(file, ec);
  if (!ec && size > limits.max_bytes)
    throw InputError(file.string() + ": " + what + " has " + std::to_string(size) + " bytes (this reader's limit is " +
                     std::to_string(limits.max_bytes) + ")");
  std::ifstream f(file, std::ios::binary);
  if (!f) throw InputError("cannot read " + what + " '" + file.string() + "'");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

namespace detail {

toml::table parse_toml_checked(std::string_view text, const std::string& source_name) {
#ifndef ATMOSH_FUZZ_WITHOUT_TOML_PRESCAN  // defined only to show that the fuzzers find the parser's
                                          // crash without the pre-scan (docs/hostile-input.md, "Fuzzing")
  check_toml_limits(text, source_name);
#endif
  try {
    return toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    std::string d(e.description());
    if (auto p = d.find('\n'); p != std::string::npos) d.resize(p);
    throw InputError(source_name + ":" + std::to_string(e.source().begin.line) + ":" +
                     std::to_string(e.source().begin.column) + ": TOML syntax error: " + d);
  }
}

}  // namespace detail

}  // namespace atmosh::scene
