// atmosh/sh/convolution.hpp — zonal convolution (Funk–Hecke), irradiance, ringing
// windows, band energy and normalisation conversions.
//
// Funk–Hecke: for a zonal kernel k(cos g) with zonal coefficients z_l (zonal.hpp,
// k = sum_l z_l Y_l0), the convolution (k * f)(n) = integral k(n . w) f(w) dOmega has
// coefficients  c'_lm = sqrt(4 pi / (2l+1)) z_l c_lm.
// Irradiance (Ramamoorthi & Hanrahan 2001, eq. 8-9): E(n) = integral max(0, n.w) L(w) dOmega,
// i.e. the clamped-cosine kernel, A_l = sqrt(4 pi/(2l+1)) z_l = pi, 2 pi/3, pi/4, 0,
// -pi/24, 0, pi/64, ... Units: E in W m^-2 (per nm) for L in W m^-2 sr^-1 (per nm).
// clamped_cosine_zonal() integrates max(0, mu) P_l(mu) exactly (Gauss–Legendre on [0, 1]).
//
// Windows w_l (multiply band l) against ringing:
//   * hanning:  w_l = (1 + cos(pi l / L)) / 2   (Sloan 2008, "Stupid SH tricks", sec. 4)
//   * lanczos:  w_l = sinc(l / L) = sin(pi l / L) / (pi l / L)   (ibid.)
//   * nonnegative: w_l = exp(-h l (l+1)) with the smallest h (bisection) for which the
//     windowed delta function sum_l (2l+1)/(4 pi) w_l P_l(mu) is >= 0 on a fine grid
//     (8L + 64 points per unit, relative tolerance 1e-9) — removes the negative lobes
//     for this band limit (the goal of Sloan 2008's windowing).
// What each costs in accuracy is measured in docs/sh.md (`atmosh demo`: windows.csv).
//
// Band energy: e_l = sum_m c_lm^2 (rotation invariant); fraction = cumulative / total.
//
// Conversions (coefficients of the same function in another basis):
//   * four_pi (4 pi-normalised, integral Y^2 = 4 pi):  c = c_ortho / sqrt(4 pi)
//   * schmidt (semi-normalised, integral Y^2 = 4 pi/(2l+1)): c = c_ortho * sqrt((2l+1)/(4 pi))
//   * condon_shortley = false multiplies basis functions by (-1)^m, so c *= (-1)^m.
//   * complex SH Y_l^m (with CS phase): a_l,m = (c_l,m - i c_l,-m)/sqrt2 (m > 0),
//     a_l,0 = c_l,0, a_l,-m = (-1)^m conj(a_l,m).
#pragma once

#include <complex>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

namespace atmosh::sh {

/// Zonal coefficients of max(0, mu): exact.
std::vector<double> clamped_cosine_zonal(int bands);
/// Funk–Hecke factors sqrt(4 pi/(2l+1)) z_l for a zonal kernel k(mu) (projected by
/// Gauss–Legendre with `quadrature_points`, 0 = default of zonal_coefficients).
std::vector<double> funk_hecke_factors(const std::function<double(double)>& kernel, int bands,
                                       int quadrature_points = 0);
/// Factors of the clamped cosine (irradiance): A_l.
std::vector<double> irradiance_factors(int bands);
/// c_lm *= factor_l (in place).
void convolve_zonal(std::vector<double>& coeffs, int bands, const std::vector<double>& factor);
/// Irradiance coefficients from radiance coefficients.
std::vector<double> irradiance(const std::vector<double>& radiance, int bands);
/// Irradiance at normal n from radiance coefficients.
double irradiance_at(const std::vector<double>& radiance, int bands, const glm::dvec3& normal);

enum class Window { none, hanning, lanczos, nonnegative };
Window parse_window(const std::string& name);
std::vector<double> window_weights(Window w, int bands);
/// Minimum over mu in [-1, 1] of the windowed delta sum_l (2l+1)/(4 pi) w_l P_l(mu),
/// relative to its value at mu = 1 (negative: ringing lobes).
double windowed_delta_min(const std::vector<double>& w);

/// Power per band e_l = sum_m c_lm^2 (size bands).
std::vector<double> band_energy(const std::vector<double>& coeffs, int bands);
/// Cumulative fraction of energy up to and including band l.
std::vector<double> cumulative_energy_fraction(const std::vector<double>& energy);

enum class Normalization { orthonormal, four_pi, schmidt };
/// Converts coefficients between normalisations and Condon–Shortley conventions.
std::vector<double> convert(const std::vector<double>& coeffs, int bands, Normalization from, bool from_cs,
                            Normalization to, bool to_cs);
/// Complex coefficients a_l^m at index l(l+1)+m.
std::vector<std::complex<double>> to_complex(const std::vector<double>& coeffs, int bands);
std::vector<double> from_complex(const std::vector<std::complex<double>>& a, int bands);

}  // namespace atmosh::sh
