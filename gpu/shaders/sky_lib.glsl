// Buffers and table lookups of the GPU's atmosphere passes (sky.comp, sun_lookup.comp,
// lut_build.comp and the test drivers), assembled after the shared headers
// (shared/geometry.glsl.hpp and shared/lut.glsl.hpp in float and double,
// shared/scatter.glsl.hpp, shared/view_ray.glsl.hpp in double,
// shared/sky_params.glsl.hpp: the parameter block, the binding points and the
// buffers' index math). What is left here reads the storage buffers into the shared
// functions: the densities (atmo::DensityProfile), the table interpolation
// (OpticalDepthLut::interpolate) and the sun-table lookup (OpticalDepthLut::sun).
// Positions along rays and the interpolation weights are double; everything else float.
// Constituents: 0 Rayleigh, 1 Mie (exponential, tabulated with log encoding),
// 2 ozone (piecewise linear, closed-form column); Rayleigh may also be a
// positive tabulated profile (its column still comes from the log tables).

layout(std430, binding = ATMOSH_BIND_ITEMS) readonly buffer Items { vec4 dirs[]; };
layout(std430, binding = ATMOSH_BIND_TABLES) readonly buffer Tables { float tab[]; };
layout(std430, binding = ATMOSH_BIND_NODES) readonly buffer Nodes { float shell[]; };
layout(std430, binding = ATMOSH_BIND_SPECTRAL) readonly buffer Spectral { float spec[]; };
layout(std430, binding = ATMOSH_BIND_RESULT) writeonly buffer Result { float radiance[]; };
layout(std430, binding = ATMOSH_BIND_SHELLS) readonly buffer Shells { double shell_d[]; };
layout(std430, binding = ATMOSH_BIND_PARAMS) readonly buffer Params { GpuSkyParams params; };

float phase_value(int c, float nu) {
  return phase_analytic(params.phase_model[c], nu, params.phase_p[4 * c], params.phase_p[4 * c + 1],
                        params.phase_p[4 * c + 2]);
}

// Relative density of a piecewise-linear profile (nodes at shell[off_nodes[c]]) at
// altitude h [m], 0 outside its nodes, as atmo::DensityProfile: the node interval by
// the shared bisection, the value by the shared linear_between.
#define NODE_ALTITUDE(i) shell[o + (i)]
float density_nodes(int c, float h) {
  int o = params.off_nodes[c], n = params.n_nodes[c], k;
  if (n < 2 || h < shell[o] || h > shell[o + n - 1]) return 0.0;
  ATMOSH_LUT_SHELL_INDEX(k, n, h, NODE_ALTITUDE);
  k = clamp(k, 0, n - 2);
  return linear_between(h, shell[o + k], shell[o + k + 1], shell[o + n + k], shell[o + n + k + 1]);
}

vec3 density_at(float h) {
  vec3 d = vec3(0.0);
  for (int c = 0; c < 3; ++c)
    if (params.has_ext[c] != 0) d[c] = params.n_nodes[c] > 0 ? density_nodes(c, h) : density_exponential(h, params.scale_height[c]);
  return d;
}

// ---- OpticalDepthLut::interpolate: the shared window choice and weights (double) ----
#define SHELL_RHO(i) shell_d[i]
#define SHELL_DEN(i) shell_d[params.n_shells + (i)]
#define TABLE_ENTRY(i, m) table_entry(lut_table_entry(base, n, w + (i), jw + (m), 0))
dvec3 table_entry(int e) { return dvec3(tab[e], tab[e + 1], tab[e + 2]); }
// Weights and sums in double: the columns come out with ~1e-7 relative error
// (float weights would give ~1e-5, and a horizon ray's optical depth of ~30
// turns that into 3e-4 in the transmittance).
dvec3 interpolate(int base, int n, double rho, double x) {
  int k, w, jw;
  double lw[4], xw[4];
  dvec3 acc;
  ATMOSH_LUT_SHELL_INDEX(k, params.n_shells, rho, SHELL_RHO);
  ATMOSH_LUT_SHELL_WEIGHTS(lw, w, k, params.n_shells, rho, SHELL_RHO, SHELL_DEN);
  ATMOSH_LUT_DIRECTION_WEIGHTS(xw, jw, x, n);
  ATMOSH_LUT_WINDOW_SUM(dvec3, dvec3(0.0LF), acc, lw, xw, TABLE_ENTRY);
  return acc;
}

// The ozone column (a density: >= 0), the shared closed form on the block's nodes.
float ozone_column(float r, float mu, float len) {
  float q[kMaxLinearNodes];
  return max(piecewise_linear_column(r, mu, len, params.ozone.radius, params.ozone.value, params.ozone.slope,
                                     params.ozone.n, q), 0.0);
}

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
  dvec3 v = interpolate(params.off_sun, params.n_sun, rho, lut_x(dd, params.top_radius_d - rd, rho + params.horizon_rho_d));
  float d = float(dd), r = params.ground_radius + h, q[kMaxLinearNodes];
  vec3 col = vec3(0.0);
  for (int c = 0; c < 3; ++c) col[c] = params.tabulated[c] != 0 ? lut_decode(float(v[c]), true) * d : 0.0;
  if (params.has_ext[2] != 0 && params.tabulated[2] == 0) col[2] = ozone_column(r, mu, d);
  for (int c = 0; c < 2; ++c)  // OpticalDepthLut's subtracted kinks, added back
    if (params.sub[c].n >= 2)
      col[c] = column_added_back(col[c], piecewise_linear_column(r, mu, d, params.sub[c].radius, params.sub[c].value,
                                                                 params.sub[c].slope, params.sub[c].n, q),
                                 quadratic_ramps_column(r, mu, d, params.subq[c].radius, params.subq[c].half_curv, params.subq[c].n));
  return vec4(col, 0.0);
}
