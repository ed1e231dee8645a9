// atmosh/sh/zonal.hpp — zonal (axially symmetric) functions and their SH coefficients.
//
// Convention: real orthonormal SH with Condon–Shortley phase (see basis.hpp);
// the zonal harmonics are Y_l0(mu) = sqrt((2l+1)/(4 pi)) P_l(mu), mu = cos(theta),
// theta measured from the +z axis.
//
// zonal_coefficients(f, bands) returns z_l, l = 0..bands-1, with
//     f(mu) ~ sum_l z_l Y_l0(mu),
//     z_l   = 2 pi * integral_{-1}^{1} f(mu) Y_l0(mu) dmu,
// computed by Gauss–Legendre quadrature in mu. With the default number of
// points (max(64, bands + 1), exact for polynomial integrands of degree
// <= 2*bands + 1) the result is exact (to rounding, ~1e-15 relative to
// max|f|) whenever f is a polynomial in mu of degree <= bands; for non-smooth
// f (e.g. the clamped cosine) the quadrature error decreases like the
// Legendre-series tail — pass more points for those.
//
// legendre_polynomials(mu, bands) returns P_0(mu) .. P_{bands-1}(mu) by the
// three-term recurrence (Bonnet); |P_l| <= 1 on [-1, 1], error ~ l * 1e-16.
//
// Throws atmosh::InputError for bands < 1, quadrature_points < 0, mu not finite.
#pragma once

#include <functional>
#include <vector>

namespace atmosh::sh {

/// Zonal SH coefficients z_l (l = 0..bands-1) of f(mu), mu = cos(theta).
/// quadrature_points = 0 picks max(64, bands + 1).
std::vector<double> zonal_coefficients(const std::function<double(double)>& f, int bands,
                                       int quadrature_points = 0);

/// The same by composite Gauss–Legendre quadrature over the pieces between the
/// ascending `breaks` in [-1, 1] (f is taken as 0 outside them): for functions
/// with narrow features whose place and width the caller knows, such as the
/// forward peak of a phase function with g -> 1 (graded pieces toward mu = 1).
/// A piece of angular width dtheta gets min_points + ceil(bands * dtheta / pi)
/// points, so that the oscillations of P_l are resolved on wide pieces. Error:
/// that of Gauss–Legendre on each piece (geometric in the points when f is
/// analytic near the piece). InputError for bands < 1, min_points < 1, fewer
/// than 2 breaks, or breaks not ascending in [-1, 1].
std::vector<double> zonal_coefficients(const std::function<double(double)>& f, int bands,
                                       const std::vector<double>& breaks, int min_points);

/// Legendre polynomials P_0(mu) .. P_{bands-1}(mu).
std::vector<double> legendre_polynomials(double mu, int bands);

}  // namespace atmosh::sh
