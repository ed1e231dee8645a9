// Stored Monte-Carlo reference rows of the sky (luminance with its standard error),
// shared by orders_accuracy_test.cpp and test_ms_convergence.cpp.
//
// The reference is atmosh's Monte-Carlo radiative transfer (radiative_transfer.hpp:
// every order of scattering, spherical geometry, next-event estimation through the exact
// transmittance; its plane-parallel mode is checked against DISORT's published test
// problems in test_radiative_transfer.cpp), an independent solver: backward paths, no
// table, no sphere rule. Its values are stored here because a run precise enough to
// judge a 1 % bound takes minutes to hours per row on a 2-core machine. They were
// produced by `rt_reference_views(MonteCarloSky(atmosphere, solar, RtSkyOptions{}),
// rt_reference_view_set(), {sun}, 0, run)` (the same rows as `atmosh converge ms` and
// `atmosh rt sky --sun-elevation E --view-elevation V --view-azimuth A`), seed 7, on the
// built-in default scene's atmosphere: the AtmosphereSpec defaults (earth-graphics
// constituents: Rayleigh, Mie, ozone; 100 km top) with 16 wavelengths 380-780 nm and a
// black ground. Each row gives the luminance and its standard error (cd/m^2) and the
// number of paths; "guided" rows used the reference's guided scattering (its default
// below -5 deg), the others the plain estimator. Two independent runs are kept at -6 deg.
// docs/radiative-transfer.md ("Orders at the default tables") lists the errors of the
// orders tables against them.
//
// The views are the study's fixed set: the zenith, 5 deg up toward / across / away from
// the sun, and 30 and 60 deg up away from it.
#pragma once

#include <cstdint>

namespace atmosh::test {

struct McRow {
  double sun_deg, view_el_deg, view_rel_az_deg;  // relative azimuth: 0 toward the sun
  double luminance, stderr_;                     // cd/m^2
  std::int64_t paths;
  bool guided;
};

// clang-format off
inline constexpr McRow kMcSkyReference[] = {
    {60, 90, 0, 1357.42633, 1.01165807, 1280000, false},
    {60, 60, 180, 1085.25749, 0.94265966, 1280000, false},
    {60, 30, 180, 1511.85355, 1.47907479, 1280000, false},
    {60, 5, 0, 6658.57529, 5.22564366, 1280000, false},
    {60, 5, 90, 5219.8263, 4.77805291, 1280000, false},
    {60, 5, 180, 5897.92455, 5.03731017, 1280000, false},
    {30, 90, 0, 896.627205, 0.809866755, 1280000, false},
    {30, 60, 180, 860.192778, 0.888270686, 1280000, false},
    {30, 30, 180, 1722.86495, 1.62477885, 1280000, false},
    {30, 5, 0, 9780.91878, 6.77627955, 1280000, false},
    {30, 5, 90, 4942.27418, 4.84075863, 1280000, false},
    {30, 5, 180, 7428.53325, 5.67695162, 1280000, false},
    {10, 90, 0, 600.143359, 0.621840283, 1280000, false},
    {10, 60, 180, 735.757277, 0.74218299, 1280000, false},
    {10, 30, 180, 1636.90422, 1.39854581, 1280000, false},
    {10, 5, 0, 17866.8543, 19.328346, 1280000, false},
    {10, 5, 90, 3771.63385, 3.87082315, 1280000, false},
    {10, 5, 180, 6293.83867, 4.6602776, 1280000, false},
    {0, 90, 0, 157.752248, 0.218516988, 1280000, false},
    {0, 60, 180, 213.25923, 0.279064232, 1280000, false},
    {0, 30, 180, 445.003657, 0.545315705, 1280000, false},
    {0, 5, 0, 2925.28894, 2.07841319, 1280000, false},
    {0, 5, 90, 826.449953, 1.25585338, 1280000, false},
    {0, 5, 180, 981.155558, 1.2740765, 1280000, false},
    {-2, 90, 0, 52.0559061, 0.0942561911, 2560000, false},
    {-2, 60, 180, 69.0314147, 0.124418681, 2560000, false},
    {-2, 30, 180, 130.130784, 0.23885855, 2560000, false},
    {-2, 5, 0, 737.433474, 1.06187385, 2560000, false},
    {-2, 5, 90, 220.734626, 0.458817905, 2560000, false},
    {-2, 5, 180, 95.8836313, 0.304936864, 2560000, false},
    {-3, 90, 0, 23.5577103, 0.0501361547, 5120000, false},
    {-3, 60, 180, 30.2147103, 0.0654618885, 5120000, false},
    {-3, 30, 180, 51.7170555, 0.117927822, 5120000, false},
    {-3, 5, 0, 404.999382, 0.57478068, 5120000, false},
    {-3, 5, 90, 89.74325, 0.22628773, 5120000, false},
    {-3, 5, 180, 22.0419966, 0.147662583, 5120000, false},
    {-4, 90, 0, 9.06500983, 0.0498796381, 2560000, false},
    {-4, 60, 180, 10.9244507, 0.0629051554, 2560000, false},
    {-4, 30, 180, 15.8878901, 0.101676081, 2560000, false},
    {-4, 5, 0, 214.683523, 0.642144939, 2560000, false},
    {-4, 5, 90, 31.1668271, 0.211297423, 2560000, false},
    {-4, 5, 180, 8.72930176, 0.140582562, 2560000, false},
    {-6, 90, 0, 0.872273816, 0.0184467846, 2560000, false},
    {-6, 60, 180, 0.919895497, 0.0211887716, 2560000, false},
    {-6, 30, 180, 1.07450962, 0.0293672202, 2560000, false},
    {-6, 5, 0, 52.277491, 0.439157248, 2560000, false},
    {-6, 5, 90, 3.22387608, 0.0967607703, 2560000, false},
    {-6, 5, 180, 1.54748915, 0.0695534625, 2560000, false},
    {-6, 90, 0, 0.878011, 0.009834, 128000, true},
    {-6, 60, 180, 0.910195, 0.004096, 128000, true},
    {-6, 30, 180, 1.05791, 0.006771, 128000, true},
    {-6, 5, 0, 52.3224, 0.2145, 128000, true},
    {-6, 5, 90, 3.18257, 0.01973, 128000, true},
    {-6, 5, 180, 1.54246, 0.01188, 128000, true},
    {-9, 90, 0, 0.0258517, 0.000274, 256000, true},
    {-9, 60, 180, 0.0321685, 0.0004439, 256000, true},
    {-9, 30, 180, 0.0612068, 0.001426, 256000, true},
    {-9, 5, 0, 4.96207, 0.01191, 256000, true},
    {-9, 5, 90, 0.156187, 0.00303, 256000, true},
    {-9, 5, 180, 0.123695, 0.001262, 256000, true},
    {-12, 90, 0, 0.00225461, 2.976e-05, 512000, true},
    {-12, 60, 180, 0.0030434, 9.252e-05, 512000, true},
    {-12, 30, 180, 0.00539595, 7.824e-05, 512000, true},
    {-12, 5, 0, 0.291919, 0.001022, 512000, true},
    {-12, 5, 90, 0.0130574, 0.0004244, 512000, true},
    {-12, 5, 180, 0.00959494, 0.0003032, 512000, true},
};
// clang-format on

}  // namespace atmosh::test
