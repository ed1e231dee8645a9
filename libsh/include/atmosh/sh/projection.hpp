// atmosh/sh/projection.hpp — projecting functions and images onto real SH; reconstruction.
//
// Coefficients: c_i = integral f(w) Y_i(w) dOmega (convention of basis.hpp), so the units
// are those of f times sr. Directions: unit vectors, t from +z, p from +x towards +y.
//
// Functions (project_function):
//   * Method::quadrature — Gauss–Legendre in cos t (nlat = bands) x uniform p
//     (nphi = power of two >= 2 bands - 1): exact (to ~1e-15 relative) for functions
//     band-limited to `bands` bands; for others the error is the aliasing of the tail.
//   * Method::jittered — stratified Monte Carlo as in Green 2003: n x n strata of the unit
//     square mapped to the sphere by t = acos(1 - 2u), p = 2 pi v, one uniform sample per
//     stratum, weight 4 pi / n^2 (unbiased; error ~ n^-3/2 for smooth f).
//   * Method::uniform — N independent uniform samples, weight 4 pi / N (error ~ N^-1/2).
//   Every sampler takes an explicit seed (std::mt19937_64); same seed, same result.
//
// Images (planar float data, channel-major: data[(c * height + row) * width + col]):
//   * equirect: width x height, row 0 at t = 0 (+z), column 0 at p = 0; the pixel centre
//     (col + 1/2, row + 1/2) maps to p = 2 pi (col + 1/2) / width, t = pi (row + 1/2) / height.
//     Three rules (PixelRule), each with the basis taken at or integrated over the pixels:
//     - exact (Method::quadrature, the default): Fejér's first rule in cos t on the H
//       pixel-centre rings times the uniform rule in p (weight 2 pi / W). For samples of a
//       function band-limited to B bands (degree <= B-1), coefficient (l, m) is exact (to
//       rounding, ~1e-15 relative in double) when
//          l + B - 1 <= H - 1 (<= H when H is odd)   and   |m| + B - 1 <= W - 1,
//       i.e. for all coefficients of L = B bands: 2L - 1 <= H and 2L - 1 <= W (L <= H/2 on a
//       2:1 image). Beyond that the result is the aliased (folded) tail.
//     - solid_angle (Method::solid_angle): pixel-centre basis value times the exact pixel
//       solid angle (2 pi / W)(cos t0 - cos t1) (sum 4 pi); second-order accurate only
//       (a constant 64 x 32 image leaks 5e-3 into c_60).
//     - pixel_integrated (Method::pixel_integrated): each pixel a constant patch; the exact
//       integral of Y_lm over the pixel: in p in closed form ((2/m) sin(m pi / W) cos(m p_c),
//       likewise sin), in t by an n-point Gauss–Legendre rule per ring in t with
//       n = 10 + ceil(0.75 L pi / H) (the integrand Pbar_lm(cos t) sin t is a trigonometric
//       polynomial of degree <= L in t; the rule's error is below rounding). Exact
//       coefficients of the piecewise-constant image (not of a band-limited function).
//   * cube map: six square faces of size N, in the order +X, -X, +Y, -Y, +Z, -Z, with
//     the OpenGL orientation: texel (i, j) (j = row from the top) has
//     u = 2 (i + 1/2) / N - 1, v = 2 (j + 1/2) / N - 1 and direction
//        +X: ( 1, -v, -u)   -X: (-1, -v,  u)   +Y: ( u,  1,  v)
//        -Y: ( u, -1, -v)   +Z: ( u, -v,  1)   -Z: (-u, -v, -1)   (then normalised).
//     Exact texel solid angle from the corners: A(u,v) = atan2(u v, sqrt(u^2+v^2+1)),
//     Omega = A(u0,v0) - A(u0,v1) - A(u1,v0) + A(u1,v1); sums to 4 pi at every N.
//     Texel-centre basis value times that solid angle is second-order accurate (error
//     ~ N^-2 for smooth content; measured in docs/sh.md); it is not exact for
//     band-limited content (no rule on these texel centres is used that would be).
//     unpack_cross() turns a horizontal cross (4N x 3N: +Y above, then -X +Z +X -Z, -Y
//     below) or a vertical cross (3N x 4N: the same with -Z below -Y, rotated 180 deg)
//     into the six faces; these layouts are seamless with the orientation above.
// Image methods: pixel integration (exact per-pixel solid angle, all pixels), or the
// same Monte Carlo samplers / Gauss grid reading the image by bilinear interpolation.
//
// Throws atmosh::InputError on bands < 1, empty or inconsistent images, non-finite
// samples, samples < 1.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/work.hpp"

namespace atmosh::sh {

enum class Method { quadrature, jittered, uniform, solid_angle, pixel_integrated };

/// Weighting of equirect pixels (see above). Method::quadrature on an image is `exact`.
enum class PixelRule { exact, solid_angle, pixel_integrated };

/// Parses "quadrature" | "jittered" | "uniform" | "solid-angle" | "pixel-integrated"
/// (InputError otherwise). solid-angle and pixel-integrated apply to images only.
Method parse_method(const std::string& name);

struct ProjectOptions {
  Method method = Method::quadrature;
  /// jittered: strata per side n (n^2 samples, default 45 -> 2025);
  /// uniform: number of samples (default 2025); quadrature: ignored (0 = default grid).
  int samples = 0;
  std::uint64_t seed = 1;
  int threads = 1;
};

/// The sample directions (unit) and equal weights (4 pi / count, sr) of a Monte Carlo
/// sampler (Method::jittered or Method::uniform), exactly as project_function uses them.
void sampler_directions(const ProjectOptions& opt, std::vector<glm::dvec3>& dirs, std::vector<double>& weights);
/// Bytes a Monte Carlo projection (Method::jittered or Method::uniform) holds for its
/// samples: directions and weights (sampler_directions) and `channels` values per
/// sample; 0 for Method::quadrature. Saturates at SIZE_MAX. For a budget check first.
std::size_t sampler_bytes(const ProjectOptions& opt, int channels);
/// The work of a Monte Carlo projection of an image (atmosh/work.hpp), before it:
/// samples x bands^2 x channels, at the cost of one unit measured for
/// project_equirect_sampled (docs/hostile-input.md, "Work estimates"); units 0 for the
/// image rules (Method::quadrature, solid_angle, pixel_integrated).
WorkEstimate sampler_work(const ProjectOptions& opt, int bands, int channels);

/// Coefficients (bands^2) of a scalar function of direction.
std::vector<double> project_function(const std::function<double(const glm::dvec3&)>& f, int bands,
                                     const ProjectOptions& opt = {});

/// A planar image (not owned), float (ImageView) or double (ImageViewD).
template <class T>
struct BasicImageView {
  int width = 0, height = 0, channels = 0;
  const T* data = nullptr;  ///< data[(c * height + row) * width + col]
  T at(int c, int row, int col) const {
    return data[(static_cast<std::size_t>(c) * height + row) * width + col];
  }
};
using ImageView = BasicImageView<float>;
using ImageViewD = BasicImageView<double>;

/// Per-channel coefficients: result[c][i].
using Channels = std::vector<std::vector<double>>;

/// Equirect image by the pixel rule `rule` (default: exact for band-limited content).
Channels project_equirect(const ImageView& img, int bands, int threads = 1, PixelRule rule = PixelRule::exact);
/// The same for double samples (for band-limited content exact to ~1e-15 relative).
Channels project_equirect(const ImageViewD& img, int bands, int threads = 1, PixelRule rule = PixelRule::exact);
/// Weight in cos t of each pixel ring under `rule` (exact: Fejér's first rule; solid_angle:
/// cos t0 - cos t1; pixel_integrated: the same as solid_angle for the constant m = 0 part).
/// Sums to 2 for every rule.
std::vector<double> equirect_ring_weights(int height, PixelRule rule);
/// Equirect image by a sampler (bilinear lookup; wraps in p, clamps in t).
Channels project_equirect_sampled(const ImageView& img, int bands, const ProjectOptions& opt);
/// Bilinear lookup of an equirect image at a unit direction.
void sample_equirect(const ImageView& img, const glm::dvec3& dir, double* out);
/// Solid angle of an equirect pixel row (all pixels in a row are equal).
double equirect_pixel_solid_angle(int width, int height, int row);

/// Six faces: faces[f] is an N x N planar image (channels as in ImageView).
struct CubeMap {
  int size = 0, channels = 0;
  std::vector<float> faces[6];  ///< faces[f][(c * size + row) * size + col]
};
/// The point (u, v) in [-1, 1]^2 of face f on the cube [-1, 1]^3 (not unit length): the
/// faces' orientation of CubeMap; InputError for f outside 0..5.
glm::dvec3 cube_face_point(int face, double u, double v);
/// Direction of the centre of texel (col, row) of face f (unit length).
glm::dvec3 cube_texel_direction(int face, int col, int row, int size);
/// Exact solid angle of texel (col, row) (same on every face).
double cube_texel_solid_angle(int col, int row, int size);
/// Unpacks a horizontal (4N x 3N) or vertical (3N x 4N) cross.
CubeMap unpack_cross(const ImageView& img);
/// Nearest-texel lookup of a cube map at a unit direction.
void sample_cube(const CubeMap& cube, const glm::dvec3& dir, double* out);
/// Cube map by a sampler (nearest-texel lookup) — Method::jittered or Method::uniform.
Channels project_cube_sampled(const CubeMap& cube, int bands, const ProjectOptions& opt);
/// Cube map: texel-centre basis values times the exact texel solid angle (second order;
/// see above).
Channels project_cube(const CubeMap& cube, int bands, int threads = 1);

/// Reconstruction of one channel on an equirect grid (pixel centres), height rows.
std::vector<float> render_equirect(const std::vector<double>& coeffs, int bands, int width, int height);

}  // namespace atmosh::sh
