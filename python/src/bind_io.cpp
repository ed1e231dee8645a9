// bind_io.cpp — atmosh._atmosh.io: the EXR files atmosh writes (sky images, per-pixel
// transfer, SH reconstructions) read into numpy, with their attributes.
#include <optional>

#include "atmosh/io/csv.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/netcdf.hpp"
#include "atmosh/scene/sweep.hpp"
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

  m.def(
      "sweep_to_netcdf",
      [](const std::string& csv, const std::string& nc, const std::optional<std::vector<std::string>>& keys) {
        std::vector<std::string> k;
        if (keys) {
          k = *keys;
        } else {  // the keys of the sweep file the CSV names (its `sweep` provenance line)
          const io::CsvData d = io::read_csv(csv);
          const auto it = d.provenance.find("sweep");
          if (it == d.provenance.end())
            throw InputError(csv + ": no 'sweep' provenance line; give the parameter keys");
          k = scene::load_sweep(it->second).keys;
        }
        py::gil_scoped_release release;
        io::write_sweep_csv_as_netcdf(csv, nc, k);
      },
      py::arg("csv"), py::arg("netcdf"), py::arg("keys") = py::none());
}

}  // namespace atmosh::python
