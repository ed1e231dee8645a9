// The atmospheres the benchmarks time, in one place.
#pragma once

#include <string>

#include "atmosh/atmo/presets.hpp"

namespace atmosh::bench {

// A preset's atmosphere with the visible band 380-780 nm split into `wavelengths` bins
// (16: the built-in default scene's spectrum).
inline atmo::AtmosphereSpec spec_with(int wavelengths, const std::string& preset_name = "earth-physical") {
  atmo::AtmosphereSpec s = atmo::preset(preset_name);
  s.spectrum.wavelengths_nm.clear();
  s.spectrum.from_nm = 380;
  s.spectrum.to_nm = 780;
  s.spectrum.count = wavelengths;
  return s;
}

inline atmo::AtmosphereSpec spec16() { return spec_with(16); }

}  // namespace atmosh::bench
