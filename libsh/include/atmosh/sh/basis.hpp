// atmosh/sh/basis.hpp — real spherical harmonics of any band.
//
// Convention (the whole library uses it):
//   * real, orthonormal on the unit sphere: integral Y_i Y_j dOmega = delta_ij;
//   * Condon–Shortley phase included: Y_11 = -sqrt(3/(4 pi)) x, Y_1-1 = -sqrt(3/(4 pi)) y,
//     Y_10 = sqrt(3/(4 pi)) z;
//   * Y_lm = Pbar_lm(cos t) * { 1 (m = 0), sqrt2 cos(m p) (m > 0), sqrt2 sin(|m| p) (m < 0) }
//     where t is measured from +z and p from +x towards +y, and Pbar_lm is the
//     associated Legendre function (with the (-1)^m phase) normalised so that
//     integral Pbar_lm^2 dmu = 1 / (2 pi);
//   * linear index i = l(l+1) + m; "L bands" means l = 0..L-1 (L^2 coefficients).
//
// Method: Pbar_lm by the scaled "forward column" recurrences (Holmes & Featherstone
// 2002, J. Geodesy 76:279): sectoral terms Pbar_mm = -sqrt((2m+1)/(2m)) sin(t) Pbar_m-1,m-1
// carried as an extended-range number (mantissa, power-of-two exponent, as in
// Fukushima 2012's X-numbers), then Pbar_lm = a_lm cos(t) Pbar_l-1,m - b_lm Pbar_l-2,m
// along each column. No factorials. Values too small for a double (< ~1e-308, e.g.
// high m at a direction within 1e-3 rad of a pole) come out as exact zeros or
// subnormals; nothing overflows.
// Accuracy: relative error ~ 1e-16 * l for the values that matter (|Y| > 1e-30 of the
// band's scale); tested to L = 2800 (orthonormality by exact quadrature <= 1e-12).
// Cost: about 3 flops per (l, m) plus a cos/sin recurrence in m. For bands <= 8, evaluate()
// and reconstruct() run the straight-line code of fast.hpp (same values to ~1e-15). For 10 <= bands <= 128,
// evaluate() runs the same recurrence row by row (all m of a band at once, vectorised, no
// allocation or lock per call; an AVX2/FMA clone is picked at run time with GCC on x86-64);
// directions where sin^(bands-1) t < ~1e-240 (near a pole) and other band counts use the
// column path.
//
// Directions need not be normalised (they are normalised here, at any finite length,
// 1e-300 or 1e300 included); a zero, NaN or infinite direction throws atmosh::InputError. Units: dimensionless (1/sr^(1/2)).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

namespace atmosh::sh {

/// Linear index of (l, m): l(l+1) + m.
constexpr int sh_index(int l, int m) { return l * (l + 1) + m; }
/// Number of coefficients for L bands: L^2.
constexpr int sh_count(int bands) { return bands * bands; }
/// Index into a triangular (l, m >= 0) array: l(l+1)/2 + m.
constexpr std::size_t tri_index(int l, int m) {
  return static_cast<std::size_t>(l) * (l + 1) / 2 + m;
}

/// Throws InputError unless 1 <= bands <= max_bands (default 65536).
void check_bands(int bands, const char* where, int max_bands = 65536);

/// Normalised unit direction; throws InputError for zero/NaN/Inf components.
glm::dvec3 checked_direction(const glm::dvec3& dir, const char* where);

/// Recurrence coefficients a_lm, b_lm of the column recurrence (index tri_index(l,m)),
/// and the sectoral factors. Immutable; shared between threads.
class LegendreTable {
 public:
  explicit LegendreTable(int bands);
  int bands() const { return bands_; }
  const double* a() const { return a_.data(); }
  const double* b() const { return b_.data(); }
  /// sqrt((2m+1)/(2m)) for m >= 1 (index m), 0 at m = 0.
  const double* sectoral() const { return s_.data(); }

 private:
  int bands_;
  std::vector<double> a_, b_, s_;
};

/// A cached table with at least `bands` bands (thread safe).
std::shared_ptr<const LegendreTable> legendre_table(int bands);

/// Pbar_lm(cos t) for l < bands, 0 <= m <= l, written at out[tri_index(l, m)]
/// (size bands(bands+1)/2). Give both cos t and sin t (sin t >= 0) so that directions
/// near the poles keep full accuracy.
void legendre_normalized(int bands, double cos_t, double sin_t, double* out);

/// One column: Pbar_lm(cos t) for l = m..bands-1 into out[l - m] (size bands - m).
/// O(m + bands) — for tests and zonal/sectoral work at very high band.
void legendre_column(int bands, int m, double cos_t, double sin_t, double* out);

/// Y_i(dir) for the bands^2 coefficients, into out (size bands^2).
void evaluate(int bands, const glm::dvec3& dir, double* out);
std::vector<double> evaluate(int bands, const glm::dvec3& dir);

/// Y_i at n directions at once, for bands <= 128: structure-of-arrays input (xs, ys, zs,
/// need not be unit length), coefficient-major output out[i * stride + k] for
/// coefficient i of direction k (stride >= n; out holds bands^2 * stride values).
/// The column recurrence is vectorised across directions (4 per vector; AVX2/FMA clone
/// picked at run time with GCC on x86-64); directions whose sectoral terms leave the
/// double range (within ~1e-16 rad of a pole at L = 16) take the extended-range path.
/// Same values as evaluate() to ~1e-16 * l relative (tested to <= 1e-13).
/// Choose a stride that is not a multiple of 4 KiB / 8 (equal-offset output streams
/// alias in the L1 cache; docs/sh.md). Throws InputError for bands outside [1, 128],
/// stride < n, or a zero/NaN/infinite direction (output then partly written).
void evaluate_batch(int bands, std::size_t n, const double* xs, const double* ys, const double* zs, double* out,
                    std::size_t stride);

/// The same in single precision: the recurrence runs in float on twice as many
/// directions per vector (8 per AVX register, 16 per AVX-512 register). Directions need
/// only be finite and non-zero (float directions whose squares would overflow or
/// underflow are rescaled exactly). A lane whose last sectoral term falls below 2^-100
/// (sin t below ~0.01 at L = 16, ~0.35 at L = 64) is computed in double and rounded.
/// Accuracy against evaluate(): <= 2e-6 * (l + 1) absolute for |Y| <= sqrt((2l+1)/4pi)
/// (tested at L = 2..128).
void evaluate_batch(int bands, std::size_t n, const float* xs, const float* ys, const float* zs, float* out,
                    std::size_t stride);

/// Y_i at (t, p) in radians (t from +z, p from +x towards +y).
void evaluate_angles(int bands, double theta, double phi, double* out);

/// Sum_i c_i Y_i(dir) (a coefficient vector of length >= bands^2). No allocation per call
/// (a per-thread buffer above 8 bands). Throws InputError as evaluate().
double reconstruct(int bands, const double* coeffs, const glm::dvec3& dir);

/// Unit direction of spherical angles (t, p) and back (p in [0, 2 pi)).
glm::dvec3 direction_from_angles(double theta, double phi);

}  // namespace atmosh::sh
