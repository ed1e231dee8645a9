// module.cpp — the extension module atmosh._atmosh: one submodule per library area
// (sun, atmo, sky, sh, prt, io, studies); the pure-Python package atmosh wraps them with the
// numpy conveniences and docstrings (python/atmosh/).
#include "common.hpp"

PYBIND11_MODULE(_atmosh, m) {
  m.doc() = "atmosh: atmospheric scattering and spherical harmonics (C++ core)";
  // The libraries' InputError (a bad value, one-line message naming it) becomes a
  // ValueError subclass carrying the same message.
  py::register_exception<atmosh::InputError>(m, "InputError", PyExc_ValueError);
  auto sun = m.def_submodule("sun", "Solar position (NREL SPA, Grena 2012)");
  auto atmo = m.def_submodule("atmo", "Atmospheres, optical depth, phase functions");
  auto sky = m.def_submodule("sky", "Sky radiance, images and colour");
  auto sh = m.def_submodule("sh", "Real spherical harmonics");
  auto prt = m.def_submodule("prt", "Precomputed radiance transfer");
  auto io = m.def_submodule("io", "Files atmosh writes");
  auto studies = m.def_submodule("studies", "The studies as tables (atmosh::studies)");
  atmosh::python::bind_sun(sun);
  atmosh::python::bind_atmo(atmo);
  atmosh::python::bind_sky(sky);
  atmosh::python::bind_sh(sh);
  atmosh::python::bind_prt(prt);
  atmosh::python::bind_io(io);
  atmosh::python::bind_studies(studies);
}
