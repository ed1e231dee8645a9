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
// Method: per ring a real FFT in p (FFTW3, any nphi, plans made once per size; powers of
// two take two rings per split-format complex FFT, sizes with a prime factor above 5 two
// rings per complex FFT, and above 13 Bluestein's chirp convolution through power-of-two
// FFTs: one thread, L = 256, analysis at nphi = 525 and 768 in ~1.3x the time at 512, at
// 511 in ~1.8x (SHTns: ~3.3x); GaussGrid::fft = FftPlanning::measure takes 768 to ~1.1x,
// docs/sh.md), then the
// Legendre sums, m outer, vectorised over
// blocks of ring pairs and using the equatorial symmetry Pbar_lm(-x) = (-1)^(l+m)
// Pbar_lm(x). Analysis recurs only the degrees of the parity of m, in x^2 (two FMAs per
// ring pair for two degrees), and gets the other parity from sums of x times the odd ring
// sums by a forward substitution; synthesis runs the same recurrence, with the odd degrees
// through a backward substitution (the transpose), on blocks of 8 (AVX-512) or 4 (AVX2)
// ring pairs (transform.cpp). Work is split over m between `threads` threads (0 = all
// hardware threads). FFTW's planner is not thread safe: plans are made under a lock held
// by libsh only — other code in the process that plans FFTW transforms concurrently must
// not race with the first transform of a new nphi. At exit libsh destroys its own plans
// and nothing else (no fftw_cleanup(): FFTW plans held by other code stay valid).
//
// Accuracy: analysis of synthesis reproduces coefficients to ~3e-13 relative at
// L = 1024; synthesised values are within ~1e-12 of max |f| at L = 1024 (1.3e-13 at
// L = 256) of a long-double reference (docs/sh.md). Units: coefficients carry the units of the
// samples times sr^(1/2) (integral f Y dOmega).
#pragma once

#include <memory>
#include <vector>

namespace atmosh::sh {

namespace detail {
struct GridPlan;
}

/// Rule in latitude of a grid: Gauss–Legendre nodes, equiangular pixel-centre rings
/// t_i = (i + 1/2) pi / nlat with Fejér's first rule, or equiangular rings with both poles
/// t_i = i pi / (nlat - 1) with the Clenshaw–Curtis rule (quadrature.hpp).
enum class LatitudeRule { gauss, fejer, clenshaw_curtis };

/// How the FFTs in longitude are planned (FFTW3).
/// estimate (default): the method and FFTW's plans follow from nphi alone (FFTW_ESTIMATE, made
///   with the process's FFTW wisdom set aside, since FFTW_ESTIMATE plans follow wisdom), so
///   the same input gives the same bits in every run.
/// measure: FFTW chooses its plans by timing candidates (FFTW_MEASURE) at the first transform
///   of each nphi in the process (0.2-1 s at nphi = 512 ... 3072, once; kept to exit).
///   Faster for some sizes other than powers of two (one thread, L = 256, Zen 5: nphi = 768
///   12 % less time per analysis and synthesis, 511 3-5 %, 512 1-2 %), but the chosen plans,
///   and so the last bits of the results (~1e-16 relative), may differ between runs and
///   machines. Within one process every transform of a size uses the same plans. The wisdom
///   FFTW_MEASURE records is dropped again (the process's FFTW wisdom is put back as it
///   was), so other code's FFTW_ESTIMATE plans do not follow it.
/// Both set the process's FFTW wisdom aside and put it back while libsh plans (under libsh's
/// lock, see below): other code must not plan FFTW transforms, or use wisdom, concurrently
/// with the first transform of a new nphi.
enum class FftPlanning { estimate, measure };

struct GaussGrid {
  int bands = 0;
  LatitudeRule rule = LatitudeRule::gauss;
  int nlat = 0;
  int nphi = 0;
  std::vector<double> cos_t;    ///< per ring, descending (ring 0 nearest +z)
  std::vector<double> sin_t;    ///< per ring, >= 0
  std::vector<double> weights;  ///< Gauss–Legendre weight per ring (sum 2)
  double phi(int j) const;      ///< longitude of column j, radians
  /// Set-up of the transforms made once with the grid by gauss_grid / regular_grid and shared
  /// by copies (ring pairs, sectoral start values of every order and ring, and the polar
  /// starts of every order, found by the first transform that needs them):
  /// used only while it matches the fields above (compared on every call), otherwise made
  /// again per call.
  std::shared_ptr<const detail::GridPlan> plan;
  FftPlanning fft = FftPlanning::estimate;  ///< planning of the FFTs in longitude (above)
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
/// The same into caller-provided arrays (bands^2 coefficients / nlat*nphi samples; every
/// value written, none read, so the array need not be initialised; it must not overlap the
/// input). The result is neither allocated nor cleared (the large work arrays are kept per
/// calling thread; each worker's scratch arrays, ~0.4 L kB, are still made per call).
/// Same results, bit for bit, as the forms above.
void analyse(const GaussGrid& grid, const double* values, double* coeffs, int threads = 1);
void synthesise(const GaussGrid& grid, const double* coeffs, double* values, int threads = 1);

}  // namespace atmosh::sh
