// atmosh/atmo/chapman.hpp — the Chapman grazing-incidence function and the
// scaled complementary error function.
//
// Ch(x, mu) is the column of an exponential atmosphere (scale height H) above a
// sphere, along a straight ray from radius r with zenith cosine mu, divided by
// the vertical column H exp(-h/H); x = r / H (no planet blocks the ray: for
// mu < 0 the ray passes its tangent point and climbs again).
//
//  * chapman_exact: Huestis (2001), "Accurate evaluation of the Chapman function
//    for atmospheric attenuation", JQSRT 69, 709-721 (integral form):
//      Ch(x, chi) = 1 + x sin(chi) int_0^chi exp(x (1 - sin chi / sin l)) / (1 + cos l) dl,
//    for chi <= 90 deg, integrated by adaptive Gauss-Kronrod to ~1e-14 relative,
//    and for chi > 90 deg the tangent-point relation
//      Ch(x, chi) = 2 exp(x (1 - sin chi)) Ch(x sin chi, 90) - Ch(x, 180 - chi).
//  * chapman_horizontal_exact: Ch(x, 90 deg) = x e^x K_1(x) (K_1 the modified
//    Bessel function; Huestis 2001), from std::cyl_bessel_k for x < 50 and the
//    asymptotic series of e^x K_1 (Abramowitz & Stegun 9.7.2), summed to
//    1e-17, beyond. Relative accuracy ~1e-15.
//  * chapman_erfcx: the classical closed form from the parabolic expansion of the
//    radius along the ray (e.g. Kocifaj 1996; Huestis 2001 sec. 3):
//      Ch ~ sqrt(pi x / 2) / sin(chi) erfcx(cos(chi) sqrt(x / 2) / sin(chi)),
//    with the same tangent-point relation for chi > 90 deg. Relative error
//    O(1/x): <= 5e-4 at x = 800 (H = 8 km on Earth), smaller at large x.
//  * chapman_horizontal_asymptotic(x, terms): sqrt(pi x / 2) (1 + 3/(8x) - 15/(128 x^2) + ...).
//
// erfcx(y) = exp(y^2) erfc(y), for any real y, relative accuracy ~1e-14:
// exp(y^2) erfc(y) with y^2 split into head and tail for |y| <= 26, the
// continued-fraction/asymptotic series beyond; erfcx(-y) = 2 exp(y^2) - erfcx(y)
// (which overflows to +inf for y < -26.6).
//
// Inputs: x > 0, mu in [-1, 1]; InputError otherwise. Results may be +inf for
// mu < 0 with x (1 - sin chi) > ~709 (a ray through the planet's centre).
#pragma once

namespace atmosh::atmo {

double erfcx(double y);
double chapman_exact(double x, double mu);
double chapman_horizontal_exact(double x);
double chapman_erfcx(double x, double mu);
double chapman_horizontal_asymptotic(double x, int terms = 3);

}  // namespace atmosh::atmo
