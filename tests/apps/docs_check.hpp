// The docs read against what the program writes: file names the docs list for the main
// job (docs/outputs.md and docs/cli.md, between `<!-- main-job-files: begin/end -->`;
// every paragraph of docs/*.md that says what `atmosh demo` writes), the preset those
// paragraphs name, and the runnable examples (```sh blocks) of a page.
#pragma once

#include <fnmatch.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "atmosh/io/csv.hpp"
#include "run_cli.hpp"

namespace atmosh::test {

inline std::string doc_text(const std::string& name) {
  return slurp(std::filesystem::path(ATMOSH_SOURCE_DIR) / "docs" / name);
}

inline std::vector<std::string> doc_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// Backticked file names in `text`: `a.csv`, `dir/b_*.png.json`, shorthands `a.csv/.png`,
// `a.csv/png` and `a.{csv,png}` expanded.
inline std::vector<std::string> file_names_in(const std::string& text) {
  static const std::regex tick("`([^`]+)`");
  static const std::regex file(R"(^[A-Za-z0-9_./*-]+\.(csv|png|exr|json|ply|toml|txt)$)");
  std::vector<std::string> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), tick); it != std::sregex_iterator(); ++it) {
    std::string t = (*it)[1];
    std::vector<std::string> expanded;
    if (const auto b = t.find(".{"); b != std::string::npos && t.back() == '}') {
      std::stringstream exts(t.substr(b + 2, t.size() - b - 3));
      for (std::string e; std::getline(exts, e, ',');) expanded.push_back(t.substr(0, b + 1) + e);
    } else {
      // a.csv/.png or a.csv/png: the stem with each extension.
      static const std::regex pair(R"(^(.+)\.(\w+)/\.?(\w+)$)");
      std::smatch m;
      if (std::regex_match(t, m, pair) && std::regex_match(m[1].str() + "." + m[2].str(), file))
        expanded = {m[1].str() + "." + m[2].str(), m[1].str() + "." + m[3].str()};
      else
        expanded.push_back(t);
    }
    for (const auto& e : expanded)
      if (std::regex_match(e, file)) out.push_back(e);
  }
  return out;
}

// The text between the main-job-files markers of a page.
inline std::string main_job_block(const std::string& page) {
  const std::string text = doc_text(page);
  const auto a = text.find("<!-- main-job-files: begin -->"), b = text.find("<!-- main-job-files: end -->");
  EXPECT_NE(a, std::string::npos) << page << ": no main-job-files block";
  EXPECT_NE(b, std::string::npos) << page << ": no main-job-files end marker";
  if (a == std::string::npos || b == std::string::npos || b < a) return {};
  return text.substr(a, b - a);
}

inline bool matches(const std::string& pattern, const std::string& file) {
  return ::fnmatch(pattern.c_str(), file.c_str(), FNM_PATHNAME) == 0;
}

// Every file the docs name for the main job is written by the main job run into `out`
// (listed in its MANIFEST.txt), every written file is documented in outputs.md, and a
// preset named beside a file is the atmosphere its provenance records.
inline void check_docs_against_main_job(const std::filesystem::path& out) {
  std::vector<std::string> written;
  {
    std::ifstream m(out / "MANIFEST.txt");
    for (std::string l; std::getline(m, l);)
      if (!l.empty() && l[0] != '#') written.push_back(l);
  }
  ASSERT_FALSE(written.empty());
  auto written_somewhere = [&](const std::string& pattern) {
    for (const auto& w : written)
      if (matches(pattern, w)) return true;
    return false;
  };
  const std::vector<std::string> table = file_names_in(main_job_block("outputs.md"));
  EXPECT_GT(table.size(), 30u);
  for (const auto& f : table) EXPECT_TRUE(written_somewhere(f)) << "docs/outputs.md names " << f << ", not written";
  for (const auto& f : file_names_in(main_job_block("cli.md")))
    EXPECT_TRUE(written_somewhere(f) || f == "MANIFEST.txt") << "docs/cli.md names " << f << ", not written";
  for (const auto& w : written) {
    bool documented = false;
    for (const auto& f : table) documented = documented || matches(f, w);
    EXPECT_TRUE(documented) << w << " is written by the main job but not in docs/outputs.md";
  }
  // Paragraphs elsewhere that say what `atmosh demo` writes; a preset named in them
  // is the one the file records.
  static const char* const presets[] = {"earth-default", "earth-graphics", "earth-physical", "test-planet"};
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(ATMOSH_SOURCE_DIR) / "docs")) {
    if (entry.path().extension() != ".md") continue;
    const auto lines = doc_lines(slurp(entry.path()));
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (lines[i].find("`atmosh demo` writes") == std::string::npos) continue;
      std::string para;
      for (std::size_t j = i; j < lines.size() && !lines[j].empty() && (j == i || lines[j].rfind("* ", 0) != 0); ++j)
        para += lines[j] + "\n";
      const auto files = file_names_in(para);
      EXPECT_FALSE(files.empty()) << entry.path().filename() << ":" << i + 1;
      for (const auto& f : files) {
        EXPECT_TRUE(written_somewhere(f)) << entry.path().filename() << ":" << i + 1 << " names " << f
                                          << ", which the main job does not write";
        if (f.size() < 4 || f.substr(f.size() - 4) != ".csv" || !written_somewhere(f)) continue;
        const auto csv = io::read_csv(out / f);
        const auto atm = csv.provenance.find("atmosphere");
        for (const char* p : presets)
          if (para.find(p) != std::string::npos && atm != csv.provenance.end())
            EXPECT_EQ(atm->second, p) << entry.path().filename() << ":" << i + 1 << " says " << f << " is on " << p;
      }
    }
  }
}

// Runs the examples of docs/<page> in a fresh folder: ```toml blocks whose first line
// is `# file: NAME` are written to NAME; ```sh blocks run in order under bash -e with
// atmosh on the PATH (a command marked "by Cli.DemoQuickEndToEnd" is run there, with
// --quick, and skipped here); the files on `# writes:` lines must exist afterwards.
// Returns the number of commands run.
inline int run_doc_examples(const std::string& page) {
  const auto dir = scratch_dir("atmosh_docs", page);
  const auto lines = doc_lines(doc_text(page));
  const std::string bin_dir = std::filesystem::path(ATMOSH_BIN).parent_path().string();
  int commands = 0, block = 0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i] == "```toml" && i + 1 < lines.size() && lines[i + 1].rfind("# file: ", 0) == 0) {
      const std::string name = lines[i + 1].substr(8);
      std::string body;
      for (std::size_t j = i + 1; j < lines.size() && lines[j] != "```"; ++j) body += lines[j] + "\n";
      std::ofstream(dir / name) << body;
      continue;
    }
    if (lines[i] != "```sh") continue;
    std::string script = "set -euo pipefail\ncd '" + dir.string() + "'\nexport PATH='" + bin_dir + "':\"$PATH\"\n";
    std::vector<std::string> expect;
    std::size_t j = i + 1;
    for (; j < lines.size() && lines[j] != "```"; ++j) {
      const std::string& l = lines[j];
      if (l.rfind("# writes:", 0) == 0) {
        std::istringstream names(l.substr(9));
        for (std::string n; names >> n;) expect.push_back(n);
      } else if (l.find("by Cli.DemoQuickEndToEnd") != std::string::npos) {
        continue;
      } else if (!l.empty() && l[0] != '#') {
        script += l + "\n";
        ++commands;
      }
    }
    const auto sh = dir / ("block" + std::to_string(block++) + ".sh");
    std::ofstream(sh) << script;
    const auto log = dir / "log.txt";
    const int status = std::system(("bash '" + sh.string() + "' >'" + log.string() + "' 2>&1").c_str());
    EXPECT_EQ(status, 0) << page << ":" << i + 1 << ": the example fails:\n" << script << "\n" << slurp(log);
    for (const auto& f : expect) EXPECT_TRUE(std::filesystem::exists(dir / f)) << page << ":" << i + 1 << ": " << f;
    i = j;
  }
  return commands;
}

}  // namespace atmosh::test
