// atmosh/atmo/presets.hpp — built-in atmospheres and validation of parameters.
//
// Presets (same schema as a scene's [planet]/[rayleigh]/[mie]/[ozone]/[spectrum]
// tables, see docs/atmosphere.md):
//  * "earth-physical": mean Earth radius 6371 km, top 100 km; Rayleigh from
//    Bodhaine et al. (1999) at 1013.25 hPa, 288.15 K, 360 ppm CO2 with the
//    U.S. Standard Atmosphere 1976 density (tabulated every 0.5 km, computed from
//    its defining temperature layers, continued isothermally above 86 km);
//    continental-like aerosol (optical depth 0.1 at 550 nm, 1.2 km scale height,
//    Angstrom 1.3, albedo 0.9, Cornette-Shanks g = 0.8); 300 DU ozone (tent
//    10-25-40 km).
//  * "earth-graphics": the constants of E. Bruneton's 2017 Precomputed Atmospheric
//    Scattering demo (ground 6360 km, top 6420 km; Rayleigh 1.24062e-6 /m at
//    1 micrometre scaled as lambda^-4, i.e. 5.802e-6, 13.558e-6, 33.1e-6 /m at
//    680, 550, 440 nm, scale height 8 km; Mie extinction 5.328e-3/1200 m = 4.44e-6 /m,
//    albedo 0.9, Angstrom 0, scale height 1.2 km, Cornette-Shanks g = 0.8; ozone
//    300 DU in a 10-25-40 km tent; ground albedo 0.1).
//  * "test-planet": a small planet (radius 200 km, 20 km atmosphere) for fast
//    tests.
//
// validate(spec) throws InputError whose message names the key path and value,
// e.g. "mie.profile.scale_height_m = -5: must be > 0".
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "atmosh/atmo/spec.hpp"

namespace atmosh::atmo {

std::vector<std::string> preset_names();
// Throws InputError for an unknown name, listing the valid ones.
AtmosphereSpec preset(std::string_view name);
void validate(const AtmosphereSpec& spec);
// The wavelengths [nm] a spectrum spec designates (explicit list or bin centres).
std::vector<double> spectrum_wavelengths(const SpectrumSpec& spectrum);
// U.S. Standard Atmosphere 1976 density relative to sea level (1.2250 kg/m^3)
// sampled every step_m from 0 to top_m and at the geometric altitudes of its layer
// boundaries (11.019, 20.063, 32.162, 47.350, 51.412, 71.802, 86.000 km: the kinks of
// its density, which thus fall on nodes; a grid node within step_m / 10 of one moves
// onto it), from the standard's defining layers.
DensityProfileSpec us_standard_1976_profile(double top_m, double step_m = 500.0);

}  // namespace atmosh::atmo
