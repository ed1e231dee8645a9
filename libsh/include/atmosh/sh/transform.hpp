// atmosh/sh/transform.hpp — exact SH analysis and synthesis on a Gauss–Legendre grid.
//
// Grid (gauss_grid): nlat rings at the Gauss–Legendre nodes cos t_i (t from +z, ring 0 nearest +z,
// i.e. descending cos t) times nphi equally spaced longitudes p_j = 2 pi j / nphi
// (p from +x towards +y). Sample layout: values[i * nphi + j].
// Default size for L bands: nlat = L, nphi = the smallest power of two >= 2L - 1.
// Analysis is exact (to rounding) for band-limited functions of L bands whenever
// nlat >= L and nphi >= 2L - 1 (the Gauss rule integrates the degree <= 2L-2 products
// in cos t; the uniform rule the trigonometric ones in p).
//
// Method: per ring a real FFT in p (FFTW3, any nphi, plans made once per size), then the
// Legendre sums, m outer, vectorised over
// blocks of ring pairs and using the equatorial symmetry Pbar_lm(-x) = (-1)^(l+m)
// Pbar_lm(x). Analysis recurs only the degrees of the parity of m, in x^2 (two FMAs per
// ring pair for two degrees), and gets the other parity from sums of x times the odd ring
// sums by a forward substitution; synthesis runs the same recurrence, with the odd degrees
// through a backward substitution (the transpose), on blocks of 8 (AVX-512) or 4 (AVX2)
// ring pairs (transform.cpp). Work is split over m between `threads` threads (0 = all
// hardware threads). FFTW's planner is not thread safe: plans are made under a lock held
// by libsh only — other code in the process that plans FFTW transforms concurrently must
// not race with the first transform of a new nphi. At exit libsh destroys its plans and
// calls fftw_cleanup() (no leak reports).
//
// Accuracy: analysis of synthesis reproduces coefficients to ~3e-13 relative at
// L = 1024; synthesised values are within ~1e-12 of max |f| at L = 1024 (1.3e-13 at
// L = 256) of a long-double reference (docs/sh.md). Units: coefficients carry the units of the
// samples times sr^(1/2) (integral f Y dOmega).
#pragma once

#include <vector>

namespace atmosh::sh {

/// Rule in latitude of a grid: Gauss–Legendre nodes, equiangular pixel-centre rings
/// t_i = (i + 1/2) pi / nlat with Fejér's first rule, or equiangular rings with both poles
/// t_i = i pi / (nlat - 1) with the Clenshaw–Curtis rule (quadrature.hpp).
enum class LatitudeRule { gauss, fejer, clenshaw_curtis };

struct GaussGrid {
  int bands = 0;
  LatitudeRule rule = LatitudeRule::gauss;
  int nlat = 0;
  int nphi = 0;
  std::vector<double> cos_t;    ///< per ring, descending (ring 0 nearest +z)
  std::vector<double> sin_t;    ///< per ring, >= 0
  std::vector<double> weights;  ///< Gauss–Legendre weight per ring (sum 2)
  double phi(int j) const;      ///< longitude of column j, radians
};

/// Grid for `bands` bands; nlat = 0 / nphi = 0 pick the defaults above.
/// Throws InputError for bands < 1 or a grid too small to be exact (nlat < bands or
/// nphi < 2*bands-1).
GaussGrid gauss_grid(int bands, int nlat = 0, int nphi = 0);

/// Equiangular ("regular", Driscoll–Healy type) grid: rule fejer (rings at the pixel centres
/// t_i = (i + 1/2) pi / nlat, no pole) or clenshaw_curtis (t_i = i pi / (nlat - 1), both poles).
/// The products Pbar_lm Pbar_l'm of a band-limited function's analysis are polynomials of
/// degree <= 2L - 2 in cos t, so both rules are exact when nlat >= 2L - 1 (and nphi >= 2L - 1);
/// default nlat = 2L, nphi as for gauss_grid. Throws InputError for smaller grids or for
/// rule = gauss (use gauss_grid).
GaussGrid regular_grid(int bands, LatitudeRule rule, int nlat = 0, int nphi = 0);

/// Coefficients (bands^2) of samples on the grid (size nlat*nphi).
std::vector<double> analyse(const GaussGrid& grid, const double* values, int threads = 1);
/// Samples (nlat*nphi) of a coefficient vector (bands^2) on the grid.
std::vector<double> synthesise(const GaussGrid& grid, const double* coeffs, int threads = 1);

namespace detail {
/// Ring-wise Legendre analysis shared by grids and equirect images.
/// Rings: cos_t[r], sin_t[r]; fourier[(r * bands + m) * 2 + {0,1}] holds the already
/// weighted ring sums for Y_lm (cos part) and Y_l-m (sin part); coefficients accumulate
/// into coeffs (bands^2). Rings r and nrings-1-r must be mirror images when
/// `symmetric` (cos_t[r] = -cos_t[nrings-1-r]).
void legendre_analysis(int bands, int nrings, const double* cos_t, const double* sin_t,
                       const double* fourier, bool symmetric, double* coeffs, int threads);
/// Inverse: fourier[(r * bands + m) * 2 + {0,1}] = sum_l c_l,+-m Pbar_lm(x_r) (times sqrt2 for m>0).
void legendre_synthesis(int bands, int nrings, const double* cos_t, const double* sin_t,
                        const double* coeffs, bool symmetric, double* fourier, int threads);
/// In-place complex FFT of size n (power of two), sign -1 forward, +1 inverse (unscaled).
void fft(double* re, double* im, int n, int sign);
/// Real FFT of any size n >= 1 through FFTW3. The plans are made once per size (FFTW's
/// planner is not thread safe: under a process-wide lock) with FFTW_ESTIMATE, so the same
/// input gives the same bits from run to run; executing them is thread safe. Each object
/// owns aligned work arrays: one per thread.
class RealFft {
 public:
  explicit RealFft(int n);
  ~RealFft();
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;
  int size() const { return n_; }
  /// a_m = sum_j f_j cos(2 pi j m / n), b_m = sum_j f_j sin(2 pi j m / n) into out[2m],
  /// out[2m+1] for m < count (any count: orders above n/2 are the aliases).
  template <class T>
  void forward(const T* f, int count, double* out);
  /// v_j = sum_{m < count} (C_m cos(2 pi j m / n) + S_m sin(2 pi j m / n)) from cs[2m], cs[2m+1];
  /// needs 2 count - 1 <= n.
  void inverse(const double* cs, int count, double* v);

 private:
  int n_;
  const void* plans_;  // the shared plans of size n
  double* real_;       // n values (FFTW-aligned)
  double* spec_;       // n/2 + 1 complex values
};
}  // namespace detail

}  // namespace atmosh::sh
