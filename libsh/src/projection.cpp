// Projection of functions and images onto real SH; reconstruction to equirect.
#include "atmosh/sh/projection.hpp"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/fast.hpp"
#include "atmosh/sh/quadrature.hpp"
#include "atmosh/sh/shared/cube.glsl.hpp"
#include "atmosh/sh/transform.hpp"
#include "transform_impl.hpp"

namespace atmosh::sh {

namespace {
constexpr double kPi = std::numbers::pi;

// Sample directions and weights of a sampler.
void sampler_points(const ProjectOptions& opt, std::vector<glm::dvec3>& dirs, std::vector<double>& w) {
  std::mt19937_64 rng(opt.seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto dir_of = [](double u, double v) {
    const double ct = 1.0 - 2.0 * u;
    const double st = std::sqrt(std::max(0.0, (1.0 - ct) * (1.0 + ct)));
    const double p = 2.0 * kPi * v;
    return glm::dvec3(st * std::cos(p), st * std::sin(p), ct);
  };
  if (opt.method == Method::jittered) {
    const int n = opt.samples > 0 ? opt.samples : 45;
    if (n > 20000) throw InputError("jittered: strata per side must be <= 20000, got " + std::to_string(n));
    dirs.reserve(static_cast<std::size_t>(n) * n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) dirs.push_back(dir_of((i + U(rng)) / n, (j + U(rng)) / n));
  } else {
    const long long n = opt.samples > 0 ? opt.samples : 2025;
    dirs.reserve(n);
    for (long long k = 0; k < n; ++k) {
      const double u = U(rng), v = U(rng);
      dirs.push_back(dir_of(u, v));
    }
  }
  w.assign(dirs.size(), 4.0 * kPi / static_cast<double>(dirs.size()));
}

// Basis at a unit direction into y (fast path for low bands).
inline void basis_unit(int bands, const glm::dvec3& d, double* y) {
  if (bands <= kFastMaxBands)
    evaluate_fast(bands, d.x, d.y, d.z, y);
  else
    evaluate(bands, d, y);
}

// The SH projection of a function of C channels, sample(direction, values), by a Monte
// Carlo sampler (jittered or uniform): sum of value x weight x Y over its points.
template <class Sample>
Channels project_sampled_points(const ProjectOptions& opt, int bands, int C, Sample&& sample) {
  Channels out(C, std::vector<double>(sh_count(bands), 0.0));
  std::vector<double> val(C), y(sh_count(bands));
  std::vector<glm::dvec3> dirs;
  std::vector<double> w;
  sampler_points(opt, dirs, w);
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    sample(dirs[k], val.data());
    basis_unit(bands, dirs[k], y.data());
    for (int c = 0; c < C; ++c) {
      const double s = val[c] * w[k];
      double* o = out[c].data();
      for (int i = 0; i < sh_count(bands); ++i) o[i] += s * y[i];
    }
  }
  return out;
}

// The same by the exact Gauss quadrature: the function sampled on the Gauss grid of
// `bands` (opt.samples > bands rings if asked), then analysed.
template <class Sample>
Channels project_on_gauss_grid(const ProjectOptions& opt, int bands, int C, Sample&& sample) {
  const GaussGrid g = gauss_grid(bands, opt.samples > bands ? opt.samples : 0);
  std::vector<std::vector<double>> v(C, std::vector<double>(static_cast<std::size_t>(g.nlat) * g.nphi));
  std::vector<double> val(C);
  for (int i = 0; i < g.nlat; ++i)
    for (int j = 0; j < g.nphi; ++j) {
      const double p = g.phi(j);
      sample(glm::dvec3(g.sin_t[i] * std::cos(p), g.sin_t[i] * std::sin(p), g.cos_t[i]), val.data());
      for (int c = 0; c < C; ++c) v[c][static_cast<std::size_t>(i) * g.nphi + j] = val[c];
    }
  Channels out(C);
  for (int c = 0; c < C; ++c) out[c] = analyse(g, v[c].data(), opt.threads);
  return out;
}

void check_image(const ImageView& img, const char* where) {
  if (img.width < 1 || img.height < 1 || img.channels < 1 || img.data == nullptr)
    throw InputError(std::string(where) + ": empty image (" + std::to_string(img.width) + " x " +
                     std::to_string(img.height) + " x " + std::to_string(img.channels) + ")");
}

}  // namespace

std::size_t sampler_bytes(const ProjectOptions& opt, int channels) {
  long double n = 0;
  if (opt.method == Method::jittered) n = static_cast<long double>(opt.samples > 0 ? opt.samples : 45) * (opt.samples > 0 ? opt.samples : 45);
  else if (opt.method == Method::uniform) n = opt.samples > 0 ? opt.samples : 2025;
  const long double b = n * (sizeof(glm::dvec3) + sizeof(double) + sizeof(double) * std::max(channels, 1));
  return b >= static_cast<long double>(SIZE_MAX) ? SIZE_MAX : static_cast<std::size_t>(b);
}

WorkEstimate sampler_work(const ProjectOptions& opt, int bands, int channels) {
  // project_equirect_sampled on one core: a per sample (direction, image lookup) + b per
  // coefficient and channel, fitted to bench_work BM_WorkShUniform at 3, 8 and 16 bands
  // (docs/hostile-input.md, "Work estimates"); as a cost per unit, b + a / (bands^2 channels).
  constexpr double a = 174e-9, b = 0.72e-9;
  double n = 0;
  if (opt.method == Method::jittered) n = mul_units(opt.samples > 0 ? opt.samples : 45, opt.samples > 0 ? opt.samples : 45);
  else if (opt.method == Method::uniform) n = opt.samples > 0 ? opt.samples : 2025;
  const double per_sample = mul_units(std::max(bands, 1), std::max(bands, 1), std::max(channels, 1));
  return {mul_units(n, mul_units(std::max(bands, 0), std::max(bands, 0)), std::max(channels, 1)), b + a / per_sample,
          "samples x SH coefficients x channels"};
}

void sampler_directions(const ProjectOptions& opt, std::vector<glm::dvec3>& dirs, std::vector<double>& weights) {
  if (opt.method != Method::jittered && opt.method != Method::uniform)
    throw InputError("sampler_directions: only jittered and uniform are Monte Carlo samplers");
  if (opt.samples < 0) throw InputError("sampler_directions: samples must be >= 1, got " + std::to_string(opt.samples));
  dirs.clear();
  weights.clear();
  sampler_points(opt, dirs, weights);
}

Method parse_method(const std::string& name) {
  if (name == "quadrature") return Method::quadrature;
  if (name == "jittered") return Method::jittered;
  if (name == "uniform") return Method::uniform;
  if (name == "solid-angle") return Method::solid_angle;
  if (name == "pixel-integrated") return Method::pixel_integrated;
  throw InputError("unknown projection method '" + name +
                   "' (quadrature, solid-angle, pixel-integrated, jittered, uniform)");
}

std::vector<double> project_function(const std::function<double(const glm::dvec3&)>& f, int bands,
                                     const ProjectOptions& opt) {
  check_bands(bands, "project_function");
  if (opt.samples < 0) throw InputError("project_function: samples must be >= 0, got " + std::to_string(opt.samples));
  if (opt.method == Method::solid_angle || opt.method == Method::pixel_integrated)
    throw InputError("project_function: solid-angle and pixel-integrated apply to images only");
  auto sample = [&](const glm::dvec3& d, double* val) {
    val[0] = f(d);
    if (!std::isfinite(val[0])) throw InputError("project_function: function returned a non-finite value");
  };
  if (opt.method == Method::quadrature) return project_on_gauss_grid(opt, bands, 1, sample)[0];
  return project_sampled_points(opt, bands, 1, sample)[0];
}

double equirect_pixel_solid_angle(int width, int height, int row) {
  const double t0 = kPi * row / height, t1 = kPi * (row + 1) / height;
  // cos t0 - cos t1 = 2 sin((t0+t1)/2) sin((t1-t0)/2), accurate near the poles
  return 2.0 * kPi / width * 2.0 * std::sin(0.5 * (t0 + t1)) * std::sin(0.5 * (t1 - t0));
}

std::vector<double> equirect_ring_weights(int height, PixelRule rule) {
  if (height < 1) throw InputError("equirect_ring_weights: height must be >= 1, got " + std::to_string(height));
  if (rule == PixelRule::exact) return fejer1_weights(height);
  std::vector<double> w(height);
  for (int r = 0; r < height; ++r) w[r] = equirect_pixel_solid_angle(1, height, r) / (2.0 * kPi);
  return w;
}

namespace {
template <class T>
void check_image_t(const BasicImageView<T>& img, const char* where) {
  if (img.width < 1 || img.height < 1 || img.channels < 1 || img.data == nullptr)
    throw InputError(std::string(where) + ": empty image (" + std::to_string(img.width) + " x " +
                     std::to_string(img.height) + " x " + std::to_string(img.channels) + ")");
}

// Ring sums a_m = sum_j f_j cos(m p_j), b_m = sum_j f_j sin(m p_j), p_j = 2 pi (j + 1/2) / W:
// a real FFT (p = 2 pi j / W) and the phase shift by m pi / W (c2, s2: cos, sin of k pi / W).
template <class T>
void ring_sums_centred_t(int bands, int W, const T* f, const std::vector<double>& c2, const std::vector<double>& s2,
                         detail::RealFft& fft, double* out) {
  fft.forward(f, bands, out);
  for (int m = 0; m < bands; ++m) {
    const int k = static_cast<int>(static_cast<long long>(m) % (2LL * W));
    const double a = out[2 * m], b = out[2 * m + 1];
    out[2 * m] = a * c2[k] - b * s2[k];
    out[2 * m + 1] = b * c2[k] + a * s2[k];
  }
}

template <class T>
Channels project_equirect_t(const BasicImageView<T>& img, int bands, int threads, PixelRule rule) {
  check_image_t(img, "project_equirect");
  check_bands(bands, "project_equirect");
  const int W = img.width, H = img.height, L = bands;
  std::vector<double> c2(2 * W), s2(2 * W);
  for (int k = 0; k < 2 * W; ++k) {
    c2[k] = std::cos(kPi * k / W);
    s2[k] = std::sin(kPi * k / W);
  }
  // Rings of the Legendre stage: one per pixel row (exact, solid_angle), or nsub Gauss
  // nodes in t per pixel row (pixel_integrated). wt: weight in cos t of each ring.
  const double h = kPi / H;
  int nsub = 1;
  std::vector<double> gx{0.0}, gw{2.0};
  if (rule == PixelRule::pixel_integrated) {
    nsub = 10 + static_cast<int>(std::ceil(0.75 * L * h));
    const GaussLegendre gl = gauss_legendre(nsub);
    gx = gl.nodes;
    gw = gl.weights;
  }
  const int R = H * nsub;
  std::vector<double> ct(R), st(R), wt(R);
  const std::vector<double> rw = rule == PixelRule::pixel_integrated ? std::vector<double>{} : equirect_ring_weights(H, rule);
  for (int i = 0; i < (R + 1) / 2; ++i) {
    const int row = i / nsub, k = i % nsub;
    const double t = (row + 0.5) * h + 0.5 * h * gx[k];
    const bool centre = 2 * i + 1 == R;
    ct[i] = centre ? 0.0 : std::cos(t);
    st[i] = centre ? 1.0 : std::sin(t);
    ct[R - 1 - i] = -ct[i];
    st[R - 1 - i] = st[i];
    // d(cos t) = sin t dt: the Gauss weight in t times sin t
    wt[i] = wt[R - 1 - i] = rule == PixelRule::pixel_integrated ? 0.5 * h * gw[k] * st[i] : rw[row];
  }
  // weight in p per order m (the sqrt2 of the real basis included)
  std::vector<double> pm(L);
  for (int m = 0; m < L; ++m) {
    double f = 2.0 * kPi / W;
    if (rule == PixelRule::pixel_integrated && m > 0) f = 2.0 / m * std::sin(m * kPi / W);
    pm[m] = m > 0 ? std::numbers::sqrt2 * f : f;
  }
  Channels out(img.channels);
  std::vector<double> rows(static_cast<std::size_t>(H) * L * 2);
  std::vector<double> four(static_cast<std::size_t>(R) * L * 2);
  detail::RealFft fft(W);
  for (int c = 0; c < img.channels; ++c) {
    for (int r = 0; r < H; ++r) {
      const T* src = img.data + (static_cast<std::size_t>(c) * H + r) * W;
      for (int j = 0; j < W; ++j)
        if (!std::isfinite(src[j]))
          throw InputError("project_equirect: pixel (" + std::to_string(j) + ", " + std::to_string(r) + ") channel " +
                           std::to_string(c) + " is not finite");
      ring_sums_centred_t(L, W, src, c2, s2, fft, rows.data() + static_cast<std::size_t>(r) * L * 2);
    }
    for (int i = 0; i < R; ++i) {
      const double* a = rows.data() + static_cast<std::size_t>(i / nsub) * L * 2;
      double* o = four.data() + static_cast<std::size_t>(i) * L * 2;
      for (int m = 0; m < L; ++m) {
        const double f = wt[i] * pm[m];
        o[2 * m] = a[2 * m] * f;
        o[2 * m + 1] = m > 0 ? a[2 * m + 1] * f : 0.0;
      }
    }
    out[c].assign(sh_count(L), 0.0);
    detail::legendre_analysis(L, R, ct.data(), st.data(), four.data(), true, out[c].data(), threads);
  }
  return out;
}
}  // namespace

Channels project_equirect(const ImageView& img, int bands, int threads, PixelRule rule) {
  return project_equirect_t(img, bands, threads, rule);
}
Channels project_equirect(const ImageViewD& img, int bands, int threads, PixelRule rule) {
  return project_equirect_t(img, bands, threads, rule);
}

void sample_equirect(const ImageView& img, const glm::dvec3& d, double* out) {
  const double t = std::atan2(std::sqrt(d.x * d.x + d.y * d.y), d.z);
  double p = std::atan2(d.y, d.x);
  if (p < 0) p += 2.0 * kPi;
  const double fx = p / (2.0 * kPi) * img.width - 0.5;
  const double fy = t / kPi * img.height - 0.5;
  const int x0 = static_cast<int>(std::floor(fx));
  const int y0 = static_cast<int>(std::floor(fy));
  const double ax = fx - x0, ay = fy - y0;
  auto wrapx = [&](int x) { return ((x % img.width) + img.width) % img.width; };
  auto clampy = [&](int y) { return std::clamp(y, 0, img.height - 1); };
  const int xa = wrapx(x0), xb = wrapx(x0 + 1), ya = clampy(y0), yb = clampy(y0 + 1);
  for (int c = 0; c < img.channels; ++c) {
    out[c] = (1 - ay) * ((1 - ax) * img.at(c, ya, xa) + ax * img.at(c, ya, xb)) +
             ay * ((1 - ax) * img.at(c, yb, xa) + ax * img.at(c, yb, xb));
  }
}

Channels project_equirect_sampled(const ImageView& img, int bands, const ProjectOptions& opt) {
  check_image(img, "project_equirect_sampled");
  check_bands(bands, "project_equirect_sampled");
  if (opt.method == Method::solid_angle) return project_equirect(img, bands, opt.threads, PixelRule::solid_angle);
  if (opt.method == Method::pixel_integrated)
    return project_equirect(img, bands, opt.threads, PixelRule::pixel_integrated);
  auto sample = [&](const glm::dvec3& d, double* val) { sample_equirect(img, d, val); };
  if (opt.method == Method::quadrature) return project_on_gauss_grid(opt, bands, img.channels, sample);
  return project_sampled_points(opt, bands, img.channels, sample);
}

// The cube geometry is the shared C++/GLSL block (atmosh/sh/shared/cube.glsl.hpp), so that
// the GPU probes' projection uses the very same texel directions and solid angles.
glm::dvec3 cube_face_point(int face, double u, double v) {
  if (face < 0 || face > 5) throw InputError("cube face must be 0..5, got " + std::to_string(face));
  return shared::sh_cube_face_point(face, u, v);
}

glm::dvec3 cube_texel_direction(int face, int col, int row, int size) {
  if (face < 0 || face > 5) throw InputError("cube face must be 0..5, got " + std::to_string(face));
  return shared::sh_cube_texel_direction(face, col, row, size);
}

double cube_texel_solid_angle(int col, int row, int size) { return shared::sh_cube_texel_solid_angle(col, row, size); }

CubeMap unpack_cross(const ImageView& img) {
  check_image(img, "unpack_cross");
  CubeMap cube;
  cube.channels = img.channels;
  bool horizontal;
  if (img.width * 3 == img.height * 4 && img.width % 4 == 0) {
    horizontal = true;
    cube.size = img.width / 4;
  } else if (img.width * 4 == img.height * 3 && img.width % 3 == 0) {
    horizontal = false;
    cube.size = img.width / 3;
  } else {
    throw InputError("unpack_cross: " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                     " is neither a 4:3 nor a 3:4 cross");
  }
  const int N = cube.size;
  // (face, cell col, cell row, rotated 180)
  struct Cell { int face, cx, cy; bool rot; };
  std::vector<Cell> cells = {{2, 1, 0, false}, {1, 0, 1, false}, {4, 1, 1, false}, {0, 2, 1, false}, {3, 1, 2, false}};
  if (horizontal)
    cells.push_back({5, 3, 1, false});
  else
    cells.push_back({5, 1, 3, true});
  for (const Cell& cell : cells) {
    auto& f = cube.faces[cell.face];
    f.resize(static_cast<std::size_t>(img.channels) * N * N);
    for (int c = 0; c < img.channels; ++c)
      for (int r = 0; r < N; ++r)
        for (int q = 0; q < N; ++q) {
          const int sr = cell.rot ? N - 1 - r : r, sq = cell.rot ? N - 1 - q : q;
          f[(static_cast<std::size_t>(c) * N + r) * N + q] = img.at(c, cell.cy * N + sr, cell.cx * N + sq);
        }
  }
  return cube;
}

Channels project_cube(const CubeMap& cube, int bands, int threads) {
  (void)threads;
  check_bands(bands, "project_cube");
  const int N = cube.size, C = cube.channels;
  if (N < 1 || C < 1) throw InputError("project_cube: empty cube map");
  for (int f = 0; f < 6; ++f)
    if (cube.faces[f].size() != static_cast<std::size_t>(C) * N * N)
      throw InputError("project_cube: face " + std::to_string(f) + " has the wrong size");
  Channels out(C, std::vector<double>(sh_count(bands), 0.0));
  const int n = sh_count(bands);
  std::vector<double> y(n);
  std::vector<double> omega(static_cast<std::size_t>(N) * N);
  for (int r = 0; r < N; ++r)
    for (int q = 0; q < N; ++q) omega[static_cast<std::size_t>(r) * N + q] = cube_texel_solid_angle(q, r, N);
  for (int f = 0; f < 6; ++f)
    for (int r = 0; r < N; ++r)
      for (int q = 0; q < N; ++q) {
        basis_unit(bands, cube_texel_direction(f, q, r, N), y.data());
        const double om = omega[static_cast<std::size_t>(r) * N + q];
        for (int c = 0; c < C; ++c) {
          const double v = cube.faces[f][(static_cast<std::size_t>(c) * N + r) * N + q];
          if (!std::isfinite(v)) throw InputError("project_cube: texel value is not finite");
          const double s = v * om;
          double* o = out[c].data();
          for (int i = 0; i < n; ++i) o[i] += s * y[i];
        }
      }
  return out;
}

void sample_cube(const CubeMap& cube, const glm::dvec3& d, double* out) {
  const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
  int face;
  double u, v;  // inverse of cube_texel_direction
  if (ax >= ay && ax >= az) {
    face = d.x > 0 ? 0 : 1;
    u = d.x > 0 ? -d.z / ax : d.z / ax;
    v = -d.y / ax;
  } else if (ay >= az) {
    face = d.y > 0 ? 2 : 3;
    u = d.x / ay;
    v = d.y > 0 ? d.z / ay : -d.z / ay;
  } else {
    face = d.z > 0 ? 4 : 5;
    u = d.z > 0 ? d.x / az : -d.x / az;
    v = -d.y / az;
  }
  const int N = cube.size;
  const int col = std::clamp(static_cast<int>(std::floor((u + 1.0) * 0.5 * N)), 0, N - 1);
  const int row = std::clamp(static_cast<int>(std::floor((v + 1.0) * 0.5 * N)), 0, N - 1);
  for (int c = 0; c < cube.channels; ++c) out[c] = cube.faces[face][(static_cast<std::size_t>(c) * N + row) * N + col];
}

Channels project_cube_sampled(const CubeMap& cube, int bands, const ProjectOptions& opt) {
  check_bands(bands, "project_cube_sampled");
  if (cube.size < 1 || cube.channels < 1) throw InputError("project_cube_sampled: empty cube map");
  if (opt.method == Method::quadrature || opt.method == Method::solid_angle)
    return project_cube(cube, bands, opt.threads);
  if (opt.method == Method::pixel_integrated)
    throw InputError("project_cube: pixel-integrated is available for equirect images only");
  return project_sampled_points(opt, bands, cube.channels,
                                [&](const glm::dvec3& d, double* val) { sample_cube(cube, d, val); });
}

std::vector<float> render_equirect(const std::vector<double>& coeffs, int bands, int width, int height) {
  check_bands(bands, "render_equirect");
  if (width < 1 || height < 1 || width > 65536 || height > 65536)
    throw InputError("render_equirect: bad size " + std::to_string(width) + " x " + std::to_string(height));
  if (static_cast<int>(coeffs.size()) < sh_count(bands))
    throw InputError("render_equirect: need " + std::to_string(sh_count(bands)) + " coefficients, got " +
                     std::to_string(coeffs.size()));
  const int H = height, W = width, L = bands;
  std::vector<double> ct(H), st(H);
  for (int r = 0; r < H; ++r) {
    const double t = kPi * (r + 0.5) / H;
    ct[r] = std::cos(t);
    st[r] = std::sin(t);
  }
  for (int r = 0; r < H / 2; ++r) ct[H - 1 - r] = -ct[r], st[H - 1 - r] = st[r];
  if (H % 2) ct[H / 2] = 0.0, st[H / 2] = 1.0;
  std::vector<double> four(static_cast<std::size_t>(H) * L * 2);
  detail::legendre_synthesis(L, H, ct.data(), st.data(), coeffs.data(), true, four.data(), 1);
  std::vector<double> c2(2 * W), s2(2 * W);
  for (int k = 0; k < 2 * W; ++k) {
    c2[k] = std::cos(kPi * k / W);
    s2[k] = std::sin(kPi * k / W);
  }
  std::vector<float> img(static_cast<std::size_t>(W) * H);
  std::vector<double> acc(W);
  if (2 * L - 1 <= W) {
    // real inverse FFT with the coefficients turned by the half-pixel phase m pi / W
    detail::RealFft fft(W);
    std::vector<double> cs(2 * static_cast<std::size_t>(L));
    for (int r = 0; r < H; ++r) {
      const double* f = four.data() + static_cast<std::size_t>(r) * L * 2;
      for (int m = 0; m < L; ++m) {
        const double C = f[2 * m], S = f[2 * m + 1], c = c2[m % (2 * W)], s = s2[m % (2 * W)];
        cs[2 * m] = C * c + S * s;
        cs[2 * m + 1] = S * c - C * s;
      }
      fft.inverse(cs.data(), L, acc.data());
      for (int j = 0; j < W; ++j) img[static_cast<std::size_t>(r) * W + j] = static_cast<float>(acc[j]);
    }
    return img;
  }
  for (int r = 0; r < H; ++r) {
    std::fill(acc.begin(), acc.end(), 0.0);
    const double* f = four.data() + static_cast<std::size_t>(r) * L * 2;
    for (int m = 0; m < L; ++m) {
      const long long mod = 2LL * W, step = 2LL * m % mod;
      long long idx = m % mod;
      for (int j = 0; j < W; ++j) {
        acc[j] += f[2 * m] * c2[idx] + f[2 * m + 1] * s2[idx];
        idx += step;
        if (idx >= mod) idx -= mod;
      }
    }
    for (int j = 0; j < W; ++j) img[static_cast<std::size_t>(r) * W + j] = static_cast<float>(acc[j]);
  }
  return img;
}

}  // namespace atmosh::sh
