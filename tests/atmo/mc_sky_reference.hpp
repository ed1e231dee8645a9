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
// below -5 deg; switched on for the later -4 deg runs), the others the plain estimator.
// Several independent runs (other seeds, the `seed` member) are kept where one was not
// enough: the tests pool them (pooled_mc_reference below). The later runs were made
// with the library call below, RtSkyOptions::guide switched on (the option that
// `atmosh rt sky --guide on` sets):
//   RtSkyOptions ro; ro.guide = RtLineEstimate::On;  // -4 deg; default elsewhere
//   RtOptions run{.paths = P, .seed = S, .threads = 1}; ro.run = run;
//   rt_reference_views(MonteCarloSky(atm, solar_spectrum_for_bins(spec.spectrum), ro),
//                      {{view_el, view_rel_az}}, {sun}, 0.0, run);
// (2-core VM shared with other builds: 300-450 s per 320 000-path row at -4 deg, ~400 s
// per 256 000-path row at -6 deg, 40-100 s per 64 000-path row at -9 and -12 deg.)
// docs/sky.md ("Multiple scattering") lists the errors of the orders tables against them
// (docs/radiative-transfer.md, "Orders at the default tables": the earlier rounds').
//
// The views are the study's fixed set: the zenith, 5 deg up toward / across / away from
// the sun, and 30 and 60 deg up away from it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace atmosh::test {

struct McRow {
  double sun_deg, view_el_deg, view_rel_az_deg;  // relative azimuth: 0 toward the sun
  double luminance, stderr_;                     // cd/m^2
  std::int64_t paths;
  bool guided;
  std::uint64_t seed = 7;
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
    // Later runs (2026-11-26; RtSkyOptions guide = On, every other option at its default;
    // the -9 and -12 deg rows guided by default): the library call of the comment above with
    // run = {.paths = P, .seed = S, .threads = 1}, one view per call.
    {-2, 5, 180, 95.5841961, 0.224962, 320000, true, 11},
    {-2, 5, 180, 95.6895268, 0.223421, 320000, true, 12},
    {-3, 5, 180, 21.7723447, 0.0676939, 320000, true, 11},
    {-3, 5, 180, 21.9185068, 0.0708577, 320000, true, 12},
    {-4, 90, 0, 8.93436625, 0.023499, 320000, true, 11},
    {-4, 60, 180, 10.9278686, 0.0273001, 320000, true, 11},
    {-4, 30, 180, 16.153099, 0.0380375, 320000, true, 11},
    {-4, 5, 0, 214.669721, 0.493153, 320000, true, 11},
    {-4, 5, 90, 31.4968065, 0.0975145, 320000, true, 11},
    {-4, 5, 180, 8.89227946, 0.0608311, 320000, true, 11},
    {-6, 90, 0, 0.868752619, 0.00469016, 256000, true, 11},
    {-6, 5, 90, 3.25938923, 0.0443787, 256000, true, 11},
    {-6, 30, 180, 1.07355769, 0.00830925, 256000, true, 11},
    {-6, 5, 180, 1.54896395, 0.0097605, 256000, true, 11},
    {-6, 60, 180, 0.910129751, 0.00331326, 256000, true, 11},
    {-6, 5, 0, 52.4201697, 0.155012, 256000, true, 11},
    {-9, 60, 180, 0.0282287539, 0.000662228, 16000, true, 11},
    {-9, 60, 180, 0.032726245, 0.000689696, 64000, true, 21},
    {-9, 30, 180, 0.0645060021, 0.00380183, 64000, true, 21},
    {-9, 5, 90, 0.155151277, 0.00355421, 64000, true, 21},
    {-9, 60, 180, 0.0323986684, 0.000721332, 64000, true, 22},
    {-9, 30, 180, 0.0585592744, 0.00103024, 64000, true, 22},
    {-9, 5, 90, 0.148173706, 0.00249949, 64000, true, 22},
    {-9, 60, 180, 0.0311680494, 0.000535917, 64000, true, 23},
    {-12, 60, 180, 0.00288189635, 0.000156041, 16000, true, 11},
    {-12, 60, 180, 0.00315755437, 0.000124212, 64000, true, 21},
    {-12, 5, 180, 0.00932839255, 0.000340191, 64000, true, 21},
    {-12, 5, 90, 0.0128439833, 0.000587455, 64000, true, 21},
    {-12, 60, 180, 0.00296479908, 9.73073e-05, 64000, true, 22},
    {-12, 5, 180, 0.00957854678, 0.000328071, 64000, true, 22},
    {-12, 5, 90, 0.0119091056, 0.000399358, 64000, true, 22},
    {-12, 60, 180, 0.00278685692, 7.58673e-05, 64000, true, 23},
    {-12, 5, 180, 0.00911659163, 0.000203719, 64000, true, 23},
    {-12, 5, 90, 0.0129424256, 0.000491161, 64000, true, 23},
    // Later runs (2026-11-27; RtSkyOptions guide = On at every elevation here, the
    // default below -5 deg): the same call with run = {.paths = 1 000 000, .seed = 41 or
    // 42, .threads = 1}, one view per call, every view at -4, -6, -9 and -12 deg
    // (25-64 s per row on one core of the idle 2-core VM).
    {-4, 90, 0, 8.94635206, 0.0121733, 1000000, true, 41},
    {-4, 60, 180, 10.9286737, 0.0157592, 1000000, true, 41},
    {-4, 30, 180, 16.1511428, 0.0231651, 1000000, true, 41},
    {-4, 5, 0, 214.352138, 0.272492, 1000000, true, 41},
    {-4, 5, 90, 31.3742079, 0.0560156, 1000000, true, 41},
    {-4, 5, 180, 8.82237522, 0.0210734, 1000000, true, 41},
    {-6, 90, 0, 0.869295392, 0.00204538, 1000000, true, 41},
    {-6, 60, 180, 0.910811403, 0.00168465, 1000000, true, 41},
    {-6, 30, 180, 1.06287391, 0.00303095, 1000000, true, 41},
    {-6, 5, 0, 52.2874985, 0.0781194, 1000000, true, 41},
    {-6, 5, 90, 3.19785324, 0.0069274, 1000000, true, 41},
    {-6, 5, 180, 1.54599893, 0.00425321, 1000000, true, 41},
    {-9, 90, 0, 0.0266610542, 0.000214776, 1000000, true, 41},
    {-9, 60, 180, 0.0321508004, 0.000216613, 1000000, true, 41},
    {-9, 30, 180, 0.060709954, 0.000377601, 1000000, true, 41},
    {-9, 5, 0, 4.96861986, 0.0187683, 1000000, true, 41},
    {-9, 5, 90, 0.154571586, 0.000909524, 1000000, true, 41},
    {-9, 5, 180, 0.125265658, 0.000801735, 1000000, true, 41},
    {-12, 90, 0, 0.00233445575, 2.78717e-05, 1000000, true, 41},
    {-12, 60, 180, 0.00301334772, 4.27873e-05, 1000000, true, 41},
    {-12, 30, 180, 0.00551669797, 6.3171e-05, 1000000, true, 41},
    {-12, 5, 0, 0.292198591, 0.000598474, 1000000, true, 41},
    {-12, 5, 90, 0.0124177141, 0.000131956, 1000000, true, 41},
    {-12, 5, 180, 0.00926924792, 7.86546e-05, 1000000, true, 41},
    {-4, 90, 0, 8.95404417, 0.0163749, 1000000, true, 42},
    {-4, 60, 180, 10.9087964, 0.0145651, 1000000, true, 42},
    {-4, 30, 180, 16.165527, 0.0227273, 1000000, true, 42},
    {-4, 5, 0, 214.751999, 0.2728, 1000000, true, 42},
    {-4, 5, 90, 31.3987207, 0.0483756, 1000000, true, 42},
    {-4, 5, 180, 8.85110395, 0.0188272, 1000000, true, 42},
    {-6, 90, 0, 0.866569468, 0.00153948, 1000000, true, 42},
    {-6, 60, 180, 0.918346247, 0.00242532, 1000000, true, 42},
    {-6, 30, 180, 1.06182161, 0.00316191, 1000000, true, 42},
    {-6, 5, 0, 52.236665, 0.0793761, 1000000, true, 42},
    {-6, 5, 90, 3.20374643, 0.00661393, 1000000, true, 42},
    {-6, 5, 180, 1.56404318, 0.0104663, 1000000, true, 42},
    {-9, 90, 0, 0.026515022, 0.000183229, 1000000, true, 42},
    {-9, 60, 180, 0.0320962221, 0.000254743, 1000000, true, 42},
    {-9, 30, 180, 0.0610884213, 0.000772473, 1000000, true, 42},
    {-9, 5, 0, 4.94799696, 0.00499232, 1000000, true, 42},
    {-9, 5, 90, 0.155175121, 0.00137843, 1000000, true, 42},
    {-9, 5, 180, 0.126648439, 0.000984513, 1000000, true, 42},
    {-12, 90, 0, 0.00233952076, 3.54401e-05, 1000000, true, 42},
    {-12, 60, 180, 0.00295781941, 3.91267e-05, 1000000, true, 42},
    {-12, 30, 180, 0.00548026634, 6.98779e-05, 1000000, true, 42},
    {-12, 5, 0, 0.291050396, 0.000560763, 1000000, true, 42},
    {-12, 5, 90, 0.0124440236, 0.000233024, 1000000, true, 42},
    {-12, 5, 180, 0.00951680196, 0.000239183, 1000000, true, 42},
};
// clang-format on

// The runs of one view pooled: the path-weighted mean of its rows (independent runs of
// other seeds; where a view has guided runs, only those: the plain estimator is
// heavy-tailed below about -3 deg, its mean and standard error unreliable -- at -4 deg,
// zenith, 2 560 000 plain paths gave 9.065 +- 0.050 and 320 000 guided ones 8.934 +-
// 0.023 cd/m^2), with the larger of the formal standard
// error sqrt(sum (p_i / P)^2 s_i^2) and, for two runs or more, the one the runs' scatter
// gives, sqrt(n / (n - 1) sum (p_i / P)^2 (L_i - L)^2): in deep twilight the estimates are
// heavy-tailed and a run's own standard error can be too small (at -9 and -12 deg, 60 deg
// up away from the sun, 64 000-path runs of three seeds scatter by 2-3 times their stated
// errors).
struct McPooled {
  double sun_deg, view_el_deg, view_rel_az_deg;
  double luminance, stderr_;  // cd/m^2
  std::int64_t paths;
  int runs;
};
inline std::vector<McPooled> pooled_mc_reference() {
  std::vector<McPooled> out;
  for (const McRow& r : kMcSkyReference) {
    bool seen = false, has_guided = false;
    for (const McPooled& q : out)
      seen = seen ||
             (q.sun_deg == r.sun_deg && q.view_el_deg == r.view_el_deg && q.view_rel_az_deg == r.view_rel_az_deg);
    if (seen) continue;
    auto same = [&](const McRow& o) {
      return o.sun_deg == r.sun_deg && o.view_el_deg == r.view_el_deg && o.view_rel_az_deg == r.view_rel_az_deg;
    };
    for (const McRow& o : kMcSkyReference) has_guided = has_guided || (same(o) && o.guided);
    auto used = [&](const McRow& o) { return same(o) && (o.guided || !has_guided); };
    double P = 0, sum = 0;
    int n = 0;
    for (const McRow& o : kMcSkyReference)
      if (used(o)) {
        P += static_cast<double>(o.paths);
        sum += static_cast<double>(o.paths) * o.luminance;
        ++n;
      }
    const double mean = sum / P;
    double var_formal = 0, var_scatter = 0;
    for (const McRow& o : kMcSkyReference)
      if (used(o)) {
        const double w = static_cast<double>(o.paths) / P;
        var_formal += w * w * o.stderr_ * o.stderr_;
        var_scatter += w * w * (o.luminance - mean) * (o.luminance - mean);
      }
    if (n >= 2) var_scatter *= static_cast<double>(n) / (n - 1);
    out.push_back({r.sun_deg, r.view_el_deg, r.view_rel_az_deg, mean,
                   std::sqrt(std::max(var_formal, n >= 2 ? var_scatter : 0.0)), static_cast<std::int64_t>(P), n});
  }
  return out;
}

}  // namespace atmosh::test
