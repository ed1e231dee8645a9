#include "atmosh/io/netcdf.hpp"

#include <netcdf.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <set>
#include <stdexcept>

#include "atmosh/error.hpp"
#include "atmosh/io/atomic.hpp"
#include "atmosh/io/exr.hpp"

namespace atmosh::io {
namespace {

// One open netCDF file; every call checked, the file closed on all paths.
class NcFile {
 public:
  explicit NcFile(const std::filesystem::path& path) : path_(path) {
    check(nc_create(path.c_str(), NC_NETCDF4 | NC_CLOBBER, &id_), "create");
    open_ = true;
    int old = 0;
    check(nc_set_fill(id_, NC_NOFILL, &old), "set_fill");
  }
  NcFile(const NcFile&) = delete;
  NcFile& operator=(const NcFile&) = delete;
  ~NcFile() {
    if (open_) nc_close(id_);
  }
  void close() {
    open_ = false;
    check(nc_close(id_), "close");
  }
  int id() const { return id_; }

  void check(int status, const char* what) const {
    if (status != NC_NOERR)
      throw std::runtime_error(path_.string() + ": netCDF " + what + ": " + nc_strerror(status));
  }
  int dim(const std::string& name, std::size_t len) {
    int d = 0;
    check(nc_def_dim(id_, name.c_str(), len, &d), "def_dim");
    return d;
  }
  int var(const std::string& name, nc_type type, std::vector<int> dims) {
    int v = 0;
    check(nc_def_var(id_, name.c_str(), type, static_cast<int>(dims.size()), dims.data(), &v), "def_var");
    return v;
  }
  void text(int var, const std::string& name, const std::string& value) {
    check(nc_put_att_text(id_, var, name.c_str(), value.size(), value.c_str()), "put_att_text");
  }
  void number(int var, const std::string& name, double value) {
    check(nc_put_att_double(id_, var, name.c_str(), NC_DOUBLE, 1, &value), "put_att_double");
  }
  void end_define() { check(nc_enddef(id_), "enddef"); }

 private:
  std::filesystem::path path_;
  int id_ = -1;
  bool open_ = false;
};

std::string attribute_key(const std::string& key) {
  std::string s = "atmosh_";
  for (char c : key) s += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '_';
  return s;
}

std::string entry(const Provenance& p, const std::string& key) {
  for (const auto& [k, v] : p.entries)
    if (k == key) return v;
  return "";
}

void global_attributes(NcFile& f, const std::string& title, const Provenance& p) {
  f.text(NC_GLOBAL, "Conventions", "CF-1.8");
  f.text(NC_GLOBAL, "title", title);
  f.text(NC_GLOBAL, "source", "atmosh " + version_string() + " (" + git_commit() + ")");
  std::string when = entry(p, "run_utc"), cmd = entry(p, "command_line");
  if (when.empty()) when = utc_now_iso8601();
  if (cmd.empty()) cmd = command_line().empty() ? std::string("(library call)") : command_line();
  f.text(NC_GLOBAL, "history", when + " " + cmd);
  for (const auto& [k, v] : p.entries) f.text(NC_GLOBAL, attribute_key(k), v);
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

void write_sky_netcdf(const std::filesystem::path& file, const NetcdfSkyImage& sky, const Provenance& provenance) {
  if (sky.width < 1 || sky.height < 1)
    throw InputError(file.string() + ": sky image of " + std::to_string(sky.width) + " x " +
                     std::to_string(sky.height) + " pixels");
  const std::size_t w = static_cast<std::size_t>(sky.width), h = static_cast<std::size_t>(sky.height);
  const std::size_t n = w * h, nw = sky.wavelengths_nm.size();
  if (sky.X.size() != n || sky.Y.size() != n || sky.Z.size() != n)
    throw InputError(file.string() + ": X, Y, Z need " + std::to_string(n) + " values each");
  if (!sky.spectral.empty() && (nw == 0 || sky.spectral.size() != n * nw))
    throw InputError(file.string() + ": the spectral cube needs " + std::to_string(n * nw) + " values, has " +
                     std::to_string(sky.spectral.size()));

  std::vector<double> elevation(h), azimuth(w);
  for (std::size_t y = 0; y < h; ++y) elevation[y] = 90.0 - (static_cast<double>(y) + 0.5) / static_cast<double>(h) * 180.0;
  for (std::size_t x = 0; x < w; ++x) azimuth[x] = (static_cast<double>(x) + 0.5) / static_cast<double>(w) * 360.0;

  write_atomically(file, [&](const std::filesystem::path& tmp) {
    NcFile f(tmp);
    global_attributes(f, sky.title, provenance);
    const int de = f.dim("elevation", h), da = f.dim("azimuth", w);
    int dw = -1, vw = -1, vs = -1;
    if (nw > 0) {
      dw = f.dim("wavelength", nw);
      vw = f.var("wavelength", NC_DOUBLE, {dw});
      f.text(vw, "standard_name", "radiation_wavelength");
      f.text(vw, "long_name", "vacuum wavelength");
      f.text(vw, "units", "nm");
    }
    const int ve = f.var("elevation", NC_DOUBLE, {de});
    f.text(ve, "long_name", "elevation of the view direction above the horizon (pixel centre)");
    f.text(ve, "units", "degree");
    const int va = f.var("azimuth", NC_DOUBLE, {da});
    f.text(va, "long_name", "azimuth of the view direction, clockwise from north (pixel centre)");
    f.text(va, "units", "degree");
    if (!sky.spectral.empty()) {
      vs = f.var("spectral_radiance", NC_FLOAT, {dw, de, da});
      f.text(vs, "standard_name", "downwelling_radiance_per_unit_wavelength_in_air");
      f.text(vs, "long_name", "spectral radiance reaching the observer from the view direction");
      f.text(vs, "units", "W m-2 sr-1 nm-1");
      const std::size_t chunk[3] = {1, h, w};
      f.check(nc_def_var_chunking(f.id(), vs, NC_CHUNKED, chunk), "def_var_chunking");
    }
    const char* names[3] = {"X", "Y", "Z"};
    const char* longs[3] = {"CIE 1931 tristimulus X (same scale as Y)", "luminance (CIE 1931 tristimulus Y)",
                            "CIE 1931 tristimulus Z (same scale as Y)"};
    int vxyz[3];
    for (int c = 0; c < 3; ++c) {
      vxyz[c] = f.var(names[c], NC_FLOAT, {de, da});
      f.text(vxyz[c], "long_name", longs[c]);
      f.text(vxyz[c], "units", "cd m-2");
    }
    int vsz = -1, vsa = -1;
    if (sky.sun_zenith_deg) {
      vsz = f.var("solar_zenith_angle", NC_DOUBLE, {});
      f.text(vsz, "standard_name", "solar_zenith_angle");
      f.text(vsz, "units", "degree");
    }
    if (sky.sun_azimuth_deg) {
      vsa = f.var("solar_azimuth_angle", NC_DOUBLE, {});
      f.text(vsa, "standard_name", "solar_azimuth_angle");
      f.text(vsa, "long_name", "solar azimuth angle, clockwise from north");
      f.text(vsa, "units", "degree");
    }
    f.end_define();

    if (nw > 0) f.check(nc_put_var_double(f.id(), vw, sky.wavelengths_nm.data()), "put_var wavelength");
    f.check(nc_put_var_double(f.id(), ve, elevation.data()), "put_var elevation");
    f.check(nc_put_var_double(f.id(), va, azimuth.data()), "put_var azimuth");
    if (vs >= 0) {
      // The image keeps wavelengths innermost; the file keeps one plane per wavelength.
      std::vector<float> plane(n);
      for (std::size_t i = 0; i < nw; ++i) {
        for (std::size_t p = 0; p < n; ++p) plane[p] = sky.spectral[p * nw + i];
        const std::size_t start[3] = {i, 0, 0}, count[3] = {1, h, w};
        f.check(nc_put_vara_float(f.id(), vs, start, count, plane.data()), "put_vara spectral_radiance");
      }
    }
    const std::span<const float> xyz[3] = {sky.X, sky.Y, sky.Z};
    for (int c = 0; c < 3; ++c) f.check(nc_put_var_float(f.id(), vxyz[c], xyz[c].data()), "put_var XYZ");
    if (vsz >= 0) f.check(nc_put_var_double(f.id(), vsz, &*sky.sun_zenith_deg), "put_var solar_zenith_angle");
    if (vsa >= 0) f.check(nc_put_var_double(f.id(), vsa, &*sky.sun_azimuth_deg), "put_var solar_azimuth_angle");
    f.close();
  });
}

std::string units_from_column_name(const std::string& c) {
  static const std::pair<const char*, const char*> suffixes[] = {
      {"_cd_m2", "cd m-2"}, {"_per_m", "m-1"}, {"_w_m2", "W m-2"}, {"_deg", "degree"}, {"_min", "min"},
      {"_lux", "lx"},       {"_rel", "1"},     {"_nm", "nm"},      {"_km", "km"},      {"_pa", "Pa"},
      {"_s", "s"},          {"_m", "m"},       {"_k", "K"}};
  for (const auto& [suffix, units] : suffixes)
    if (ends_with(c, suffix)) return units;
  return "";
}

std::map<std::string, std::string> default_standard_names() {
  return {{"sun_elevation_deg", "solar_elevation_angle"},
          {"sun_azimuth_deg", "solar_azimuth_angle"},
          {"sun_zenith_deg", "solar_zenith_angle"}};
}

NetcdfTableOptions sun_track_netcdf_options() {
  NetcdfTableOptions o;
  o.title = "atmosh sun track";
  o.julian_date_column = "jd_utc";
  o.standard_names = {{"zenith_deg", "solar_zenith_angle"},
                      {"azimuth_deg", "solar_azimuth_angle"},
                      {"elevation_deg", "solar_elevation_angle"}};
  return o;
}

std::string netcdf_variable_name(const std::string& column) {
  std::string s;
  for (char c : column) {
    if (c == '.') s += "__";
    else s += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '_';
  }
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) s = "_" + s;
  return s;
}

void write_table_netcdf(const std::filesystem::path& file, const CsvTable& table, const Provenance& provenance,
                        const NetcdfTableOptions& options) {
  const auto& cols = table.columns();
  const auto& rows = table.rows();
  const std::size_t nr = rows.size();
  enum class Kind { Int, Double, String };
  std::vector<Kind> kinds(cols.size(), Kind::Int);
  std::vector<std::string> names(cols.size());
  std::set<std::string> taken;
  const bool with_jd = !options.julian_date_column.empty();
  const bool with_time = with_jd || !options.time_unix_s.empty();
  if (!with_jd && with_time && options.time_unix_s.size() != rows.size())
    throw InputError(file.string() + ": " + std::to_string(options.time_unix_s.size()) + " times for " +
                     std::to_string(rows.size()) + " rows");
  if (with_time) taken.insert("time");
  for (const auto& [name, s] : options.scalars) taken.insert(name);
  std::size_t jd_col = cols.size();
  for (std::size_t c = 0; c < cols.size(); ++c) {
    bool any_string = false, any_number = false, any_double = false;
    for (const auto& r : rows) {
      if (std::holds_alternative<std::string>(r[c])) any_string = true;
      else any_number = true;
      if (std::holds_alternative<double>(r[c])) any_double = true;
    }
    if (any_string && any_number)
      throw InputError(file.string() + ": column '" + cols[c] + "' mixes text and numbers");
    kinds[c] = any_string ? Kind::String : any_double ? Kind::Double : Kind::Int;
    names[c] = netcdf_variable_name(cols[c]);
    if (!taken.insert(names[c]).second)
      throw InputError(file.string() + ": column '" + cols[c] + "' has the netCDF name '" + names[c] +
                       "' of another variable");
    if (with_jd && cols[c] == options.julian_date_column) jd_col = c;
  }
  if (with_jd && jd_col == cols.size())
    throw InputError(file.string() + ": no column '" + options.julian_date_column + "' for the time coordinate");
  const bool with_coordinate = !with_time && !options.coordinate_column.empty();
  if (with_coordinate) {
    const auto it = std::find(cols.begin(), cols.end(), options.coordinate_column);
    if (it == cols.end() || kinds[static_cast<std::size_t>(it - cols.begin())] == Kind::String)
      throw InputError(file.string() + ": no numeric column '" + options.coordinate_column + "' for the coordinate");
  }
  if (with_jd && kinds[jd_col] == Kind::String)
    throw InputError(file.string() + ": column '" + options.julian_date_column + "' is not numeric");
  auto number = [](const CsvCell& v) {
    return std::holds_alternative<double>(v) ? std::get<double>(v) : static_cast<double>(std::get<std::int64_t>(v));
  };
  std::map<std::string, std::string> standard = default_standard_names();
  for (const auto& [k, v] : options.standard_names) standard[k] = v;

  write_atomically(file, [&](const std::filesystem::path& tmp) {
    NcFile f(tmp);
    global_attributes(f, options.title, provenance);
    const int d =
        f.dim(with_time ? "time" : with_coordinate ? netcdf_variable_name(options.coordinate_column) : "row", nr);
    int vt = -1;
    if (with_time) {
      vt = f.var("time", NC_DOUBLE, {d});
      f.text(vt, "standard_name", "time");
      f.text(vt, "units", "seconds since 1970-01-01 00:00:00 UTC");
      f.text(vt, "calendar", "standard");
      f.text(vt, "axis", "T");
    }
    std::vector<int> vars(cols.size());
    for (std::size_t c = 0; c < cols.size(); ++c) {
      const nc_type t = kinds[c] == Kind::String ? NC_STRING : kinds[c] == Kind::Double ? NC_DOUBLE : NC_INT64;
      vars[c] = f.var(names[c], t, {d});
      f.text(vars[c], "long_name", cols[c]);
      f.text(vars[c], "atmosh_column", cols[c]);
      if (kinds[c] != Kind::String) {
        const auto it = standard.find(cols[c]);
        if (it != standard.end()) f.text(vars[c], "standard_name", it->second);
        const std::string u = units_from_column_name(cols[c]);
        if (!u.empty()) f.text(vars[c], "units", u);
      }
    }
    std::vector<int> scalar_vars;
    for (const auto& [name, s] : options.scalars) {
      const int v = f.var(name, NC_DOUBLE, {});
      if (!s.standard_name.empty()) f.text(v, "standard_name", s.standard_name);
      if (!s.units.empty()) f.text(v, "units", s.units);
      scalar_vars.push_back(v);
    }
    f.end_define();

    if (with_time) {
      // Julian date 2440587.5 is 1970-01-01T00:00:00 UTC.
      std::vector<double> t(nr);
      for (std::size_t r = 0; r < nr; ++r)
        t[r] = with_jd ? (number(rows[r][jd_col]) - 2440587.5) * 86400.0 : options.time_unix_s[r];
      if (nr) f.check(nc_put_var_double(f.id(), vt, t.data()), "put_var time");
    }
    for (std::size_t c = 0; c < cols.size() && nr > 0; ++c) {
      if (kinds[c] == Kind::String) {
        std::vector<const char*> p(nr);
        for (std::size_t r = 0; r < nr; ++r) p[r] = std::get<std::string>(rows[r][c]).c_str();
        f.check(nc_put_var_string(f.id(), vars[c], p.data()), "put_var_string");
      } else if (kinds[c] == Kind::Double) {
        std::vector<double> v(nr);
        for (std::size_t r = 0; r < nr; ++r) v[r] = number(rows[r][c]);
        f.check(nc_put_var_double(f.id(), vars[c], v.data()), "put_var_double");
      } else {
        std::vector<long long> v(nr);
        for (std::size_t r = 0; r < nr; ++r) v[r] = std::get<std::int64_t>(rows[r][c]);
        f.check(nc_put_var_longlong(f.id(), vars[c], v.data()), "put_var_longlong");
      }
    }
    std::size_t k = 0;
    for (const auto& [name, s] : options.scalars)
      f.check(nc_put_var_double(f.id(), scalar_vars[k++], &s.value), "put_var scalar");
    f.close();
  });
}

void write_exr_sky_as_netcdf(const std::filesystem::path& exr_file, const std::filesystem::path& netcdf_file) {
  const ExrImage e = read_exr(exr_file);
  const auto proj = e.string_attributes.find("projection");
  if (proj != e.string_attributes.end() && proj->second.rfind("equirect", 0) != 0)
    throw InputError(exr_file.string() + ": projection '" + proj->second.substr(0, proj->second.find(':')) +
                     "' is not equirect; netCDF sky files hold equirect images");
  for (const char* c : {"X", "Y", "Z"})
    if (e.find_channel(c) < 0) throw InputError(exr_file.string() + ": no channel " + c);
  std::vector<std::pair<double, std::size_t>> spectral_channels;
  for (std::size_t c = 0; c < e.channels.size(); ++c) {
    const std::string& n = e.channels[c];
    if (n.size() > 4 && n.rfind("L_", 0) == 0 && ends_with(n, "nm")) {
      const std::string num = n.substr(2, n.size() - 4);
      char* end = nullptr;
      const double w = std::strtod(num.c_str(), &end);
      if (end == num.c_str() + num.size()) spectral_channels.emplace_back(w, c);
    }
  }
  std::sort(spectral_channels.begin(), spectral_channels.end());
  const std::size_t n = static_cast<std::size_t>(e.width) * static_cast<std::size_t>(e.height);
  const std::size_t nw = spectral_channels.size();
  std::vector<double> wl(nw);
  std::vector<float> spectral(n * nw);
  for (std::size_t i = 0; i < nw; ++i) {
    wl[i] = spectral_channels[i].first;
    const auto& plane = e.data[spectral_channels[i].second];
    for (std::size_t p = 0; p < n; ++p) spectral[p * nw + i] = plane[p];
  }
  NetcdfSkyImage sky;
  sky.width = e.width;
  sky.height = e.height;
  sky.wavelengths_nm = wl;
  sky.spectral = spectral;
  sky.X = e.channel("X");
  sky.Y = e.channel("Y");
  sky.Z = e.channel("Z");
  if (auto it = e.float_attributes.find("sun_elevation_deg"); it != e.float_attributes.end())
    sky.sun_zenith_deg = 90.0 - static_cast<double>(it->second);
  if (auto it = e.float_attributes.find("sun_azimuth_deg"); it != e.float_attributes.end())
    sky.sun_azimuth_deg = static_cast<double>(it->second);
  Provenance p;
  for (const auto& [k, v] : e.string_attributes)
    if (k.rfind("atmosh:", 0) == 0) p.add(k.substr(7), v);
  write_sky_netcdf(netcdf_file, sky, p);
}

CsvTable table_from_csv(const CsvData& csv, Provenance& provenance) {
  for (const auto& [k, v] : csv.provenance) provenance.add(k, v);
  const std::size_t nc = csv.columns.size();
  enum class Kind { Int, Double, String };
  std::vector<Kind> kinds(nc, Kind::Int);
  auto is_int = [](const std::string& s) {
    if (s.empty() || s.size() > 18) return false;
    std::size_t i = (s[0] == '-' || s[0] == '+') ? 1 : 0;
    if (i == s.size()) return false;
    for (; i < s.size(); ++i)
      if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
    return true;
  };
  auto parse = [](const std::string& s, double& v) {
    if (s.empty()) return false;
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size();
  };
  for (std::size_t c = 0; c < nc; ++c)
    for (const auto& r : csv.rows) {
      double v = 0;
      if (kinds[c] == Kind::Int && !is_int(r[c])) kinds[c] = Kind::Double;
      if (kinds[c] == Kind::Double && !parse(r[c], v)) {
        kinds[c] = Kind::String;
        break;
      }
    }
  CsvTable t(csv.columns);
  for (const auto& r : csv.rows) {
    std::vector<CsvCell> row(nc);
    for (std::size_t c = 0; c < nc; ++c) {
      double v = 0;
      if (kinds[c] == Kind::Int) row[c] = static_cast<std::int64_t>(std::stoll(r[c]));
      else if (kinds[c] == Kind::Double && parse(r[c], v)) row[c] = v;
      else row[c] = r[c];
    }
    t.add_row(std::move(row));
  }
  return t;
}

void write_csv_as_netcdf(const std::filesystem::path& csv_file, const std::filesystem::path& netcdf_file,
                         const NetcdfTableOptions& options) {
  Provenance p;
  const CsvTable t = table_from_csv(read_csv(csv_file), p);
  write_table_netcdf(netcdf_file, t, p, options);
}

// ---- table outputs in CSV and netCDF-CF --------------------------------------------

bool parse_table_format(const std::string& value, const std::string& what) {
  if (value == "csv") return false;
  if (value == "netcdf") return true;
  throw InputError(what + ": '" + value + "' is not csv or netcdf");
}

std::filesystem::path table_output_stem(const std::filesystem::path& stem, bool& netcdf) {
  if (stem.extension() != ".nc") return stem;
  netcdf = true;
  std::filesystem::path s = stem;
  s.replace_extension();
  return s;
}

std::vector<std::filesystem::path> write_table_files(const std::filesystem::path& csv_file, const CsvTable& table,
                                                     const Provenance& provenance, bool netcdf,
                                                     const NetcdfTableOptions& options) {
  std::vector<std::filesystem::path> written = {csv_file};
  table.write(csv_file, provenance);
  if (netcdf) {
    std::filesystem::path nc = csv_file;
    nc.replace_extension(".nc");
    write_table_netcdf(nc, table, provenance, options);
    written.push_back(nc);
  }
  return written;
}

namespace {

// A column's type in a netCDF file: strings, 64-bit integers where every cell is an
// integer, else doubles. InputError for a column mixing text and numbers.
enum class CellKind { Int, Double, String };
CellKind column_kind(const CsvTable& t, std::size_t c, const std::filesystem::path& file) {
  bool any_string = false, any_number = false, any_double = false;
  for (const auto& r : t.rows()) {
    if (std::holds_alternative<std::string>(r[c])) any_string = true;
    else any_number = true;
    if (std::holds_alternative<double>(r[c])) any_double = true;
  }
  if (any_string && any_number)
    throw InputError(file.string() + ": column '" + t.columns()[c] + "' mixes text and numbers");
  return any_string ? CellKind::String : any_double ? CellKind::Double : CellKind::Int;
}

double cell_number(const CsvCell& v) {
  return std::holds_alternative<double>(v) ? std::get<double>(v) : static_cast<double>(std::get<std::int64_t>(v));
}

// Writes column c of the table into variable v, row r at flat position slot[r] of an
// array of n values.
void put_column(NcFile& f, int v, const CsvTable& t, std::size_t c, CellKind kind, const std::vector<std::size_t>& slot,
                std::size_t n) {
  if (n == 0) return;
  const auto& rows = t.rows();
  if (kind == CellKind::String) {
    std::vector<std::string> s(n);
    for (std::size_t r = 0; r < rows.size(); ++r) s[slot[r]] = std::get<std::string>(rows[r][c]);
    std::vector<const char*> p(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = s[i].c_str();
    f.check(nc_put_var_string(f.id(), v, p.data()), "put_var_string");
  } else if (kind == CellKind::Double) {
    std::vector<double> d(n, std::numeric_limits<double>::quiet_NaN());
    for (std::size_t r = 0; r < rows.size(); ++r) d[slot[r]] = cell_number(rows[r][c]);
    f.check(nc_put_var_double(f.id(), v, d.data()), "put_var_double");
  } else {
    std::vector<long long> d(n, 0);
    for (std::size_t r = 0; r < rows.size(); ++r) d[slot[r]] = std::get<std::int64_t>(rows[r][c]);
    f.check(nc_put_var_longlong(f.id(), v, d.data()), "put_var_longlong");
  }
}

nc_type nc_type_of(CellKind k) { return k == CellKind::String ? NC_STRING : k == CellKind::Double ? NC_DOUBLE : NC_INT64; }

std::string cell_key(const CsvCell& v) {
  std::string k = std::holds_alternative<std::string>(v) ? std::get<std::string>(v) : format_double(cell_number(v));
  k.push_back(std::holds_alternative<std::string>(v) ? 's' : 'n');
  return k;
}

}  // namespace

void write_sweep_netcdf(const std::filesystem::path& file, const CsvTable& table, const Provenance& provenance,
                        const std::vector<std::string>& keys) {
  const auto& cols = table.columns();
  const auto& rows = table.rows();
  const std::size_t nr = rows.size(), nk = keys.size();
  std::vector<std::size_t> key_col(nk);
  for (std::size_t k = 0; k < nk; ++k) {
    const auto it = std::find(cols.begin(), cols.end(), keys[k]);
    if (it == cols.end()) throw InputError(file.string() + ": the sweep table has no column '" + keys[k] + "'");
    key_col[k] = static_cast<std::size_t>(it - cols.begin());
  }
  std::vector<CellKind> kinds(cols.size());
  std::vector<std::string> names(cols.size());
  std::set<std::string> taken;
  for (std::size_t c = 0; c < cols.size(); ++c) {
    kinds[c] = column_kind(table, c, file);
    names[c] = netcdf_variable_name(cols[c]);
    if (!taken.insert(names[c]).second)
      throw InputError(file.string() + ": column '" + cols[c] + "' has the netCDF name '" + names[c] +
                       "' of another variable");
  }
  // A grid: each key's distinct values (in order of first appearance) and every
  // combination exactly once.
  std::vector<std::vector<std::size_t>> row_index(nk, std::vector<std::size_t>(nr));
  std::vector<std::vector<std::size_t>> first_row(nk);  // per key: the row of each distinct value
  for (std::size_t k = 0; k < nk; ++k) {
    std::map<std::string, std::size_t> seen;
    for (std::size_t r = 0; r < nr; ++r) {
      const auto [it, fresh] = seen.emplace(cell_key(rows[r][key_col[k]]), seen.size());
      if (fresh) first_row[k].push_back(r);
      row_index[k][r] = it->second;
    }
  }
  bool grid = nk > 0 && nr > 0;
  std::size_t cells = 1;
  for (std::size_t k = 0; k < nk && grid; ++k) {
    cells *= first_row[k].size();
    if (cells > nr) grid = false;
  }
  std::vector<std::size_t> slot(nr);
  if (grid && cells == nr) {
    std::vector<char> filled(nr, 0);
    for (std::size_t r = 0; r < nr && grid; ++r) {
      std::size_t flat = 0;
      for (std::size_t k = 0; k < nk; ++k) flat = flat * first_row[k].size() + row_index[k][r];
      if (filled[flat]) grid = false;
      filled[flat] = 1;
      slot[r] = flat;
    }
  } else {
    grid = false;
  }
  if (!grid)
    for (std::size_t r = 0; r < nr; ++r) slot[r] = r;

  std::map<std::string, std::string> standard = default_standard_names();
  standard["sun.elevation_deg"] = "solar_elevation_angle";
  standard["sun.azimuth_deg"] = "solar_azimuth_angle";
  auto describe = [&](NcFile& f, int v, std::size_t c) {
    f.text(v, "long_name", cols[c]);
    f.text(v, "atmosh_column", cols[c]);
    if (kinds[c] == CellKind::String) return;
    if (const auto it = standard.find(cols[c]); it != standard.end()) f.text(v, "standard_name", it->second);
    const std::string leaf = cols[c].substr(cols[c].find_last_of('.') + 1);
    if (const std::string u = units_from_column_name(leaf); !u.empty()) f.text(v, "units", u);
  };

  write_atomically(file, [&](const std::filesystem::path& tmp) {
    NcFile f(tmp);
    global_attributes(f, "atmosh sweep", provenance);
    f.text(NC_GLOBAL, "atmosh_sweep_layout", grid ? "grid" : "points");
    std::vector<int> dims;
    std::vector<int> vars(cols.size(), -1);
    std::vector<char> is_key(cols.size(), 0);
    for (std::size_t c : key_col) is_key[c] = 1;
    if (grid) {
      for (std::size_t k = 0; k < nk; ++k) {
        const std::size_t c = key_col[k];
        dims.push_back(f.dim(names[c], first_row[k].size()));
        vars[c] = f.var(names[c], nc_type_of(kinds[c]), {dims.back()});
        describe(f, vars[c], c);
      }
    } else {
      dims.push_back(f.dim("point", nr));
    }
    std::string coordinates;
    for (std::size_t c : key_col) coordinates += (coordinates.empty() ? "" : " ") + names[c];
    for (std::size_t c = 0; c < cols.size(); ++c) {
      if (grid && is_key[c]) continue;
      vars[c] = f.var(names[c], nc_type_of(kinds[c]), dims);
      describe(f, vars[c], c);
      if (!grid && !is_key[c] && !coordinates.empty()) f.text(vars[c], "coordinates", coordinates);
    }
    f.end_define();
    if (grid) {
      for (std::size_t k = 0; k < nk; ++k) {
        std::vector<std::size_t> s(first_row[k].size());
        std::iota(s.begin(), s.end(), std::size_t{0});
        CsvTable one({cols[key_col[k]]});
        for (std::size_t r : first_row[k]) one.add_row({rows[r][key_col[k]]});
        put_column(f, vars[key_col[k]], one, 0, kinds[key_col[k]], s, s.size());
      }
    }
    for (std::size_t c = 0; c < cols.size(); ++c)
      if (!(grid && is_key[c])) put_column(f, vars[c], table, c, kinds[c], slot, nr);
    f.close();
  });
}

void write_sweep_csv_as_netcdf(const std::filesystem::path& csv_file, const std::filesystem::path& netcdf_file,
                               const std::vector<std::string>& keys) {
  Provenance p;
  const CsvTable t = table_from_csv(read_csv(csv_file), p);
  write_sweep_netcdf(netcdf_file, t, p, keys);
}

}  // namespace atmosh::io
