// atmosh/atmo/spec.hpp — plain parameters of an atmosphere (what a scene file's
// [planet], [rayleigh], [mie], [ozone] and [spectrum] tables hold).
//
// Units: metres, per metre, nanometres, Dobson units, pascals, kelvin.
// A constituent that is std::nullopt is left out of every computation (no table,
// no pass, no cost). The same structures back the built-in presets and the scene
// TOML schema (docs/scene-format.md), so a preset printed as TOML reads back equal.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace atmosh::atmo {

// Relative density (dimensionless, 1 at the reference altitude) against altitude h
// above the ground in metres.
struct DensityProfileSpec {
  enum class Kind { Exponential, Tent, Tabulated };
  Kind kind = Kind::Exponential;
  double scale_height_m = 8000.0;  // Exponential: exp(-h / H)
  // Tent: 0 below bottom, rises linearly to 1 at peak, falls to 0 at top.
  double bottom_m = 10e3, peak_m = 25e3, top_m = 40e3;
  // Tabulated: piecewise linear through (altitude_m[i], value[i]), 0 outside.
  std::vector<double> altitude_m, value;

  static DensityProfileSpec exponential(double scale_height) {
    DensityProfileSpec p;
    p.kind = Kind::Exponential;
    p.scale_height_m = scale_height;
    return p;
  }
  static DensityProfileSpec tent(double bottom, double peak, double top) {
    DensityProfileSpec p;
    p.kind = Kind::Tent;
    p.bottom_m = bottom;
    p.peak_m = peak;
    p.top_m = top;
    return p;
  }
};

struct PhaseSpec {
  enum class Model { Rayleigh, HenyeyGreenstein, CornetteShanks, DoubleHenyeyGreenstein, Tabulated };
  Model model = Model::CornetteShanks;
  double g = 0.8;           // asymmetry parameter (not the mean cosine for Cornette-Shanks)
  double g2 = -0.3;         // double HG: second lobe
  double weight = 0.9;      // double HG: weight of the first lobe
  double depolarization = 0.0279;  // Rayleigh: depolarisation factor rho_n
  std::vector<double> cos_theta, value;  // Tabulated (per steradian, unnormalised ok)

  static PhaseSpec of(Model m, double g_ = 0.0) {
    PhaseSpec p;
    p.model = m;
    p.g = g_;
    return p;
  }
};

struct PlanetSpec {
  double radius_m = 6360e3;         // ground radius
  double atmosphere_top_m = 100e3;  // height of the top of the atmosphere above ground
  double ground_albedo = 0.0;
};

struct RayleighSpec {
  enum class Model { Physical, Coefficients };
  Model model = Model::Physical;
  // Physical (Bodhaine et al. 1999): ground conditions for the number density.
  double pressure_pa = 101325.0;
  double temperature_k = 288.15;
  double co2_ppm = 360.0;
  // Coefficients: scattering at the ground at reference_nm, scaled as lambda^-4.
  double scattering_per_m = 13.558e-6;
  double reference_nm = 550.0;
  DensityProfileSpec profile = DensityProfileSpec::exponential(8000.0);
  PhaseSpec phase = PhaseSpec::of(PhaseSpec::Model::Rayleigh);
};

struct MieSpec {
  double scattering_per_m = 3.996e-6;  // at the ground, at reference_nm
  double reference_nm = 550.0;
  double angstrom = 0.0;               // beta(lambda) = beta_ref * (lambda/ref)^-angstrom
  double single_scattering_albedo = 0.9;
  DensityProfileSpec profile = DensityProfileSpec::exponential(1200.0);
  PhaseSpec phase = PhaseSpec::of(PhaseSpec::Model::CornetteShanks, 0.8);
};

struct OzoneSpec {
  double column_du = 300.0;  // total column in Dobson units (2.6867e20 molecules/m^2 per DU)
  DensityProfileSpec profile = DensityProfileSpec::tent(10e3, 25e3, 40e3);
};

struct SpectrumSpec {
  double from_nm = 360.0;
  double to_nm = 830.0;
  int count = 47;  // wavelengths at bin centres of count equal bins (10 nm bins by default)
  // When not empty, these wavelengths [nm] are used instead of from/to/count.
  std::vector<double> wavelengths_nm;
};

struct AtmosphereSpec {
  std::string name = "custom";
  PlanetSpec planet;
  std::optional<RayleighSpec> rayleigh = RayleighSpec{};
  std::optional<MieSpec> mie = MieSpec{};
  std::optional<OzoneSpec> ozone = OzoneSpec{};
  SpectrumSpec spectrum;
};

}  // namespace atmosh::atmo
