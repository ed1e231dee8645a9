// bind_io.cpp — atmosh._atmosh.io: the EXR files atmosh writes (sky images, per-pixel
// transfer, SH reconstructions) read into numpy, with their attributes.
#include "atmosh/io/exr.hpp"
#include "common.hpp"

namespace atmosh::python {

void bind_io(py::module_& m) {
  m.def(
      "read_exr",
      [](const std::string& path) {
        io::ExrImage img;
        {
          py::gil_scoped_release release;
          img = io::read_exr(path);
        }
        const auto H = static_cast<py::ssize_t>(img.height), W = static_cast<py::ssize_t>(img.width);
        py::dict channels;
        for (std::size_t c = 0; c < img.channels.size(); ++c) {
          py::array_t<float> a({H, W});
          std::copy(img.data[c].begin(), img.data[c].end(), a.mutable_data());
          channels[py::str(img.channels[c])] = a;
        }
        py::dict attributes;
        for (const auto& [k, v] : img.string_attributes) attributes[py::str(k)] = v;
        for (const auto& [k, v] : img.float_attributes) attributes[py::str(k)] = v;
        py::dict d;
        d["width"] = img.width;
        d["height"] = img.height;
        d["channels"] = channels;
        d["attributes"] = attributes;
        return d;
      },
      py::arg("path"));
}

}  // namespace atmosh::python
