// Derives the passes a scene needs from its outputs, and says why the others
// are left out.
#include <algorithm>

#include "atmosh/scene/scene.hpp"

namespace atmosh::scene {

namespace {
bool wants(const Scene& s, std::initializer_list<const char*> kinds) {
  return std::any_of(s.outputs.begin(), s.outputs.end(), [&](const Output& o) {
    return std::any_of(kinds.begin(), kinds.end(), [&](const char* k) { return o.kind == k; });
  });
}
}  // namespace

std::vector<Pass> plan(const Scene& s) {
  std::vector<Pass> p;
  const auto& a = s.atmosphere;
  const bool sky = wants(s, {"sky-image", "sun-elevation-study"});
  const bool needs_atmosphere = sky || wants(s, {"optical-depth", "lut-convergence"});
  const bool needs_sun = sky || wants(s, {"sun-track"});
  const int sh_bands = [&] {
    int b = 0;
    for (const auto& o : s.outputs)
      if (o.kind == "sh-coefficients") b = std::max(b, o.bands > 0 ? o.bands : 3);
    return b;
  }();

  if (!needs_sun)
    p.push_back({"sun-position", false, "no output depends on the sun"});
  else if (s.observer)
    p.push_back({"sun-position:spa", true,
                 "sun from [observer] place and time " + s.observer->time_utc + " (NREL SPA)"});
  else if (s.sun)
    p.push_back({"sun-position", false, "sun given directly by [sun] elevation/azimuth"});
  else
    p.push_back({"sun-position", false, "no [observer] or [sun]: outputs use their own sun settings"});

  struct C {
    const char* name;
    bool present;
  } cs[] = {{"rayleigh", a.rayleigh.has_value()}, {"mie", a.mie.has_value()}, {"ozone", a.ozone.has_value()}};
  for (const auto& c : cs) {
    const std::string name = std::string("constituent:") + c.name;
    if (!c.present)
      p.push_back({name, false, std::string("no [") + c.name + "] table in the scene"});
    else if (!needs_atmosphere)
      p.push_back({name, false, "no output needs the atmosphere"});
    else
      p.push_back({name, true, "present in the scene and needed by the outputs"});
  }
  int constituents = 0;
  for (const auto& c : cs) constituents += c.present ? 1 : 0;
  const bool tables = sky && constituents > 0;
  // The sky accumulates view-ray optical depths along each ray: no view table is built.
  p.push_back({"optical-depth-lut:view", false,
               tables ? "the sky accumulates view-ray optical depths along each ray"
                      : "no sky output (or no constituent)"});
  p.push_back({"optical-depth-lut:sun", tables,
               tables ? "sun-ray optical depths for " + std::to_string(constituents) + " constituent(s)"
                      : "no sky output (or no constituent)"});
  p.push_back({"spectrum", needs_atmosphere,
               needs_atmosphere ? std::to_string(a.spectrum.count) + " wavelengths " + std::to_string(a.spectrum.from_nm) +
                                      "-" + std::to_string(a.spectrum.to_nm) + " nm"
                                : "no output needs spectral quantities"});
  p.push_back({"sky-radiance:single-scattering", sky, sky ? "sky-image or sun-elevation-study output" : "no sky output"});
  p.push_back({"lut-convergence-study", wants(s, {"lut-convergence"}),
               wants(s, {"lut-convergence"}) ? "lut-convergence output" : "not requested"});
  p.push_back({"sh-projection", sh_bands > 0,
               sh_bands > 0 ? std::to_string(sh_bands) + " bands (" + std::to_string(sh_bands * sh_bands) + " coefficients)"
                            : "no sh-coefficients output"});
  return p;
}

}  // namespace atmosh::scene
