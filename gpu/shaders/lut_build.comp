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


// The densities the tables hold at altitude h >= 0: density_at's (the profiles' less
// the subtracted kinks' p, on the nodes) less their quadratic ramps q.
vec3 table_density(float h) {
  vec3 d = density_at(h);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < params.n_q[c]; ++k) {
      float e = max(shell[params.off_q[c] + k] - h, 0.0);
      d[c] -= shell[params.off_q[c] + params.n_q[c] + k] * e * e;
    }
  return d;
}

// Density of the present constituents at distance s along (r, mu) (the altitude as
// OpticalDepthLut::build_column takes it: shared radius_along, sky_altitude).
dvec3 density_along(double r, double mu, double s) {
  return dvec3(table_density(float(sky_altitude(radius_along(r, mu, s), params.ground_radius_d))));
}

// Smallest scale height relevant at altitude h (exponential constituents whose
// density there exceeds ~1e-15); 0 when none.
double scale_at(double h) {
  double H = 0.0LF;
  for (int c = 0; c < 3; ++c) {
    if (params.tab_present[c] == 0 || params.is_exponential[c] == 0) continue;
    double Hc = double(params.scale_height[c]);
    if (h < 34.5LF * Hc && (H == 0.0LF || Hc < H)) H = Hc;
  }
  return H;
}

// One piece [a, b] of the ray: equal sub-pieces (shared lut_piece_count), each
// with the build's Gauss-Legendre rule.
dvec3 piece(double r, double mu, double rt2, double a, double b) {
  dvec3 sum = dvec3(0.0LF);
  double ra = radius_along(r, mu, a), rb = radius_along(r, mu, b);
  int m = lut_piece_count(ra, rb, b - a, rt2, scale_at(min(ra, rb) - params.ground_radius_d));
  double len = (b - a) / double(m);
  for (int p = 0; p < m; ++p) {
    double lo = a + double(p) * len;
    for (int g = 0; g < params.n_rule; ++g)
      sum += (rule[params.n_rule + g] * len) * density_along(r, mu, lo + rule[g] * len);
  }
  return sum;
}

double crossing_radius(int i) { return cross_r[i]; }  // for ATMOSH_LUT_RAY_PIECES

// Column over s in [0, L]: the shared traversal of the cuts (lut.glsl.hpp).
dvec3 column(double r, double mu, double L) {
  dvec3 sum = dvec3(0.0LF);
  if (!(L > 0.0LF)) return sum;
  double rt2 = tangent_radius_sq(r, mu);
#define LUT_BUILD_PIECE(a, b) sum += piece(r, mu, rt2, a, b)
  ATMOSH_LUT_RAY_PIECES(double, r, mu, L, params.n_cross, crossing_radius, LUT_BUILD_PIECE);
#undef LUT_BUILD_PIECE
  return sum;
}

void main() {
  int e = int(gl_GlobalInvocationID.x);
  if (e >= params.n_items) return;
  int k = e / params.n_dirs, j = e - k * params.n_dirs;
  double R = params.ground_radius_d, T = params.top_radius_d;
  double r = shell_r[k];
  double rho = sqrt(max(0.0LF, (r - R) * (r + R)));
  bool ground = params.table_kind != 0;
  double d = lut_table_distance(r, rho, double(j) / double(params.n_dirs - 1), R, T, params.horizon_rho_d, ground);
  dvec3 mean = d > 0.0LF ? column(r, lut_table_mu(r, rho, d, T, ground), d) / d
                         : dvec3(table_density(max(float(r - R), 0.0)));
  // log in double range: GLSL's log is float only; split off the exponent.
  for (int c = 0; c < 3; ++c) {
    int ex;
    double mant = frexp(max(mean[c], 1e-300LF), ex);
    double lg = double(log(float(mant))) + double(ex) * 0.69314718055994530942LF;
    table_out[3 * e + c] = params.log_encoded[c] != 0 ? float(lg) : 0.0;
  }
}
