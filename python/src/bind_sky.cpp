// bind_sky.cpp — atmosh._atmosh.sky: a sky integrator over an atmosphere, radiance for
// arrays of view directions, CPU sky images, irradiance, colour conversions.
#include <algorithm>
#include <cmath>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include "atmosh/atmo/colour.hpp"
#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/atmo/sun_disc.hpp"
#include "atmosphere_object.hpp"
#include "common.hpp"

namespace atmosh::python {

namespace {

struct PySky {
  std::unique_ptr<atmo::SkyIntegrator> sky;
};

glm::dvec3 vec3(const DArray& a, const char* what) {
  if (a.ndim() != 1 || a.shape(0) != 3)
    throw InputError(std::string(what) + ": expected an array of shape (3,), got shape " + shape_string(a));
  return {a.data()[0], a.data()[1], a.data()[2]};
}

// Runs body(i) for i < n on `threads` threads (0: the hardware's), the first exception
// rethrown on the caller.
template <class Body>
void parallel_for(std::size_t n, int threads, Body&& body) {
  unsigned t = threads > 0 ? static_cast<unsigned>(threads) : std::max(1u, std::thread::hardware_concurrency());
  t = static_cast<unsigned>(std::min<std::size_t>(t, std::max<std::size_t>(n / 16, 1)));
  if (t <= 1) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
  std::exception_ptr error;
  std::mutex mu;
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < t; ++k)
    pool.emplace_back([&, k] {
      try {
        for (std::size_t i = k; i < n; i += t) body(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mu);
        if (!error) error = std::current_exception();
      }
    });
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

DArray radiance(const PySky& s, const DArray& views, const DArray& sun, double altitude, int threads) {
  const std::size_t n = rows3(views, "views");
  const glm::dvec3 l = vec3(sun, "sun");
  const std::size_t nw = s.sky->atmosphere().wavelengths_nm().size();
  DArray out = new_array({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(nw)});
  const double* pv = views.data();
  double* po = out.mutable_data();
  {
    py::gil_scoped_release release;
    parallel_for(n, threads, [&](std::size_t i) {
      s.sky->radiance(altitude, glm::dvec3(pv[3 * i], pv[3 * i + 1], pv[3 * i + 2]), l, po + i * nw);
    });
  }
  return out;
}

py::dict image(const PySky& s, const DArray& sun, int width, int height, const std::string& projection,
               double altitude, bool spectral, bool sun_disc, int threads) {
  if (width < 1 || height < 1 || width > 65536 || height > 65536)
    throw InputError("size " + std::to_string(width) + "x" + std::to_string(height) + ": each side in [1, 65536]");
  const atmo::SkyProjection proj = atmo::parse_sky_projection(projection);
  const glm::dvec3 l = vec3(sun, "sun");
  atmo::SkyImage img;
  {
    py::gil_scoped_release release;
    img = atmo::render_sky(*s.sky, proj, width, height, altitude, l, spectral, threads);
    if (sun_disc) atmo::add_sun_disc(img, *s.sky, proj, altitude, l);
  }
  const auto H = static_cast<py::ssize_t>(height), W = static_cast<py::ssize_t>(width);
  const std::size_t np = static_cast<std::size_t>(width) * height;
  auto planar3 = [&](const std::vector<float>& a, const std::vector<float>& b, const std::vector<float>& c) {
    DArray out = new_array({H, W, 3});
    double* p = out.mutable_data();
    for (std::size_t i = 0; i < np; ++i) {
      p[3 * i] = a[i];
      p[3 * i + 1] = b[i];
      p[3 * i + 2] = c[i];
    }
    return out;
  };
  py::dict d;
  d["xyz"] = planar3(img.X, img.Y, img.Z);
  d["srgb"] = planar3(img.R, img.G, img.B);
  py::array_t<bool> valid({H, W});
  for (std::size_t i = 0; i < np; ++i) valid.mutable_data()[i] = img.valid[i] != 0;
  d["valid"] = valid;
  d["wavelengths_nm"] = to_array(img.wavelengths_nm);
  if (spectral) {
    const auto nw = static_cast<py::ssize_t>(img.wavelengths_nm.size());
    DArray sp = new_array({H, W, nw});
    std::copy(img.spectral.begin(), img.spectral.end(), sp.mutable_data());
    d["spectral"] = sp;
  }
  d["seconds"] = img.seconds;
  d["rays"] = img.rays;
  return d;
}

// XYZ (..., 3) of spectral radiance (..., nw) at `wavelengths`.
DArray to_xyz(const DArray& spectral, const std::vector<double>& wavelengths) {
  const atmo::SpectralToXyz cmf(wavelengths);
  const std::size_t nw = wavelengths.size();
  if (spectral.ndim() < 1 || static_cast<std::size_t>(spectral.shape(spectral.ndim() - 1)) != nw)
    throw InputError("spectral: last axis must have one value per wavelength (" + std::to_string(nw) +
                     "), got shape " + shape_string(spectral));
  std::vector<py::ssize_t> shape(spectral.shape(), spectral.shape() + spectral.ndim());
  shape.back() = 3;
  DArray out(shape);
  const std::size_t m = static_cast<std::size_t>(spectral.size()) / nw;
  const double* ps = spectral.data();
  double* po = out.mutable_data();
  for (std::size_t i = 0; i < m; ++i) {
    const atmo::Xyz c = cmf(std::span<const double>(ps + i * nw, nw));
    po[3 * i] = c.X;
    po[3 * i + 1] = c.Y;
    po[3 * i + 2] = c.Z;
  }
  return out;
}

DArray matrix_apply(const DArray& in, const atmo::Matrix3& M, const char* what) {
  if (in.ndim() < 1 || in.shape(in.ndim() - 1) != 3)
    throw InputError(std::string(what) + ": last axis must have 3 values, got shape " + shape_string(in));
  DArray out(std::vector<py::ssize_t>(in.shape(), in.shape() + in.ndim()));
  const std::size_t m = static_cast<std::size_t>(in.size()) / 3;
  const double* pi = in.data();
  double* po = out.mutable_data();
  for (std::size_t i = 0; i < m; ++i)
    for (int r = 0; r < 3; ++r)
      po[3 * i + r] = M[r][0] * pi[3 * i] + M[r][1] * pi[3 * i + 1] + M[r][2] * pi[3 * i + 2];
  return out;
}

}  // namespace

void bind_sky(py::module_& m) {
  py::class_<PySky>(m, "Sky")
      .def(py::init([](PyAtmosphere& a, const std::optional<std::string>& scattering, std::optional<int> orders,
                       const std::optional<std::string>& sun_model, int shells, int segments, int samples,
                       double max_piece_tau, double sun_distance_au) {
             atmo::SkyOptions o;
             o.lut.shells = shells;
             o.segments = segments;
             o.samples_per_segment = samples;
             o.max_piece_optical_depth = max_piece_tau;
             o.sun_distance_au = sun_distance_au;
             o.scattering = a.scene.scattering;
             if (scattering) o.scattering.method = atmo::parse_scattering_method(*scattering, "scattering");
             if (orders) o.scattering.orders = *orders;
             o.sun_model = atmo::parse_sun_model(sun_model ? *sun_model : a.scene.sun_model);
             auto s = std::make_unique<PySky>();
             {
               py::gil_scoped_release release;
               s->sky = std::make_unique<atmo::SkyIntegrator>(
                   *a.atm, atmo::solar_spectrum_for_bins(a.atm->spec().spectrum), o);
             }
             return s;
           }),
           py::keep_alive<1, 2>(), py::arg("atmosphere"), py::arg("scattering") = py::none(),
           py::arg("orders") = py::none(), py::arg("sun_model") = py::none(), py::arg("shells") = 32,
           py::arg("segments") = 16, py::arg("samples") = 2, py::arg("max_piece_tau") = 0.5,
           py::arg("sun_distance_au") = 1.0)
      .def_property_readonly("wavelengths_nm",
                             [](const PySky& s) { return to_array(s.sky->atmosphere().wavelengths_nm()); })
      .def_property_readonly("scattering_method",
                             [](const PySky& s) { return std::string(atmo::scattering_method_name(s.sky->method())); })
      .def_property_readonly("sun_model",
                             [](const PySky& s) { return std::string(atmo::sun_model_name(s.sky->options().sun_model)); })
      .def("radiance", &radiance, py::arg("views"), py::arg("sun"), py::arg("altitude_m") = 0.0,
           py::arg("threads") = 0)
      .def("image", &image, py::arg("sun"), py::arg("width"), py::arg("height"), py::arg("projection") = "equirect",
           py::arg("altitude_m") = 0.0, py::arg("spectral") = false, py::arg("sun_disc") = true,
           py::arg("threads") = 0)
      .def(
          "sun_transmittance",
          [](const PySky& s, const DArray& sun, double altitude) {
            return to_array(s.sky->sun_transmittance(altitude, vec3(sun, "sun")));
          },
          py::arg("sun"), py::arg("altitude_m") = 0.0)
      .def(
          "irradiance",
          [](const PySky& s, const DArray& sun, double altitude, int zenith, int azimuth) {
            atmo::SkyIrradiance irr;
            const glm::dvec3 l = vec3(sun, "sun");
            {
              py::gil_scoped_release release;
              irr = atmo::sky_irradiance(*s.sky, altitude, l, zenith, azimuth);
            }
            py::dict d;
            d["direct_w_m2_nm"] = to_array(irr.direct);
            d["diffuse_w_m2_nm"] = to_array(irr.diffuse);
            d["direct_lux"] = irr.direct_lux;
            d["diffuse_lux"] = irr.diffuse_lux;
            return d;
          },
          py::arg("sun"), py::arg("altitude_m") = 0.0, py::arg("zenith") = 24, py::arg("azimuth") = 48);

  m.def(
      "directions",
      [](const DArray& elevation, const DArray& azimuth) {
        const std::size_t n = len1(elevation, "elevation_deg");
        if (len1(azimuth, "azimuth_deg") != n) throw InputError("directions: elevation and azimuth differ in length");
        DArray out = new_array({static_cast<py::ssize_t>(n), 3});
        for (std::size_t i = 0; i < n; ++i) {
          if (!std::isfinite(elevation.data()[i]) || !std::isfinite(azimuth.data()[i]))
            throw InputError("directions[" + std::to_string(i) + "]: non-finite angle");
          const glm::dvec3 d = atmo::enu_direction_from_zenith(90.0 - elevation.data()[i], azimuth.data()[i]);
          for (int k = 0; k < 3; ++k) out.mutable_data()[3 * i + k] = d[k];
        }
        return out;
      },
      py::arg("elevation_deg"), py::arg("azimuth_deg"));
  m.def("to_xyz", &to_xyz, py::arg("spectral"), py::arg("wavelengths_nm"));
  m.def(
      "xyz_weights",
      [](const std::vector<double>& wl) {
        const atmo::SpectralToXyz cmf(wl);
        DArray out = new_array({static_cast<py::ssize_t>(wl.size()), 3});
        for (std::size_t i = 0; i < wl.size(); ++i) {
          out.mutable_data()[3 * i] = cmf.weights()[i].x;
          out.mutable_data()[3 * i + 1] = cmf.weights()[i].y;
          out.mutable_data()[3 * i + 2] = cmf.weights()[i].z;
        }
        return out;
      },
      py::arg("wavelengths_nm"));
  m.def("xyz_to_linear_srgb", [](const DArray& xyz) { return matrix_apply(xyz, atmo::srgb_from_xyz_matrix(), "xyz"); },
        py::arg("xyz"));
  m.def("linear_srgb_to_xyz", [](const DArray& rgb) { return matrix_apply(rgb, atmo::xyz_from_srgb_matrix(), "rgb"); },
        py::arg("rgb"));
  m.def("srgb_encode", [](const DArray& v) {
    DArray out(std::vector<py::ssize_t>(v.shape(), v.shape() + v.ndim()));
    for (py::ssize_t i = 0; i < v.size(); ++i) out.mutable_data()[i] = atmo::srgb_encode(v.data()[i]);
    return out;
  });
  m.def("srgb_decode", [](const DArray& v) {
    DArray out(std::vector<py::ssize_t>(v.shape(), v.shape() + v.ndim()));
    for (py::ssize_t i = 0; i < v.size(); ++i) out.mutable_data()[i] = atmo::srgb_decode(v.data()[i]);
    return out;
  });
  m.def(
      "xy_chromaticity",
      [](const DArray& xyz) {
        if (xyz.ndim() < 1 || xyz.shape(xyz.ndim() - 1) != 3)
          throw InputError("xyz: last axis must have 3 values, got shape " + shape_string(xyz));
        std::vector<py::ssize_t> shape(xyz.shape(), xyz.shape() + xyz.ndim());
        shape.back() = 2;
        DArray out(shape);
        for (py::ssize_t i = 0; i < xyz.size() / 3; ++i) {
          const double* p = xyz.data() + 3 * i;
          const atmo::Chromaticity c = atmo::xy_chromaticity_or_nan({p[0], p[1], p[2]});
          out.mutable_data()[2 * i] = c.x;
          out.mutable_data()[2 * i + 1] = c.y;
        }
        return out;
      },
      py::arg("xyz"));
  m.def(
      "solar_spectrum",
      [](const PyAtmosphere& a) { return to_array(atmo::solar_spectrum_for_bins(a.atm->spec().spectrum)); },
      py::arg("atmosphere"));
}

}  // namespace atmosh::python
