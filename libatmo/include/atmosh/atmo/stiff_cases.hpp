// atmosh/atmo/stiff_cases.hpp — the named suite of stiff and extreme cases
// (grazing and tangent rays, limb views from space, rays into the planet,
// transmittance underflow, g = +-0.999 phase functions, wavelengths at the ends
// of the grid). Each case computes a value, an independent reference (closed
// form, exact Chapman function, or a conservation identity) and a stated bound;
// it passes when the value is finite and within the bound. Used by
// `atmosh stability` and by the test suite.
#pragma once

#include <string>
#include <vector>

namespace atmosh::atmo {

struct StiffCase {
  std::string name;
  std::string quantity;   // what `value` is, with unit
  double value = 0.0;
  double reference = 0.0;
  double error = 0.0;     // |value - reference| / |reference| (or absolute if reference == 0)
  double bound = 0.0;     // stated bound on `error`
  bool pass = false;
};

// lut_shells / lut_directions: LUT resolution used for the LUT cases.
std::vector<StiffCase> run_stiff_cases(int lut_shells = 32, int lut_directions = 64);

}  // namespace atmosh::atmo
