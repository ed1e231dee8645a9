// Tests of atmosh/atmo/colour.hpp against published colorimetric tables and
// closed forms. Sources are cited beside each reference value.
#include "atmosh/atmo/colour.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "atmosh/error.hpp"

namespace {

using namespace atmosh::atmo;

// CIE standard illuminant D65, relative spectral power at 10 nm, 300-830 nm
// (CIE 015:2018 Table 5 / ISO 11664-2:2007). The CIE 1 nm D65 table
// (CIE_std_illum_D65.csv) is the linear interpolation of these values, so
// d65() below reproduces the official 1 nm table exactly.
constexpr double kD65_10nm[] = {
    0.0341,  3.2945,  20.236,  37.0535, 39.9488, 44.9117, 46.6383, 52.0891, 49.9755,
    54.6482, 82.7549, 91.486,  93.4318, 86.6823, 104.865, 117.008, 117.812, 114.861,
    115.923, 108.811, 109.354, 107.802, 104.79,  107.689, 104.405, 104.046, 100.0,
    96.3342, 95.788,  88.6856, 90.0062, 89.5991, 87.6987, 83.2886, 83.6992, 80.0268,
    80.2146, 82.2778, 78.2842, 69.7213, 71.6091, 74.349,  61.604,  69.8856, 75.087,
    63.5927, 46.4182, 66.8054, 63.3828, 64.304,  59.4519, 51.959,  57.4406, 60.3125};

double d65(double nm) {
  const double u = (nm - 300.0) / 10.0;
  if (u < 0.0 || u > 53.0) return 0.0;
  const int i = std::min(static_cast<int>(u), 52);
  const double t = u - i;
  return kD65_10nm[i] + t * (kD65_10nm[i + 1] - kD65_10nm[i]);
}

// Planck's law as spectral radiance [W m^-2 sr^-1 nm^-1] with second radiation
// constant c2 [m K] (CODATA 2018 h, c, k; the first constant c1L = 2 h c^2).
double planck(double nm, double kelvin, double c2 = 1.438776877e-2) {
  const double c1l = 2.0 * 6.62607015e-34 * 299792458.0 * 299792458.0;
  const double l = nm * 1e-9;
  return c1l / (std::pow(l, 5) * std::expm1(c2 / (l * kelvin))) * 1e-9;
}

// n bin centres of equal bins over [from, to].
std::vector<double> bin_centres(double from, double to, int n) {
  std::vector<double> w(n);
  for (int i = 0; i < n; ++i) w[i] = from + (i + 0.5) * (to - from) / n;
  return w;
}

template <class F>
std::vector<double> sample(const std::vector<double>& nm, F f) {
  std::vector<double> v;
  for (double l : nm) v.push_back(f(l));
  return v;
}

double xy_error(const Xyz& a, const Xyz& b) {
  const auto p = xy_chromaticity(a), q = xy_chromaticity(b);
  return std::hypot(p.x - q.x, p.y - q.y);
}

double rgb_spread(const Rgb& c) {
  const double mean = (c.r + c.g + c.b) / 3.0;
  return std::max({std::abs(c.r - mean), std::abs(c.g - mean), std::abs(c.b - mean)}) / mean;
}

TEST(Colour, CmfSpotValuesMatchCieTable) {
  // CIE 1931 2-degree observer, 5 nm table (CIE 015:2018 Table 1; Wyszecki &
  // Stiles, Color Science 2nd ed., Table I(3.3.1)).
  struct Row {
    double nm, x, y, z;
  };
  const Row rows[] = {{380, 0.001368, 0.000039, 0.006450}, {450, 0.33620, 0.03800, 1.77211},
                      {500, 0.00490, 0.32300, 0.27200},    {555, 0.51205, 1.00000, 0.00575},
                      {600, 1.06220, 0.63100, 0.00080},    {650, 0.28350, 0.10700, 0.00000},
                      {700, 0.011359, 0.004102, 0.0},       {780, 0.0000415, 0.0000150, 0.0}};
  for (const auto& r : rows) {
    const Cmf c = cie1931_2deg(r.nm);
    EXPECT_NEAR(c.x, r.x, 5e-6 + 1e-5 * r.x) << r.nm;
    EXPECT_NEAR(c.y, r.y, 5e-6 + 1e-5 * r.y) << r.nm;
    EXPECT_NEAR(c.z, r.z, 5e-6 + 1e-5 * r.z) << r.nm;
  }
  // Between table points: linear interpolation of the 1 nm rows 555 and 556
  // (ybar 1.000000 and 0.9998567 in the CIE 1 nm table).
  EXPECT_NEAR(cie1931_2deg(555.5).y, 0.5 * (1.0 + 0.9998567), 1e-12);
  // ybar has its maximum, 1, at 555 nm.
  double best = 0, best_nm = 0;
  for (double l = 360; l <= 830; l += 0.25) {
    if (cie1931_2deg(l).y > best) best = cie1931_2deg(l).y, best_nm = l;
  }
  EXPECT_EQ(best_nm, 555.0);
  EXPECT_EQ(best, 1.0);
}

TEST(Colour, CmfOutsideTableIsZeroNotNan) {
  for (double l : {0.0, 359.99, 830.01, 1e6, -5.0, std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity()}) {
    const Cmf c = cie1931_2deg(l);
    EXPECT_EQ(c.x, 0.0) << l;
    EXPECT_EQ(c.y, 0.0) << l;
    EXPECT_EQ(c.z, 0.0) << l;
  }
  EXPECT_GT(cie1931_2deg(360.0).z, 0.0);
  EXPECT_GT(cie1931_2deg(830.0).y, 0.0);
  EXPECT_THROW(cie1931_2deg(std::nan("")), atmosh::InputError);
}

TEST(Colour, EqualEnergySpectrumIsAtOneThird) {
  // The CIE 1931 functions are scaled to equal integrals; the published 1 nm
  // table, rounded, has sums 106.8655, 106.8569, 106.8923 (CIE 015:2018), so
  // x and y miss 1/3 by about 5e-5: the precision the table allows.
  const Xyz ref = xyz_reference_1nm([](double) { return 1.0; });
  const auto c = xy_chromaticity(ref);
  EXPECT_NEAR(c.x, 1.0 / 3.0, 1e-4);
  EXPECT_NEAR(c.y, 1.0 / 3.0, 1e-4);
  EXPECT_NEAR(ref.Y / 683.0, 106.856917, 1e-5);

  // Piecewise-linear weights integrate a constant exactly for any grid; the
  // 1 nm sum and that (trapezoid) integral differ only by half the end values
  // (zbar(360 nm)/2 = 3e-4 against a sum of 107), hence 1e-6, not 1e-12.
  for (int n : {1, 3, 16, 47}) {
    const SpectralToXyz conv(bin_centres(380, 780, n));
    const Xyz e = conv(std::vector<double>(n, 1.0));
    EXPECT_LT(xy_error(e, ref), 1e-6) << n;
    EXPECT_NEAR(e.Y / ref.Y, 1.0, 1e-6) << n;
  }
}

TEST(Colour, D65IsWhiteInSrgb) {
  // 1 nm reference: D65 chromaticity is (0.31272, 0.32903) (CIE 015:2018
  // Table 3, 2-degree observer) and maps to R = G = B.
  const Xyz ref = xyz_reference_1nm(d65);
  const auto c = xy_chromaticity(ref);
  EXPECT_NEAR(c.x, 0.31272, 1e-5);
  EXPECT_NEAR(c.y, 0.32903, 1e-5);
  EXPECT_LT(rgb_spread(linear_srgb_from_xyz(ref)), 1e-3);  // measured 2.2e-4

  // 16 wavelengths over 380-780 nm, piecewise-linear weights (measured:
  // xy off by 1.2e-3, RGB spread 8.5e-3; D65 is not smooth, its 10 nm
  // segments and dips alias at 25 nm spacing).
  const auto nm = bin_centres(380, 780, 16);
  const SpectralToXyz conv(nm);
  const Xyz e = conv(sample(nm, d65));
  EXPECT_LT(xy_error(e, ref), 3e-3);
  EXPECT_LT(rgb_spread(linear_srgb_from_xyz(e)), 2e-2);
  // 47 x 10 nm bins over 360-830 nm (the default spectrum): closer.
  const auto nm47 = bin_centres(360, 830, 47);
  const Xyz e47 = SpectralToXyz(nm47)(sample(nm47, d65));
  EXPECT_LT(xy_error(e47, ref), 2e-4);
  EXPECT_LT(rgb_spread(linear_srgb_from_xyz(e47)), 2e-3);
}

TEST(Colour, IlluminantAChromaticity) {
  // CIE illuminant A: relative SPD of Planck's law with c2 = 1.435e-2 m K at
  // 2848 K (CIE 015:2018 eq. 4.1; = 2856 K with the modern c2); its
  // chromaticity is (0.44757, 0.40745) (CIE 015:2018 Table 3).
  const Xyz a = xyz_reference_1nm([](double nm) { return planck(nm, 2848.0, 1.435e-2); });
  const auto c = xy_chromaticity(a);
  EXPECT_NEAR(c.x, 0.44757, 2e-5);
  EXPECT_NEAR(c.y, 0.40745, 2e-5);
}

TEST(Colour, LuminousEfficacy683AtMonochromatic555) {
  // 1/683 W m^-2 sr^-1 at 555 nm, where ybar = 1.0000 (CIE table), is 1 cd/m^2.
  EXPECT_DOUBLE_EQ(683.0 * cie1931_2deg(555.0).y * (1.0 / 683.0), 1.0);
  // The same as a narrow triangular line (area 1/683 W m^-2 sr^-1).
  const SpectralToXyz conv({554.0, 555.0, 556.0});
  const Xyz e = conv(std::vector<double>{0.0, 1.0 / 683.0, 0.0});
  EXPECT_NEAR(luminance_cd_m2(e), 1.0, 2e-4);
}

TEST(Colour, PiecewiseLinearWeightsIntegrateTheInterpolant) {
  // Independent quadrature: composite Simpson with 0.01 nm steps of
  // L_interp(lambda) * cmf(lambda) (exact on each 1 nm piece within rounding).
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  const std::vector<double> nm = {371.3, 402.0, 433.7, 480.0, 501.5, 555.0,
                                  590.25, 640.0, 700.0, 769.9};
  std::vector<double> v(nm.size());
  for (auto& x : v) x = u(rng);
  auto interp = [&](double l) {
    if (l <= nm.front()) return v.front();
    if (l >= nm.back()) return v.back();
    const auto it = std::upper_bound(nm.begin(), nm.end(), l);
    const std::size_t k = static_cast<std::size_t>(it - nm.begin()) - 1;
    const double t = (l - nm[k]) / (nm[k + 1] - nm[k]);
    return v[k] + t * (v[k + 1] - v[k]);
  };
  Xyz q;
  const int steps = 47000;
  const double h = (830.0 - 360.0) / steps;
  for (int i = 0; i <= steps; ++i) {
    const double l = 360.0 + i * h;
    const double w = (i == 0 || i == steps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    const Cmf c = cie1931_2deg(l);
    const double f = interp(l) * w * h / 3.0 * 683.0;
    q.X += f * c.x;
    q.Y += f * c.y;
    q.Z += f * c.z;
  }
  const Xyz e = SpectralToXyz(nm)(v);
  EXPECT_NEAR(e.X / q.X, 1.0, 1e-6);
  EXPECT_NEAR(e.Y / q.Y, 1.0, 1e-6);
  EXPECT_NEAR(e.Z / q.Z, 1.0, 1e-6);
}

TEST(Colour, BlackbodiesWithSixteenWavelengths) {
  // Smooth spectra sampled at 16 bin centres over 380-780 nm versus the 1 nm
  // CIE sum (measured with piecewise-linear weights: xy error 7e-5..3.5e-4 and
  // Y error < 2.2e-3 for 3000-20000 K; 8e-4 and 5.8e-3 at 2000 K, where the
  // steep convex spectrum makes the chords overshoot).
  const auto nm = bin_centres(380, 780, 16);
  const auto nm32 = bin_centres(380, 780, 32);
  const SpectralToXyz pl(nm), pl32(nm32);
  const SpectralToXyz mid(nm, SpectralQuadrature::Midpoint);
  for (double t : {2000.0, 3000.0, 5772.0, 6500.0, 10000.0, 20000.0}) {
    auto f = [t](double l) { return planck(l, t); };
    const Xyz ref = xyz_reference_1nm(f);
    const Xyz e = pl(sample(nm, f));
    EXPECT_LT(xy_error(e, ref), t < 2500 ? 1e-3 : 5e-4) << t;
    EXPECT_NEAR(e.Y / ref.Y, 1.0, t < 2500 ? 1e-2 : 3e-3) << t;
    // Second order: doubling the wavelengths cuts the error about 4 times.
    const Xyz e32 = pl32(sample(nm32, f));
    EXPECT_GT(xy_error(e, ref) / xy_error(e32, ref), 3.0) << t;
    // For daylight-like and bluer spectra the crude midpoint rule, which
    // samples the CMFs at 16 points only, is several times worse.
    if (t > 5000) {
      const Xyz m = mid(sample(nm, f));
      EXPECT_GT(xy_error(m, ref), 5.0 * xy_error(e, ref)) << t;
    }
  }
}

TEST(Colour, SolarSpectrumNeedsBandMeans) {
  // The TOA solar spectrum is full of absorption lines: point samples at 16
  // wavelengths alias (measured xy error 4.4e-3, Y -1.7e-2); band means over
  // the 25 nm bins bring it to 6.3e-4 and -3.7e-4.
  const Xyz ref = xyz_reference_1nm([](double l) { return solar_irradiance_toa(l); });
  const int n = 16;
  const auto nm = bin_centres(380, 780, n);
  std::vector<double> points, means;
  for (int i = 0; i < n; ++i) {
    points.push_back(solar_irradiance_toa(nm[i]));
    means.push_back(solar_irradiance_toa_mean(380.0 + 25.0 * i, 380.0 + 25.0 * (i + 1)));
  }
  const SpectralToXyz conv(nm);
  const Xyz p = conv(points), m = conv(means);
  EXPECT_LT(xy_error(m, ref), 1.5e-3);
  EXPECT_NEAR(m.Y / ref.Y, 1.0, 2e-3);
  EXPECT_LT(xy_error(m, ref), xy_error(p, ref));
}

TEST(Colour, SrgbMatrixMatchesIec61966) {
  // IEC 61966-2-1:1999 section 5.2, linear RGB -> XYZ, 4 decimals.
  const double fwd[3][3] = {
      {0.4124, 0.3576, 0.1805}, {0.2126, 0.7152, 0.0722}, {0.0193, 0.1192, 0.9505}};
  const auto& f = xyz_from_srgb_matrix();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(f[i][j], fwd[i][j], 5e-5) << i << j;
  }
  // The standard's XYZ -> RGB matrix is the inverse of the rounded forward
  // matrix, printed to 4 decimals; the exact inverse differs by up to 3.7e-4.
  const double iec[3][3] = {
      {3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
  const auto& m = srgb_from_xyz_matrix();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(m[i][j], iec[i][j], 5e-4) << i << j;
  }
  // Middle row of RGB -> XYZ: luminance coefficients 0.2126, 0.7152, 0.0722
  // (ITU-R BT.709-6 item 3.2, same primaries and white).
  const auto& inv = xyz_from_srgb_matrix();
  EXPECT_NEAR(inv[1][0], 0.2126, 5e-5);
  EXPECT_NEAR(inv[1][1], 0.7152, 5e-5);
  EXPECT_NEAR(inv[1][2], 0.0722, 5e-5);
  // White (1,1,1) <-> D65 with Y = 1: X = x/y, Z = (1-x-y)/y for (0.3127, 0.3290).
  const Xyz w = xyz_from_linear_srgb({1.0, 1.0, 1.0});
  EXPECT_NEAR(w.Y, 1.0, 1e-12);
  EXPECT_NEAR(w.X, 0.3127 / 0.3290, 1e-12);
  EXPECT_NEAR(w.Z, (1.0 - 0.3127 - 0.3290) / 0.3290, 1e-12);
  const Rgb back = linear_srgb_from_xyz(w);
  EXPECT_NEAR(back.r, 1.0, 1e-12);
  EXPECT_NEAR(back.g, 1.0, 1e-12);
  EXPECT_NEAR(back.b, 1.0, 1e-12);
  // Each primary's chromaticity maps to a pure channel.
  const Chromaticity prim[3] = {kSrgbRed, kSrgbGreen, kSrgbBlue};
  for (int k = 0; k < 3; ++k) {
    const Xyz p{prim[k].x / prim[k].y, 1.0, (1.0 - prim[k].x - prim[k].y) / prim[k].y};
    const Rgb c = linear_srgb_from_xyz(p);
    const double ch[3] = {c.r, c.g, c.b};
    for (int j = 0; j < 3; ++j) {
      if (j != k) {
        EXPECT_NEAR(ch[j], 0.0, 1e-12) << k << j;
      }
    }
    EXPECT_GT(ch[k], 0.0);
  }
}

TEST(Colour, SrgbTransferCurve) {
  // IEC 61966-2-1: breakpoints 0.0031308 (linear) <-> 0.04045 (encoded).
  EXPECT_NEAR(srgb_encode(0.0031308), 0.04045, 1e-5);
  // The two published pieces meet only to 3e-8 at the breakpoint.
  EXPECT_NEAR(srgb_encode(0.0031308 * (1 + 1e-12)), srgb_encode(0.0031308), 1e-7);
  EXPECT_DOUBLE_EQ(srgb_encode(1.0), 1.0);
  // 1.055 * 0.5^(1/2.4) - 0.055 = 0.735356983...
  EXPECT_NEAR(srgb_encode(0.5), 0.7353569830524495, 1e-12);
  EXPECT_EQ(srgb_encode(-1.0), 0.0);
  EXPECT_EQ(srgb_encode(std::nan("")), 0.0);
  EXPECT_EQ(srgb_decode(-1.0), 0.0);
  for (double v : {1e-5, 0.002, 0.01, 0.18, 0.5, 0.99, 1.0, 4.0}) {
    EXPECT_NEAR(srgb_decode(srgb_encode(v)), v, 1e-12 * std::max(1.0, v)) << v;
  }
  EXPECT_TRUE(std::isfinite(srgb_encode(1e300)));
}

TEST(Colour, ChromaticityOfBlackIsWhitePointNotNan) {
  const auto c = xy_chromaticity({0.0, 0.0, 0.0});
  EXPECT_EQ(c.x, kD65White.x);
  EXPECT_EQ(c.y, kD65White.y);
}

TEST(Colour, SolarSpectrumMatchesAstmG173AndBlackbody) {
  // Spot values of the ASTM G173-03 extraterrestrial column [W m^-2 nm^-1].
  EXPECT_DOUBLE_EQ(solar_irradiance_toa(500.0), 1.916);
  EXPECT_DOUBLE_EQ(solar_irradiance_toa(393.0), 0.745);  // Ca II K line
  EXPECT_DOUBLE_EQ(solar_irradiance_toa(656.0), 1.3233);  // H-alpha
  EXPECT_DOUBLE_EQ(solar_irradiance_toa(360.0), 1.089);
  EXPECT_DOUBLE_EQ(solar_irradiance_toa(830.0), 1.0563);
  EXPECT_NEAR(solar_irradiance_toa(400.5), 0.5 * (1.6885 + 1.752), 1e-12);
  EXPECT_NEAR(solar_irradiance_toa_mean(400.0, 401.0), 0.5 * (1.6885 + 1.752), 1e-12);
  EXPECT_DOUBLE_EQ(solar_irradiance_toa_mean(450.0, 450.0), 2.069);

  // Band integral versus the Sun as a black body: effective temperature
  // 5772 K and total solar irradiance 1361 W/m^2 (IAU 2015 Resolution B3
  // nominal values). Planck fraction of sigma T^4 in 380-780 nm: 0.46497,
  // in 360-830 nm: 0.52697 (numerical integration of Planck's law), i.e.
  // 632.8 and 717.2 W/m^2. The real spectrum differs from a black body by a few
  // percent in the visible (more blue-green, less near-UV light), so allow 5%.
  const double vis = 400.0 * solar_irradiance_toa_mean(380.0, 780.0);
  const double all = 470.0 * solar_irradiance_toa_mean(360.0, 830.0);
  const double sigma = 5.670374419e-8, teff = 5772.0, tsi = 1361.0;
  auto bb_band = [&](double a, double b) {
    const int n = 4000;
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += planck(a + (i + 0.5) * (b - a) / n, teff);
    return s * (b - a) / n * std::numbers::pi / (sigma * std::pow(teff, 4)) * tsi;
  };
  EXPECT_NEAR(vis / bb_band(380, 780), 1.0, 0.05);
  EXPECT_NEAR(all / bb_band(360, 830), 1.0, 0.05);
  // Visible fraction of the total solar irradiance.
  EXPECT_GT(vis / tsi, 0.44);
  EXPECT_LT(vis / tsi, 0.50);
}

TEST(Colour, SolarSpectrumRejectsOutOfRange) {
  EXPECT_THROW(solar_irradiance_toa(359.9), atmosh::InputError);
  EXPECT_THROW(solar_irradiance_toa(830.1), atmosh::InputError);
  EXPECT_THROW(solar_irradiance_toa(std::nan("")), atmosh::InputError);
  EXPECT_THROW(solar_irradiance_toa_mean(500.0, 400.0), atmosh::InputError);
  EXPECT_THROW(solar_irradiance_toa_mean(300.0, 400.0), atmosh::InputError);
}

TEST(Colour, SpectralToXyzRejectsBadGrids) {
  EXPECT_THROW(SpectralToXyz({}), atmosh::InputError);
  EXPECT_THROW(SpectralToXyz({500.0}, SpectralQuadrature::Midpoint), atmosh::InputError);
  EXPECT_THROW(SpectralToXyz({500.0, 450.0}), atmosh::InputError);
  EXPECT_THROW(SpectralToXyz({500.0, 500.0}), atmosh::InputError);
  EXPECT_THROW(SpectralToXyz({400.0, std::nan("")}), atmosh::InputError);
  const SpectralToXyz conv({400.0, 500.0});
  EXPECT_THROW(conv(std::vector<double>{1.0}), atmosh::InputError);
  // Grids reaching beyond the CMF table are fine (finite weights, no NaN).
  const SpectralToXyz wide({200.0, 300.0, 600.0, 1000.0});
  for (const auto& w : wide.weights()) {
    EXPECT_TRUE(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z));
  }
  EXPECT_EQ(wide.weights()[0].y, 0.0);
}

}  // namespace
