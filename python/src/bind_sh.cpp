// bind_sh.cpp — atmosh._atmosh.sh: real spherical harmonics on arrays. Coefficient
// arrays are (C, L^2) here (one row per channel, index l(l+1)+m as in basis.hpp); the
// Python layer adds the 1-D (L^2,) form.
#include <cmath>

#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/convolution.hpp"
#include "atmosh/sh/projection.hpp"
#include "atmosh/sh/rotation.hpp"
#include "atmosh/sh/transform.hpp"
#include "common.hpp"

namespace atmosh::python {

namespace {

// Band count of a (C, L^2) array; InputError unless the last axis is a square.
int bands_of(const DArray& c) {
  if (c.ndim() != 2) throw InputError("coefficients: expected shape (C, L^2), got shape " + shape_string(c));
  const auto n = c.shape(1);
  const auto L = static_cast<py::ssize_t>(std::llround(std::sqrt(static_cast<double>(n))));
  if (n < 1 || L * L != n)
    throw InputError("coefficients: last axis has " + std::to_string(n) + " values, not a square L^2 >= 1");
  return static_cast<int>(L);
}

std::vector<double> row(const DArray& c, py::ssize_t r) {
  const auto n = c.shape(1);
  return std::vector<double>(c.data() + r * n, c.data() + (r + 1) * n);
}

DArray from_channels(const sh::Channels& ch, std::size_t n) {
  DArray out = new_array({static_cast<py::ssize_t>(ch.size()), static_cast<py::ssize_t>(n)});
  for (std::size_t c = 0; c < ch.size(); ++c) std::copy(ch[c].begin(), ch[c].end(), out.mutable_data() + c * n);
  return out;
}

sh::LatitudeRule parse_rule(const std::string& name) {
  if (name == "gauss") return sh::LatitudeRule::gauss;
  if (name == "fejer") return sh::LatitudeRule::fejer;
  if (name == "clenshaw-curtis") return sh::LatitudeRule::clenshaw_curtis;
  throw InputError("rule: '" + name + "' is not gauss, fejer or clenshaw-curtis");
}

sh::FftPlanning parse_fft(const std::string& name) {
  if (name == "estimate") return sh::FftPlanning::estimate;
  if (name == "measure") return sh::FftPlanning::measure;
  throw InputError("fft: '" + name + "' is not estimate or measure");
}

sh::GaussGrid make_grid(int bands, const std::string& rule, int nlat, int nphi, const std::string& fft = "estimate") {
  const auto planning = parse_fft(fft);
  const auto r = parse_rule(rule);
  sh::GaussGrid g =
      r == sh::LatitudeRule::gauss ? sh::gauss_grid(bands, nlat, nphi) : sh::regular_grid(bands, r, nlat, nphi);
  g.fft = planning;
  return g;
}

sh::PixelRule parse_pixel_rule(const std::string& name) {
  if (name == "exact") return sh::PixelRule::exact;
  if (name == "solid-angle") return sh::PixelRule::solid_angle;
  if (name == "pixel-integrated") return sh::PixelRule::pixel_integrated;
  throw InputError("rule: '" + name + "' is not exact, solid-angle or pixel-integrated");
}

DArray apply_rotation(const DArray& c, const sh::Rotation& R) {
  DArray out(std::vector<py::ssize_t>{c.shape(0), c.shape(1)});
  for (py::ssize_t r = 0; r < c.shape(0); ++r) R.apply(c.data() + r * c.shape(1), out.mutable_data() + r * c.shape(1));
  return out;
}

}  // namespace

void bind_sh(py::module_& m) {
  m.def(
      "evaluate",
      [](int bands, const DArray& dirs) {
        sh::check_bands(bands, "bands");
        const std::size_t n = rows3(dirs, "directions");
        const auto nc = static_cast<std::size_t>(bands) * bands;
        DArray out = new_array({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(nc)});
        for (std::size_t i = 0; i < n; ++i) {
          const double* d = dirs.data() + 3 * i;
          sh::evaluate(bands, sh::checked_direction({d[0], d[1], d[2]}, "direction"), out.mutable_data() + i * nc);
        }
        return out;
      },
      py::arg("bands"), py::arg("directions"));
  m.def(
      "grid",
      [](int bands, const std::string& rule, int nlat, int nphi) {
        const sh::GaussGrid g = make_grid(bands, rule, nlat, nphi);
        py::dict d;
        d["cos_theta"] = to_array(g.cos_t);
        d["sin_theta"] = to_array(g.sin_t);
        d["weights"] = to_array(g.weights);
        std::vector<double> phi(static_cast<std::size_t>(g.nphi));
        for (int j = 0; j < g.nphi; ++j) phi[static_cast<std::size_t>(j)] = g.phi(j);
        d["phi"] = to_array(phi);
        return d;
      },
      py::arg("bands"), py::arg("rule") = "gauss", py::arg("nlat") = 0, py::arg("nphi") = 0);
  m.def(
      "analyse",
      [](const DArray& values, int bands, const std::string& rule, int threads, const std::string& fft) {
        if (values.ndim() != 3) throw InputError("values: expected shape (C, nlat, nphi), got " + shape_string(values));
        const int nlat = static_cast<int>(values.shape(1)), nphi = static_cast<int>(values.shape(2));
        const sh::GaussGrid g = make_grid(bands, rule, nlat, nphi, fft);
        if (g.nlat != nlat || g.nphi != nphi)
          throw InputError("values: grid of " + std::to_string(nlat) + " x " + std::to_string(nphi) + " does not fit");
        const auto nc = static_cast<std::size_t>(bands) * bands;
        const auto per = static_cast<std::size_t>(nlat) * nphi;
        DArray out = new_array({values.shape(0), static_cast<py::ssize_t>(nc)});
        for (py::ssize_t c = 0; c < values.shape(0); ++c) {
          const auto a = sh::analyse(g, values.data() + c * per, threads);
          std::copy(a.begin(), a.end(), out.mutable_data() + c * nc);
        }
        return out;
      },
      py::arg("values"), py::arg("bands"), py::arg("rule") = "gauss", py::arg("threads") = 1,
      py::arg("fft") = "estimate");
  m.def(
      "synthesise",
      [](const DArray& coeffs, const std::string& rule, int nlat, int nphi, int threads, const std::string& fft) {
        const int bands = bands_of(coeffs);
        const sh::GaussGrid g = make_grid(bands, rule, nlat, nphi, fft);
        const auto per = static_cast<std::size_t>(g.nlat) * g.nphi;
        DArray out = new_array({coeffs.shape(0), g.nlat, g.nphi});
        for (py::ssize_t c = 0; c < coeffs.shape(0); ++c) {
          const auto v = sh::synthesise(g, coeffs.data() + c * coeffs.shape(1), threads);
          std::copy(v.begin(), v.end(), out.mutable_data() + c * per);
        }
        return out;
      },
      py::arg("coeffs"), py::arg("rule") = "gauss", py::arg("nlat") = 0, py::arg("nphi") = 0, py::arg("threads") = 1,
      py::arg("fft") = "estimate");
  m.def(
      "project_equirect",
      [](const DArray& img, int bands, const std::string& rule, int threads) {
        if (img.ndim() != 3) throw InputError("image: expected shape (H, W, C), got shape " + shape_string(img));
        const auto H = img.shape(0), W = img.shape(1), C = img.shape(2);
        std::vector<double> planar(static_cast<std::size_t>(img.size()));
        for (py::ssize_t y = 0; y < H; ++y)
          for (py::ssize_t x = 0; x < W; ++x)
            for (py::ssize_t c = 0; c < C; ++c) planar[(c * H + y) * W + x] = img.data()[(y * W + x) * C + c];
        sh::ImageViewD v{static_cast<int>(W), static_cast<int>(H), static_cast<int>(C), planar.data()};
        sh::Channels ch;
        {
          py::gil_scoped_release release;
          ch = sh::project_equirect(v, bands, threads, parse_pixel_rule(rule));
        }
        return from_channels(ch, static_cast<std::size_t>(bands) * bands);
      },
      py::arg("image"), py::arg("bands"), py::arg("rule") = "exact", py::arg("threads") = 1);
  m.def(
      "project_cube",
      [](const DArray& faces, int bands, int threads) {
        if (faces.ndim() != 4 || faces.shape(0) != 6 || faces.shape(1) != faces.shape(2))
          throw InputError("faces: expected shape (6, N, N, C), got shape " + shape_string(faces));
        const auto N = faces.shape(1), C = faces.shape(3);
        sh::CubeMap cube;
        cube.size = static_cast<int>(N);
        cube.channels = static_cast<int>(C);
        for (int f = 0; f < 6; ++f) {
          cube.faces[f].resize(static_cast<std::size_t>(N * N * C));
          const double* p = faces.data() + f * N * N * C;
          for (py::ssize_t y = 0; y < N; ++y)
            for (py::ssize_t x = 0; x < N; ++x)
              for (py::ssize_t c = 0; c < C; ++c)
                cube.faces[f][static_cast<std::size_t>((c * N + y) * N + x)] = static_cast<float>(p[(y * N + x) * C + c]);
        }
        sh::Channels ch;
        {
          py::gil_scoped_release release;
          ch = sh::project_cube(cube, bands, threads);
        }
        return from_channels(ch, static_cast<std::size_t>(bands) * bands);
      },
      py::arg("faces"), py::arg("bands"), py::arg("threads") = 1);
  m.def(
      "cube_directions",
      [](int size) {
        if (size < 1 || size > 16384) throw InputError("size " + std::to_string(size) + ": must be in [1, 16384]");
        DArray out = new_array({6, size, size, 3});
        double* p = out.mutable_data();
        for (int f = 0; f < 6; ++f)
          for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
              const glm::dvec3 d = sh::cube_texel_direction(f, x, y, size);
              for (int k = 0; k < 3; ++k) *p++ = d[k];
            }
        return out;
      },
      py::arg("size"));
  m.def(
      "render_equirect",
      [](const DArray& coeffs, int width, int height) {
        const int bands = bands_of(coeffs);
        if (width < 1 || height < 1) throw InputError("size " + std::to_string(width) + "x" + std::to_string(height) + ": must be >= 1");
        const auto C = coeffs.shape(0);
        DArray out = new_array({height, width, C});
        for (py::ssize_t c = 0; c < C; ++c) {
          const auto v = sh::render_equirect(row(coeffs, c), bands, width, height);
          for (std::size_t i = 0; i < v.size(); ++i) out.mutable_data()[i * C + c] = v[i];
        }
        return out;
      },
      py::arg("coeffs"), py::arg("width"), py::arg("height"));
  m.def(
      "rotate_matrix",
      [](const DArray& coeffs, const DArray& R) {
        if (R.ndim() != 2 || R.shape(0) != 3 || R.shape(1) != 3)
          throw InputError("matrix: expected shape (3, 3), got shape " + shape_string(R));
        glm::dmat3 M;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) M[j][i] = R.data()[3 * i + j];
        return apply_rotation(coeffs, sh::Rotation(bands_of(coeffs), M));
      },
      py::arg("coeffs"), py::arg("matrix"));
  m.def(
      "rotate_euler",
      [](const DArray& coeffs, double alpha, double beta, double gamma) {
        return apply_rotation(coeffs, sh::Rotation(bands_of(coeffs), sh::EulerZYZ{alpha, beta, gamma}));
      },
      py::arg("coeffs"), py::arg("alpha"), py::arg("beta"), py::arg("gamma"));
  m.def("irradiance_factors", &sh::irradiance_factors, py::arg("bands"));
  m.def(
      "convolve",
      [](const DArray& coeffs, const std::vector<double>& factors) {
        const int bands = bands_of(coeffs);
        DArray out(std::vector<py::ssize_t>{coeffs.shape(0), coeffs.shape(1)});
        for (py::ssize_t c = 0; c < coeffs.shape(0); ++c) {
          auto v = row(coeffs, c);
          sh::convolve_zonal(v, bands, factors);
          std::copy(v.begin(), v.end(), out.mutable_data() + c * coeffs.shape(1));
        }
        return out;
      },
      py::arg("coeffs"), py::arg("factors"));
  m.def(
      "irradiance_at",
      [](const DArray& coeffs, const DArray& normals) {
        const int bands = bands_of(coeffs);
        const std::size_t n = rows3(normals, "normals");
        const auto C = coeffs.shape(0);
        DArray out = new_array({static_cast<py::ssize_t>(n), C});
        for (py::ssize_t c = 0; c < C; ++c) {
          const auto v = row(coeffs, c);
          for (std::size_t i = 0; i < n; ++i) {
            const double* d = normals.data() + 3 * i;
            out.mutable_data()[static_cast<py::ssize_t>(i) * C + c] = sh::irradiance_at(v, bands, {d[0], d[1], d[2]});
          }
        }
        return out;
      },
      py::arg("coeffs"), py::arg("normals"));
  m.def(
      "band_energy",
      [](const DArray& coeffs) {
        const int bands = bands_of(coeffs);
        DArray out = new_array({coeffs.shape(0), bands});
        for (py::ssize_t c = 0; c < coeffs.shape(0); ++c) {
          const auto e = sh::band_energy(row(coeffs, c), bands);
          std::copy(e.begin(), e.end(), out.mutable_data() + c * bands);
        }
        return out;
      },
      py::arg("coeffs"));
  m.def(
      "window_weights",
      [](const std::string& name, int bands) { return sh::window_weights(sh::parse_window(name), bands); },
      py::arg("name"), py::arg("bands"));
  m.def(
      "convert",
      [](const DArray& coeffs, const std::string& from, bool from_cs, const std::string& to, bool to_cs) {
        auto norm = [](const std::string& s) {
          if (s == "orthonormal") return sh::Normalization::orthonormal;
          if (s == "4pi") return sh::Normalization::four_pi;
          if (s == "schmidt") return sh::Normalization::schmidt;
          throw InputError("normalization: '" + s + "' is not orthonormal, 4pi or schmidt");
        };
        const int bands = bands_of(coeffs);
        const auto f = norm(from), t = norm(to);
        DArray out(std::vector<py::ssize_t>{coeffs.shape(0), coeffs.shape(1)});
        for (py::ssize_t c = 0; c < coeffs.shape(0); ++c) {
          const auto v = sh::convert(row(coeffs, c), bands, f, from_cs, t, to_cs);
          std::copy(v.begin(), v.end(), out.mutable_data() + c * coeffs.shape(1));
        }
        return out;
      },
      py::arg("coeffs"), py::arg("from_normalization"), py::arg("from_condon_shortley"), py::arg("to_normalization"),
      py::arg("to_condon_shortley"));
}

}  // namespace atmosh::python
