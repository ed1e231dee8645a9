// atmosphere_object.hpp — the Python-side atmosphere: a scene (atmosphere spec, sun,
// scattering method, sun model) and the atmo::Atmosphere built from it.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/scene/scene.hpp"

namespace atmosh::python {

struct PyAtmosphere {
  scene::Scene scene;
  std::unique_ptr<atmo::Atmosphere> atm;
  // Builds atm from scene (with `wavelengths_nm` instead of the scene's spectrum when given).
  PyAtmosphere(scene::Scene s, const std::optional<std::vector<double>>& wavelengths_nm);
};

}  // namespace atmosh::python
