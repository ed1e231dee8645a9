// bind_atmo.cpp — atmosh._atmosh.atmo: atmospheres from presets and scenes, columns and
// optical depths along arrays of rays, phase functions on arrays.
#include <cmath>
#include <optional>

#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/sun_position.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/atmo/sun_disc.hpp"
#include "atmosphere_object.hpp"
#include "common.hpp"

namespace atmosh::python {

PyAtmosphere::PyAtmosphere(scene::Scene s, const std::optional<std::vector<double>>& wavelengths_nm)
    : scene(std::move(s)) {
  if (wavelengths_nm) {
    if (wavelengths_nm->empty()) throw InputError("wavelengths_nm: empty");
    scene.atmosphere.spectrum.wavelengths_nm = *wavelengths_nm;
  }
  atm = std::make_unique<atmo::Atmosphere>(scene.atmosphere);
}

namespace {

scene::Scene preset_scene(const std::string& name) {
  scene::Scene s;
  s.source = "preset " + name;
  s.atmosphere = atmo::preset(name);
  return s;
}

// Columns [m] per constituent along rays (origin altitude above the ground [m], cosine of
// the zenith angle, optional length [m]; < 0 or NaN: to the end of the ray).
py::tuple columns(const PyAtmosphere& a, const DArray& altitude, const DArray& mu, const std::optional<DArray>& length,
                  const std::string& method, int shells, int directions) {
  const std::size_t n = len1(altitude, "altitude_m");
  if (len1(mu, "cos_zenith") != n) throw InputError("columns: altitude_m and cos_zenith differ in length");
  if (length && len1(*length, "length_m") != n) throw InputError("columns: length_m differs in length");
  if (method != "reference" && method != "lut")
    throw InputError("method: '" + method + "' is not reference or lut");
  DArray col = new_array({static_cast<py::ssize_t>(n), 3}), err = new_array({static_cast<py::ssize_t>(n), 3});
  py::array_t<bool> hits(static_cast<py::ssize_t>(n));
  double *pc = col.mutable_data(), *pe = err.mutable_data();
  bool* ph = hits.mutable_data();
  const double *pa = altitude.data(), *pm = mu.data(), *pl = length ? length->data() : nullptr;
  const atmo::Atmosphere& atm = *a.atm;
  auto check = [&](std::size_t i) {
    if (!std::isfinite(pa[i]) || pa[i] < 0.0)
      throw InputError("altitude_m[" + std::to_string(i) + "] = " + atmosh::format_double(pa[i]) +
                       ": must be finite and >= 0 (above the ground)");
    if (!(std::abs(pm[i]) <= 1.0))
      throw InputError("cos_zenith[" + std::to_string(i) + "] = " + atmosh::format_double(pm[i]) + ": must be in [-1, 1]");
  };
  for (std::size_t i = 0; i < n; ++i) check(i);
  {
    py::gil_scoped_release release;
    if (method == "reference") {
      atmo::OpticalDepthReference ref(atm);
      for (std::size_t i = 0; i < n; ++i) {
        const double L = pl && std::isfinite(pl[i]) ? pl[i] : -1.0;
        const atmo::RayColumn c = ref.column(atm.ground_radius() + pa[i], pm[i], L);
        for (int k = 0; k < 3; ++k) {
          pc[3 * i + k] = c.column[k];
          pe[3 * i + k] = c.error[k];
        }
        ph[i] = c.hits_ground;
      }
    } else {
      if (pl)
        for (std::size_t i = 0; i < n; ++i)
          if (std::isfinite(pl[i]) && pl[i] >= 0.0) throw InputError("length_m: only with method 'reference'");
      atmo::LutOptions lo;
      lo.shells = shells;
      lo.view_directions = lo.sun_directions = directions;
      atmo::OpticalDepthLut lut(atm, lo);
      for (std::size_t i = 0; i < n; ++i) {
        const atmo::LutColumn c = lut.view(atm.ground_radius() + pa[i], pm[i]);
        for (int k = 0; k < 3; ++k) {
          pc[3 * i + k] = c.column[k];
          pe[3 * i + k] = std::nan("");
        }
        ph[i] = c.hits_ground;
      }
    }
  }
  return py::make_tuple(col, err, hits);
}

DArray coefficient_table(const PyAtmosphere& a, bool scattering) {
  const std::size_t nw = a.atm->wavelengths_nm().size();
  DArray out = new_array({static_cast<py::ssize_t>(nw), 3});
  for (std::size_t i = 0; i < nw; ++i) {
    const auto& c = a.atm->coefficients(i);
    for (int k = 0; k < 3; ++k) out.mutable_data()[3 * i + k] = scattering ? c.scattering[k] : c.extinction[k];
  }
  return out;
}

atmo::PhaseSpec phase_spec(const std::string& model, double g, double g2, double weight, double depolarization,
                           const std::optional<std::vector<double>>& cos_theta,
                           const std::optional<std::vector<double>>& value) {
  atmo::PhaseSpec s;
  if (model == "rayleigh") s.model = atmo::PhaseSpec::Model::Rayleigh;
  else if (model == "hg") s.model = atmo::PhaseSpec::Model::HenyeyGreenstein;
  else if (model == "cornette-shanks") s.model = atmo::PhaseSpec::Model::CornetteShanks;
  else if (model == "double-hg") s.model = atmo::PhaseSpec::Model::DoubleHenyeyGreenstein;
  else if (model == "tabulated") s.model = atmo::PhaseSpec::Model::Tabulated;
  else throw InputError("model: '" + model + "' is not rayleigh, hg, cornette-shanks, double-hg or tabulated");
  s.g = g;
  s.g2 = g2;
  s.weight = weight;
  s.depolarization = depolarization;
  if (s.model == atmo::PhaseSpec::Model::Tabulated) {
    if (!cos_theta || !value) throw InputError("model 'tabulated': needs cos_theta and value");
    s.cos_theta = *cos_theta;
    s.value = *value;
  }
  return s;
}

template <class F>
DArray map_array(const DArray& x, F&& f) {
  DArray out(std::vector<py::ssize_t>(x.shape(), x.shape() + x.ndim()));
  const double* px = x.data();
  double* po = out.mutable_data();
  const auto n = static_cast<std::size_t>(x.size());
  {
    py::gil_scoped_release release;
    for (std::size_t i = 0; i < n; ++i) po[i] = f(px[i]);
  }
  return out;
}

}  // namespace

void bind_atmo(py::module_& m) {
  m.def("preset_names", &atmo::preset_names, "Names of the built-in atmospheres.");
  py::class_<PyAtmosphere>(m, "Atmosphere", "An atmosphere ready for computation (see atmosh.atmo.atmosphere)")
      .def_static(
          "from_preset",
          [](const std::string& name, const std::optional<std::vector<double>>& wl) {
            return std::make_unique<PyAtmosphere>(preset_scene(name), wl);
          },
          py::arg("name"), py::arg("wavelengths_nm") = py::none())
      .def_static(
          "from_toml",
          [](const std::string& text, const std::string& source, const std::optional<std::vector<double>>& wl) {
            return std::make_unique<PyAtmosphere>(scene::parse_scene(text, source), wl);
          },
          py::arg("text"), py::arg("source") = "<toml>", py::arg("wavelengths_nm") = py::none())
      .def_static(
          "from_file",
          [](const std::string& path, const std::optional<std::vector<double>>& wl) {
            return std::make_unique<PyAtmosphere>(scene::load_scene(path), wl);
          },
          py::arg("path"), py::arg("wavelengths_nm") = py::none())
      .def_static(
          "default_scene",
          [](const std::optional<std::vector<double>>& wl) {
            return std::make_unique<PyAtmosphere>(scene::default_scene(), wl);
          },
          py::arg("wavelengths_nm") = py::none())
      .def_property_readonly("name", [](const PyAtmosphere& a) { return a.scene.atmosphere.name; })
      .def_property_readonly("source", [](const PyAtmosphere& a) { return a.scene.source; })
      .def_property_readonly("wavelengths_nm", [](const PyAtmosphere& a) { return to_array(a.atm->wavelengths_nm()); })
      .def_property_readonly("ground_radius_m", [](const PyAtmosphere& a) { return a.atm->ground_radius(); })
      .def_property_readonly("top_radius_m", [](const PyAtmosphere& a) { return a.atm->top_radius(); })
      .def_property_readonly("ground_albedo", [](const PyAtmosphere& a) { return a.scene.atmosphere.planet.ground_albedo; })
      .def_property_readonly("constituents",
                             [](const PyAtmosphere& a) {
                               std::vector<std::string> c;
                               for (int k = 0; k < atmo::kConstituents; ++k)
                                 if (a.atm->has(k)) c.push_back(atmo::constituent_name(k));
                               return c;
                             })
      .def_property_readonly("scattering_method",
                             [](const PyAtmosphere& a) { return std::string(atmo::scattering_method_name(a.scene.scattering.method)); })
      .def_property_readonly("scattering_orders", [](const PyAtmosphere& a) { return a.scene.scattering.orders; })
      .def_property_readonly("sun_model", [](const PyAtmosphere& a) { return a.scene.sun_model; })
      .def("to_toml", [](const PyAtmosphere& a) { return scene::to_toml(a.scene); })
      .def(
          "scene_sun",
          [](const PyAtmosphere& a) -> py::object {
            // The scene's sun: [observer] (NREL SPA at its place and time) or [sun].
            py::dict d;
            if (a.scene.observer) {
              const auto& o = *a.scene.observer;
              atmo::SunQuery q;
              q.jd_utc = atmo::parse_iso8601(o.time_utc).jd_utc;
              q.latitude_deg = o.latitude_deg;
              q.longitude_deg = o.longitude_deg;
              q.height_m = o.height_m;
              q.rise_transit_set = false;
              const auto s = atmo::sun_position(q);
              d["elevation_deg"] = s.elevation_deg;
              d["azimuth_deg"] = s.azimuth_deg;
              d["apparent_elevation_deg"] = s.apparent_elevation_deg;
              d["earth_sun_distance_au"] = s.earth_sun_distance_au;
              d["observer_height_m"] = o.height_m;
              return d;
            }
            if (a.scene.sun) {
              d["elevation_deg"] = a.scene.sun->elevation_deg;
              d["azimuth_deg"] = a.scene.sun->azimuth_deg;
              d["earth_sun_distance_au"] = 1.0;
              d["observer_height_m"] = 0.0;
              return d;
            }
            return py::none();
          })
      .def("extinction", [](const PyAtmosphere& a) { return coefficient_table(a, false); })
      .def("scattering", [](const PyAtmosphere& a) { return coefficient_table(a, true); })
      .def("density",
           [](const PyAtmosphere& a, const DArray& h) {
             const std::size_t n = len1(h, "altitude_m");
             DArray out = new_array({static_cast<py::ssize_t>(n), 3});
             for (std::size_t i = 0; i < n; ++i) {
               const glm::dvec3 d = a.atm->density(h.data()[i]);
               for (int k = 0; k < 3; ++k) out.mutable_data()[3 * i + k] = d[k];
             }
             return out;
           })
      .def("columns", &columns, py::arg("altitude_m"), py::arg("cos_zenith"), py::arg("length_m") = py::none(),
           py::arg("method") = "reference", py::arg("shells") = 40, py::arg("directions") = 64);

  py::class_<atmo::PhaseFunction>(m, "PhaseFunction")
      .def(py::init([](const std::string& model, double g, double g2, double weight, double depolarization,
                       const std::optional<std::vector<double>>& cos_theta,
                       const std::optional<std::vector<double>>& value) {
             return atmo::PhaseFunction(phase_spec(model, g, g2, weight, depolarization, cos_theta, value), "phase");
           }),
           py::arg("model"), py::arg("g") = 0.0, py::arg("g2") = -0.3, py::arg("weight") = 0.9,
           py::arg("depolarization") = 0.0279, py::arg("cos_theta") = py::none(), py::arg("value") = py::none())
      .def("value",
           [](const atmo::PhaseFunction& p, const DArray& mu) {
             return map_array(mu, [&p](double x) {
               if (!(std::abs(x) <= 1.0)) throw InputError("cos_theta = " + atmosh::format_double(x) + ": must be in [-1, 1]");
               return p.value(x);
             });
           })
      .def("sample",
           [](const atmo::PhaseFunction& p, const DArray& u) {
             return map_array(u, [&p](double x) {
               if (!(x >= 0.0 && x <= 1.0)) throw InputError("u = " + atmosh::format_double(x) + ": must be in [0, 1]");
               return p.sample(x);
             });
           })
      .def_property_readonly("mean_cosine", &atmo::PhaseFunction::mean_cosine)
      .def("legendre_moments", [](const atmo::PhaseFunction& p, int n) {
        const auto lm = p.legendre_moments(n);
        return py::make_tuple(to_array(lm.chi), lm.error_estimate);
      });
}

}  // namespace atmosh::python
