// atmosh/atmo/sun_spa.hpp — the NREL Solar Position Algorithm (SPA).
//
// Reference: I. Reda and A. Andreas, "Solar Position Algorithm for Solar
// Radiation Applications", NREL/TP-560-34302, revised January 2008 (Solar
// Energy 76(5), 577–589, 2004). Valid for the years -2000..6000.
//
// Accuracy: ±0.0003° in zenith and azimuth (the report's stated uncertainty)
// PROVIDED that ΔT = TT − UT1 and UT1 − UTC are supplied from observation (IERS
// Bulletin A). With the default ΔT model (time_utc.hpp, Espenak & Meeus) the
// error is dominated by the ΔT error: 1 s of ΔT or of UT1−UTC moves the sun by up
// to 15 arcsec = 0.0042° in hour angle. UT1 − UTC is below 0.9 s by definition.
//
// The periodic-term sums have an AVX2 and a baseline x86-64 version, chosen at load
// time; both round alike, so results are bit-identical on every x86-64 CPU (run
// times: docs/sun.md; checks: docs/validation.md, "Sun position").
//
// Units: degrees for angles, metres for heights, hPa (= mbar) for pressure, °C
// for temperature, seconds for ΔT and UT1−UTC, AU for distances, Julian days for
// instants. Azimuth is measured from north towards east (0..360).
//
// Every intermediate quantity of the report (Section 3, Table A5.1) is exposed
// so that the worked example can be checked step by step.
#pragma once

namespace atmosh::atmo {

struct SpaInput {
  double jd_utc = 2451545.0;   // instant, UTC Julian day
  double delta_ut1_s = 0.0;    // UT1 − UTC, s (|x| < 1)
  double delta_t_s = 69.0;     // TT − UT1, s
  double latitude_deg = 0.0;   // geodetic, north positive, -90..90
  double longitude_deg = 0.0;  // east positive, -180..180
  double elevation_m = 0.0;    // height of the observer (the report uses metres above sea level)
  double pressure_hpa = 1013.25;
  double temperature_c = 15.0;
};

// Geocentric part (report Sections 3.1–3.8), depends on time only.
struct SpaGeocentric {
  double jd = 0, jc = 0, jde = 0, jce = 0, jme = 0;     // eqs. 4–8 (JD on the UT1 scale)
  double l_deg = 0, b_deg = 0, r_au = 0;                // eqs. 9–11 heliocentric L, B, R
  double theta_deg = 0, beta_deg = 0;                   // eqs. 13–14 geocentric Θ, β
  double x_deg[5] = {0, 0, 0, 0, 0};                    // eqs. 15–19 X0..X4 (unreduced)
  double delta_psi_deg = 0, delta_epsilon_deg = 0;      // eqs. 20–23 Δψ, Δε
  double epsilon0_arcsec = 0, epsilon_deg = 0;          // eqs. 24–25 ε0, ε
  double delta_tau_deg = 0, lambda_deg = 0;             // eqs. 26–27 Δτ, λ
  double nu0_deg = 0, nu_deg = 0;                       // eqs. 28–29 ν0, ν (Greenwich sidereal time)
  double alpha_deg = 0, delta_deg = 0;                  // eqs. 30–31 α, δ
};

// Full result (adds report Sections 3.9–3.15 and Appendix A.1).
struct SpaResult {
  SpaGeocentric geo;
  double h_deg = 0;                                     // eq. 32 observer local hour angle H (0..360)
  double xi_deg = 0, delta_alpha_deg = 0;               // eqs. 33–38 ξ, Δα
  double alpha_prime_deg = 0, delta_prime_deg = 0;      // α', δ' topocentric
  double h_prime_deg = 0;                               // eq. 40 H'
  double e0_deg = 0;                                    // eq. 41 geometric topocentric elevation
  double delta_e_deg = 0, e_deg = 0;                    // eqs. 42–43 refraction, apparent elevation
  double zenith_deg = 0;                                // eq. 44 apparent topocentric zenith θ
  double azimuth_astro_deg = 0;                         // eq. 45 Γ (westward from south)
  double azimuth_deg = 0;                               // eq. 46 Φ (eastward from north)
  double eot_min = 0;                                   // eq. A.1 equation of time, minutes
};

// Geocentric quantities at the UT1 Julian day jd_ut1 with ΔT (s).
SpaGeocentric spa_geocentric(double jd_ut1, double delta_t_s);

// The whole algorithm. The refraction Δe uses refraction_deg() (sun_refraction.hpp),
// which equals the report's eq. 42 for elevations above -1° and stays finite and
// continuous below. Throws InputError for out-of-range inputs.
SpaResult spa_compute(const SpaInput& in);

// Sunrise, transit and sunset per the report's Appendix A.2 (h0' = -0.8333°:
// the sun's upper limb on a standard-refraction horizon).
struct SpaRiseTransitSet {
  // Fractions of the local calendar day (0..1) in the given zone offset, or
  // negative when absent (polar day or night).
  double rise_day_fraction = -1, transit_day_fraction = -1, set_day_fraction = -1;
  int polar = 0;  // 0: rises and sets, +1: polar day (always above h0'), -1: polar night
};
// year/month/day: the local calendar date; offset_hours: its zone offset from UTC.
SpaRiseTransitSet spa_rise_transit_set(int year, int month, int day, double offset_hours, double latitude_deg,
                                       double longitude_deg, double delta_t_s, double delta_ut1_s = 0.0);

}  // namespace atmosh::atmo
