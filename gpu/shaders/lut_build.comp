// Optical-depth table build (OpticalDepthLut::fill / build_column in
// libatmo/src/optical_depth.cpp), one invocation per table entry: the entry's ray
// (shared lut_table_distance, lut_table_mu) is cut at the tangent point and at every
// crossing of the shells and profile kinks (shared ATMOSH_LUT_RAY_PIECES), its pieces
// are split into sub-pieces with their Gauss-Legendre nodes (shared
// ATMOSH_LUT_PIECE_NODES, by the build's scale height OpticalDepthLut::build_scale_height).
// Positions and sums in double, densities in float (shared density functions through
// sky_lib.glsl's density_at). Output: log of the mean relative density for the
// tabulated (log-encoded) constituents, 0 otherwise.
layout(local_size_x = 64) in;

layout(std430, binding = ATMOSH_BIND_CROSSINGS) readonly buffer Crossings { double cross_r[]; };  // sorted radii
layout(std430, binding = ATMOSH_BIND_TABLE_OUT) writeonly buffer TableOut { float table_out[]; };
layout(std430, binding = ATMOSH_BIND_RULE) readonly buffer BuildRule { double rule[]; };  // x[n] in (0,1), w[n]
layout(std430, binding = ATMOSH_BIND_SHELL_RADII) readonly buffer ShellRadii { double shell_r[]; };

// The densities the tables hold at altitude h >= 0: density_at's (the profiles' less
// the subtracted kinks' p, on the nodes) less their quadratic ramps q.
vec3 table_density(float h) {
  vec3 d = density_at(h);
  for (int c = 0; c < 3; ++c)
    d[c] -= quadratic_ramps_at(h, params.build_ramps[c].radius, params.build_ramps[c].half_curv, params.build_ramps[c].n, 0.0);
  return d;
}

#define RULE_X(g) rule[g]
#define RULE_W(g) rule[params.n_rule + (g)]
#define CROSSING_RADIUS(i) cross_r[i]
#define ADD_NODE(s, w) sum += (w) * dvec3(table_density(float(sky_altitude(radius_along(r, mu, s), params.ground_radius_d))))
#define ADD_PIECE(a, b) ATMOSH_LUT_PIECE_NODES(double, r, mu, rt2, a, b, params.build_scale_height, params.n_rule, RULE_X, RULE_W, ADD_NODE)

void main() {
  int e = int(gl_GlobalInvocationID.x);
  if (e >= params.n_items) return;
  int k = e / params.n_dirs, j = e - k * params.n_dirs;
  double R = params.ground_radius_d, T = params.top_radius_d;
  double r = shell_r[k], rho = shell_d[k];  // OpticalDepthLut::shell_radii(), shell_rho()
  bool ground = params.table_kind != 0;
  double d = lut_table_distance(r, rho, double(j) / double(params.n_dirs - 1), R, T, params.horizon_rho_d, ground);
  double mu = lut_table_mu(r, rho, d, T, ground), rt2 = tangent_radius_sq(r, mu);
  dvec3 sum = dvec3(0.0LF);  // the column over [0, d]: the shared traversal of the cuts
  if (d > 0.0LF) ATMOSH_LUT_RAY_PIECES(double, r, mu, d, params.n_cross, CROSSING_RADIUS, ADD_PIECE);
  dvec3 mean = d > 0.0LF ? sum / d : dvec3(table_density(max(float(r - R), 0.0)));
  // log in double range: GLSL's log is float only; split off the exponent.
  for (int c = 0; c < 3; ++c) {
    int ex;
    double mant = frexp(max(mean[c], 1e-300LF), ex);
    double lg = double(log(float(mant))) + double(ex) * 0.69314718055994530942LF;
    table_out[3 * e + c] = params.log_encoded[c] != 0 ? float(lg) : 0.0;
  }
}
