// atmosh/atmo/sun_disc.hpp — the sun as a limb-darkened disc: its angular size, its
// radiance, the direct beam averaged over it, and its image in sky images.
//
// Size: angular radius alpha_s = asin(R_sun / (d * AU)), R_sun = 695,700 km (IAU 2015
// Resolution B3 nominal solar radius), 1 AU = 149,597,870.7 km (IAU 2012 Resolution
// B2), d the Earth-Sun distance [AU]: 0.2666 deg at 1 AU (0.2621-0.2711 deg over the year).
//
// Limb darkening: the single-parameter law of Hestroffer & Magnan (1998), A&A 333, 338,
//   I(mu, lambda) / I(1, lambda) = mu^alpha(lambda),  alpha = -0.023 + 0.292 / lambda[um]
// (their fit to the continuum centre-to-limb measurements; alpha = 0.745 at 380 nm, 0.561
// at 500 nm, 0.351 at 780 nm), mu the cosine of the heliocentric angle; on the sky
// mu = sqrt(1 - u^2) with u = sin(rho) / sin(alpha_s) at angular distance rho from the
// disc centre (exact for a sphere seen from outside: the projection is orthographic
// in u). Irradiance normal to the beam is E = int L cos(rho) dOmega, and
// cos(rho) dOmega = sin^2(alpha_s) u du dphi exactly, so with the law integrated
// analytically, int_0^1 mu^alpha 2 u du = 2 / (alpha + 2):
//   L(rho, lambda) = E(lambda) mu^alpha / (pi sin^2(alpha_s) * 2 / (alpha + 2)).
//
// Direct beam through the atmosphere: the transmittance averaged over the disc with the
// disc's own weights (limb darkening), T_disc(lambda) = int T mu^alpha dA / int mu^alpha dA
// over the disc's projected plane. The part below the horizon (straight rays meeting
// the ground: elevation below -acos(R / (R + h))) contributes 0: partial occultation.
// T varies across the disc with elevation (differential extinction, steep near the
// horizon); along a horizontal chord of the disc the elevation changes by at most
// alpha_s^2 tan(e) / 2 (< 1.1e-5 rad tan e), neglected: T is taken on the disc's vertical
// diameter and each horizontal chord carries its exact weight, (1 - y^2)^((alpha+1)/2)
// for the law above (y: height in disc radii). With y = sin(theta) the weight is
// cos^(alpha+2)(theta) dtheta, integrated by Gauss-Legendre on the visible and the
// hidden part of [-pi/2, pi/2] separately (n nodes each), the visible fraction being
// the visible part's share of the sum: no atmosphere and the disc centre on the
// horizon give exactly 1/2 (the two parts are mirror images), a disc wholly above it
// and no atmosphere exactly 1.
//
// The point sun (SunModel::Point) keeps the direct beam of the disc centre's direction
// and no disc in images; sky radiance (in-scattering) is the same for both models.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"

namespace atmosh::atmo {

inline constexpr double kSolarRadiusM = 6.957e8;              // IAU 2015 Resolution B3
inline constexpr double kAstronomicalUnitM = 1.495978707e11;  // IAU 2012 Resolution B2

// "disc" | "point"; InputError naming the value otherwise.
SunModel parse_sun_model(const std::string& name);
const char* sun_model_name(SunModel model);

// Angular radius of the sun [rad] at `distance_au`; InputError unless distance > R_sun.
double sun_angular_radius_rad(double distance_au);

// Hestroffer & Magnan (1998) exponent alpha(lambda) and the law mu^alpha (mu clamped to
// [0, 1]).
double limb_darkening_exponent(double wavelength_nm);
double limb_darkening(double mu, double wavelength_nm);
// Mean of the law over the disc's projected area, 2 / (alpha + 2) (closed form).
double limb_darkening_disc_mean(double wavelength_nm);

// Radiance of the disc per unit irradiance [1/sr] at angular distance rho [rad] from
// its centre: mu^alpha / (pi sin^2(alpha_s) * 2 / (alpha + 2)), 0 outside the disc.
double sun_disc_radiance_per_irradiance(double rho_rad, double angular_radius_rad, double wavelength_nm);

// Direct-beam transmittance averaged over the disc (see above), per wavelength of the
// sky's atmosphere; `nodes` Gauss-Legendre nodes per part (1..64).
std::vector<double> sun_disc_transmittance(const SkyIntegrator& sky, double altitude_m, const glm::dvec3& sun,
                                           int nodes = 16);
// The direct beam's transmittance for the sky's SkyOptions::sun_model: the disc average,
// or the centre's (SkyIntegrator::sun_transmittance) for the point sun.
std::vector<double> direct_sun_transmittance(const SkyIntegrator& sky, double altitude_m, const glm::dvec3& sun);

// The visible disc in a sky image rendered for (sky, projection, altitude, sun): every
// pixel whose centre direction lies within alpha_s of the sun gets the disc's radiance
// there, attenuated along that direction (0 below the horizon), added to its sky
// radiance (spectral channels if kept, X,Y,Z and R,G,B). No bloom, no spreading: pixels
// whose centres miss the disc are unchanged. Nothing for the point sun. Returns the
// number of pixels changed.
int add_sun_disc(SkyImage& image, const SkyIntegrator& sky, SkyProjection projection, double altitude_m,
                 const glm::dvec3& sun);

}  // namespace atmosh::atmo
