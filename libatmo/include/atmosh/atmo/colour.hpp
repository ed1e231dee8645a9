// atmosh/atmo/colour.hpp — spectral radiance to CIE XYZ, luminance and linear
// sRGB; the extraterrestrial solar spectrum.
//
// Units
//   * wavelengths in nanometres;
//   * spectral radiance L(lambda) in W m^-2 sr^-1 nm^-1;
//   * X, Y, Z photometric: Y is luminance in cd/m^2 (= lm m^-2 sr^-1) when the
//     input is spectral radiance; X and Z on the same scale;
//   * linear sRGB on the scale where Y = 1 is reference white (R = G = B = 1 for
//     D65 light with Y = 1), so RGB carry cd/m^2 too when XYZ does;
//   * solar spectral irradiance in W m^-2 nm^-1 at 1 AU, outside the atmosphere.
//
// Definitions
//   X = K_m * integral L(lambda) xbar(lambda) dlambda   (Y, Z with ybar, zbar)
// with K_m = 683 lm/W (the maximum luminous efficacy fixed by the SI definition
// of the candela at 540e12 Hz, where ybar is 1 to 4 decimals; CIE 015:2018
// section 7.1).
//
// Data
//   * Colour-matching functions: CIE 1931 2-degree standard colorimetric
//     observer, 1 nm table 360-830 nm (CIE 015:2018 Table 1 / ISO/CIE 11664-1;
//     the same table is published by the CVRL database, file ciexyz31_1.csv).
//     Between table points the functions are interpolated linearly; outside
//     360-830 nm they are 0.
//   * Extraterrestrial solar spectrum: ASTM G173-03 "Extraterrestrial"
//     column (derived from SMARTS 2.9.2, Gueymard 2004 Sol. Energy 76, 423),
//     0.5 nm steps for 360-400 nm, 1 nm steps for 400-830 nm, interpolated
//     linearly. Its integral over 360-830 nm is 734.8 W/m^2, 655.9 W/m^2 over
//     380-780 nm (trapezoid over the table nodes, exact for the interpolant).
//
// Accuracy (measured, see docs/colour.md)
//   * Equal-energy spectrum -> x, y within 5e-5 of 1/3: the residual is that of
//     the CIE table itself (its 1 nm sums are 106.8655, 106.8569, 106.8923).
//   * CIE D65 -> linear sRGB: R = G = B within 2.2e-4 relative with the 1 nm
//     reference sum (chromaticity 0.312727, 0.329023); with SpectralToXyz at 16
//     wavelengths over 380-780 nm, within 8.5e-3 (xy off by 1.2e-3).
//   * SpectralToXyz (piecewise-linear weights) is exact for any spectrum that is
//     piecewise linear between the given wavelengths (and constant beyond the
//     first and last one). For black bodies of 3000-20000 K sampled at 16
//     wavelengths over 380-780 nm: xy error <= 3.5e-4, Y error <= 2.2e-3
//     (2000 K: 8e-4 and 5.8e-3); the error falls as the square of the spacing.
//     Spectra with lines (the solar spectrum) must be given as band means
//     (solar_irradiance_toa_mean), not point samples. docs/colour.md has tables.
#pragma once

#include <array>
#include <functional>
#include <span>
#include <vector>

namespace atmosh::atmo {

// Maximum luminous efficacy of radiation for photopic vision [lm/W].
inline constexpr double kLuminousEfficacyLmPerW = 683.0;

// Wavelength range of the CIE 1931 table [nm].
inline constexpr double kCmfFirstNm = 360.0;
inline constexpr double kCmfLastNm = 830.0;

// Wavelength range of the solar spectrum table [nm].
inline constexpr double kSolarSpectrumFirstNm = 360.0;
inline constexpr double kSolarSpectrumLastNm = 830.0;

// Values of the three colour-matching functions (dimensionless, ybar peaks at 1).
struct Cmf {
  double x = 0.0, y = 0.0, z = 0.0;
};

// Tristimulus values. With spectral radiance as input, Y is in cd/m^2.
struct Xyz {
  double X = 0.0, Y = 0.0, Z = 0.0;
};

// Linear (not gamma-encoded) sRGB, same scale as Y.
struct Rgb {
  double r = 0.0, g = 0.0, b = 0.0;
};

// CIE 1931 chromaticity coordinates.
struct Chromaticity {
  double x = 0.0, y = 0.0;
};

using Matrix3 = std::array<std::array<double, 3>, 3>;

// CIE 1931 2-degree colour-matching functions at `wavelength_nm`: linear
// interpolation of the 1 nm table; {0,0,0} outside 360-830 nm (and for +-inf).
// Throws InputError for NaN.
Cmf cie1931_2deg(double wavelength_nm);

// How SpectralToXyz turns samples L_i at wavelengths lambda_i into XYZ.
enum class SpectralQuadrature {
  // Integrate the 1 nm CMF table against the piecewise-linear interpolant of the
  // samples (hat functions), held constant beyond the first and last wavelength
  // up to 360 and 830 nm. Exact (to rounding) for such interpolants; the
  // recommended choice.
  PiecewiseLinear,
  // Sample the CMFs at lambda_i and multiply by the width of the cell around
  // lambda_i (half-way to the neighbours; the end cells mirror their inner
  // half). Crude with few wavelengths; kept for comparison.
  Midpoint,
};

// Precomputed weights turning spectral samples into XYZ:
//   X = sum_i w_i.x * L_i  (same for Y, Z),
// w_i in cd m^-2 per (W m^-2 sr^-1 nm^-1) (683 lm/W and the nm widths included).
class SpectralToXyz {
 public:
  // `wavelengths_nm`: finite, strictly increasing; at least 1 (PiecewiseLinear)
  // or 2 (Midpoint). Throws InputError naming the offending value otherwise.
  explicit SpectralToXyz(std::vector<double> wavelengths_nm,
                         SpectralQuadrature quadrature = SpectralQuadrature::PiecewiseLinear);

  const std::vector<double>& wavelengths_nm() const { return wavelengths_; }
  const std::vector<Cmf>& weights() const { return weights_; }
  SpectralQuadrature quadrature() const { return quadrature_; }

  // XYZ of samples L_i (one per wavelength, W m^-2 sr^-1 nm^-1). Throws
  // InputError when the count differs from the number of wavelengths.
  Xyz operator()(std::span<const double> radiance) const;

 private:
  std::vector<double> wavelengths_;
  std::vector<Cmf> weights_;
  SpectralQuadrature quadrature_;
};

// Reference XYZ of a spectrum given as a function: the CIE summation at 1 nm,
// X = 683 * sum_{lambda = 360..830 nm} L(lambda) xbar(lambda) * 1 nm
// (CIE 015:2018 section 7.1). Calls `radiance` 471 times.
Xyz xyz_reference_1nm(const std::function<double(double)>& radiance);

// Chromaticity x = X/(X+Y+Z), y = Y/(X+Y+Z). For X+Y+Z == 0 (black) returns the
// D65 white point (0.3127, 0.3290) rather than NaN.
Chromaticity xy_chromaticity(const Xyz& xyz);

// Chromaticity where it is defined: NaN, NaN for black (X+Y+Z not > 0, or not
// finite), which has no colour. The rule of every output that reports a colour's
// chromaticity (study and sweep CSVs, `sky --json`, SkySummary): NaN in the library,
// `nan` in CSV, `null` in JSON (docs/outputs.md).
Chromaticity xy_chromaticity_or_nan(const Xyz& xyz);

// Luminance [cd/m^2] of tristimulus values computed from spectral radiance: Y.
inline double luminance_cd_m2(const Xyz& xyz) { return xyz.Y; }

// sRGB (IEC 61966-2-1:1999) primaries and D65 white chromaticities.
inline constexpr Chromaticity kSrgbRed{0.64, 0.33};
inline constexpr Chromaticity kSrgbGreen{0.30, 0.60};
inline constexpr Chromaticity kSrgbBlue{0.15, 0.06};
inline constexpr Chromaticity kD65White{0.3127, 0.3290};

// XYZ -> linear sRGB matrix, derived (in double precision) from the primaries
// and white above so that white with Y = 1 maps to R = G = B = 1. The
// RGB -> XYZ matrix agrees with the 4-decimal one printed in IEC 61966-2-1 to
// 5e-5; the printed XYZ -> RGB matrix (the inverse of the rounded forward one)
// differs from the exact inverse by up to 3.7e-4.
const Matrix3& srgb_from_xyz_matrix();
// Its inverse (linear sRGB -> XYZ); the middle row gives Y = luminance.
const Matrix3& xyz_from_srgb_matrix();

Rgb linear_srgb_from_xyz(const Xyz& xyz);
Xyz xyz_from_linear_srgb(const Rgb& rgb);

// sRGB transfer function (IEC 61966-2-1): linear value -> encoded value.
// v <= 0 -> 0 (and NaN -> 0); above 1 the curve is continued (no clamping).
double srgb_encode(double linear);
// Inverse transfer function; encoded <= 0 (or NaN) -> 0.
double srgb_decode(double encoded);

// Extraterrestrial solar spectral irradiance [W m^-2 nm^-1] at 1 AU (ASTM G173-03
// ETR, linear interpolation). Throws InputError outside 360-830 nm or for NaN.
double solar_irradiance_toa(double wavelength_nm);

// Mean of solar_irradiance_toa over [from_nm, to_nm] [W m^-2 nm^-1] (exact
// integral of the interpolant divided by the width). Prefer it to point samples
// when a wavelength stands for a bin: Fraunhofer lines (Ca II H and K at 393 and
// 397 nm, H-alpha at 656 nm...) make point values jump by tens of percent.
// Requires kSolarSpectrumFirstNm <= from_nm < to_nm <= kSolarSpectrumLastNm;
// from_nm == to_nm gives the point value.
double solar_irradiance_toa_mean(double from_nm, double to_nm);

}  // namespace atmosh::atmo
