#include "atmosh/scene/sweep.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <toml++/toml.h>

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/io/atomic.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/hash.hpp"
#include "atmosh/scene/toml_limits.hpp"
#include "toml_read.hpp"

namespace atmosh::scene {

namespace fs = std::filesystem;
using Value = std::variant<double, std::int64_t, std::string>;

namespace {

std::string slurp(const fs::path& p, const std::string& what) {
  std::ifstream f(p, std::ios::binary);
  if (!f) throw InputError("cannot read " + what + " '" + p.string() + "'");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// A computed range value rounded to 15 significant digits: from + i * step carries
// the rounding error of the product (2e-6 + 3 * 2e-6 = 7.999999999999999e-06), which
// a user comparing with the literal 8e-6 would not expect.
double round_range_value(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.15g", v);
  return std::strtod(b, nullptr);
}

std::vector<Value> read_values(const toml::table& t, const std::string& path, const std::string& src) {
  std::vector<Value> out;
  struct Fail {  // a function object, so that it can be [[noreturn]]
    const std::string &src, &path;
    [[noreturn]] void operator()(const std::string& key, const std::string& what) const {
      throw InputError(src + ": " + path + "." + key + ": " + what);
    }
  } const fail{src, path};
  std::set<std::string> known = {"key", "values", "from", "to", "step", "count"};
  for (const auto& [k, v] : t)
    if (!known.count(std::string(k.str()))) fail(std::string(k.str()), "unknown key");
  if (const auto* arr = t.get_as<toml::array>("values")) {
    if (t.contains("from") || t.contains("to")) fail("values", "give either values or from/to, not both");
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const toml::node& n = *arr->get(i);
      if (auto x = n.as_integer()) out.emplace_back(x->get());
      else if (auto f = n.as_floating_point()) {
        if (!std::isfinite(f->get())) fail("values[" + std::to_string(i) + "]", "not finite");
        out.emplace_back(f->get());
      } else if (auto s = n.as_string()) out.emplace_back(s->get());
      else fail("values[" + std::to_string(i) + "]", "expected a number or string");
    }
  } else if (t.contains("values")) {
    fail("values", "expected an array");
  } else {
    auto num = [&](const char* key) -> std::optional<double> {
      const toml::node* n = t.get(key);
      if (!n) return std::nullopt;
      if (auto x = n->as_integer()) return static_cast<double>(x->get());
      if (auto f = n->as_floating_point()) {
        if (!std::isfinite(f->get())) fail(key, "not finite");
        return f->get();
      }
      fail(key, "expected a number");
    };
    const auto from = num("from"), to = num("to"), step = num("step");
    const toml::node* cn = t.get("count");
    if (!from || !to) fail("values", "missing (give values = [...] or from, to and step or count)");
    if (step && cn) fail("step", "give either step or count, not both");
    if (step) {
      if (!(*step > 0)) fail("step", "must be > 0");
      const double n = std::floor((*to - *from) / *step + 1e-9);
      if (n < 0) fail("to", "is below from");
      if (n > 1e6) fail("step", "gives more than a million values");
      for (int i = 0; i <= static_cast<int>(n); ++i) out.emplace_back(round_range_value(*from + i * *step));
    } else if (cn) {
      auto c = cn->as_integer();
      if (!c || c->get() < 1 || c->get() > 1000000) fail("count", "must be an integer in [1, 1000000]");
      const auto n = c->get();
      for (std::int64_t i = 0; i < n; ++i)
        out.emplace_back(n == 1 ? *from
                                : round_range_value(*from + (*to - *from) * static_cast<double>(i) /
                                                                 static_cast<double>(n - 1)));
    } else {
      fail("step", "missing (or give count)");
    }
  }
  if (out.empty()) fail("values", "is empty");
  return out;
}

std::string value_cell(const Value& v) { return override_value_string(Override{"", v}); }

// The fixed header of a sweep's journal and CSV.
std::vector<std::string> columns_for(const SweepSpec& spec, const SweepOutputs& outputs) {
  std::vector<std::string> cols = {"point"};
  cols.insert(cols.end(), spec.keys.begin(), spec.keys.end());
  for (const auto& [name, v] : outputs) cols.push_back(name);
  cols.push_back("time_s");
  return cols;
}

// The lines of a journal or CSV: provenance ("# key: value"), the header, the rows.
struct SweepText {
  std::map<std::string, std::string> provenance;
  std::string header;
  std::vector<std::string> rows;
  std::size_t complete_bytes = 0;  // up to the last newline (a torn last line is dropped)
};

SweepText read_sweep_text(const std::string& text) {
  SweepText t;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const auto nl = text.find('\n', pos);
    if (nl == std::string::npos) break;  // torn last line
    const std::string line = text.substr(pos, nl - pos);
    pos = t.complete_bytes = nl + 1;
    if (t.header.empty() && line.rfind("# ", 0) == 0) {
      const auto colon = line.find(": ");
      if (colon != std::string::npos) t.provenance[line.substr(2, colon - 2)] = line.substr(colon + 2);
    } else if (t.header.empty()) {
      t.header = line;
    } else if (!line.empty()) {
      t.rows.push_back(line);
    }
  }
  return t;
}

int row_point(const std::string& line, const fs::path& file) {
  const std::string cell = line.substr(0, line.find(','));
  int idx = -1;
  const auto r = std::from_chars(cell.data(), cell.data() + cell.size(), idx);
  if (r.ec != std::errc() || r.ptr != cell.data() + cell.size())
    throw InputError(file.string() + ": row '" + line.substr(0, 40) + "' does not start with a point number");
  return idx;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + v[i];
  return s;
}

}  // namespace

SweepSpec parse_sweep(std::string_view text, const std::string& src, const fs::path& base_dir) {
  toml::table root = detail::parse_toml_checked(text, src);
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    if (key != "version" && key != "scene" && key != "mode" && key != "parameter")
      throw InputError(src + ": " + key + ": unknown key");
  }
  const auto version = root["version"].value<std::int64_t>();
  if (!version || *version != 1) throw InputError(src + ": version: missing or not 1");
  SweepSpec spec;
  spec.source = src;
  if (const toml::node* n = root.get("scene")) {
    auto s = n->as_string();
    if (!s) throw InputError(src + ": scene: expected a file name");
    fs::path p = s->get();
    if (p.is_relative()) p = base_dir / p;
    spec.base_scene_text = read_toml_file(p, "scene file");
    spec.base_scene_source = p.string();
  } else {
    spec.base_scene_text = std::string(default_scene_toml());
    spec.base_scene_source = "<built-in default scene>";
  }
  const std::string mode = root["mode"].value<std::string>().value_or("grid");
  if (mode != "grid" && mode != "zip") throw InputError(src + ": mode: '" + mode + "' is not one of grid, zip");
  const auto* params = root.get_as<toml::array>("parameter");
  if (!params || params->empty()) throw InputError(src + ": parameter: missing (need at least one [[parameter]])");
  std::vector<std::vector<Value>> values;
  for (std::size_t i = 0; i < params->size(); ++i) {
    const std::string path = "parameter[" + std::to_string(i) + "]";
    const auto* t = params->get(i)->as_table();
    if (!t) throw InputError(src + ": " + path + ": expected a table");
    const auto key = (*t)["key"].value<std::string>();
    if (!key || key->empty()) throw InputError(src + ": " + path + ".key: missing");
    for (const auto& k : spec.keys)
      if (k == *key) throw InputError(src + ": " + path + ".key: '" + *key + "' appears twice");
    spec.keys.push_back(*key);
    values.push_back(read_values(*t, path, src));
  }
  if (mode == "zip") {
    for (std::size_t i = 1; i < values.size(); ++i)
      if (values[i].size() != values[0].size())
        throw InputError(src + ": parameter[" + std::to_string(i) + "].values: zip mode needs equal lengths (" +
                         std::to_string(values[i].size()) + " vs " + std::to_string(values[0].size()) + ")");
    for (std::size_t j = 0; j < values[0].size(); ++j) {
      std::vector<Override> pt;
      for (std::size_t i = 0; i < values.size(); ++i) pt.push_back({spec.keys[i], values[i][j]});
      spec.points.push_back(std::move(pt));
    }
  } else {
    std::size_t total = 1;
    for (const auto& v : values) {
      total *= v.size();
      if (total > 10000000) throw InputError(src + ": the grid has more than 10 million points");
    }
    for (std::size_t p = 0; p < total; ++p) {
      std::vector<Override> pt(values.size());
      std::size_t r = p;
      for (std::size_t i = values.size(); i-- > 0;) {
        pt[i] = {spec.keys[i], values[i][r % values[i].size()]};
        r /= values[i].size();
      }
      spec.points.push_back(std::move(pt));
    }
  }
  return spec;
}

SweepSpec load_sweep(const fs::path& file) {
  return parse_sweep(read_toml_file(file, "sweep file"), file.string(), file.has_parent_path() ? file.parent_path() : ".");
}

std::string sweep_identity(const SweepSpec& spec, const SweepSettings& settings) {
  io::ContentHash h;
  h.field("atmosh sweep identity 1");
  h.field("keys");
  for (const auto& k : spec.keys) h.field(k);
  h.field("points " + std::to_string(spec.points.size()));
  for (const auto& pt : spec.points) {
    for (const auto& o : pt) {
      // The type matters too: 2 (integer) and 2.0 set different TOML types.
      h.field(std::to_string(o.value.index()));
      h.field(value_cell(o.value));
    }
    h.field("/");
  }
  h.field("base scene");
  std::string scene = spec.base_scene_text;
  try {  // normalized: comments, layout and key order do not matter
    std::ostringstream os;
    os << detail::parse_toml_checked(spec.base_scene_text, spec.base_scene_source);
    scene = os.str();
  } catch (const InputError&) {
    // unparsable or beyond the limits: the raw bytes (the run fails on it anyway)
  } catch (const toml::parse_error&) {
  }
  h.field(scene);
  h.field("settings");
  for (const auto& [k, v] : settings) {
    h.field(k);
    h.field(v);
  }
  return h.hex();
}

SweepResult run_sweep(const SweepSpec& spec, const SweepEvaluator& eval, const SweepOptions& opt) {
  if (opt.shards < 1 || opt.shard < 1 || opt.shard > opt.shards)
    throw InputError("--shard " + std::to_string(opt.shard) + "/" + std::to_string(opt.shards) +
                     ": need 1 <= k <= N");
  const int total = static_cast<int>(spec.points.size());
  std::vector<int> mine;
  for (int i = 0; i < total; ++i)
    if (i % opt.shards == opt.shard - 1) mine.push_back(i);
  // Validate every point's scene before any work.
  std::vector<Scene> scenes;
  scenes.reserve(mine.size());
  for (int i : mine) scenes.push_back(parse_scene(spec.base_scene_text, spec.source + " point " + std::to_string(i),
                                                  spec.points[static_cast<std::size_t>(i)]));

  const std::string stem = opt.shards == 1 ? "sweep"
                                           : "sweep.shard-" + std::to_string(opt.shard) + "-of-" +
                                                 std::to_string(opt.shards);
  fs::create_directories(opt.out_dir);
  const fs::path journal = opt.out_dir / ("." + stem + ".journal");
  const fs::path csv_path = opt.out_dir / (stem + ".csv");

  const std::string id = sweep_identity(spec, opt.settings);
  auto refuse_other = [&](const fs::path& file, const std::string& other) {
    throw InputError(file.string() + " belongs to sweep " + (other.empty() ? "(no sweep_id: an older atmosh)" : other) +
                     ", not to this one (" + id + ", " + spec.source +
                     " with these settings): run without --resume, or into another -o folder");
  };
  // Resume: the rows of a completed CSV of this sweep, then the complete journal
  // lines (a torn tail is dropped).
  std::map<int, std::string> done;  // point -> full CSV line
  std::string header;
  bool csv_complete = false;
  auto take = [&](const SweepText& t, const fs::path& file) {
    if (!header.empty() && !t.header.empty() && t.header != header)
      throw InputError(file.string() + ": its columns differ from " + csv_path.string() + "'s");
    if (header.empty()) header = t.header;
    for (const auto& line : t.rows) {
      const int idx = row_point(line, file);
      if (idx < 0 || idx >= total || idx % opt.shards != opt.shard - 1)
        throw InputError(file.string() + ": point " + std::to_string(idx) + " does not belong to this sweep");
      done[idx] = line;
    }
  };
  if (opt.resume) {
    if (fs::exists(csv_path)) {
      const SweepText t = read_sweep_text(slurp(csv_path, "sweep CSV"));
      const auto it = t.provenance.find("sweep_id");
      if (it == t.provenance.end() || it->second != id) refuse_other(csv_path, it == t.provenance.end() ? "" : it->second);
      take(t, csv_path);
      csv_complete = done.size() == mine.size();
    }
    if (fs::exists(journal)) {
      const std::string text = slurp(journal, "sweep journal");
      const SweepText t = read_sweep_text(text);
      const auto it = t.provenance.find("sweep_id");
      if (it == t.provenance.end() || it->second != id) refuse_other(journal, it == t.provenance.end() ? "" : it->second);
      take(t, journal);
      if (t.complete_bytes < text.size()) fs::resize_file(journal, t.complete_bytes);
    }
  } else {
    fs::remove(journal);
  }
  if (csv_complete && !fs::exists(journal)) {  // nothing to do: leave the CSV as it is
    SweepResult res;
    res.csv = csv_path;
    res.points_total = total;
    res.points_in_shard = res.points_resumed = static_cast<int>(mine.size());
    res.sweep_id = id;
    if (opt.progress) opt.progress(1.0);
    return res;
  }
  const bool journal_has_header = fs::exists(journal) && !header.empty();

  std::mutex mu;
  int fd = -1;
  auto append = [&](const std::string& line) {  // under mu
    if (fd < 0) {
      fd = ::open(journal.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
      if (fd < 0) throw std::runtime_error("cannot open " + journal.string());
    }
    const std::string l = line + "\n";
    if (::write(fd, l.data(), l.size()) != static_cast<ssize_t>(l.size()))
      throw std::runtime_error("write failed: " + journal.string());
    ::fsync(fd);
  };

  std::vector<std::size_t> todo;
  for (std::size_t j = 0; j < mine.size(); ++j)
    if (!done.count(mine[j])) todo.push_back(j);
  SweepResult res;
  res.points_total = total;
  res.points_in_shard = static_cast<int>(mine.size());
  res.points_resumed = static_cast<int>(mine.size() - todo.size());

  bool journal_started = false;  // under mu
  // One point at a time from the toolkit's parallel loop; the first failure stops the
  // others from taking new points and is rethrown here (the journal keeps what finished).
  auto point = [&](std::size_t t) {
    const std::size_t j = todo[t];
    const int idx = mine[j];
    const auto t0 = std::chrono::steady_clock::now();
    const SweepOutputs out = eval(scenes[j]);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<std::string> cells = {std::to_string(idx)};
    for (const auto& o : spec.points[static_cast<std::size_t>(idx)]) {
      std::string c = value_cell(o.value);
      if (c.find_first_of(",\"\n") != std::string::npos) c = "\"" + c + "\"";
      cells.push_back(c);
    }
    for (const auto& [name, v] : out) cells.push_back(io::format_double(v));
    cells.push_back(io::format_double(secs));
    const std::string hdr = join(columns_for(spec, out));
    std::lock_guard<std::mutex> lk(mu);
    if (!journal_started) {
      if (!header.empty() && header != hdr)
        throw InputError(journal.string() + ": its columns differ from this sweep's; remove it or run without --resume");
      header = hdr;
      if (!journal_has_header) {
        append("# sweep_id: " + id);
        append(header);
      }
      journal_started = true;
    } else if (header != hdr) {
      throw InputError("sweep point " + std::to_string(idx) + ": its outputs differ from the other points'");
    }
    append(join(cells));
    done[idx] = join(cells);
    if (opt.progress) opt.progress(static_cast<double>(done.size()) / static_cast<double>(mine.size()));
  };
  try {
    parallel_for(todo.size(), opt.threads, point);
  } catch (...) {
    if (fd >= 0) ::close(fd);
    throw;
  }
  if (fd >= 0) ::close(fd);
  res.points_computed = static_cast<int>(todo.size());

  // Final CSV (atomic), rows sorted by point.
  std::string text;
  io::Provenance prov = io::Provenance::current();
  prov.add("sweep", spec.source);
  prov.add("base_scene", spec.base_scene_source);
  prov.add("sweep_id", id);
  for (const auto& [k, v] : opt.settings) prov.add(k, v);
  prov.add("sweep_points", static_cast<double>(total));
  prov.add("shard", std::to_string(opt.shard) + "/" + std::to_string(opt.shards));
  for (const auto& [k, v] : prov.entries) text += "# " + k + ": " + v + "\n";
  text += header + "\n";
  for (const auto& [idx, line] : done) text += line + "\n";
  io::write_text_atomically(csv_path, text);
  fs::remove(journal);
  res.csv = csv_path;
  res.sweep_id = id;
  return res;
}

void merge_sweep(const std::vector<fs::path>& inputs, const fs::path& output) {
  if (inputs.empty()) throw InputError("sweep merge: no input files");
  std::vector<std::string> columns;
  std::map<long, std::vector<std::string>> rows;
  long total = -1;
  std::string id;
  std::map<std::string, std::string> first_prov;
  for (const auto& in : inputs) {
    const io::CsvData d = io::read_csv(in);
    const auto idit = d.provenance.find("sweep_id");
    if (idit == d.provenance.end())
      throw InputError(in.string() + ": no '# sweep_id' line (not a sweep shard, or written by an older atmosh)");
    if (id.empty()) {
      id = idit->second;
      first_prov = d.provenance;
    } else if (idit->second != id) {
      throw InputError(in.string() + " is from sweep " + idit->second + ", " + inputs[0].string() + " from sweep " + id +
                       ": shards of different sweeps cannot be merged");
    }
    if (columns.empty()) columns = d.columns;
    else if (d.columns != columns) throw InputError(in.string() + ": columns differ from " + inputs[0].string());
    if (columns.empty() || columns[0] != "point") throw InputError(in.string() + ": not a sweep file (no 'point' column)");
    auto it = d.provenance.find("sweep_points");
    if (it == d.provenance.end()) throw InputError(in.string() + ": no '# sweep_points' line");
    const long n = std::stol(it->second);
    if (total >= 0 && n != total) throw InputError(in.string() + ": from a sweep of " + std::to_string(n) + " points, not " + std::to_string(total));
    total = n;
    for (std::size_t r = 0; r < d.rows.size(); ++r) {
      const long idx = static_cast<long>(d.number(r, 0));
      if (rows.count(idx)) throw InputError(in.string() + ": point " + std::to_string(idx) + " appears twice");
      rows[idx] = d.rows[r];
    }
  }
  for (long i = 0; i < total; ++i)
    if (!rows.count(i)) throw InputError("sweep merge: point " + std::to_string(i) + " of " + std::to_string(total) + " is missing");
  if (static_cast<long>(rows.size()) != total) throw InputError("sweep merge: points outside 0.." + std::to_string(total - 1));
  io::CsvTable t(columns);
  for (auto& [idx, r] : rows) {
    std::vector<io::CsvCell> cells(r.begin(), r.end());
    t.add_row(std::move(cells));
  }
  io::Provenance prov = io::Provenance::current();
  // The shards' sweep provenance (sweep, base_scene, sweep_id, settings), without
  // what belongs to each shard's own run.
  std::set<std::string> own = {"shard", "sweep_points", "merged_from"};
  for (const auto& [k, v] : prov.entries) own.insert(k);
  for (const char* k : {"sweep", "base_scene", "sweep_id"})
    if (auto it = first_prov.find(k); it != first_prov.end()) prov.add(k, it->second);
  for (const auto& [k, v] : first_prov)
    if (!own.count(k) && k != "sweep" && k != "base_scene" && k != "sweep_id") prov.add(k, v);
  prov.add("sweep_points", static_cast<double>(total));
  prov.add("merged_from", std::to_string(inputs.size()) + " shard file(s)");
  t.write(output, prov);
}

void SweepOptions::set_shard(const std::string& text) {
  const auto slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("");
    shard = std::stoi(text.substr(0, slash));
    shards = std::stoi(text.substr(slash + 1));
  } catch (const std::logic_error&) {
    throw InputError("--shard '" + text + "' is not k/N");
  }
}

}  // namespace atmosh::scene
