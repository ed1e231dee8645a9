// atmosh/atmo/phase.hpp — scattering phase functions.
//
// Models: Rayleigh (with depolarisation), Henyey-Greenstein, Cornette-Shanks,
// double Henyey-Greenstein, tabulated (piecewise linear in cos_theta,
// normalised on construction). Formulas: shared/geometry.glsl.hpp.
//
// Conventions: value(cos_theta) in 1/sr, normalised so that
// 2 pi int_{-1}^{1} p(mu) dmu = 1; cos_theta = 1 is forward scattering (angle
// between the propagation directions before and after scattering).
//
//  * mean_cosine(): <mu> = 2 pi int p mu dmu, closed form where there is one
//    (HG: g; double HG: w g1 + (1-w) g2; Cornette-Shanks:
//    3 g (4 + g^2) / (5 (2 + g^2)); Rayleigh: 0), exact quadrature for tables.
//  * sample(u): inverse-CDF map of u in [0, 1) to cos_theta distributed with
//    density 2 pi p: closed form for HG; Newton on the closed-form cubic CDF
//    for Rayleigh; for Cornette-Shanks the CDF is tabulated in the HG-CDF variable,
//    where it is smooth (2049 points uniform in it, plus 511 at mu uniform in
//    [-1, 1], which keep the backward hemisphere resolved for g -> 1), and inverted
//    by cubic Hermite interpolation (error < 1e-9 in u, g = +-0.999 included, test
//    against the exact CDF); double HG picks the lobe by u; tabulated
//    inverts its exact piecewise-quadratic CDF. pdf(mu) = 2 pi p(mu).
//  * legendre_moments(n): chi_l = 2 pi int p P_l dmu, l < n, through the libsh
//    zonal projection (chi_l = z_l / sqrt((2l+1)/(4 pi))): composite
//    Gauss-Legendre on pieces graded geometrically toward mu = +-1 from the peak
//    width (1 - |g|)^2 / 2 (24 points per piece plus n dtheta / pi; error
//    estimate against 12 points per piece, returned alongside); tabulated: the
//    pieces between its nodes (16 points each, estimate against 8). HG uses its closed form
//    chi_l = g^l. Accuracy: ~1e-15 for smooth functions; 3e-11 at g = 0.999
//    (closed-form Cornette-Shanks and double-HG moments, tests), limited by the
//    rounding of 1 - mu within the 5e-7-wide peak.
//  * delta_m(n): delta-M truncation (Wiscombe 1977, J. Atmos. Sci. 34, 1408):
//    f = chi_n, truncated moments chi*_l = (chi_l - f) / (1 - f), l < n; the
//    scaled optical depth is (1 - omega f) tau. For forward-peaked functions only:
//    InputError when the mean cosine is < 0 or chi_n >= 1.
// Valid parameters: |g| < 1 (g = +-0.999 is fine), depolarisation in [0, 0.5).
#pragma once

#include <vector>

#include "atmosh/atmo/spec.hpp"

namespace atmosh::atmo {

struct LegendreMoments {
  std::vector<double> chi;     // chi_0 = 1, chi_1 = mean cosine, ...
  double error_estimate = 0.0; // max |chi_l(N) - chi_l(2N)| of the quadrature
};

struct DeltaM {
  double f = 0.0;                 // truncated forward fraction
  std::vector<double> truncated;  // chi*_l, l < n
};

class PhaseFunction {
 public:
  // Validates (InputError naming `key`).
  explicit PhaseFunction(const PhaseSpec& spec, const std::string& key = "phase");
  double value(double cos_theta) const;
  double mean_cosine() const;
  double pdf(double cos_theta) const { return 2.0 * 3.14159265358979323846 * value(cos_theta); }
  double sample(double u) const;
  LegendreMoments legendre_moments(int n) const;
  DeltaM delta_m(int n) const;
  const PhaseSpec& spec() const { return spec_; }

 private:
  double cdf_rayleigh(double mu) const;
  PhaseSpec spec_;
  double table_norm_ = 1.0;
  std::vector<double> table_cdf_;  // tabulated model
  std::vector<double> cs_v_;       // Cornette-Shanks CDF nodes in the HG-CDF variable
  std::vector<double> cs_cdf_;     // Cornette-Shanks CDF at cs_v_
  double mean_cos_ = 0.0;
};

// Inverse CDF of HG (closed form), u in [0, 1].
double sample_hg(double g, double u);

}  // namespace atmosh::atmo
