// atmosh/atmo/rayleigh.hpp — physical Rayleigh scattering of dry air after
// Bodhaine, Wood, Dutton & Slusser (1999), "On Rayleigh optical depth
// calculations", J. Atmos. Oceanic Technol. 16, 1854-1861.
//
//  * refractive index of standard air (15 C, 1013.25 hPa, 300 ppm CO2) from
//    Peck & Reeder (1972) as their eq. (4), scaled to the CO2 content with
//    their eq. (19): (n - 1) = (n300 - 1) (1 + 0.54 (C - 0.0003)), C in ppv;
//  * King correction factor of air, their eq. (23), from F(N2), F(O2) (their
//    eqs. 5, 6 after Bates 1984), F(Ar) = 1.00, F(CO2) = 1.15;
//  * cross-section, their eq. (2):
//      sigma = 24 pi^3 (n^2 - 1)^2 / (lambda^4 Ns^2 (n^2 + 2)^2) F_air,
//    Ns = 2.546899e25 m^-3 (288.15 K, 1013.25 hPa);
//  * number density at the ground from the ideal gas law, N = p / (k T).
//
// Units: wavelength in nm, cross-section in m^2, number density in m^-3,
// scattering coefficient in 1/m. Valid 240-1690 nm (the wavelengths of the
// measurements Peck & Reeder's refractivity formula fits; a physical Rayleigh
// constituent rejects spectra outside them); accuracy that
// of the published formulas (1e-4 against Bodhaine's eq. 30 with their column,
// tests). Throws InputError for non-positive or non-finite input.
#pragma once

namespace atmosh::atmo {

inline constexpr double kRayleighPhysicalFirstNm = 240.0;
inline constexpr double kRayleighPhysicalLastNm = 1690.0;

// (n - 1) of standard air with co2_ppm CO2.
double air_refractivity(double wavelength_nm, double co2_ppm);
// King correction factor F_air (Bodhaine eq. 23).
double king_factor_air(double wavelength_nm, double co2_ppm);
// Depolarisation ratio rho_n from the King factor: F = (6 + 3 rho)/(6 - 7 rho).
double depolarization_from_king(double king_factor);
// Rayleigh scattering cross-section per molecule [m^2].
double rayleigh_cross_section(double wavelength_nm, double co2_ppm);
// Number density of an ideal gas [m^-3].
double number_density(double pressure_pa, double temperature_k);
// Sea-level Rayleigh optical depth by Bodhaine et al. (1999) eq. (30): their
// fit to the full calculation for 1013.25 hPa, 45 deg latitude, 360 ppm CO2
// (quoted accuracy better than 0.01 % from 250 to 850 nm). A published
// reference, used by the tests.
double bodhaine_eq30_optical_depth(double wavelength_nm);

}  // namespace atmosh::atmo
