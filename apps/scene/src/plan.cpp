// Derives the passes a scene needs from its outputs, and says why the others
// are left out.
#include <algorithm>
#include <sstream>

#include "atmosh/atmo/presets.hpp"
#include "atmosh/scene/outputs.hpp"
#include "atmosh/scene/scene.hpp"

namespace atmosh::scene {

namespace {
// Whether any output's kind has the property.
bool any_kind(const Scene& s, bool OutputKind::*what) {
  return std::any_of(s.outputs.begin(), s.outputs.end(), [&](const Output& o) {
    const OutputKind* k = find_output_kind(o.kind);
    return k != nullptr && k->*what;
  });
}
bool wants(const Scene& s, std::string_view kind) {
  return std::any_of(s.outputs.begin(), s.outputs.end(), [&](const Output& o) { return o.kind == kind; });
}
std::string kinds_with(const Scene& s, bool OutputKind::*what) {
  std::string names;
  for (const auto& o : s.outputs) {
    const OutputKind* k = find_output_kind(o.kind);
    if (k != nullptr && k->*what && names.find(o.kind) == std::string::npos)
      names += (names.empty() ? "" : ", ") + o.kind;
  }
  return names;
}
std::string nm(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}
// The wavelengths the run uses: the explicit list, or the bins' centres.
std::string spectrum_summary(const atmo::SpectrumSpec& sp) {
  const auto w = atmo::spectrum_wavelengths(sp);
  if (!sp.wavelengths_nm.empty())
    return std::to_string(w.size()) + (w.size() == 1 ? " wavelength " : " wavelengths ") + nm(w.front()) +
           (w.size() > 1 ? "\u2013" + nm(w.back()) : "") + " nm (listed)";
  return std::to_string(w.size()) + (w.size() == 1 ? " wavelength" : " wavelengths") + " in " +
         std::to_string(sp.count) + " bins " + nm(sp.from_nm) + "\u2013" + nm(sp.to_nm) + " nm (centres " +
         nm(w.front()) + "\u2013" + nm(w.back()) + " nm)";
}
}  // namespace

std::vector<Pass> plan(const Scene& s) {
  std::vector<Pass> p;
  const auto& a = s.atmosphere;
  const bool sky = any_kind(s, &OutputKind::sky);
  const bool needs_atmosphere = sky || any_kind(s, &OutputKind::atmosphere);
  const bool needs_sun = any_kind(s, &OutputKind::sun) || any_kind(s, &OutputKind::observer);
  const int sh_bands = [&] {
    int b = 0;
    for (const auto& o : s.outputs)
      if (const OutputKind* k = find_output_kind(o.kind); k != nullptr && k->bands)
        b = std::max(b, o.bands > 0 ? o.bands : k->default_bands);
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
    p.push_back({"sun-position", false, "no [observer] or [sun]"});  // check_outputs refused it already

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
               needs_atmosphere ? spectrum_summary(a.spectrum) : "no output needs spectral quantities"});
  p.push_back({"sky-radiance:single-scattering", sky, sky ? kinds_with(s, &OutputKind::sky) + " output" : "no sky output"});
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
  for (const auto& k : output_kinds())  // the kinds that are a pass of their own
    if (!k.plan_pass.empty()) {
      const bool w = wants(s, k.name);
      p.push_back({std::string(k.plan_pass), w, w ? std::string(k.name) + " output" : "not requested"});
    }
  p.push_back({"sh-projection", sh_bands > 0,
               sh_bands > 0 ? std::to_string(sh_bands) + " bands (" + std::to_string(sh_bands * sh_bands) + " coefficients)"
                            : "no sh-coefficients output"});
  return p;
}

}  // namespace atmosh::scene
