// atmosh/atmo/sun_refraction.hpp — atmospheric refraction of the sun, finite and
// continuous for every geometric elevation in [-90°, 90°].
//
// Model (angles in degrees, pressure P in hPa, temperature T in °C):
//   above the blend point h >= h_b = -1°: the formula of the NREL SPA report
//   (Reda & Andreas 2008, eq. 42; Saemundsson 1986 form of Bennett's fit)
//       R(h) = (P/1010)·(283/(273+T))·1.02 / (60·tan(h + 10.3/(h + 5.11)))
//   below it, a smooth bounded continuation that matches R and dR/dh at h_b
//   (C¹ continuity) and dies off like a Gaussian of width w = 2°:
//       R(h) = (R_b + R'_b·(h − h_b))·exp(−((h − h_b)/w)²),   h < h_b.
// Properties (tested for -90..90° at 1e-3° steps): finite, continuous, no jump
// at -0.83° (SPA sets R = 0 there), no pole near -5.11° (Saemundsson's has one),
// R ≤ 0.7° for standard air, apparent elevation h + R(h) strictly increasing.
// Below the horizon the apparent elevation is a convention, not an observable:
// the sky is always driven by the GEOMETRIC elevation; the apparent one is
// reported beside it. Accuracy above the horizon: that of Bennett/Saemundsson,
// about 0.07 arcmin (0.001°) for h > 5° in standard air, worse near the horizon
// where real refraction depends on the temperature profile (several arcmin).
// P <= 0 gives no refraction (vacuum). Throws InputError for T <= -273 °C or
// non-finite inputs.
#pragma once

namespace atmosh::atmo {

inline constexpr double kRefractionBlendDeg = -1.0;
inline constexpr double kRefractionTailWidthDeg = 2.0;

// Refraction R in degrees (apparent elevation = geometric + R).
double refraction_deg(double geometric_elevation_deg, double pressure_hpa, double temperature_c);

// geometric + refraction_deg(...).
double apparent_elevation_deg(double geometric_elevation_deg, double pressure_hpa, double temperature_c);

}  // namespace atmosh::atmo
