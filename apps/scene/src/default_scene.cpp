// The built-in default scene and the TOML writer.
#include <sstream>

#include "atmosh/scene/scene.hpp"

namespace atmosh::scene {

namespace {
constexpr std::string_view kDefaultScene = R"toml(# atmosh built-in default scene (print it with `atmosh scene show`).
# Units: metres, per metre, nanometres, degrees, Dobson units; time in UTC.
version = 1
name = "earth-default"

[planet]
radius_m = 6360000.0
atmosphere_top_m = 100000.0

[rayleigh]
model = "physical"            # Bodhaine et al. 1999 cross-section, number density from p and T
pressure_pa = 101325.0
temperature_k = 288.15
profile = { model = "exponential", scale_height_m = 8000.0 }

[mie]
scattering_per_m = 3.996e-6   # at the ground, at reference_nm
reference_nm = 550.0
angstrom = 0.0
single_scattering_albedo = 0.9
profile = { model = "exponential", scale_height_m = 1200.0 }
phase = { model = "cornette-shanks", g = 0.8 }

[ozone]
column_du = 300.0
profile = { model = "tent", bottom_m = 10000.0, peak_m = 25000.0, top_m = 40000.0 }

[spectrum]
from_nm = 380.0
to_nm = 780.0
count = 16

[scattering]                  # light scattered more than once (docs/sky.md, "Multiple scattering")
method = "approximate"        # single | orders | approximate

[observer]                    # Paris, summer solstice evening
latitude_deg = 48.8566
longitude_deg = 2.3522
height_m = 35.0
time_utc = "2026-06-21T18:30:00Z"

[[output]]
kind = "sky-image"
projection = "equirect"
size = [512, 256]
file = "sky.exr"

[[output]]
kind = "sun-track"
file = "sun_track.csv"

[[output]]
kind = "lut-convergence"
file = "lut_convergence.csv"

[[output]]
kind = "sun-elevation-study"
file = "sun_elevation_study"

[[output]]
kind = "sh-coefficients"
bands = 8
file = "sky_sh.csv"
)toml";

std::string num(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  std::string s = os.str();
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string profile_toml(const atmo::DensityProfileSpec& p) {
  using K = atmo::DensityProfileSpec::Kind;
  std::ostringstream os;
  switch (p.kind) {
    case K::Exponential:
      os << "{ model = \"exponential\", scale_height_m = " << num(p.scale_height_m) << " }";
      break;
    case K::Tent:
      os << "{ model = \"tent\", bottom_m = " << num(p.bottom_m) << ", peak_m = " << num(p.peak_m)
         << ", top_m = " << num(p.top_m) << " }";
      break;
    case K::Tabulated: {
      os << "{ model = \"tabulated\", altitude_m = [";
      for (std::size_t i = 0; i < p.altitude_m.size(); ++i) os << (i ? ", " : "") << num(p.altitude_m[i]);
      os << "], value = [";
      for (std::size_t i = 0; i < p.value.size(); ++i) os << (i ? ", " : "") << num(p.value[i]);
      os << "] }";
      break;
    }
  }
  return os.str();
}

std::string phase_toml(const atmo::PhaseSpec& p) {
  using M = atmo::PhaseSpec::Model;
  std::ostringstream os;
  const char* names[] = {"rayleigh", "hg", "cornette-shanks", "double-hg", "tabulated"};
  os << "{ model = \"" << names[static_cast<int>(p.model)] << "\"";
  if (p.model == M::Rayleigh) os << ", depolarization = " << num(p.depolarization);
  if (p.model == M::HenyeyGreenstein || p.model == M::CornetteShanks || p.model == M::DoubleHenyeyGreenstein)
    os << ", g = " << num(p.g);
  if (p.model == M::DoubleHenyeyGreenstein) os << ", g2 = " << num(p.g2) << ", weight = " << num(p.weight);
  if (p.model == M::Tabulated) {
    os << ", cos_theta = [";
    for (std::size_t i = 0; i < p.cos_theta.size(); ++i) os << (i ? ", " : "") << num(p.cos_theta[i]);
    os << "], value = [";
    for (std::size_t i = 0; i < p.value.size(); ++i) os << (i ? ", " : "") << num(p.value[i]);
    os << "]";
  }
  os << " }";
  return os.str();
}

std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}
}  // namespace

std::string_view default_scene_toml() { return kDefaultScene; }

Scene default_scene() { return parse_scene(kDefaultScene, "<built-in default scene>"); }

std::string to_toml(const Scene& s) {
  std::ostringstream os;
  const auto& a = s.atmosphere;
  os << "version = 1\nname = " << quoted(a.name) << "\nsun_model = " << quoted(s.sun_model) << "\n\n";
  os << "[planet]\nradius_m = " << num(a.planet.radius_m) << "\natmosphere_top_m = " << num(a.planet.atmosphere_top_m)
     << "\nground_albedo = " << num(a.planet.ground_albedo) << "\n\n";
  if (a.rayleigh) {
    const auto& r = *a.rayleigh;
    os << "[rayleigh]\n";
    if (r.model == atmo::RayleighSpec::Model::Physical)
      os << "model = \"physical\"\npressure_pa = " << num(r.pressure_pa) << "\ntemperature_k = " << num(r.temperature_k)
         << "\nco2_ppm = " << num(r.co2_ppm) << "\n";
    else
      os << "model = \"coefficients\"\nscattering_per_m = " << num(r.scattering_per_m)
         << "\nreference_nm = " << num(r.reference_nm) << "\n";
    os << "profile = " << profile_toml(r.profile) << "\nphase = " << phase_toml(r.phase) << "\n\n";
  }
  if (a.mie) {
    const auto& m = *a.mie;
    os << "[mie]\nscattering_per_m = " << num(m.scattering_per_m) << "\nreference_nm = " << num(m.reference_nm)
       << "\nangstrom = " << num(m.angstrom) << "\nsingle_scattering_albedo = " << num(m.single_scattering_albedo)
       << "\nprofile = " << profile_toml(m.profile) << "\nphase = " << phase_toml(m.phase) << "\n\n";
  }
  if (a.ozone)
    os << "[ozone]\ncolumn_du = " << num(a.ozone->column_du) << "\nprofile = " << profile_toml(a.ozone->profile)
       << "\n\n";
  if (a.spectrum.wavelengths_nm.empty()) {
    os << "[spectrum]\nfrom_nm = " << num(a.spectrum.from_nm) << "\nto_nm = " << num(a.spectrum.to_nm)
       << "\ncount = " << a.spectrum.count << "\n\n";
  } else {
    os << "[spectrum]\nwavelengths_nm = [";
    for (std::size_t i = 0; i < a.spectrum.wavelengths_nm.size(); ++i)
      os << (i ? ", " : "") << num(a.spectrum.wavelengths_nm[i]);
    os << "]\n\n";
  }
  {
    const atmo::MultipleScatteringOptions d, &m = s.scattering;
    std::ostringstream t;
    auto key = [&](const char* name, int v, int def) {
      if (v != def) t << name << " = " << v << "\n";
    };
    key("orders", m.orders, d.orders);
    key("ms_altitudes", m.ms_altitudes, d.ms_altitudes);
    key("ms_sun_directions", m.ms_sun_directions, d.ms_sun_directions);
    key("ms_zenith_directions", m.ms_zenith_directions, d.ms_zenith_directions);
    key("ms_azimuth_directions", m.ms_azimuth_directions, d.ms_azimuth_directions);
    key("ms_ray_steps", m.ms_ray_steps, d.ms_ray_steps);
    key("orders_radii", m.orders_radii, d.orders_radii);
    key("orders_view_directions", m.orders_view_directions, d.orders_view_directions);
    key("orders_sun_directions", m.orders_sun_directions, d.orders_sun_directions);
    key("orders_azimuths", m.orders_azimuths, d.orders_azimuths);
    key("orders_sphere_zenith", m.orders_sphere_zenith, d.orders_sphere_zenith);
    key("orders_sphere_azimuth", m.orders_sphere_azimuth, d.orders_sphere_azimuth);
    key("orders_ray_steps", m.orders_ray_steps, d.orders_ray_steps);
    if (m.method != d.method || !t.str().empty())
      os << "[scattering]\nmethod = " << quoted(atmo::scattering_method_name(m.method)) << "\n" << t.str() << "\n";
  }
  if (s.observer)
    os << "[observer]\nlatitude_deg = " << num(s.observer->latitude_deg) << "\nlongitude_deg = "
       << num(s.observer->longitude_deg) << "\nheight_m = " << num(s.observer->height_m)
       << "\ntime_utc = " << quoted(s.observer->time_utc) << "\n\n";
  if (s.sun)
    os << "[sun]\nelevation_deg = " << num(s.sun->elevation_deg) << "\nazimuth_deg = " << num(s.sun->azimuth_deg)
       << "\n\n";
  for (const auto& o : s.outputs) {
    os << "[[output]]\nkind = " << quoted(o.kind) << "\nfile = " << quoted(o.file) << "\n";
    if (o.kind == "sky-image")
      os << "projection = " << quoted(o.projection) << "\nsize = [" << o.size[0] << ", " << o.size[1]
         << "]\nspectral = " << (o.spectral ? "true" : "false") << "\n";
    if (o.bands > 0) os << "bands = " << o.bands << "\n";
    os << "\n";
  }
  return os.str();
}

}  // namespace atmosh::scene
