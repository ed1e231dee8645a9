// bind_prt.cpp — atmosh._atmosh.prt: per-vertex transfer bakes of a mesh given as
// arrays, built-in meshes, relighting.
#include <cmath>
#include <optional>

#include "atmosh/prt/bake.hpp"
#include "atmosh/prt/mesh.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/prt.hpp"
#include "common.hpp"

namespace atmosh::python {

namespace {

using IArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

py::dict mesh_dict(const prt::Mesh& m) {
  const auto V = static_cast<py::ssize_t>(m.vertex_count()), T = static_cast<py::ssize_t>(m.triangles.size());
  DArray pos = new_array({V, 3}), nrm = new_array({V, 3});
  py::array_t<std::int64_t> tri({T, static_cast<py::ssize_t>(3)});
  for (py::ssize_t v = 0; v < V; ++v)
    for (int k = 0; k < 3; ++k) {
      pos.mutable_data()[3 * v + k] = m.positions[static_cast<std::size_t>(v)][k];
      nrm.mutable_data()[3 * v + k] = m.normals[static_cast<std::size_t>(v)][k];
    }
  for (py::ssize_t t = 0; t < T; ++t)
    for (int k = 0; k < 3; ++k) tri.mutable_data()[3 * t + k] = m.triangles[static_cast<std::size_t>(t)][static_cast<std::size_t>(k)];
  py::dict d;
  d["vertices"] = pos;
  d["triangles"] = tri;
  d["normals"] = nrm;
  d["albedo"] = m.albedo.empty() ? py::object(py::none()) : py::object(to_array(m.albedo));
  return d;
}

prt::Mesh mesh_from_arrays(const DArray& vertices, const IArray& triangles, const std::optional<DArray>& normals,
                           const std::optional<DArray>& albedo) {
  prt::Mesh m;
  m.name = "<arrays>";
  const std::size_t V = rows3(vertices, "vertices");
  if (triangles.ndim() != 2 || triangles.shape(1) != 3)
    throw InputError("triangles: expected an array of shape (T, 3), got shape " + shape_string(triangles));
  for (std::size_t v = 0; v < V; ++v) {
    const double* p = vertices.data() + 3 * v;
    m.positions.emplace_back(p[0], p[1], p[2]);
  }
  for (py::ssize_t t = 0; t < triangles.shape(0); ++t) {
    std::array<std::uint32_t, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const std::int64_t i = triangles.data()[3 * t + k];
      if (i < 0 || static_cast<std::size_t>(i) >= V)
        throw InputError("triangles[" + std::to_string(t) + "]: vertex index " + std::to_string(i) +
                         " outside [0, " + std::to_string(V) + ")");
      tri[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(i);
    }
    m.triangles.push_back(tri);
  }
  if (normals) {
    if (rows3(*normals, "normals") != V) throw InputError("normals: one per vertex expected");
    for (std::size_t v = 0; v < V; ++v) {
      const double* p = normals->data() + 3 * v;
      m.normals.emplace_back(p[0], p[1], p[2]);
    }
  } else {
    prt::compute_normals(m);
  }
  if (albedo) {
    if (len1(*albedo, "albedo") != V) throw InputError("albedo: one per vertex expected");
    m.albedo.assign(albedo->data(), albedo->data() + V);
  }
  prt::validate(m);
  return m;
}

}  // namespace

void bind_prt(py::module_& m) {
  m.def("builtin_scene_names", &prt::builtin_scene_names);
  m.def(
      "builtin_scene", [](const std::string& name, int resolution) { return mesh_dict(prt::builtin_scene(name, resolution)); },
      py::arg("name"), py::arg("resolution") = 32);
  m.def(
      "load_mesh", [](const std::string& path) { return mesh_dict(prt::load_mesh(path)); }, py::arg("path"));
  m.def(
      "bake",
      [](const DArray& vertices, const IArray& triangles, const std::optional<DArray>& normals,
         const std::optional<DArray>& albedo, int bands, const std::string& mode, int strata, std::uint64_t seed,
         int bounces, double default_albedo, int threads) {
        const prt::Mesh mesh = mesh_from_arrays(vertices, triangles, normals, albedo);
        prt::BakeOptions o;
        o.bands = bands;
        o.mode = sh::prt::parse_transfer_mode(mode);
        o.strata = strata;
        o.seed = seed;
        o.bounces = bounces;
        o.default_albedo = default_albedo;
        o.threads = threads;
        prt::Transfer t;
        {
          py::gil_scoped_release release;
          t = prt::bake(mesh, o);
        }
        const auto V = static_cast<py::ssize_t>(mesh.vertex_count()), nc = static_cast<py::ssize_t>(t.bands) * t.bands;
        DArray tr = new_array({V, nc});
        std::copy(t.coeffs.begin(), t.coeffs.end(), tr.mutable_data());
        py::dict d;
        d["transfer"] = tr;
        d["ao"] = to_array(t.ao);
        d["albedo"] = to_array(t.mesh.albedo);
        d["normals"] = mesh_dict(t.mesh)["normals"];
        d["bounce_energy"] = to_array(t.bounce_energy);
        d["samples"] = t.samples;
        d["rays"] = t.rays;
        d["ray_seconds"] = t.ray_seconds;
        d["mode"] = std::string(sh::prt::transfer_mode_name(t.mode));
        return d;
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("normals") = py::none(), py::arg("albedo") = py::none(),
      py::arg("bands") = 3, py::arg("mode") = "shadowed", py::arg("strata") = 45, py::arg("seed") = 1,
      py::arg("bounces") = 2, py::arg("default_albedo") = 0.8, py::arg("threads") = 0);
  m.def(
      "render_vertex_values",
      [](const DArray& vertices, const IArray& triangles, const DArray& values, int width, int height,
         const DArray& view_dir) {
        const prt::Mesh mesh = mesh_from_arrays(vertices, triangles, std::nullopt, std::nullopt);
        if (values.ndim() != 2 || static_cast<std::size_t>(values.shape(0)) != mesh.vertex_count())
          throw InputError("values: expected shape (V, C) with V = " + std::to_string(mesh.vertex_count()) +
                           ", got shape " + shape_string(values));
        if (view_dir.ndim() != 1 || view_dir.shape(0) != 3)
          throw InputError("view_dir: expected shape (3,), got shape " + shape_string(view_dir));
        const auto C = values.shape(1);
        std::vector<std::vector<double>> per_vertex(mesh.vertex_count());
        for (std::size_t v = 0; v < per_vertex.size(); ++v)
          per_vertex[v].assign(values.data() + v * C, values.data() + (v + 1) * C);
        const glm::dvec3 dir(view_dir.data()[0], view_dir.data()[1], view_dir.data()[2]);
        std::vector<std::vector<float>> img;
        {
          py::gil_scoped_release release;
          const prt::RayScene scene(mesh);
          img = prt::render_vertex_values(scene, mesh, per_vertex, width, height, dir);
        }
        DArray out = new_array({height, width, C});
        const std::size_t np = static_cast<std::size_t>(width) * height;
        for (py::ssize_t c = 0; c < C; ++c)
          for (std::size_t i = 0; i < np; ++i) out.mutable_data()[i * C + c] = img[c][i];
        return out;
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("values"), py::arg("width"), py::arg("height"),
      py::arg("view_dir"));
  m.def(
      "unshadowed_transfer",
      [](int bands, const DArray& normals, const DArray& albedo) {
        sh::check_bands(bands, "bands");
        const std::size_t n = rows3(normals, "normals");
        if (len1(albedo, "albedo") != n) throw InputError("albedo: one per normal expected");
        const auto nc = static_cast<std::size_t>(bands) * bands;
        DArray out = new_array({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(nc)});
        for (std::size_t i = 0; i < n; ++i) {
          const double* d = normals.data() + 3 * i;
          sh::prt::unshadowed_transfer(bands, sh::checked_direction({d[0], d[1], d[2]}, "normal"), albedo.data()[i],
                                       out.mutable_data() + i * nc);
        }
        return out;
      },
      py::arg("bands"), py::arg("normals"), py::arg("albedo"));
  m.def(
      "directional_light",
      [](int bands, const DArray& dir, double irradiance) {
        if (dir.ndim() != 1 || dir.shape(0) != 3) throw InputError("direction: expected shape (3,), got shape " + shape_string(dir));
        return to_array(sh::prt::directional_light(
            bands, sh::checked_direction({dir.data()[0], dir.data()[1], dir.data()[2]}, "direction"), irradiance));
      },
      py::arg("bands"), py::arg("direction"), py::arg("irradiance") = 1.0);
}

}  // namespace atmosh::python
