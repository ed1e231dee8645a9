// The named stiff/extreme-case suite: every case finite and within its bound. The
// bounds are stated HERE, each with the source of its reference, and each value is
// asserted against its reference with the test's own error: loosening a bound (or
// the pass flag) in stiff_cases.cpp cannot make this test pass. A case without a
// bound here fails, and so does a bound that no case uses.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "atmosh/atmo/stiff_cases.hpp"

using namespace atmosh::atmo;

namespace {

struct Bound {
  const char* prefix;  // case names starting with this
  double bound;        // on |value - reference| / |reference| (absolute when reference = 0)
  const char* source;  // where the reference comes from and why the bound holds
};

// clang-format off
const Bound kBounds[] = {
    // Column / vertical column of one exponential layer against the exact Chapman
    // function (its integral form; the Bessel form at 90 deg, chapman.hpp): the adaptive
    // reference's tolerance, 1e-9 (OpticalDepthReference).
    {"horizontal_sea_level_H8km", 1e-9, "exact Chapman function"},
    {"horizontal_sea_level_H1.2km", 1e-9, "exact Chapman function"},
    {"horizontal_at_10km_H8km", 1e-9, "exact Chapman function"},
    {"horizontal_at_10km_H1.2km", 1e-9, "exact Chapman function"},
    {"grazing_from_20km_tangent_100m_H8km", 1e-9, "exact Chapman function"},
    {"grazing_from_10km_tangent_1m_H1.2km", 1e-9, "exact Chapman function"},
    {"grazing_from_10km_tangent_1mm_H8km", 1e-9, "exact Chapman function"},
    // Straight down from 1 km: H (1 - e^{-1000/H}), closed form; rounding only.
    {"ray_hits_planet_nadir_from_1km", 1e-12, "closed form H (1 - exp(-h/H))"},
    // Just below the horizon: the half chord H [Ch(R/H, 90) - e^{-h/H} Ch(r/H, -mu)];
    // the ray meets the ground ~1 m past its tangent point: ~2 m of ground density in
    // ~2.5e5 m of column (< 1e-5), bound 1e-4.
    {"ray_hits_planet_just_below_horizon", 1e-4, "half chord from exact Chapman functions"},
    // Limb from 500 km above the top: the whole chord 2 H e^{-h_t/H} Ch(r_t/H, 90 deg)
    // (Bessel form), density beyond the top e^{-60} negligible; reference tolerance 1e-9.
    {"limb_from_500km_above_top", 1e-9, "Bessel form of the horizontal Chapman function"},
    // exp(-tau) for tau ~ 1e3 and tau = inf: exactly 0 (IEEE underflow), never NaN.
    {"transmittance_underflow_tau_", 0.0, "exp(-tau) underflows to exactly 0"},
    {"transmittance_of_infinite_depth", 0.0, "exp(-inf) = 0"},
    // Phase functions at g = +-0.999 integrate to 1 over the sphere (definition of a
    // normalised phase function; adaptive quadrature to 1e-12).
    {"hg_normalisation_g", 1e-10, "normalisation 2 pi int p dmu = 1"},
    {"cornette_shanks_normalisation_g", 1e-10, "normalisation 2 pi int p dmu = 1"},
    // Mean of sample() at 1e5 evenly spaced quantiles: the HG mean cosine is g
    // (Henyey & Greenstein 1941); midpoint quantile error ~1e-5, bound 1e-4.
    {"hg_sampling_mean_g", 1e-4, "HG mean cosine = g"},
    // Legendre moments through the zonal projection: chi_0 = 1 (normalisation) and
    // chi_1 = 3 g (4 + g^2) / (5 (2 + g^2)) (Cornette & Shanks 1992 mean cosine).
    {"cornette_shanks_chi0_g", 1e-10, "chi_0 = 1"},
    {"cornette_shanks_chi1_g", 1e-9, "Cornette & Shanks 1992 closed-form mean cosine"},
    // Probability of the hemisphere away from the peak by bisection on sample(),
    // against the exact integral (adaptive quadrature); ~1.3e-4 total, bound 1e-5.
    {"cornette_shanks_sampling_tail_g", 1e-5, "exact hemisphere integral of the phase function"},
    // Rayleigh optical depth from the cross-section and Bodhaine et al. (1999)'s column
    // against their eq. (30) fit, which they state good to 0.01 %.
    {"rayleigh_physical_", 1e-4, "Bodhaine et al. 1999 eq. (30)"},
    // Vertical ozone optical depth = sigma x column (DU x 2.6867811e20 m^-2): the
    // quadrature must reproduce the tent's area (reference tolerance).
    {"ozone_vertical_column_consistency_", 1e-9, "sigma x Dobson column"},
    // LUT (24 shells x 48 directions here) on grazing and tangent rays against the exact
    // optical depth: 1e-4, the tables' stated accuracy near the horizon (docs/atmosphere.md).
    {"lut_", 1e-4, "exact optical depth (OpticalDepthReference)"},
};
// clang-format on

const Bound* bound_of(const std::string& name) {
  const Bound* best = nullptr;
  for (const auto& b : kBounds)
    if (name.rfind(b.prefix, 0) == 0 && (!best || std::string(b.prefix).size() > std::string(best->prefix).size()))
      best = &b;
  return best;
}

}  // namespace

TEST(StiffCases, EachValueWithinTheBoundStatedHere) {
  const auto cases = run_stiff_cases(24, 48);
  ASSERT_GE(cases.size(), 20u);
  std::map<std::string, int> used;
  for (const auto& c : cases) {
    const Bound* b = bound_of(c.name);
    ASSERT_NE(b, nullptr) << c.name << ": no bound stated in this test";
    ++used[b->prefix];
    ASSERT_TRUE(std::isfinite(c.value)) << c.name;
    ASSERT_TRUE(std::isfinite(c.reference)) << c.name;
    const double err = c.reference != 0.0 ? std::fabs(c.value - c.reference) / std::fabs(c.reference)
                                          : std::fabs(c.value - c.reference);
    EXPECT_LE(err, b->bound) << c.name << ": value " << c.value << " reference " << c.reference << " ("
                             << b->source << ")";
    // The suite's own report agrees with what is measured here.
    EXPECT_NEAR(c.error, err, 1e-15 + 1e-12 * err) << c.name;
    EXPECT_EQ(c.pass, err <= c.bound) << c.name;
  }
  for (const auto& b : kBounds) EXPECT_GT(used[b.prefix], 0) << b.prefix << ": no case uses this bound";
}
