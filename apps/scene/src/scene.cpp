#include "atmosh/scene/scene.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/format.hpp"
#include "atmosh/scene/outputs.hpp"
#include "atmosh/scene/toml_limits.hpp"
#include "toml_read.hpp"

namespace atmosh::scene {

namespace fs = std::filesystem;

namespace {

std::string fmt_num(double v) { return atmosh::format_double(v); }

// A view of one TOML table that remembers which keys were read, so that unknown
// keys can be reported by path.
class Reader {
 public:
  Reader(const toml::table& t, std::string path, const std::string& src) : t_(t), path_(std::move(path)), src_(src) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError(src_ + ": " + full(key) + ": " + what);
  }
  std::string full(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  bool has(const std::string& key) const { return t_.contains(key); }
  void used_mark(const std::string& key) { used_.insert(key); }

  std::optional<double> number(const std::string& key) {
    used_.insert(key);
    const toml::node* n = t_.get(key);
    if (!n) return std::nullopt;
    double v;
    if (auto i = n->as_integer()) v = static_cast<double>(i->get());
    else if (auto f = n->as_floating_point()) v = f->get();
    else fail(key, "expected a number");
    if (!std::isfinite(v)) fail(key, fmt_num(v) + " is not finite");
    return v;
  }
  double number(const std::string& key, double def) { return number(key).value_or(def); }
  // Number with a range check (inclusive unless open_lo/open_hi).
  double number_in(const std::string& key, double def, double lo, double hi, bool open_lo = false, bool open_hi = false) {
    const double v = number(key, def);
    const bool bad = (open_lo ? v <= lo : v < lo) || (open_hi ? v >= hi : v > hi);
    if (bad)
      fail(key, fmt_num(v) + " is out of range " + std::string(open_lo ? "(" : "[") + fmt_num(lo) + ", " + fmt_num(hi) +
                    (open_hi ? ")" : "]"));
    return v;
  }
  std::optional<std::int64_t> integer(const std::string& key) {
    used_.insert(key);
    const toml::node* n = t_.get(key);
    if (!n) return std::nullopt;
    auto i = n->as_integer();
    if (!i) fail(key, "expected an integer");
    return i->get();
  }
  std::optional<std::string> string(const std::string& key) {
    used_.insert(key);
    const toml::node* n = t_.get(key);
    if (!n) return std::nullopt;
    auto s = n->as_string();
    if (!s) fail(key, "expected a string");
    return s->get();
  }
  std::optional<bool> boolean(const std::string& key) {
    used_.insert(key);
    const toml::node* n = t_.get(key);
    if (!n) return std::nullopt;
    auto b = n->as_boolean();
    if (!b) fail(key, "expected true or false");
    return b->get();
  }
  std::vector<double> numbers(const std::string& key) {
    used_.insert(key);
    std::vector<double> out;
    const toml::node* n = t_.get(key);
    if (!n) return out;
    auto a = n->as_array();
    if (!a) fail(key, "expected an array of numbers");
    for (std::size_t i = 0; i < a->size(); ++i) {
      const toml::node& e = *a->get(i);
      double v;
      if (auto ii = e.as_integer()) v = static_cast<double>(ii->get());
      else if (auto f = e.as_floating_point()) v = f->get();
      else fail(key + "[" + std::to_string(i) + "]", "expected a number");
      if (!std::isfinite(v)) fail(key + "[" + std::to_string(i) + "]", "not finite");
      out.push_back(v);
    }
    return out;
  }
  const toml::table* table(const std::string& key) {
    used_.insert(key);
    const toml::node* n = t_.get(key);
    if (!n) return nullptr;
    auto tt = n->as_table();
    if (!tt) fail(key, "expected a table");
    return tt;
  }
  void finish() const {
    for (const auto& [k, v] : t_) {
      const std::string key(k.str());
      if (!used_.count(key)) fail(key, "unknown key");
    }
  }

 private:
  const toml::table& t_;
  std::string path_;
  const std::string& src_;
  std::set<std::string> used_;
};

using atmo::DensityProfileSpec;
using atmo::PhaseSpec;

DensityProfileSpec read_profile(const toml::table& t, const std::string& path, const std::string& src,
                                DensityProfileSpec p) {
  Reader r(t, path, src);
  const std::string model = r.string("model").value_or("exponential");
  if (model == "exponential") {
    p.kind = DensityProfileSpec::Kind::Exponential;
    p.scale_height_m = r.number("scale_height_m", p.scale_height_m);
  } else if (model == "tent") {
    p.kind = DensityProfileSpec::Kind::Tent;
    p.bottom_m = r.number("bottom_m", p.bottom_m);
    p.peak_m = r.number("peak_m", p.peak_m);
    p.top_m = r.number("top_m", p.top_m);
  } else if (model == "tabulated") {
    p.kind = DensityProfileSpec::Kind::Tabulated;
    p.altitude_m = r.numbers("altitude_m");
    p.value = r.numbers("value");
  } else if (model == "us-standard-1976") {
    // The U.S. 1976 density ratio tabulated every step_m up to top_m (earth-physical's
    // Rayleigh profile: 500 m, 100 km).
    const double top = r.number_in("top_m", 100e3, 0.0, 1e6, true);
    const double step = r.number_in("step_m", 500.0, 10.0, 5000.0);
    p = atmo::us_standard_1976_profile(top, step);
  } else {
    r.fail("model", "'" + model + "' is not one of exponential, tent, tabulated, us-standard-1976");
  }
  r.finish();
  return p;
}

PhaseSpec read_phase(const toml::table& t, const std::string& path, const std::string& src, PhaseSpec p) {
  Reader r(t, path, src);
  const std::string model = r.string("model").value_or("cornette-shanks");
  if (model == "rayleigh") p.model = PhaseSpec::Model::Rayleigh;
  else if (model == "hg" || model == "henyey-greenstein") p.model = PhaseSpec::Model::HenyeyGreenstein;
  else if (model == "cornette-shanks") p.model = PhaseSpec::Model::CornetteShanks;
  else if (model == "double-hg") p.model = PhaseSpec::Model::DoubleHenyeyGreenstein;
  else if (model == "tabulated") p.model = PhaseSpec::Model::Tabulated;
  else r.fail("model", "'" + model + "' is not one of rayleigh, hg, cornette-shanks, double-hg, tabulated");
  p.g = r.number("g", p.g);
  p.g2 = r.number("g2", p.g2);
  p.weight = r.number("weight", p.weight);
  p.depolarization = r.number("depolarization", p.depolarization);
  p.cos_theta = r.numbers("cos_theta");
  p.value = r.numbers("value");
  r.finish();
  return p;
}

// Profile given either as `profile = {...}` or as the shorthand `scale_height_m`.
DensityProfileSpec read_profile_or_shorthand(Reader& r, const std::string& src, DensityProfileSpec def) {
  const auto* pt = r.table("profile");
  if (pt && r.has("scale_height_m")) r.fail("scale_height_m", "give either scale_height_m or profile, not both");
  if (pt) return read_profile(*pt, r.full("profile"), src, def);
  if (auto h = r.number("scale_height_m")) {
    def.kind = DensityProfileSpec::Kind::Exponential;
    def.scale_height_m = *h;
  }
  return def;
}

Scene parse_table(const toml::table& root, const std::string& src) {
  Scene s;
  s.source = src;
  Reader r(root, "", src);
  const auto version = r.integer("version");
  if (!version) r.fail("version", "missing (this reader understands version = 1)");
  if (*version != 1) r.fail("version", std::to_string(*version) + " is not supported (expected 1)");
  s.version = 1;

  auto& a = s.atmosphere;
  a.name = r.string("name").value_or("custom");
  s.sun_model = r.string("sun_model").value_or("disc");
  if (s.sun_model != "disc" && s.sun_model != "point")
    r.fail("sun_model", "'" + s.sun_model + "' is not one of disc, point");
  if (const auto* t = r.table("planet")) {
    Reader p(*t, "planet", src);
    a.planet.radius_m = p.number("radius_m", a.planet.radius_m);
    a.planet.atmosphere_top_m = p.number("atmosphere_top_m", a.planet.atmosphere_top_m);
    a.planet.ground_albedo = p.number("ground_albedo", a.planet.ground_albedo);
    p.finish();
  }
  a.rayleigh.reset();
  if (const auto* t = r.table("rayleigh")) {
    Reader p(*t, "rayleigh", src);
    atmo::RayleighSpec ray;
    const std::string model = p.string("model").value_or("physical");
    if (model == "physical") ray.model = atmo::RayleighSpec::Model::Physical;
    else if (model == "coefficients") ray.model = atmo::RayleighSpec::Model::Coefficients;
    else p.fail("model", "'" + model + "' is not one of physical, coefficients");
    ray.pressure_pa = p.number("pressure_pa", ray.pressure_pa);
    ray.temperature_k = p.number("temperature_k", ray.temperature_k);
    ray.co2_ppm = p.number("co2_ppm", ray.co2_ppm);
    ray.scattering_per_m = p.number("scattering_per_m", ray.scattering_per_m);
    ray.reference_nm = p.number("reference_nm", ray.reference_nm);
    ray.profile = read_profile_or_shorthand(p, src, ray.profile);
    if (const auto* ph = p.table("phase")) ray.phase = read_phase(*ph, "rayleigh.phase", src, ray.phase);
    p.finish();
    a.rayleigh = ray;
  }
  a.mie.reset();
  if (const auto* t = r.table("mie")) {
    Reader p(*t, "mie", src);
    atmo::MieSpec mie;
    mie.scattering_per_m = p.number("scattering_per_m", mie.scattering_per_m);
    mie.reference_nm = p.number("reference_nm", mie.reference_nm);
    mie.angstrom = p.number("angstrom", mie.angstrom);
    mie.single_scattering_albedo = p.number("single_scattering_albedo", mie.single_scattering_albedo);
    mie.profile = read_profile_or_shorthand(p, src, mie.profile);
    if (const auto* ph = p.table("phase")) mie.phase = read_phase(*ph, "mie.phase", src, mie.phase);
    p.finish();
    a.mie = mie;
  }
  a.ozone.reset();
  if (const auto* t = r.table("ozone")) {
    Reader p(*t, "ozone", src);
    atmo::OzoneSpec oz;
    oz.column_du = p.number("column_du", oz.column_du);
    if (const auto* pt = p.table("profile")) oz.profile = read_profile(*pt, "ozone.profile", src, oz.profile);
    p.finish();
    a.ozone = oz;
  }
  if (const auto* t = r.table("spectrum")) {
    Reader p(*t, "spectrum", src);
    a.spectrum.from_nm = p.number("from_nm", a.spectrum.from_nm);
    a.spectrum.to_nm = p.number("to_nm", a.spectrum.to_nm);
    if (auto c = p.integer("count")) {
      if (*c < 1 || *c > 4096) p.fail("count", std::to_string(*c) + " is out of range [1, 4096]");
      a.spectrum.count = static_cast<int>(*c);
    }
    a.spectrum.wavelengths_nm = p.numbers("wavelengths_nm");
    if (!a.spectrum.wavelengths_nm.empty() && (p.has("from_nm") || p.has("to_nm") || p.has("count")))
      p.fail("wavelengths_nm", "give either wavelengths_nm or from_nm/to_nm/count, not both");
    p.finish();
  }
  if (const auto* t = r.table("observer")) {
    Reader p(*t, "observer", src);
    Observer o;
    // atmo::validate_observer's ranges, checked here to name the key in the message.
    o.latitude_deg = p.number_in("latitude_deg", 0.0, -90.0, 90.0);
    o.longitude_deg = p.number_in("longitude_deg", 0.0, -180.0, 180.0);
    o.height_m = p.number_in("height_m", 0.0, atmo::kObserverMinHeightM, atmo::kObserverMaxHeightM);
    auto time = p.string("time_utc");
    if (!time) p.fail("time_utc", "missing (ISO 8601, e.g. 2026-06-21T18:30:00Z)");
    o.time_utc = *time;
    try {
      (void)atmo::parse_iso8601(o.time_utc);  // the calendar and NREL SPA's years, as the run needs them
    } catch (const InputError& e) {
      p.fail("time_utc", e.what());
    }
    p.finish();
    s.observer = o;
  }
  if (const auto* t = r.table("sun")) {
    Reader p(*t, "sun", src);
    SunOverride so;
    so.elevation_deg = p.number_in("elevation_deg", so.elevation_deg, -90.0, 90.0);
    so.azimuth_deg = p.number_in("azimuth_deg", so.azimuth_deg, 0.0, 360.0, false, true);
    p.finish();
    s.sun = so;
  }
  if (const auto* t = r.table("scattering")) {
    Reader p(*t, "scattering", src);
    auto& m = s.scattering;
    if (auto v = p.string("method")) {
      try {
        m.method = atmo::parse_scattering_method(*v, "method");
      } catch (const InputError&) {
        p.fail("method", "\"" + *v + "\" is not one of single, orders, approximate");
      }
    }
    auto int_key = [&](const char* key, int& field) {
      if (auto v = p.integer(key)) {
        if (*v < -1000000 || *v > 1000000) p.fail(key, std::to_string(*v) + " is out of range");
        field = static_cast<int>(*v);
      }
    };
    int_key("orders", m.orders);
    int_key("ms_altitudes", m.ms_altitudes);
    int_key("ms_sun_directions", m.ms_sun_directions);
    int_key("ms_zenith_directions", m.ms_zenith_directions);
    int_key("ms_azimuth_directions", m.ms_azimuth_directions);
    int_key("ms_ray_steps", m.ms_ray_steps);
    int_key("orders_radii", m.orders_radii);
    int_key("orders_view_directions", m.orders_view_directions);
    int_key("orders_sun_directions", m.orders_sun_directions);
    int_key("orders_azimuths", m.orders_azimuths);
    int_key("orders_sphere_zenith", m.orders_sphere_zenith);
    int_key("orders_sphere_azimuth", m.orders_sphere_azimuth);
    int_key("orders_ray_steps", m.orders_ray_steps);
    p.finish();
    try {
      atmo::validate(m);  // its messages start with the key ("scattering.orders = 0: ...")
    } catch (const InputError& e) {
      throw InputError(src + ": " + e.what());
    }
  }
  if (s.observer && s.sun) r.fail("sun", "give either [observer] (place and time) or [sun], not both");
  r.used_mark("output");
  if (const toml::node* n = root.get("output")) {
    const auto* arr = n->as_array();
    if (!arr) r.fail("output", "expected an array of tables ([[output]])");
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const std::string path = "output[" + std::to_string(i) + "]";
      const auto* t = arr->get(i)->as_table();
      if (!t) r.fail(path, "expected a table");
      Reader p(*t, path, src);
      Output o;
      auto kind = p.string("kind");
      if (!kind) p.fail("kind", "missing");
      if (!find_output_kind(*kind)) p.fail("kind", "'" + *kind + "' is not one of " + output_kind_names());
      o.kind = *kind;
      auto file = p.string("file");
      if (!file || file->empty()) p.fail("file", "missing");
      o.file = *file;
      o.projection = p.string("projection").value_or(o.projection);
      if (o.projection != "equirect" && o.projection != "fisheye")
        p.fail("projection", "'" + o.projection + "' is not one of equirect, fisheye");
      const auto size = p.numbers("size");
      if (!size.empty()) {
        if (size.size() != 2) p.fail("size", "expected [width, height]");
        for (double v : size)
          if (v < 1 || v > 65536 || v != std::floor(v)) p.fail("size", fmt_num(v) + " is not a pixel count in [1, 65536]");
        o.size = {static_cast<int>(size[0]), static_cast<int>(size[1])};
      }
      if (auto b = p.integer("bands")) {
        if (*b < 1 || *b > 4096) p.fail("bands", std::to_string(*b) + " is out of range [1, 4096]");
        o.bands = static_cast<int>(*b);
      }
      o.spectral = p.boolean("spectral").value_or(false);
      p.finish();
      s.outputs.push_back(o);
    }
  }
  r.finish();
  check_output_files(s);
  try {
    atmo::validate(s.atmosphere);  // physical ranges, named by key path
  } catch (const InputError& e) {
    throw InputError(src + ": " + e.what());
  }
  return s;
}

}  // namespace

void check_output_files(const Scene& s) {
  std::map<std::string, std::size_t> owner;  // file -> output index
  for (std::size_t i = 0; i < s.outputs.size(); ++i) {
    const Output& o = s.outputs[i];
    const std::string key = s.source + ": output[" + std::to_string(i) + "].file: '" + o.file + "' ";
    const fs::path p(o.file);
    if (p.has_root_path()) throw InputError(key + "is an absolute path; outputs go inside the output folder (-o)");
    for (const auto& part : p)
      if (part == "..") throw InputError(key + "leaves the output folder (-o): '..' is not allowed");
    if (!p.has_filename() || p.lexically_normal().filename().empty() || p.lexically_normal() == ".")
      throw InputError(key + "names no file");
    for (const auto& f : output_files(o)) {
      const auto [it, fresh] = owner.emplace(f, i);
      if (!fresh) {
        const Output& other = s.outputs[it->second];
        throw InputError(key + "writes " + f + ", which output[" + std::to_string(it->second) + "] (" + other.kind +
                         " '" + other.file + "') writes too");
      }
    }
  }
}

std::string override_value_string(const Override& o) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::string>) return v;
        else if constexpr (std::is_same_v<T, double>) return fmt_num(v);
        else return std::to_string(v);
      },
      o.value);
}

namespace {
void apply_override(toml::table& root, const Override& o, const std::string& src) {
  std::vector<std::string> parts;
  std::stringstream ss(o.key);
  for (std::string part; std::getline(ss, part, '.');) {
    if (part.empty()) throw InputError(src + ": override key '" + o.key + "' is malformed");
    parts.push_back(part);
  }
  if (parts.empty()) throw InputError(src + ": empty override key");
  // Each part is one nested table: the same bound as a key path in a file.
  if (const std::size_t lim = TomlLimits{}.max_key_parts; parts.size() > lim)
    throw InputError(src + ": override key '" + o.key.substr(0, 64) + "...' has " + std::to_string(parts.size()) +
                     " parts (this reader's limit is " + std::to_string(lim) + ")");
  if (parts[0] == "sun") root.erase("observer");
  if (parts[0] == "observer") root.erase("sun");
  toml::table* t = &root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* n = t->get(parts[i]);
    if (!n) {
      t->insert(parts[i], toml::table{});
      n = t->get(parts[i]);
    }
    t = n->as_table();
    if (!t) throw InputError(src + ": override key '" + o.key + "': '" + parts[i] + "' is not a table");
  }
  std::visit([&](const auto& v) { t->insert_or_assign(parts.back(), v); }, o.value);
}
}  // namespace

Scene parse_scene(std::string_view text, const std::string& source_name, const std::vector<Override>& overrides) {
  toml::table root = detail::parse_toml_checked(text, source_name);
  for (const auto& o : overrides) apply_override(root, o, source_name);
  return parse_table(root, source_name);
}

Scene load_scene(const std::filesystem::path& file) {
  return parse_scene(read_toml_file(file, "scene file"), file.string());
}

}  // namespace atmosh::scene
