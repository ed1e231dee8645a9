#include "atmosh/atmo/rayleigh.hpp"

#include <cmath>
#include <string>

#include "atmosh/error.hpp"

namespace atmosh::atmo {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kBoltzmann = 1.380649e-23;    // J/K (exact, SI 2019)
constexpr double kNs = 2.546899e25;            // m^-3 at 288.15 K, 1013.25 hPa (Bodhaine et al. 1999)

void check_wavelength(double nm) {
  if (!std::isfinite(nm) || nm <= 0.0)
    throw InputError("wavelength " + std::to_string(nm) + " nm: must be finite and > 0");
}
}  // namespace

double air_refractivity(double wavelength_nm, double co2_ppm) {
  check_wavelength(wavelength_nm);
  if (!std::isfinite(co2_ppm) || co2_ppm < 0.0)
    throw InputError("rayleigh.co2_ppm = " + std::to_string(co2_ppm) + ": must be >= 0");
  double l = wavelength_nm * 1e-3;  // micrometres
  double s2 = 1.0 / (l * l);
  double n300 = (8060.51 + 2480990.0 / (132.274 - s2) + 17455.7 / (39.32957 - s2)) * 1e-8;
  return n300 * (1.0 + 0.54 * (co2_ppm * 1e-6 - 0.0003));
}

double king_factor_air(double wavelength_nm, double co2_ppm) {
  check_wavelength(wavelength_nm);
  double l = wavelength_nm * 1e-3;
  double s2 = 1.0 / (l * l);
  double f_n2 = 1.034 + 3.17e-4 * s2;
  double f_o2 = 1.096 + 1.385e-3 * s2 + 1.448e-4 * s2 * s2;
  double f_ar = 1.00, f_co2 = 1.15;
  double c = co2_ppm * 1e-4;  // percent by volume
  return (78.084 * f_n2 + 20.946 * f_o2 + 0.934 * f_ar + c * f_co2) / (78.084 + 20.946 + 0.934 + c);
}

double depolarization_from_king(double f) { return 6.0 * (f - 1.0) / (3.0 + 7.0 * f); }

double rayleigh_cross_section(double wavelength_nm, double co2_ppm) {
  double nm1 = air_refractivity(wavelength_nm, co2_ppm);
  double n2 = (1.0 + nm1) * (1.0 + nm1);
  double l = wavelength_nm * 1e-9;
  double a = (n2 - 1.0) / (n2 + 2.0);
  return 24.0 * kPi * kPi * kPi * a * a / (l * l * l * l * kNs * kNs) * king_factor_air(wavelength_nm, co2_ppm);
}

double number_density(double pressure_pa, double temperature_k) {
  return pressure_pa / (kBoltzmann * temperature_k);
}

double bodhaine_eq30_optical_depth(double wavelength_nm) {
  check_wavelength(wavelength_nm);
  double l = wavelength_nm * 1e-3;
  double l2 = l * l;
  return 0.0021520 * (1.0455996 - 341.29061 / l2 - 0.90230850 * l2) /
         (1.0 + 0.0027059889 / l2 - 85.968563 * l2);
}

}  // namespace atmosh::atmo
