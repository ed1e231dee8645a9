// Buffers, uniforms and table lookups of the GPU sky (sky.comp); assembled after
// shared/geometry.glsl.hpp (float), shared/lut.glsl.hpp (float and double
// builds) and shared/view_ray.glsl.hpp (double). The GPU version of
// atmo::SkyIntegrator::radiance (libatmo/src/sky.cpp), same cuts, pieces,
// Gauss-Legendre nodes, view column accumulated along the ray and sun-table
// lookups (OpticalDepthLut). Assembled after
// shared/geometry.glsl.hpp (ray geometry, densities, phase functions, closed-form
// linear-piece columns). Positions along the ray are formed in double precision
// (altitudes to ~1 mm; float radii would carry ~0.5 m); everything else is float.
// Constituents: 0 Rayleigh, 1 Mie (exponential, tabulated with log encoding),
// 2 ozone (piecewise linear, closed-form column); Rayleigh may also be a
// positive tabulated profile (its column still comes from the log tables).

layout(std430, binding = 0) readonly buffer Directions { vec4 dirs[]; };      // xyz, w > 0: valid
layout(std430, binding = 1) readonly buffer Tables { float tab[]; };          // [shell][dir][3]
layout(std430, binding = 2) readonly buffer Shells { float shell[]; };        // rho, 1/den, ozone and subtracted-kink nodes
layout(std430, binding = 3) readonly buffer Spectral { float spec[]; };       // ext[3][nw], sca[3][nw], solar[nw]
layout(std430, binding = 4) writeonly buffer Radiance { float radiance[]; };  // [pixel][nw]
layout(std430, binding = 5) readonly buffer Quadrature { double gl[]; };      // nodes[n], weights[n], part column weights[n+1][n+2]
layout(std430, binding = 6) readonly buffer ShellsD { double shell_d[]; };    // rho[S], 1/den[(S-3)*4], cut radii
layout(std430, binding = 13) readonly buffer Params { GpuSkyParams params; };  // shared/sky_params.glsl.hpp


const int kMaxWavelengths = 64;

float phase_value(int c, float nu) {
  int m = params.phase_model[c];
  float a = params.phase_p[4 * c], b = params.phase_p[4 * c + 1], w = params.phase_p[4 * c + 2];
  if (m == 0) return phase_rayleigh(nu, a);
  if (m == 1) return phase_hg(nu, a);
  if (m == 2) return phase_cornette_shanks(nu, a);
  return phase_double_hg(nu, a, b, w);
}

// Relative densities at altitude h [m]: exponential, or piecewise linear through
// (altitude, value) nodes (0 outside them), as atmo::DensityProfile.
float density_nodes(int c, float h) {
  int o = params.off_nodes[c], n = params.n_nodes[c];
  if (n < 2 || h < shell[o] || h > shell[o + n - 1]) return 0.0;
  int lo = 0, hi = n - 1;  // shell[o + lo] <= h <= shell[o + hi]
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (shell[o + mid] <= h) lo = mid; else hi = mid;
  }
  float ha = shell[o + lo], hb = shell[o + hi], va = shell[o + n + lo], vb = shell[o + n + hi];
  return hb > ha ? va + (vb - va) * ((h - ha) / (hb - ha)) : va;
}

vec3 density_at(float h) {
  vec3 d = vec3(0.0);
  for (int c = 0; c < 3; ++c)
    if (params.has_ext[c] != 0) d[c] = params.n_nodes[c] > 0 ? density_nodes(c, h) : density_exponential(h, params.scale_height[c]);
  return d;
}

// ---- OpticalDepthLut::interpolate / lookup (exponential constituents) ----
double shell_rho(int i) { return shell_d[i]; }  // for ATMOSH_LUT_SHELL_INDEX

// Weights and sums in double: the columns come out with ~1e-7 relative error
// (float weights would give ~1e-5, and a horizon ray's optical depth of ~30
// turns that into 3e-4 in the transmittance).
dvec3 interpolate(int base, int n, double rho, double x) {
  // Window choice and weights: shared/lut.glsl.hpp (double build), as the CPU's.
  int k;
  ATMOSH_LUT_SHELL_INDEX(k, params.n_shells, rho, shell_rho);
  int w = lut_window_start(k, params.n_shells);
  double lw[4];
  for (int i = 0; i < 4; ++i)
    lw[i] = lut_shell_weight(rho, shell_d[params.n_shells + w * 4 + i], shell_d[w], shell_d[w + 1], shell_d[w + 2],
                             shell_d[w + 3], i);
  int jw = lut_direction_window(x, n);
  double p = lut_direction_offset(x, n, jw);
  double xw[4];
  for (int m = 0; m < 4; ++m) xw[m] = lagrange_cubic_weight(p, m);
  dvec3 acc = dvec3(0.0LF);
  for (int i = 0; i < 4; ++i) {
    int row = base + ((w + i) * n + jw) * 3;
    dvec3 inner = dvec3(0.0LF);
    for (int m = 0; m < 4; ++m) inner += xw[m] * dvec3(tab[row + 3 * m], tab[row + 3 * m + 1], tab[row + 3 * m + 2]);
    acc += lw[i] * inner;
  }
  return acc;
}

vec3 decode_times(dvec3 v, float d) {
  vec3 out_v = vec3(0.0);
  for (int c = 0; c < 2; ++c)
    if (params.tabulated[c] != 0) out_v[c] = exp(float(v[c])) * d;
  return out_v;
}

// PiecewiseLinearColumn::operator() for n nodes at shell[off]: the shared traversal
// (shared/geometry.glsl.hpp, float build) on the nodes (radius[n], value[n], slope[n]).
float linear_column(int off, int n_all, float r, float mu, float len) {
  if (!(len > 0.0) || n_all < 2) return 0.0;
  float radius[kMaxLinearNodes], value[kMaxLinearNodes], slope[kMaxLinearNodes], q[kMaxLinearNodes];
  int n = min(n_all, kMaxLinearNodes);
  for (int k = 0; k < n; ++k) {
    radius[k] = shell[off + k];
    value[k] = shell[off + n_all + k];
    slope[k] = shell[off + 2 * n_all + k];
  }
  return piecewise_linear_column(r, mu, len, radius, value, slope, n, q);
}

// QuadraticRampsColumn::operator() for n ramps at shell[off] (radius[n], half_curv[n]).
float curvature_column(int off, int n_all, float r, float mu, float len) {
  float radius[kMaxLinearNodes], half_curv[kMaxLinearNodes];
  int n = min(n_all, kMaxLinearNodes);
  for (int k = 0; k < n; ++k) {
    radius[k] = shell[off + k];
    half_curv[k] = shell[off + n_all + k];
  }
  return quadratic_ramps_column(r, mu, len, radius, half_curv, n);
}

// The ozone column (a density: >= 0).
float ozone_column(float r, float mu, float len) { return max(linear_column(params.off_oz, params.n_oz, r, mu, len), 0.0); }

// OpticalDepthLut::sun for an origin inside the atmosphere: h = r - R given
// separately (accurately); returns the column to the top, or w = 1 (and no column)
// when the ray hits the ground. The ray's geometry (ground test, distance to the
// top, table coordinates) is in double, as the interpolation: a float radius R + h
// is rounded by up to 0.25 m, which changes short rays near the top by ~1e-3 of
// their length. The closed-form columns (ozone, subtracted kinks) are float.
vec4 sun_lookup(float h, float mu) {
  h = max(h, 0.0);
  mu = clamp(mu, -1.0, 1.0);
  double hd = double(h), Rd = params.ground_radius_d, rd = Rd + hd, mud = double(mu);
  double rho = sqrt(hd * (hd + 2.0LF * Rd));
  if (ray_hits_ground(rd, mud, Rd)) return vec4(0.0, 0.0, 0.0, 1.0);
  double dd = distance_to_top(rd, mud, params.top_radius_d);
  double x = lut_x(dd, params.top_radius_d - rd, rho + params.horizon_rho_d);
  float d = float(dd), r = params.ground_radius + h;
  vec3 col = decode_times(interpolate(params.off_sun, params.n_sun, rho, x), d);
  if (params.has_ext[2] != 0 && params.tabulated[2] == 0) col[2] = ozone_column(r, mu, d);
  for (int c = 0; c < 2; ++c)  // OpticalDepthLut's subtracted kinks, added back
    if (params.n_sub[c] >= 2)
      col[c] = max(col[c] + linear_column(params.off_sub[c], params.n_sub[c], r, mu, d) +
                       (params.n_subq[c] > 0 ? curvature_column(params.off_subq[c], params.n_subq[c], r, mu, d) : 0.0),
                   0.0);
  return vec4(col, 0.0);
}
