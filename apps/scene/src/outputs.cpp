// The table of scene output kinds (see outputs.hpp).
#include "atmosh/scene/outputs.hpp"

#include <filesystem>

#include "atmosh/error.hpp"

namespace atmosh::scene {

const std::vector<OutputKind>& output_kinds() {
  static const std::vector<OutputKind> kinds = [] {
    std::vector<OutputKind> k;
    auto make = [](std::string_view name, std::string_view summary) {
      OutputKind o;
      o.name = name;
      o.summary = summary;
      return o;
    };
    {
      OutputKind o = make("sky-image", "sky radiance image (EXR) and tone-mapped PNG");
      o.sky = o.sun = o.image = o.gpu = true;
      o.files = {"{file}", "{stem}.png", "{stem}.png.json"};
      k.push_back(o);
    }
    {
      OutputKind o = make("sh-coefficients", "SH coefficients of the sky's radiance (CSV) and band energies");
      o.sky = o.sun = o.bands = true;
      o.default_bands = 3;
      o.files = {"{file}", "{stem}_bands.csv", "{stem}_bands.png"};
      k.push_back(o);
    }
    {
      OutputKind o = make("sun-track", "the sun (NREL SPA) over the UTC day of the observer's time");
      o.observer = true;
      o.files = {"{stem}.csv", "{stem}.png"};
      k.push_back(o);
    }
    {
      OutputKind o = make("sun-elevation-study", "sky colour against sun elevation (its own suns)");
      o.sky = true;
      o.files = {"{stem}", "{stem}/sun_elevation.csv", "{stem}/horizon_colour.png", "{stem}/zenith_colour.png",
                 "{stem}/luminance.png", "{stem}/chromaticity.png"};
      k.push_back(o);
    }
    {
      OutputKind o = make("lut-convergence", "optical-depth LUT error against build and lookup time");
      o.atmosphere = true;
      o.plan_pass = "lut-convergence-study";
      o.files = {"{stem}.csv", "{stem}.png"};
      k.push_back(o);
    }
    {
      OutputKind o = make("optical-depth", "optical depth against zenith angle");
      o.atmosphere = true;
      o.files = {"{stem}.csv", "{stem}.png"};
      k.push_back(o);
    }
    return k;
  }();
  return kinds;
}

const OutputKind* find_output_kind(std::string_view name) {
  for (const auto& k : output_kinds())
    if (k.name == name) return &k;
  return nullptr;
}

std::string output_kind_names() {
  std::string s;
  for (const auto& k : output_kinds()) s += (s.empty() ? "" : ", ") + std::string(k.name);
  return s;
}

std::vector<std::string> output_files(const Output& o) {
  std::vector<std::string> out;
  const OutputKind* k = find_output_kind(o.kind);
  if (k == nullptr) return out;
  // Normalised ("./a.csv" and "a.csv" are one file), with '/' separators.
  const std::string file = std::filesystem::path(o.file).lexically_normal().generic_string();
  std::string stem = file;
  if (const auto dot = stem.find_last_of('.'); dot != std::string::npos && stem.find('/', dot) == std::string::npos)
    stem.resize(dot);
  for (std::string_view pattern : k->files) {
    std::string f(pattern);
    if (const auto p = f.find("{file}"); p != std::string::npos) f.replace(p, 6, file);
    if (const auto p = f.find("{stem}"); p != std::string::npos) f.replace(p, 6, stem);
    out.push_back(f);
  }
  return out;
}

void check_outputs(const Scene& s) {
  for (std::size_t i = 0; i < s.outputs.size(); ++i) {
    const Output& o = s.outputs[i];
    const OutputKind* k = find_output_kind(o.kind);
    const std::string where = s.source + ": output[" + std::to_string(i) + "] (" + o.kind + ", file '" + o.file + "')";
    if (k == nullptr) throw InputError(where + ": kind is not one of " + output_kind_names());
    if (k->observer && !s.observer)
      throw InputError(where + ": needs an [observer] (latitude_deg, longitude_deg, time_utc)");
    if (k->sun && !s.observer && !s.sun)
      throw InputError(where + ": needs the sun: give [observer] with time_utc, or [sun] with elevation_deg");
  }
}

}  // namespace atmosh::scene
