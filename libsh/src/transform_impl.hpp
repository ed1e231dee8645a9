// transform_impl.hpp (private to libsh) — the ring-wise Legendre sums and the FFTs
// behind transform.cpp and projection.cpp; tests of the FFT include it from libsh/src.
#pragma once

#include <string>

namespace atmosh::sh {

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
/// For tests: whether the plans of size n (measured or not) have been made in this process,
/// and FFTW's printed form of their real forward plan (making them if need be).
bool fft_plans_made(int n, bool measured);
std::string fft_plan_text(int n, bool measured);
/// Real FFT of any size n >= 1 through FFTW3. The plans are made once per size (FFTW's
/// planner is not thread safe: under a process-wide lock) with FFTW_ESTIMATE and the
/// process's wisdom set aside, and the method is chosen from the factors of n alone
/// (transform.cpp), so the same input gives the same bits from run to run; with `measured`,
/// FFTW_MEASURE plans of the same method instead (kept apart from the others; faster for
/// some sizes, chosen by timing, so the bits may differ between runs; the wisdom they
/// record is dropped). Executing them is thread safe. Powers of two from 16 and sizes with
/// a prime factor above 5 transform two rings at once (forward2 / inverse2: one split-format
/// or interleaved complex FFT of size n, or Bluestein's chirp convolution where a prime
/// factor exceeds 13). Each object owns
/// aligned work arrays: one per thread. libsh destroys only its own plans at exit.
class RealFft {
 public:
  explicit RealFft(int n, bool measured = false);
  ~RealFft();
  RealFft(RealFft&& o) noexcept;
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;
  int size() const { return n_; }
  bool measured() const { return measured_; }
  /// Whether size n transforms two rings at once (forward2 / inverse2 then pair their rings;
  /// otherwise they are two independent real FFTs).
  static bool pairs_rings(int n);
  /// a_m = sum_j f_j cos(2 pi j m / n), b_m = sum_j f_j sin(2 pi j m / n) into out[2m],
  /// out[2m+1] for m < count (any count: orders above n/2 are the aliases).
  template <class T>
  void forward(const T* f, int count, double* out);
  /// The raw spectra X_k = sum_j f_j e^{-2 pi i j k / n}, k <= n/2 (re, im interleaved, row
  /// stride n/2 + 1 complex values) of `rows` (4 or 8) consecutive rings (stride n) by one
  /// FFTW call of a plan over all of them, made once per size. Returns false, having done
  /// nothing, where no such plan applies (odd n, sizes other than 2^a 3^b 5^c, powers of two:
  /// forward2_spectra's split FFTs of two rings are faster there; rows not aligned as
  /// FFTW's own arrays).
  bool forward_rows(const double* f, int rows, double* spectra);
  /// forward() of two rings (out1 from f1, out2 from f2).
  void forward2(const double* f1, const double* f2, int count, double* out1, double* out2);
  /// The raw spectra X_k (k < count <= n/2 + 1, re/im interleaved, as forward_rows) of two
  /// rings by the method of forward2.
  void forward2_spectra(const double* f1, const double* f2, int count, double* s1, double* s2);
  /// v_j = sum_{m < count} (C_m cos(2 pi j m / n) + S_m sin(2 pi j m / n)) from cs[2m], cs[2m+1];
  /// needs 2 count - 1 <= n.
  void inverse(const double* cs, int count, double* v);
  /// inverse() of two rings.
  void inverse2(const double* cs1, const double* cs2, int count, double* v1, double* v2);
  /// Whether size n pairs its rings through split-format complex FFTs (n a power of two >= 16);
  /// only then is inverse_split defined.
  static bool splits_rings(int n);
  /// v1_j + i v2_j = sum_k Z_k e^{2 pi i j k / n} (j, k < n) from Z_k = zr[k] + i zi[k], which
  /// it overwrites: for Z_k = V1_k + i V2_k with V_-k = conj(V_k), v1 and v2 are the rings
  /// of the real spectra V1 and V2. zr and zi must be aligned as fftw_malloc's arrays
  /// (std::logic_error otherwise); v1 and v2 are written in place where they are too, through
  /// a copy where they are not.
  void inverse_split(double* zr, double* zi, double* v1, double* v2);

 private:
  // forward2_spectra of the chirp, split and pair methods (spectra for k < cm into s1, s2)
  void chirp_spectra(const double* f1, const double* f2, int cm, double* s1, double* s2);
  void split_spectra(const double* f1, const double* f2, int cm, double* s1, double* s2);
  void pair_spectra(const double* f1, const double* f2, int cm, double* s1, double* s2);

  int n_;
  bool measured_;
  const void* plans_;  // the shared plans of size n
  double* real_;       // n values (FFTW-aligned)
  double* spec_;       // n/2 + 1 complex values
  double* spec2_;      // n/2 + 1 complex values (second ring)
  double* work_;       // complex work arrays of the paired methods (null: real FFTs only)
};
}  // namespace detail

}  // namespace atmosh::sh
