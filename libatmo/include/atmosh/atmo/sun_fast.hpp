// atmosh/atmo/sun_fast.hpp — fast solar position: R. Grena, "Five new algorithms
// for the computation of sun position from 2010 to 2110", Solar Energy 86 (2012)
// 1323–1337, algorithms 1, 3 and 5 (coefficients from that paper).
//
// Validity: UTC years 2010..2110 (InputError outside). Stated maximum error of
// the topocentric direction against SPA (Grena 2012, Table 2): algorithm 1
// 0.19°, algorithm 3 0.0093°, algorithm 5 0.0027° (the "fast" choice of the
// CLI). Measured here against our SPA with the same ΔT: see docs/sun.md and
// `atmosh sun accuracy`.
//
// Evaluation: algorithm 5 runs without libm calls (inlined sines and arctangents,
// within 5e-9 degrees of a libm evaluation of the printed formulas, tested); an order
// of magnitude faster than SPA (run times: docs/sun.md).
// Algorithms 1 and 3 use libm as printed.
//
// Units: degrees, with azimuth from north towards east; the geocentric
// declination δ and local hour angle H are also returned. Parallax is Grena's
// fixed 4.26e-5 rad horizontal parallax; refraction is NOT applied here (the
// caller uses refraction_deg()).
#pragma once

namespace atmosh::atmo {

inline constexpr int kGrenaMinYear = 2010;
inline constexpr int kGrenaMaxYear = 2110;

struct GrenaResult {
  double zenith_deg = 0;        // topocentric, geometric
  double azimuth_deg = 0;       // from north towards east, 0..360
  double declination_deg = 0;   // geocentric
  double hour_angle_deg = 0;    // local, -180..180
  double right_ascension_deg = 0;
};

// variant: 1, 3 or 5. jd_ut = UTC Julian day + (UT1−UTC)/86400; delta_t_s = TT − UT1.
// Throws InputError for another variant or a year outside 2010..2110.
GrenaResult grena_position(int variant, double jd_ut, double delta_t_s, double latitude_deg, double longitude_deg);

}  // namespace atmosh::atmo
