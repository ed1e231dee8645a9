// atmosh/atmo/atmosphere.hpp — an atmosphere ready for computation.
//
// Built from an AtmosphereSpec (validated on construction) and a list of
// wavelengths. Each constituent c (Rayleigh, Mie, ozone; absent ones are simply
// missing) has
//   * a relative density profile rho_c(h) (dimensionless),
//   * per wavelength, extinction and scattering coefficients beta_c(lambda) [1/m]
//     at relative density 1.
// The local extinction is sum_c beta_c(lambda) rho_c(h), so an optical depth is
// sum_c beta_c(lambda) * X_c with the wavelength-independent column
// X_c = integral rho_c ds [m] (see optical_depth.hpp): one column table serves
// every wavelength.
//
// Coefficients: Rayleigh physical = Bodhaine et al. (1999) cross-section times
// p/(k T) (rayleigh.hpp); Rayleigh coefficients = scattering_per_m at
// reference_nm scaled as lambda^-4; Mie scattering = scattering_per_m
// (lambda/reference_nm)^-angstrom, extinction = scattering / albedo; ozone
// absorption = cross-section (ozone.hpp) times the number density at relative
// density 1, column_du * 2.6867811e20 / (vertical integral of the profile).
// Units: metres, 1/m, nm. Accuracy: that of the data (no approximation added).
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "atmosh/atmo/density.hpp"
#include "atmosh/atmo/spec.hpp"

namespace atmosh::atmo {

enum Constituent : int { kRayleigh = 0, kMie = 1, kOzone = 2 };
inline constexpr int kConstituents = 3;
const char* constituent_name(int c);

struct Coefficients {
  glm::dvec3 extinction{0.0};  // [1/m] per constituent at relative density 1
  glm::dvec3 scattering{0.0};  // [1/m]
};

class Atmosphere {
 public:
  // Wavelengths from spec.spectrum.
  explicit Atmosphere(const AtmosphereSpec& spec);
  Atmosphere(const AtmosphereSpec& spec, std::vector<double> wavelengths_nm);

  const AtmosphereSpec& spec() const { return spec_; }
  double ground_radius() const { return spec_.planet.radius_m; }
  double top_radius() const { return spec_.planet.radius_m + spec_.planet.atmosphere_top_m; }
  double top_altitude() const { return spec_.planet.atmosphere_top_m; }
  bool has(int c) const { return present_[c]; }
  const DensityProfile& profile(int c) const { return profiles_[c]; }
  // Relative densities of the three constituents at altitude h [m] (0 if absent).
  glm::dvec3 density(double h) const;
  // Altitudes where some present profile has a kink.
  const std::vector<double>& kinks() const { return kinks_; }
  // Smallest feature length over the present profiles [m] (scale height etc.).
  double feature_length() const;
  // Vertical column from the ground to the top per constituent [m] (integrated once, at
  // construction).
  const glm::dvec3& vertical_column() const { return vertical_column_; }

  const std::vector<double>& wavelengths_nm() const { return wavelengths_; }
  const Coefficients& coefficients(std::size_t i) const { return coefficients_.at(i); }
  // Coefficients at any wavelength (InputError for ozone outside 360-830 nm).
  Coefficients coefficients_at(double wavelength_nm) const;

 private:
  AtmosphereSpec spec_;
  std::array<bool, 3> present_{false, false, false};
  std::array<DensityProfile, 3> profiles_;
  std::vector<double> kinks_;
  std::vector<double> wavelengths_;
  std::vector<Coefficients> coefficients_;
  double ozone_number_density_ = 0.0;  // m^-3 at relative density 1
  double rayleigh_number_density_ = 0.0;
  glm::dvec3 vertical_column_{0.0};
};

}  // namespace atmosh::atmo
