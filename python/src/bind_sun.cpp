// bind_sun.cpp — atmosh._atmosh.sun: sun_position over arrays of instants and places.
#include <cmath>
#include <optional>

#include "atmosh/atmo/sun_position.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "common.hpp"

namespace atmosh::python {

namespace {

const char* const kFields[] = {"zenith_deg",         "azimuth_deg",         "elevation_deg",
                               "apparent_zenith_deg", "apparent_elevation_deg", "declination_deg",
                               "hour_angle_deg",     "equation_of_time_min", "earth_sun_distance_au",
                               "delta_t_s"};
constexpr int kNumFields = 10;

py::dict positions(const DArray& jd, const DArray& lat, const DArray& lon, const DArray& height,
                   const DArray& pressure, const DArray& temperature, const std::optional<DArray>& delta_t,
                   const DArray& delta_ut1, const std::string& algorithm) {
  const std::size_t n = len1(jd, "times");
  for (const DArray* a : {&lat, &lon, &height, &pressure, &temperature, &delta_ut1})
    if (len1(*a, "sun.position argument") != n) throw InputError("sun.position: arrays of different lengths");
  if (delta_t && len1(*delta_t, "delta_t") != n) throw InputError("sun.position: arrays of different lengths");
  const atmo::SunAlgorithm alg = atmo::parse_sun_algorithm(algorithm);
  std::vector<DArray> out;
  for (int f = 0; f < kNumFields; ++f) out.push_back(new_array({static_cast<py::ssize_t>(n)}));
  double* o[kNumFields];
  for (int f = 0; f < kNumFields; ++f) o[f] = out[f].mutable_data();
  const double *pj = jd.data(), *pla = lat.data(), *plo = lon.data(), *ph = height.data(), *pp = pressure.data(),
               *pt = temperature.data(), *pu = delta_ut1.data();
  const double* pd = delta_t ? delta_t->data() : nullptr;
  {
    py::gil_scoped_release release;
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(pj[i])) throw InputError("times[" + std::to_string(i) + "]: not a valid instant (NaT)");
      atmo::SunQuery q;
      q.jd_utc = pj[i];
      q.latitude_deg = pla[i];
      q.longitude_deg = plo[i];
      q.height_m = ph[i];
      q.pressure_hpa = pp[i];
      q.temperature_c = pt[i];
      if (pd) q.delta_t_s = pd[i];
      q.delta_ut1_s = pu[i];
      q.algorithm = alg;
      q.rise_transit_set = false;
      const atmo::SunPosition s = atmo::sun_position(q);
      const double v[kNumFields] = {s.zenith_deg,          s.azimuth_deg,           s.elevation_deg,
                                    s.apparent_zenith_deg, s.apparent_elevation_deg, s.declination_deg,
                                    s.hour_angle_deg,      s.equation_of_time_min,  s.earth_sun_distance_au,
                                    s.delta_t_s};
      for (int f = 0; f < kNumFields; ++f) o[f][i] = v[f];
    }
  }
  py::dict d;
  for (int f = 0; f < kNumFields; ++f) d[kFields[f]] = out[f];
  return d;
}

}  // namespace

void bind_sun(py::module_& m) {
  m.def("positions", &positions, py::arg("jd_utc"), py::arg("latitude_deg"), py::arg("longitude_deg"),
        py::arg("height_m"), py::arg("pressure_hpa"), py::arg("temperature_c"), py::arg("delta_t_s"),
        py::arg("delta_ut1_s"), py::arg("algorithm"),
        "Sun positions for equal-length 1-D arrays (see atmosh.sun.position).");
  m.def(
      "parse_iso8601",
      [](const std::vector<std::string>& texts) {
        DArray jd(static_cast<py::ssize_t>(texts.size()));
        for (std::size_t i = 0; i < texts.size(); ++i) jd.mutable_data()[i] = atmo::parse_iso8601(texts[i]).jd_utc;
        return jd;
      },
      py::arg("texts"), "UTC Julian days of ISO 8601 strings (offsets accepted; InputError naming a bad one).");
  m.def(
      "format_iso8601",
      [](double jd, int decimals) { return atmo::format_iso8601_utc(jd, decimals); }, py::arg("jd_utc"),
      py::arg("decimals") = 0, "ISO 8601 UTC string of a Julian day.");
  m.def("delta_t_espenak_meeus", &atmo::delta_t_espenak_meeus, py::arg("decimal_year"),
        "Delta T = TT - UT1 [s] from the Espenak & Meeus polynomials.");
}

}  // namespace atmosh::python
