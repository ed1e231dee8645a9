// Optical-depth table build (OpticalDepthLut::fill / build_column in
// libatmo/src/optical_depth.cpp), one invocation per table entry: the ray from
// shell k in direction sample j is cut at the tangent point and at every
// crossing of the shells and profile kinks (shared ATMOSH_LUT_RAY_PIECES), pieces
// are split so that each spans at most 1.5 scale heights in altitude and is short
// enough for the curvature of the altitude near the tangent point (shared
// lut_piece_count), and each gets the same Gauss-Legendre rule. Positions and sums in double, densities in float (shared
// density functions through sky_lib.glsl's density_at). Output: log of the mean
// relative density for the tabulated (log-encoded) constituents, 0 otherwise.
layout(local_size_x = 64) in;

layout(std430, binding = 9) readonly buffer Crossings { double cross_r[]; };  // sorted radii
layout(std430, binding = 10) writeonly buffer TableOut { float table_out[]; };
layout(std430, binding = 11) readonly buffer BuildRule { double rule[]; };     // x[n] in (0,1), w[n]
layout(std430, binding = 12) readonly buffer ShellRadii { double shell_r[]; };

uniform int n_cross;
uniform int n_rule;
uniform int n_dirs;         // directions of this table
uniform int table_kind;     // 0: toward the top, 1: toward the ground
uniform int n_entries;      // shells * n_dirs
uniform int log_encoded[3];     // tabulated with log encoding (output)
uniform int tab_present[3];     // tabulated (OpticalDepthLut's present_)
uniform int is_exponential[3];  // scale heights in sky_lib's scale_height[]
uniform int off_q[3], n_q[3];   // OpticalDepthLut::subtracted_curvature(c): altitude[n], half_curv[n]; n = 0: none

// The densities the tables hold at altitude h >= 0: density_at's (the profiles' less
// the subtracted kinks' p, on the nodes) less their quadratic ramps q.
vec3 table_density(float h) {
  vec3 d = density_at(h);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < n_q[c]; ++k) {
      float e = max(shell[off_q[c] + k] - h, 0.0);
      d[c] -= shell[off_q[c] + n_q[c] + k] * e * e;
    }
  return d;
}

// Density of the present constituents at distance s along (r, mu).
dvec3 density_along(double r, double mu, double rt2, double s) {
  double u = s + r * mu;
  double rs = sqrt(u * u + rt2);
  float h = float((s * (s + 2.0LF * r * mu) + (r - ground_radius_d) * (r + ground_radius_d)) / (rs + ground_radius_d));
  return dvec3(table_density(max(h, 0.0)));
}

// Smallest scale height relevant at altitude h (exponential constituents whose
// density there exceeds ~1e-15); 0 when none.
double scale_at(double h) {
  double H = 0.0LF;
  for (int c = 0; c < 3; ++c) {
    if (tab_present[c] == 0 || is_exponential[c] == 0) continue;
    double Hc = double(scale_height[c]);
    if (h < 34.5LF * Hc && (H == 0.0LF || Hc < H)) H = Hc;
  }
  return H;
}

// One piece [a, b] of the ray: equal sub-pieces (shared lut_piece_count), each
// with the build's Gauss-Legendre rule.
dvec3 piece(double r, double mu, double rt2, double a, double b) {
  dvec3 sum = dvec3(0.0LF);
  double ua = a + r * mu, ub = b + r * mu;
  double ra = sqrt(ua * ua + rt2), rb = sqrt(ub * ub + rt2);
  int m = lut_piece_count(ra, rb, b - a, rt2, scale_at(min(ra, rb) - ground_radius_d));
  double len = (b - a) / double(m);
  for (int p = 0; p < m; ++p) {
    double lo = a + double(p) * len;
    for (int g = 0; g < n_rule; ++g)
      sum += (rule[n_rule + g] * len) * density_along(r, mu, rt2, lo + rule[g] * len);
  }
  return sum;
}

double crossing_radius(int i) { return cross_r[i]; }  // for ATMOSH_LUT_RAY_PIECES

// Column over s in [0, L]: the shared traversal of the cuts (lut.glsl.hpp).
dvec3 column(double r, double mu, double L) {
  dvec3 sum = dvec3(0.0LF);
  if (!(L > 0.0LF)) return sum;
  double rt2 = max(r * r * ((1.0LF - mu) * (1.0LF + mu)), 0.0LF);
#define LUT_BUILD_PIECE(a, b) sum += piece(r, mu, rt2, a, b)
  ATMOSH_LUT_RAY_PIECES(double, r, mu, L, n_cross, crossing_radius, LUT_BUILD_PIECE);
#undef LUT_BUILD_PIECE
  return sum;
}

void main() {
  int e = int(gl_GlobalInvocationID.x);
  if (e >= n_entries) return;
  int k = e / n_dirs, j = e - k * n_dirs;
  double R = ground_radius_d, T = top_radius_d;
  double r = shell_r[k];
  double rho = sqrt(max(0.0LF, (r - R) * (r + R)));
  double Hh = sqrt((T - R) * (T + R));
  double x = double(j) / double(n_dirs - 1);
  dvec3 mean = dvec3(table_density(max(float(r - R), 0.0)));
  if (table_kind == 0) {
    double dmin = T - r, dmax = rho + Hh, d = dmin + x * (dmax - dmin);
    if (d > 0.0LF) {
      double mu = clamp(((T - r) * (T + r) - d * d) / (2.0LF * r * d), -1.0LF, 1.0LF);
      mean = column(r, mu, d) / d;
    }
  } else {
    double dmin = r - R, dmax = rho, d = dmin + x * (dmax - dmin);
    if (d > 0.0LF) {
      double mu = clamp(-(rho * rho + d * d) / (2.0LF * r * d), -1.0LF, 1.0LF);
      mean = column(r, mu, d) / d;
    }
  }
  // log in double range: GLSL's log is float only; split off the exponent.
  for (int c = 0; c < 3; ++c) {
    int ex;
    double mant = frexp(max(mean[c], 1e-300LF), ex);
    double lg = double(log(float(mant))) + double(ex) * 0.69314718055994530942LF;
    table_out[3 * e + c] = log_encoded[c] != 0 ? float(lg) : 0.0;
  }
}
