#include "atmosh/atmo/atmosphere.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "atmosh/atmo/ozone.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/rayleigh.hpp"
#include "atmosh/error.hpp"

namespace atmosh::atmo {

const char* constituent_name(int c) {
  switch (c) {
    case kRayleigh: return "rayleigh";
    case kMie: return "mie";
    case kOzone: return "ozone";
  }
  return "?";
}

Atmosphere::Atmosphere(const AtmosphereSpec& spec) : Atmosphere(spec, spectrum_wavelengths(spec.spectrum)) {}

Atmosphere::Atmosphere(const AtmosphereSpec& spec, std::vector<double> wavelengths_nm)
    : spec_(spec), wavelengths_(std::move(wavelengths_nm)) {
  validate(spec_);
  if (spec_.rayleigh) {
    present_[kRayleigh] = true;
    profiles_[kRayleigh] = DensityProfile(spec_.rayleigh->profile, "rayleigh.profile");
    if (spec_.rayleigh->model == RayleighSpec::Model::Physical)
      rayleigh_number_density_ = number_density(spec_.rayleigh->pressure_pa, spec_.rayleigh->temperature_k);
  }
  if (spec_.mie) {
    present_[kMie] = true;
    profiles_[kMie] = DensityProfile(spec_.mie->profile, "mie.profile");
  }
  if (spec_.ozone) {
    present_[kOzone] = true;
    profiles_[kOzone] = DensityProfile(spec_.ozone->profile, "ozone.profile");
    double col = profiles_[kOzone].vertical_column(0.0, top_altitude());
    ozone_number_density_ = col > 0.0 ? spec_.ozone->column_du * kDobsonUnitPerM2 / col : 0.0;
  }
  for (int c = 0; c < kConstituents; ++c)
    if (present_[c])
      for (double k : profiles_[c].kinks())
        if (k > 0.0 && k < top_altitude()) kinks_.push_back(k);
  for (int c = 0; c < kConstituents; ++c)
    if (present_[c]) vertical_column_[c] = profiles_[c].vertical_column(0.0, top_altitude());
  std::sort(kinks_.begin(), kinks_.end());
  kinks_.erase(std::unique(kinks_.begin(), kinks_.end()), kinks_.end());
  coefficients_.reserve(wavelengths_.size());
  for (std::size_t i = 0; i < wavelengths_.size(); ++i) {
    if (!std::isfinite(wavelengths_[i]) || wavelengths_[i] <= 0.0)
      throw InputError("wavelength[" + std::to_string(i) + "] = " + std::to_string(wavelengths_[i]) +
                       " nm: must be > 0");
    coefficients_.push_back(coefficients_at(wavelengths_[i]));
  }
}

glm::dvec3 Atmosphere::density(double h) const {
  return {present_[0] ? profiles_[0](h) : 0.0, present_[1] ? profiles_[1](h) : 0.0,
          present_[2] ? profiles_[2](h) : 0.0};
}

double Atmosphere::feature_length() const {
  double m = std::numeric_limits<double>::infinity();
  for (int c = 0; c < kConstituents; ++c)
    if (present_[c]) m = std::min(m, profiles_[c].feature_length());
  return std::isfinite(m) ? m : top_altitude();
}

Coefficients Atmosphere::coefficients_at(double nm) const {
  if (!std::isfinite(nm) || nm <= 0.0) throw InputError("wavelength " + std::to_string(nm) + " nm: must be > 0");
  Coefficients k;
  if (present_[kRayleigh]) {
    const auto& r = *spec_.rayleigh;
    double b = r.model == RayleighSpec::Model::Physical
                   ? rayleigh_cross_section(nm, r.co2_ppm) * rayleigh_number_density_
                   : r.scattering_per_m * std::pow(r.reference_nm / nm, 4.0);
    k.scattering[kRayleigh] = b;
    k.extinction[kRayleigh] = b;
  }
  if (present_[kMie]) {
    const auto& m = *spec_.mie;
    double b = m.scattering_per_m * std::pow(nm / m.reference_nm, -m.angstrom);
    k.scattering[kMie] = b;
    k.extinction[kMie] = b / m.single_scattering_albedo;
  }
  if (present_[kOzone]) {
    k.extinction[kOzone] = ozone_cross_section(nm) * ozone_number_density_;
    k.scattering[kOzone] = 0.0;
  }
  return k;
}

}  // namespace atmosh::atmo
