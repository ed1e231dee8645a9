// Derives the passes a scene needs from its outputs, and says why the others
// are left out.
#include <algorithm>
#include <sstream>

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
  {
    using atmo::ScatteringMethod;
    const auto& m = s.scattering;
    const std::size_t nw = a.spectrum.wavelengths_nm.empty() ? static_cast<std::size_t>(a.spectrum.count)
                                                              : a.spectrum.wavelengths_nm.size();
    auto mib = [](double bytes) {
      std::ostringstream os;
      os.precision(3);
      os << bytes / (1024.0 * 1024.0) << " MiB";
      return os.str();
    };
    const bool approx = tables && m.method == ScatteringMethod::Approximate;
    p.push_back({"multiple-scattering:approximate-table", approx,
                 approx ? "Hillaire 2020 Psi_ms table " + std::to_string(m.ms_altitudes) + " altitudes x " +
                              std::to_string(m.ms_sun_directions) + " sun directions x " + std::to_string(nw) +
                              " wavelengths (" + mib(8.0 * m.ms_altitudes * m.ms_sun_directions * nw) + "), " +
                              std::to_string(2 * m.ms_zenith_directions * m.ms_azimuth_directions) +
                              " directions x " + std::to_string(m.ms_ray_steps) + " steps per entry"
                        : !tables ? "no sky output" : "scattering method is " + std::string(atmo::scattering_method_name(m.method))});
    const bool orders = tables && m.method == ScatteringMethod::Orders && m.orders >= 2;
    const double texels = double(m.orders_radii) * m.orders_view_directions * m.orders_sun_directions * m.orders_azimuths;
    p.push_back({"multiple-scattering:orders-tables", orders,
                 orders ? "orders 2.." + std::to_string(m.orders) + ": per order a scattering-density and an "
                              "in-scattered radiance table of " + std::to_string(m.orders_radii) + " radii x " +
                              std::to_string(m.orders_view_directions) + " view x " +
                              std::to_string(m.orders_sun_directions) + " sun directions x " +
                              std::to_string(m.orders_azimuths) + " azimuths x " + std::to_string(nw) +
                              " wavelengths (" + mib(8.0 * texels * nw) + " each; " + std::to_string(m.orders - 1) +
                              " passes, plus the single-scattering table and the ground irradiance)"
                        : !tables ? "no sky output"
                                  : m.method == ScatteringMethod::Orders
                                        ? "orders = 1: single scattering only"
                                        : "scattering method is " + std::string(atmo::scattering_method_name(m.method))});
  }
  p.push_back({"lut-convergence-study", wants(s, {"lut-convergence"}),
               wants(s, {"lut-convergence"}) ? "lut-convergence output" : "not requested"});
  p.push_back({"sh-projection", sh_bands > 0,
               sh_bands > 0 ? std::to_string(sh_bands) + " bands (" + std::to_string(sh_bands * sh_bands) + " coefficients)"
                            : "no sh-coefficients output"});
  return p;
}

}  // namespace atmosh::scene
