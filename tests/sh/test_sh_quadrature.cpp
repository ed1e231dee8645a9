// Exact image quadrature (Fejér's first rule on pixel-centre rings, Clenshaw–Curtis with
// poles), the solid-angle and pixel-integrated pixel rules, and regular-grid transforms.
// References: integrals of monomials (closed form), images synthesised from known
// coefficients with the independently tested basis (evaluate), closed-form pixel integrals
// of Y_00 and Y_1m, and brute-force tensor Gauss–Legendre integration over each pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <array>
#include <cstdint>
#include <numbers>
#include <random>

#include "atmosh/error.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/projection.hpp"
#include "atmosh/sh/quadrature.hpp"
#include "atmosh/sh/transform.hpp"
#include "transform_impl.hpp"  // private (libsh/src): detail::RealFft

using namespace atmosh::sh;

namespace {
constexpr double kPi = std::numbers::pi;

std::vector<double> random_coeffs(int bands, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd;
  std::vector<double> c(static_cast<std::size_t>(bands) * bands);
  for (auto& v : c) v = nd(rng);
  return c;
}

// Equirect image (double, one channel) of sum_i c_i Y_i at the pixel centres.
std::vector<double> image_of(const std::vector<double>& c, int bands, int W, int H) {
  std::vector<double> img(static_cast<std::size_t>(W) * H);
  std::vector<double> y(sh_count(bands));
  for (int r = 0; r < H; ++r)
    for (int j = 0; j < W; ++j) {
      evaluate_angles(bands, kPi * (r + 0.5) / H, 2 * kPi * (j + 0.5) / W, y.data());
      double v = 0;
      for (int i = 0; i < sh_count(bands); ++i) v += c[i] * y[i];
      img[static_cast<std::size_t>(r) * W + j] = v;
    }
  return img;
}
}  // namespace

TEST(Quadrature, FejerAndClenshawCurtisIntegrateMonomials) {
  // integral_{-1}^{1} x^k dx = 2/(k+1) for even k, 0 for odd k.
  for (int n : {1, 2, 3, 4, 7, 8, 16, 33, 64, 257}) {
    const auto wf = fejer1_weights(n);
    const int dmax_f = n % 2 ? n : n - 1;
    for (int k = 0; k <= dmax_f + 2; ++k) {
      double s = 0;
      for (int j = 0; j < n; ++j) s += wf[j] * std::pow(std::cos(kPi * (j + 0.5) / n), k);
      const double exact = k % 2 ? 0.0 : 2.0 / (k + 1);
      if (k <= dmax_f) {
        EXPECT_NEAR(s, exact, 4e-15 * n) << "fejer n=" << n << " k=" << k;
      } else if (k % 2 == 0 && n <= 16) {
        EXPECT_GT(std::abs(s - exact), 1e-9) << "degree bound is sharp: fejer n=" << n << " k=" << k;
      }
    }
    for (double w : wf) EXPECT_GT(w, 0.0);
    if (n < 2) continue;
    const auto wc = clenshaw_curtis_weights(n);
    const int N = n - 1, dmax_c = N % 2 ? N : N + 1;
    for (int k = 0; k <= dmax_c + 2; ++k) {
      double s = 0;
      for (int j = 0; j < n; ++j) s += wc[j] * std::pow(std::cos(kPi * j / N), k);
      const double exact = k % 2 ? 0.0 : 2.0 / (k + 1);
      if (k <= dmax_c) {
        EXPECT_NEAR(s, exact, 4e-15 * n) << "cc n=" << n << " k=" << k;
      } else if (k % 2 == 0 && n <= 16) {
        EXPECT_GT(std::abs(s - exact), 1e-9) << "degree bound is sharp: cc n=" << n << " k=" << k;
      }
    }
    for (double w : wc) EXPECT_GT(w, 0.0);
  }
  EXPECT_THROW(fejer1_weights(0), atmosh::InputError);
  EXPECT_THROW(clenshaw_curtis_weights(1), atmosh::InputError);
}

TEST(Projection, EquirectExactForBandLimitedImages) {
  // Sizes incl. odd widths and heights; B = the largest band count with 2B-1 <= H and
  // 2B-1 <= W, for which every coefficient must be exact.
  const int sizes[][2] = {{64, 32}, {63, 32}, {33, 17}, {31, 16}, {7, 4}, {128, 64}, {45, 40}};
  for (const auto& s : sizes) {
    const int W = s[0], H = s[1];
    const int B = std::min((H + 1) / 2, (W + 1) / 2);
    // constant
    std::vector<double> one(static_cast<std::size_t>(W) * H, 1.0);
    const auto c1 = project_equirect(ImageViewD{W, H, 1, one.data()}, B)[0];
    EXPECT_NEAR(c1[0], std::sqrt(4 * kPi), 1e-12) << W << "x" << H;
    for (int i = 1; i < sh_count(B); ++i) EXPECT_NEAR(c1[i], 0.0, 1e-12) << W << "x" << H << " i=" << i;
    // single Y_lm (highest band, a sectoral and a tesseral one)
    for (const auto& lm : {std::pair{B - 1, 0}, std::pair{B - 1, B - 1}, std::pair{B - 1, -(B - 1)},
                           std::pair{B / 2, -1}}) {
      if (std::abs(lm.second) > lm.first) continue;
      std::vector<double> c(sh_count(B), 0.0);
      c[sh_index(lm.first, lm.second)] = 1.0;
      const auto img = image_of(c, B, W, H);
      const auto p = project_equirect(ImageViewD{W, H, 1, img.data()}, B)[0];
      for (int i = 0; i < sh_count(B); ++i)
        EXPECT_NEAR(p[i], c[i], 1e-12) << W << "x" << H << " Y" << lm.first << "," << lm.second << " i=" << i;
    }
    // random band-limited sums
    for (std::uint64_t seed : {1u, 2u}) {
      const auto c = random_coeffs(B, seed + W);
      const auto img = image_of(c, B, W, H);
      const auto p = project_equirect(ImageViewD{W, H, 1, img.data()}, B, 2)[0];
      for (int i = 0; i < sh_count(B); ++i) EXPECT_NEAR(p[i], c[i], 1e-12) << W << "x" << H << " i=" << i;
    }
  }
  // The condition is sharp: with H even, a function of B + 1 = H/2 + 1 bands aliases.
  {
    const int W = 64, H = 32, B = H / 2 + 1;
    std::vector<double> c(sh_count(B), 0.0);
    c[sh_index(B - 1, 0)] = 1.0;
    const auto img = image_of(c, B, W, H);
    const auto p = project_equirect(ImageViewD{W, H, 1, img.data()}, B)[0];
    EXPECT_GT(std::abs(p[sh_index(B - 1, 0)] - 1.0), 1e-6);
  }
}

TEST(Projection, EquirectFloatImagesExactToFloatRounding) {
  // The float image path: errors are those of rounding the pixels to float (~6e-8 relative).
  const int W = 64, H = 32, B = 8;
  const auto c = random_coeffs(B, 5);
  const auto img = image_of(c, B, W, H);
  std::vector<float> f(img.begin(), img.end());
  const auto p = project_equirect(ImageView{W, H, 1, f.data()}, B)[0];
  for (int i = 0; i < sh_count(B); ++i) EXPECT_NEAR(p[i], c[i], 2e-6) << i;
}

TEST(Projection, SolidAngleRuleIsSecondOrder) {
  // Regression property of the solid-angle weighting (pixel-centre values times the exact
  // pixel solid angle): a constant 64 x 32 map leaks ~5e-3 into c_60; the leak falls as
  // H^-2. The exact rule gives 0 on the same pixels.
  auto leak = [](int W, int H, PixelRule rule) {
    std::vector<float> one(static_cast<std::size_t>(W) * H, 1.0f);
    return project_equirect(ImageView{W, H, 1, one.data()}, 8, 1, rule)[0][sh_index(6, 0)];
  };
  const double l32 = leak(64, 32, PixelRule::solid_angle), l64 = leak(128, 64, PixelRule::solid_angle);
  EXPECT_GT(std::abs(l32), 4e-3);
  EXPECT_LT(std::abs(l32), 6e-3);
  EXPECT_NEAR(l32 / l64, 4.0, 0.2);
  EXPECT_NEAR(leak(64, 32, PixelRule::exact), 0.0, 1e-13);
  // band-limited L = 8 image: off by ~8e-3 at 64 x 32 with solid angles, exact with Fejér.
  const auto c = random_coeffs(8, 9);
  const auto img = image_of(c, 8, 64, 32);
  const auto ps = project_equirect(ImageViewD{64, 32, 1, img.data()}, 8, 1, PixelRule::solid_angle)[0];
  const auto pe = project_equirect(ImageViewD{64, 32, 1, img.data()}, 8, 1, PixelRule::exact)[0];
  double es = 0, ee = 0;
  for (int i = 0; i < 64; ++i) {
    es = std::max(es, std::abs(ps[i] - c[i]));
    ee = std::max(ee, std::abs(pe[i] - c[i]));
  }
  EXPECT_GT(es, 1e-3);
  EXPECT_LT(ee, 1e-12);
}

TEST(Projection, PixelIntegratedMatchesClosedFormsAndBruteForce) {
  // One lit pixel: its coefficients are the integrals of Y_lm over the pixel.
  const int W = 24, H = 12;
  const int row = 3, col = 5;
  std::vector<double> img(static_cast<std::size_t>(W) * H, 0.0);
  img[static_cast<std::size_t>(row) * W + col] = 1.0;
  const int L = 12;
  const auto p = project_equirect(ImageViewD{W, H, 1, img.data()}, L, 1, PixelRule::pixel_integrated)[0];
  const double t0 = kPi * row / H, t1 = kPi * (row + 1) / H;
  const double p0 = 2 * kPi * col / W, p1 = 2 * kPi * (col + 1) / W;
  const double k1 = std::sqrt(3 / (4 * kPi));
  const double sin2 = (t1 - t0) / 2 - (std::sin(2 * t1) - std::sin(2 * t0)) / 4;  // int sin^2 t dt
  EXPECT_NEAR(p[0], (p1 - p0) * (std::cos(t0) - std::cos(t1)) / std::sqrt(4 * kPi), 1e-15);
  EXPECT_NEAR(p[sh_index(1, 0)], k1 * (p1 - p0) * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) / 2,
              1e-15);
  EXPECT_NEAR(p[sh_index(1, 1)], -k1 * (std::sin(p1) - std::sin(p0)) * sin2, 1e-15);
  EXPECT_NEAR(p[sh_index(1, -1)], -k1 * (std::cos(p0) - std::cos(p1)) * sin2, 1e-15);
  // brute force: 16 x 16 Gauss–Legendre in (t, p) over every pixel of a random image
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  for (auto& v : img) v = U(rng);
  const auto pr = project_equirect(ImageViewD{W, H, 1, img.data()}, L, 1, PixelRule::pixel_integrated)[0];
  const GaussLegendre g = gauss_legendre(16);
  std::vector<double> ref(sh_count(L), 0.0), y(sh_count(L));
  for (int r = 0; r < H; ++r)
    for (int q = 0; q < W; ++q) {
      const double v = img[static_cast<std::size_t>(r) * W + q];
      for (int a = 0; a < 16; ++a)
        for (int b = 0; b < 16; ++b) {
          const double t = kPi / H * (r + 0.5 + 0.5 * g.nodes[a]), ph = 2 * kPi / W * (q + 0.5 + 0.5 * g.nodes[b]);
          evaluate_angles(L, t, ph, y.data());
          const double w = v * 0.25 * g.weights[a] * g.weights[b] * (kPi / H) * (2 * kPi / W) * std::sin(t);
          for (int i = 0; i < sh_count(L); ++i) ref[i] += w * y[i];
        }
    }
  for (int i = 0; i < sh_count(L); ++i) EXPECT_NEAR(pr[i], ref[i], 1e-13) << i;
  // a constant image is a constant function: exactly sqrt(4 pi) Y_00
  std::vector<double> one(static_cast<std::size_t>(W) * H, 1.0);
  const auto c1 = project_equirect(ImageViewD{W, H, 1, one.data()}, L, 1, PixelRule::pixel_integrated)[0];
  EXPECT_NEAR(c1[0], std::sqrt(4 * kPi), 1e-13);
  for (int i = 1; i < sh_count(L); ++i) EXPECT_NEAR(c1[i], 0.0, 1e-13) << i;
}

TEST(Projection, MethodsParseAndApplyToImagesOnly) {
  EXPECT_EQ(parse_method("solid-angle"), Method::solid_angle);
  EXPECT_EQ(parse_method("pixel-integrated"), Method::pixel_integrated);
  EXPECT_THROW(parse_method("solid_angle"), atmosh::InputError);
  ProjectOptions o;
  o.method = Method::solid_angle;
  EXPECT_THROW(project_function([](const glm::dvec3&) { return 1.0; }, 2, o), atmosh::InputError);
  CubeMap cube;
  cube.size = 2;
  cube.channels = 1;
  for (auto& f : cube.faces) f.assign(4, 1.0f);
  o.method = Method::pixel_integrated;
  EXPECT_THROW(project_cube_sampled(cube, 2, o), atmosh::InputError);
  // the image entry point used by the CLI dispatches the pixel rules
  std::vector<float> img(16 * 8);
  for (std::size_t i = 0; i < img.size(); ++i) img[i] = static_cast<float>(std::sin(0.37 * i));
  const ImageView v{16, 8, 1, img.data()};
  for (auto [m, r] : {std::pair{Method::solid_angle, PixelRule::solid_angle},
                      std::pair{Method::pixel_integrated, PixelRule::pixel_integrated}}) {
    o.method = m;
    EXPECT_EQ(project_equirect_sampled(v, 3, o)[0], project_equirect(v, 3, 1, r)[0]);
  }
}

TEST(Projection, CubeSolidAngleRuleIsSecondOrder) {
  // Cube maps: texel-centre values times the exact texel solid angle. For a band-limited
  // image (here Y_20 + Y_43) the coefficient error falls as N^-2 — it is not exact.
  std::vector<double> c(25, 0.0);
  c[sh_index(2, 0)] = 1.0;
  c[sh_index(4, 3)] = 0.5;
  auto err = [&](int N) {
    CubeMap cube;
    cube.size = N;
    cube.channels = 1;
    std::vector<double> y(25);
    for (int f = 0; f < 6; ++f) {
      cube.faces[f].resize(static_cast<std::size_t>(N) * N);
      for (int r = 0; r < N; ++r)
        for (int q = 0; q < N; ++q) {
          evaluate(5, cube_texel_direction(f, q, r, N), y.data());
          double v = 0;
          for (int i = 0; i < 25; ++i) v += c[i] * y[i];
          cube.faces[f][static_cast<std::size_t>(r) * N + q] = static_cast<float>(v);
        }
    }
    const auto p = project_cube(cube, 5)[0];
    double e = 0;
    for (int i = 0; i < 25; ++i) e = std::max(e, std::abs(p[i] - c[i]));
    return e;
  };
  const double e16 = err(16), e32 = err(32);
  EXPECT_GT(e16, 1e-4);
  EXPECT_NEAR(e16 / e32, 4.0, 0.6);
}

TEST(Transform, RegularGridsAreExact) {
  // Fejér (pixel-centre rings) and Clenshaw–Curtis (poles included) grids, odd and even
  // nlat and nphi: analysis of a band-limited function reproduces its coefficients, and
  // synthesis agrees with the basis.
  for (auto rule : {LatitudeRule::fejer, LatitudeRule::clenshaw_curtis}) {
    for (const auto& s : {std::array<int, 3>{16, 31, 31}, std::array<int, 3>{16, 32, 33}, std::array<int, 3>{33, 65, 67},
                          std::array<int, 3>{1, 2, 1}, std::array<int, 3>{5, 9, 16}}) {
      const int L = s[0];
      const GaussGrid g = regular_grid(L, rule, s[1], s[2]);
      const auto c = random_coeffs(L, 11 + L);
      const auto v = synthesise(g, c.data());
      std::vector<double> y(sh_count(L));
      for (int i = 0; i < g.nlat; i += 3)
        for (int j = 0; j < g.nphi; j += 5) {
          evaluate_angles(L, std::atan2(g.sin_t[i], g.cos_t[i]), g.phi(j), y.data());
          double ref = 0;
          for (int k = 0; k < sh_count(L); ++k) ref += c[k] * y[k];
          EXPECT_NEAR(v[static_cast<std::size_t>(i) * g.nphi + j], ref, 1e-12 * L);
        }
      const auto a = analyse(g, v.data());
      for (int k = 0; k < sh_count(L); ++k) EXPECT_NEAR(a[k], c[k], 1e-12) << "L=" << L << " k=" << k;
    }
  }
  EXPECT_THROW(regular_grid(16, LatitudeRule::fejer, 30), atmosh::InputError);
  EXPECT_THROW(regular_grid(16, LatitudeRule::gauss), atmosh::InputError);
}

TEST(Transform, RealFftMatchesDirectSums) {
  // RealFft (FFTW3) against the direct sums, at power-of-two, odd, prime and composite sizes,
  // including orders above n/2 (aliases) forward and the largest allowed count inverse.
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int n : {1, 2, 3, 7, 16, 17, 89, 96, 511}) {
    detail::RealFft fft(n);
    std::vector<double> f(n);
    for (auto& v : f) v = U(rng);
    const int count = n + 3;
    std::vector<double> out(2 * count);
    fft.forward(f.data(), count, out.data());
    for (int m = 0; m < count; ++m) {
      long double a = 0, b = 0;
      for (int j = 0; j < n; ++j) {
        const long double p = 2.0L * std::numbers::pi_v<long double> * ((static_cast<long long>(m) * j) % n) / n;
        a += f[j] * std::cos(p);
        b += f[j] * std::sin(p);
      }
      EXPECT_NEAR(out[2 * m], static_cast<double>(a), 1e-13 * n) << n << " " << m;
      EXPECT_NEAR(out[2 * m + 1], static_cast<double>(b), 1e-13 * n) << n << " " << m;
    }
    const int cmax = (n + 1) / 2;
    std::vector<double> cs(2 * cmax), v(n);
    for (auto& x : cs) x = U(rng);
    fft.inverse(cs.data(), cmax, v.data());
    for (int j = 0; j < n; ++j) {
      long double s = 0;
      for (int m = 0; m < cmax; ++m) {
        const long double p = 2.0L * std::numbers::pi_v<long double> * ((static_cast<long long>(m) * j) % n) / n;
        s += cs[2 * m] * std::cos(p) + (m > 0 ? cs[2 * m + 1] * std::sin(p) : 0.0L);
      }
      EXPECT_NEAR(v[j], static_cast<double>(s), 1e-13 * n) << n << " " << j;
    }
    if (n > 1) {
      EXPECT_THROW(fft.inverse(cs.data(), cmax + 1, v.data()), atmosh::InputError);
    }
  }
}

namespace {
double round_trip_error(const GaussGrid& g, std::uint64_t seed, int threads) {
  const int L = g.bands;
  const auto c = random_coeffs(L, seed);
  const auto f = synthesise(g, c.data(), threads);
  const auto c2 = analyse(g, f.data(), threads);
  double e = 0, scale = 0;
  for (int i = 0; i < L * L; ++i) e = std::max(e, std::abs(c2[i] - c[i])), scale = std::max(scale, std::abs(c[i]));
  return e / scale;
}
}  // namespace

TEST(Transform, RoundTripsWithOddNphiOnGaussAndRegularGrids) {
  const int L = 256;
  EXPECT_LT(round_trip_error(gauss_grid(L, 0, 511), 1, 1), 1e-12);   // nphi = 2L - 1 (odd)
  EXPECT_LT(round_trip_error(gauss_grid(L, 257, 769), 2, 2), 1e-12);
  EXPECT_LT(round_trip_error(regular_grid(L, LatitudeRule::fejer, 511, 513), 3, 2), 1e-12);
  EXPECT_LT(round_trip_error(regular_grid(L, LatitudeRule::clenshaw_curtis, 513, 511), 4, 2), 1e-12);
}

#if !defined(__SANITIZE_ADDRESS__) && !defined(__has_feature)
#define ATMOSH_FULL_SPEED 1
#elif defined(__has_feature)
#if !__has_feature(address_sanitizer)
#define ATMOSH_FULL_SPEED 1
#endif
#endif

TEST(Transform, RoundTripAtL1024WithOddNphi) {
#ifdef ATMOSH_FULL_SPEED
  EXPECT_LT(round_trip_error(gauss_grid(1024, 0, 2047), 5, 2), 1e-12);
#else
  GTEST_SKIP() << "L = 1024 round trip runs in the optimised build only";
#endif
}

TEST(Projection, RenderEquirectMatchesReconstruct) {
  // render_equirect (real FFT when 2L - 1 <= W, direct sums otherwise) against reconstruct()
  // at the pixel centres; rendering then projecting with the exact rule returns the
  // coefficients to float rounding.
  for (const auto& s : {std::array<int, 3>{12, 64, 32}, std::array<int, 3>{12, 23, 24}, std::array<int, 3>{12, 25, 23}, std::array<int, 3>{12, 15, 9}}) {
    const int L = s[0], W = s[1], H = s[2];
    const auto c = random_coeffs(L, 21 + W);
    const auto img = render_equirect(c, L, W, H);
    for (int r = 0; r < H; r += 3)
      for (int j = 0; j < W; j += 2) {
        const double ref = reconstruct(L, c.data(), direction_from_angles(kPi * (r + 0.5) / H, 2 * kPi * (j + 0.5) / W));
        EXPECT_NEAR(img[static_cast<std::size_t>(r) * W + j], ref, 2e-6 * (1 + std::abs(ref))) << W << " " << r << " " << j;
      }
    if (2 * L - 1 <= W && 2 * L - 1 <= H) {
      const auto p = project_equirect(ImageView{W, H, 1, img.data()}, L)[0];
      for (int i = 0; i < L * L; ++i) EXPECT_NEAR(p[i], c[i], 1e-5) << i;
    }
  }
}

TEST(Projection, CubeExactRuleExistsOnlyBelowABandLimit) {
  // Does any weighting of the 6 N^2 texel centres integrate every product of band-limited
  // functions (all Y_k with k < (2B-1)^2) exactly? Equivalent: b = sqrt(4 pi) e_0 lies in the
  // span of the texel columns (Y_k(x_i))_k. Measured by Gram–Schmidt (twice) on the columns.
  auto residual = [](int N, int B) {
    const int Lq = 2 * B - 1, K = Lq * Lq;
    std::vector<std::vector<double>> Q;
    std::vector<double> y(K);
    for (int f = 0; f < 6; ++f)
      for (int r = 0; r < N; ++r)
        for (int q = 0; q < N; ++q) {
          evaluate(Lq, cube_texel_direction(f, q, r, N), y.data());
          std::vector<double> v(y);
          double n0 = 0;
          for (double x : v) n0 += x * x;
          for (int pass = 0; pass < 2; ++pass)
            for (const auto& u : Q) {
              double d = 0;
              for (int k = 0; k < K; ++k) d += u[k] * v[k];
              for (int k = 0; k < K; ++k) v[k] -= d * u[k];
            }
          double nv = 0;
          for (double x : v) nv += x * x;
          if (nv > 1e-18 * n0) {
            for (double& x : v) x /= std::sqrt(nv);
            Q.push_back(v);
          }
        }
    std::vector<double> b(K, 0.0);
    b[0] = 1.0;
    for (int pass = 0; pass < 2; ++pass)
      for (const auto& u : Q) {
        double d = 0;
        for (int k = 0; k < K; ++k) d += u[k] * b[k];
        for (int k = 0; k < K; ++k) b[k] -= d * u[k];
      }
    double r2 = 0;
    for (double x : b) r2 += x * x;
    return std::sqrt(r2);
  };
  // N = 4 (96 texels): a rule exact for band limit 4 exists, none for 5; N = 8 (384
  // texels): up to 9, none for 10 — about (2B - 1)^2 <= 6 N^2. The texel solid angles
  // are not such a rule (CubeSolidAngleRuleIsSecondOrder).
  EXPECT_LT(residual(4, 4), 1e-12);
  EXPECT_GT(residual(4, 5), 1e-3);
  EXPECT_LT(residual(8, 9), 1e-12);
  EXPECT_GT(residual(8, 10), 1e-3);
}
