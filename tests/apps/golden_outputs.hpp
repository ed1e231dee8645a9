// Normalised digests of the files the CLI writes, for the before/after output
// comparison (Cli.OutputsUnchangedByRefactor): everything the command line writes must
// stay byte-identical across a refactor, apart from what depends on the run itself —
// the time, the host, the version and commit, the command line (it names the output
// folder), the thread counts, and measured run times.
//
// What is masked (replaced by "*"):
// - provenance entries (CSV "# key: value" lines, PLY "comment atmosh:key value" lines,
//   EXR "atmosh:key" attributes, JSON object members) whose key is run-dependent: see
//   run_dependent_key();
// - CSV columns and JSON members that hold a measured time or rate: see timing_name();
// - in a plot's data file (<name>.png.plot.json), the values of an axis whose label is
//   in seconds ("[s]"): the run times of the convergence plots.
// A PNG is hashed whole unless its plot data file has such a timing axis: the picture
// then draws measured times, and it is skipped (its plot data are compared instead).
// Text files are kept line by line (so a difference names its line); binary files (EXR
// pixels, PNG) are reduced to a 64-bit FNV-1a hash of their bytes.
#pragma once

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "atmosh/io/exr.hpp"
#include "atmosh/io/hash.hpp"

namespace atmosh::test::golden {

namespace fs = std::filesystem;

inline bool ends_with(const std::string& s, const std::string& t) {
  return s.size() >= t.size() && s.compare(s.size() - t.size(), t.size(), t) == 0;
}
inline bool contains(const std::string& s, const std::string& t) { return s.find(t) != std::string::npos; }

// A column or member that holds a measured time or rate (time_s, build_time_s,
// lookup_time_ns, rays_per_s, ...).
inline bool timing_name(const std::string& name) {
  return ends_with(name, "_s") || ends_with(name, "_ns") || ends_with(name, "_ms") || ends_with(name, "_us") ||
         name == "time" || name == "seconds" || contains(name, "seconds") ||
         contains(name, "rate") || contains(name, "speedup") || contains(name, "elapsed") || contains(name, "duration");
}

// A provenance key whose value depends on the run rather than on the inputs.
inline bool run_dependent_key(const std::string& key) {
  static const char* const keys[] = {"atmosh_version", "git_commit", "command_line", "run_utc",    "host",
                                     "host_cores",     "available_cpus", "threads",  "build_threads", "timing",
                                     "machine_note",   "version",    "commit",       "date"};
  for (const char* k : keys)
    if (key == k) return true;
  return timing_name(key) || contains(key, "time_s") || contains(key, "timing");
}

inline std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string l;
  while (std::getline(in, l)) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    lines.push_back(l);
  }
  return lines;
}

// CSV fields, quotes kept as written (the digest compares text).
inline std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> f(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    if (c == ',' && !quoted) {
      f.emplace_back();
      continue;
    }
    f.back() += c;
  }
  return f;
}

inline std::string join_csv(const std::vector<std::string>& f) {
  std::string s;
  for (std::size_t i = 0; i < f.size(); ++i) s += (i ? "," : "") + f[i];
  return s;
}

inline std::string hash_bytes(const std::string& bytes) {
  io::ContentHash h;
  h.add(bytes);
  return "fnv1a64 " + h.hex() + " bytes " + std::to_string(bytes.size());
}

inline std::string read_all(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// "# key: value" -> "# key: *" where the key is run-dependent.
inline std::string mask_hash_comment(const std::string& line) {
  const auto colon = line.find(':');
  if (colon == std::string::npos || line.size() < 3) return line;
  const std::string key = line.substr(2, colon - 2);
  return run_dependent_key(key) ? "# " + key + ": *" : line;
}

// Rows and provenance lines of the GPU methods (lut_gpu, gpu-depthmap*) are there only
// where an EGL device is, and their values depend on the driver: left out.
inline bool gpu_line(const std::string& first_field) { return contains(first_field, "gpu"); }

inline std::vector<std::string> normalise_csv(const std::string& text) {
  std::vector<std::string> out;
  std::vector<bool> masked;
  bool header_seen = false;
  for (const auto& l : split_lines(text)) {
    if (!l.empty() && l[0] == '#') {
      if (!gpu_line(l.substr(0, l.find(':')))) out.push_back(mask_hash_comment(l));
      continue;
    }
    auto f = split_csv(l);
    if (header_seen && gpu_line(f[0])) continue;
    if (!header_seen) {
      header_seen = true;
      for (const auto& name : f) masked.push_back(timing_name(name));
      out.push_back(l);
      continue;
    }
    for (std::size_t i = 0; i < f.size() && i < masked.size(); ++i)
      if (masked[i]) f[i] = "*";
    out.push_back(join_csv(f));
  }
  return out;
}

inline void mask_json(nlohmann::json& j) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (!it.value().is_object() && !it.value().is_array() && run_dependent_key(it.key()))
        it.value() = "*";
      else
        mask_json(it.value());
    }
  } else if (j.is_array()) {
    for (auto& e : j) mask_json(e);
  }
}

// A plot's data file: the values of an axis in seconds are measured run times.
inline bool plot_has_timing_axis(const nlohmann::json& j, bool* x_axis = nullptr, bool* y_axis = nullptr) {
  const auto secs = [&](const char* k) { return j.contains(k) && j[k].is_string() && contains(j[k].get<std::string>(), "[s]"); };
  const bool x = secs("x_label"), y = secs("y_label");
  if (x_axis) *x_axis = x;
  if (y_axis) *y_axis = y;
  return x || y;
}

inline std::vector<std::string> normalise_json(const std::string& text, bool plot_data) {
  auto j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return split_lines(text);
  if (plot_data) {
    bool x = false, y = false;
    plot_has_timing_axis(j, &x, &y);
    // Points are drawn in the order of their run times: with one axis masked, the
    // other's values are compared as a sorted list.
    const auto masked_and_sorted = [](nlohmann::json& series, const char* masked, const char* kept) {
      if (!series.contains(masked)) return;
      series[masked] = "*";
      if (series.contains(kept) && series[kept].is_array()) {
        std::vector<double> v;
        for (const auto& e : series[kept])
          if (e.is_number()) v.push_back(e.get<double>());
        std::sort(v.begin(), v.end());
        series[kept] = v;
      }
    };
    if (j.contains("series") && j["series"].is_array()) {
      nlohmann::json kept = nlohmann::json::array();
      for (auto s : j["series"]) {
        if (s.contains("label") && s["label"].is_string() && gpu_line(s["label"].get<std::string>())) continue;
        if (x) masked_and_sorted(s, "x", "y");
        if (y) masked_and_sorted(s, "y", "x");
        kept.push_back(s);
      }
      j["series"] = kept;
    }
  } else {
    mask_json(j);
  }
  return split_lines(j.dump(1));
}

// PLY: the header's provenance comments masked; the body (ASCII or binary) kept as text
// lines for ASCII, hashed for binary.
inline std::vector<std::string> normalise_ply(const std::string& bytes) {
  const auto end = bytes.find("end_header\n");
  if (end == std::string::npos) return {hash_bytes(bytes)};
  const std::string header = bytes.substr(0, end + 11);
  std::vector<std::string> out;
  bool ascii = false;
  for (const auto& l : split_lines(header)) {
    if (l.rfind("format ascii", 0) == 0) ascii = true;
    if (l.rfind("comment atmosh:", 0) == 0) {
      const auto sp = l.find(' ', 15);
      const std::string key = l.substr(15, sp == std::string::npos ? std::string::npos : sp - 15);
      out.push_back(run_dependent_key(key) ? "comment atmosh:" + key + " *" : l);
    } else {
      out.push_back(l);
    }
  }
  const std::string body = bytes.substr(end + 11);
  if (ascii) {
    for (auto& l : split_lines(body)) out.push_back(std::move(l));
  } else {
    out.push_back(hash_bytes(body));
  }
  return out;
}

inline std::vector<std::string> normalise_exr(const fs::path& p) {
  const auto e = io::read_exr(p);
  std::vector<std::string> out;
  out.push_back("size " + std::to_string(e.width) + "x" + std::to_string(e.height));
  for (const auto& [k, v] : e.string_attributes) {
    const std::string key = k.rfind("atmosh:", 0) == 0 ? k.substr(7) : k;
    out.push_back("attr " + k + " = " + (run_dependent_key(key) ? std::string("*") : v));
  }
  for (const auto& [k, v] : e.float_attributes) {
    std::ostringstream s;
    s.precision(9);
    s << v;
    out.push_back("float " + k + " = " + (run_dependent_key(k) ? std::string("*") : s.str()));
  }
  for (std::size_t c = 0; c < e.channels.size(); ++c) {
    const auto& d = e.data[c];
    const std::string bytes(reinterpret_cast<const char*>(d.data()), d.size() * sizeof(float));
    out.push_back("channel " + e.channels[c] + " " + hash_bytes(bytes));
  }
  return out;
}

// One file's normalised lines.
inline std::vector<std::string> normalise_file(const fs::path& p) {
  const std::string name = p.filename().string();
  const std::string ext = p.extension().string();
  if (ext == ".exr") return normalise_exr(p);
  const std::string bytes = read_all(p);
  if (ext == ".csv") return normalise_csv(bytes);
  if (ext == ".json") return normalise_json(bytes, ends_with(name, ".plot.json"));
  if (ext == ".ply") return normalise_ply(bytes);
  if (ext == ".png") {
    const fs::path plot = p.string() + ".plot.json";
    if (fs::exists(plot)) {
      const auto j = nlohmann::json::parse(read_all(plot), nullptr, false);
      if (!j.is_discarded() && plot_has_timing_axis(j)) return {"skipped: the plot draws measured run times"};
    }
    return {hash_bytes(bytes)};
  }
  if (ext == ".txt" || ext == ".toml" || ext == ".md") {
    std::vector<std::string> out;
    for (const auto& l : split_lines(bytes)) out.push_back(l.size() > 1 && l[0] == '#' ? mask_hash_comment(l) : l);
    return out;
  }
  return {hash_bytes(bytes)};
}

// Digest of a folder: "=== relative/path" then its normalised lines, files sorted by path.
inline std::string digest_folder(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), dir));
  std::sort(files.begin(), files.end());
  std::string s;
  for (const auto& f : files) {
    s += "=== " + f.generic_string() + "\n";
    for (const auto& l : normalise_file(dir / f)) s += l + "\n";
  }
  return s;
}

// Stdout of a command: JSON masked like a JSON file, anything else line by line.
// In text, `folder` (the scratch folder) is written {d} and durations ("in 0.14 s",
// "12 ms") are masked.
inline std::string digest_stdout(const std::string& label, const std::string& out, const std::string& folder) {
  std::string s = "=== stdout of " + label + "\n";
  std::string text = out;
  for (std::size_t p = text.find(folder); !folder.empty() && p != std::string::npos; p = text.find(folder, p))
    text.replace(p, folder.size(), "{d}");
  static const std::regex duration(R"((^|[^\w.])[0-9][-+0-9.eE]* ?(s|ms|us|µs|ns|min)\b)");
  const auto lines = normalise_json(text, false);
  for (const auto& l : lines) s += std::regex_replace(l, duration, "$1* $2") + "\n";
  return s;
}

// The first difference between two digests: "file: line N: expected '...', got '...'",
// or an empty string when they agree.
inline std::string first_difference(const std::string& expected, const std::string& actual) {
  const auto e = split_lines(expected), a = split_lines(actual);
  std::string file = "(start)";
  int line_in_file = 0;
  for (std::size_t i = 0; i < std::max(e.size(), a.size()); ++i) {
    const std::string* el = i < e.size() ? &e[i] : nullptr;
    const std::string* al = i < a.size() ? &a[i] : nullptr;
    if (el && el->rfind("=== ", 0) == 0) {
      file = el->substr(4);
      line_in_file = 0;
    } else {
      ++line_in_file;
    }
    if (!el || !al || *el != *al) {
      std::ostringstream m;
      m << file << ": line " << line_in_file << " of its digest: expected '" << (el ? *el : std::string("<end>"))
        << "', got '" << (al ? *al : std::string("<end>")) << "'";
      return m.str();
    }
  }
  return {};
}

}  // namespace atmosh::test::golden
