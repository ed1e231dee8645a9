// common.hpp — helpers shared by the binding units of the `atmosh` Python module.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "atmosh/error.hpp"
#include "atmosh/format.hpp"

namespace py = pybind11;

namespace atmosh::python {

// C-contiguous float64 arrays (anything array-like is converted on the way in).
using DArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

inline std::string shape_string(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  if (a.ndim() == 1) s += ",";
  return s + ")";
}

// Rows of an (N, 3) array; InputError naming `what` otherwise.
inline std::size_t rows3(const DArray& a, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw InputError(std::string(what) + ": expected an array of shape (N, 3), got shape " + shape_string(a));
  return static_cast<std::size_t>(a.shape(0));
}

// Elements of a 1-D array; InputError naming `what` otherwise.
inline std::size_t len1(const DArray& a, const char* what) {
  if (a.ndim() != 1)
    throw InputError(std::string(what) + ": expected a 1-D array, got shape " + shape_string(a));
  return static_cast<std::size_t>(a.shape(0));
}

inline DArray new_array(std::vector<py::ssize_t> shape) { return DArray(shape); }

inline DArray to_array(const std::vector<double>& v) {
  DArray a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

void bind_sun(py::module_& m);
void bind_atmo(py::module_& m);
void bind_sky(py::module_& m);
void bind_sh(py::module_& m);
void bind_prt(py::module_& m);
void bind_io(py::module_& m);
void bind_studies(py::module_& m);

}  // namespace atmosh::python
