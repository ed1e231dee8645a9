// atmosh/sh/rotation.hpp — rotation of SH coefficient vectors at any band.
//
// Convention: ACTIVE rotation of the function. For a rotation R (a proper orthogonal
// 3x3 matrix acting on column vectors, r' = R r), the rotated function is
// f'(r) = f(R^-1 r), i.e. a lobe pointing along d points along R d afterwards.
// Rotating coefficients c gives c' with f'(r) = sum_i c'_i Y_i(r).
// z-y-z Euler angles (alpha, beta, gamma), radians: R = Rz(alpha) Ry(beta) Rz(gamma)
// (rotations about fixed axes, right-handed). glm matrices are column-major:
// R(i, j) = M[j][i].
//
// Method (the same at every band, stable to L in the thousands):
//   R = Rz(alpha + 90) Ry(90) Rz(beta - 180) Ry(90) Rz(gamma + 90)  [degrees]
// z-rotations in closed form (cos/sin of m*angle per (m, -m) pair), and the fixed
// real-basis matrix of Ry(90 deg) built from the Wigner d^l(pi/2) matrix by the
// three-term recurrence in m' (run from m' = l inwards, the stable direction, with
// extended-range starting values d^l_lm = (-1)^(l-m) sqrt(C(2l, l+m)) 2^-l; no
// factorials). In the real basis this matrix has checkerboard sparsity, and by the
// symmetry d_{m m'} = (-1)^(m'-m) d_{m' m} its parity blocks are symmetric or
// antisymmetric: only a quarter of the dense band (half of the non-zeros) is stored, in
// 4 x 4 tiles each used for two products. Bands below 256 use these stored matrices
// (a process-wide cache, ~22 MB, built on first use). Bands 256..1600 are applied on the fly:
// every application runs the row recurrence again and uses each row of d^l(pi/2) as it is
// made (row sums and transposed terms in one pass; three rows of work memory), which is
// faster than streaming stored matrices from memory (1.3 GB at L = 1000) and needs no
// cache; bands above 1600 are rebuilt in each application (column recurrence with
// per-column exponents). Measured in docs/sh.md.
//
// Accuracy (measured, docs/sh.md): ||D D^T - I||_max <= 1e-14 at L = 64; over all entries
// of full bands 8.8e-15 (band 256), 1.3e-14 (599), 8.6e-15 (999); rotation commutes with
// projection to rounding.
// Cost: building = O(L) trig + (first use) the cached Ry(90) table (~0.45 MB at L = 64);
// applying = about L^3 * 2/3 multiply-adds (bands >= 256: plus the row recurrence, about
// as many operations again).
// Throws atmosh::InputError for bands < 1, non-finite angles, or a matrix that is
// not a rotation (|M^T M - I| > 1e-6 or det < 0).
#pragma once

#include <memory>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

namespace atmosh::sh {

struct EulerZYZ {
  double alpha = 0, beta = 0, gamma = 0;  ///< radians
};

/// R = Rz(alpha) Ry(beta) Rz(gamma).
glm::dmat3 matrix_from_euler(const EulerZYZ& e);
/// z-y-z angles of a rotation matrix (beta in [0, pi]; gamma = 0 when beta is 0 or pi).
EulerZYZ euler_from_matrix(const glm::dmat3& m);
/// Rotation matrix of a (not necessarily unit) quaternion.
glm::dmat3 matrix_from_quaternion(const glm::dquat& q);

class Rotation {
 public:
  Rotation(int bands, const EulerZYZ& e);
  Rotation(int bands, const glm::dmat3& m);
  Rotation(int bands, const glm::dquat& q);

  int bands() const { return bands_; }
  /// out = D(R) in (both bands^2 long; may not alias).
  void apply(const double* in, double* out) const;
  std::vector<double> apply(const std::vector<double>& in) const;
  /// Dense (2l+1) x (2l+1) block of band l, row-major, rows/cols m = -l..l. Cost: 2l+1
  /// products of band l alone (O(l^3)), plus building band l if it is not cached.
  std::vector<double> band_matrix(int l) const;

 private:
  int bands_;
  EulerZYZ e_;
  // cos/sin(m * angle), m < bands, split by the parity of m (see rotation.cpp)
  std::vector<double> ca_, sa_, cb_, sb_, cg_, sg_;
};

/// Builds and keeps the Ry(90) band matrices of all bands below min(bands, 256) now (thread
/// safe; otherwise they are built on first use). Bands from 256 on are applied on the fly
/// and never stored, so this no longer grows the cache past 256 bands (at most ~22 MB).
/// InputError for bands outside [1, 8192].
void reserve_rotation_cache(int bands);
/// Number of bands whose matrices are cached now.
int rotation_cache_bands();

/// Closed-form rotation about +z by alpha (radians): in -> out (may alias).
void rotate_z(int bands, double alpha, const double* in, double* out);

}  // namespace atmosh::sh
