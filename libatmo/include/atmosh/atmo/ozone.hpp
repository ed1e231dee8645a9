// atmosh/atmo/ozone.hpp — ozone absorption cross-sections.
//
// Data: Serdyuchenko, Gorshelev, Weber, Chehade & Burrows (2014), "High spectral
// resolution ozone absorption cross-sections — Part 2: Temperature dependence",
// Atmos. Meas. Tech. 7, 625-636 (IUP Bremen o3spectra2011 data set), at 233 K,
// averaged over 10 nm bins [lambda, lambda + 10 nm) for lambda = 360, 370, ...,
// 830 nm, as tabulated in E. Bruneton's 2017 "Precomputed Atmospheric Scattering"
// demo (kOzoneCrossSection). Following that source, each value is attached to the
// lower edge of its bin and interpolated linearly in wavelength.
//
// Units: nm in, m^2 per molecule out. Valid 360-830 nm; outside it
// ozone_cross_section throws InputError naming the wavelength.
#pragma once

namespace atmosh::atmo {

inline constexpr double kOzoneTableFirstNm = 360.0;
inline constexpr double kOzoneTableLastNm = 830.0;
// Molecules per square metre in one Dobson unit (Loschmidt constant at 273.15 K
// times 10 micrometres).
inline constexpr double kDobsonUnitPerM2 = 2.6867811e20;

double ozone_cross_section(double wavelength_nm);

}  // namespace atmosh::atmo
