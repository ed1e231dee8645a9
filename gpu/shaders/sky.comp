// Single-scattering sky radiance, one invocation per pixel (see sky_lib.glsl,
// assembled before this file).
layout(local_size_x = 64) in;

float gauss_x(int q) { return gl[q]; }            // the rule on [-1, 1]
float gauss_w(int q) { return gl[n_gauss + q]; }

void main() {
  int pix = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x);
  if (pix >= n_pixels) return;
  int nwc = min(nw, kMaxWavelengths);
  float acc[kMaxWavelengths];
  for (int i = 0; i < nwc; ++i) acc[i] = 0.0;
  vec4 dv = dirs[pix];
  int out_base = pix * nw;
  if (!(dv.w > 0.0)) {
    for (int i = 0; i < nw; ++i) radiance[out_base + i] = 0.0;
    return;
  }
  // make_ray (sky.cpp): the observer inside the atmosphere or entering it from above.
  dvec3 v = dvec3(dv.xyz);
  dvec3 l = dvec3(sun_dir);
  double Rd = ground_radius_d, Td = top_radius_d;
  double r = observer_radius_d, mu = v.z, mu_s = l.z;
  double nu = clamp(dot(v, l), -1.0LF, 1.0LF);
  bool empty = false;
  if (r > Td) {
    float dtop = distance_to_top_from_outside(float(r), float(mu), top_radius);
    if (dtop < 0.0) {
      empty = true;
    } else {
      // Entry point at radius T: double for the transported cosines.
      double dd = double(dtop);
      mu = clamp((r * mu + dd) / Td, -1.0LF, 1.0LF);
      mu_s = clamp((r * mu_s + dd * nu) / Td, -1.0LF, 1.0LF);
      r = Td;
    }
  }
  float rf = float(r), muf = float(mu);
  float h0 = float(r - Rd);
  bool ground = !empty && ray_hits_ground(rf, muf, ground_radius);
  float s_end = empty ? 0.0 : (ground ? distance_to_ground(rf, muf, ground_radius) : distance_to_top(rf, muf, top_radius));
  if (!empty && s_end > 0.0) {
    float nuf = float(nu);
    float p_ray = has_ext[0] != 0 ? phase_value(0, nuf) : 0.0;
    float p_mie = has_ext[1] != 0 ? phase_value(1, nuf) : 0.0;
    double rt2 = r * r * ((1.0LF - mu) * (1.0LF + mu));
    // Cuts: shell crossings, shadow edges and the tangent point, sorted
    // (shared/view_ray.glsl.hpp, double build: the CPU's function).
    double cut_r[kMaxCutSpheres];
    for (int k = 0; k < n_cuts; ++k) cut_r[k] = shell_d[off_cuts + k];
    ViewRayCuts vc = view_ray_cuts(r, mu, mu_s, nu, Rd, double(s_end), rt2, cut_r, n_cuts);
    int nc = vc.n;
    float st = float(-r * mu);
    // View column from the observer to the start of the current part, and the
    // density there (SkyIntegrator::radiance; weights sky_part_column_weights).
    vec3 column = vec3(0.0);
    vec3 rho_start = density_at(h0);
    int n_points = n_gauss + 2;
    int off_pw = 2 * n_gauss;  // part column weights in gl[]
    for (int k = 1; k < nc; ++k) {
      float a0 = float(vc.s[k - 1]), b0 = float(vc.s[k]);
      if (!(vc.s[k] > vc.s[k - 1])) continue;
      // Densest point of the piece (shared/scatter.glsl.hpp, double overload).
      float sd = float(piece_densest_point(r, mu, double(st), vc.s[k - 1], vc.s[k]));
      double usd = double(sd) + r * mu;
      float hd = float((double(sd) * (double(sd) + 2.0LF * r * mu) + (r - Rd) * (r + Rd)) / (sqrt(usd * usd + rt2) + Rd));
      vec3 rho_d = density_at(max(hd, 0.0));  // below the ground only by rounding
      float tau_piece = (ext_max[0] * rho_d[0] + ext_max[1] * rho_d[1] + ext_max[2] * rho_d[2]) * (b0 - a0);
      int parts = piece_parts(tau_piece, max_piece_optical_depth);
      // One part [a, b] of the piece: the body of ATMOSH_SKY_PIECE_PARTS
      // (shared/scatter.glsl.hpp), the same steps as SkyIntegrator::radiance's part.
#define SKY_PART(a_arg, b_arg)                                                              \
  {                                                                                         \
    double pa = (a_arg), pb = (b_arg);                                                      \
    double part_half = 0.5LF * (pb - pa), mid = 0.5LF * (pa + pb);                          \
    double s_q[kMaxPartNodes];                                                              \
    double r_q[kMaxPartNodes];                                                              \
    float h_q[kMaxPartNodes];                                                               \
    vec3 rho_q[kMaxPartNodes];                                                              \
    for (int q = 0; q < n_gauss; ++q) {                                                     \
      double s = mid + part_half * double(gauss_x(q));                                      \
      double u = s + r * mu;                                                                \
      s_q[q] = s;                                                                           \
      r_q[q] = sqrt(u * u + rt2);                                                           \
      h_q[q] = max(float((s * (s + 2.0LF * r * mu) + (r - Rd) * (r + Rd)) / (r_q[q] + Rd)), 0.0); \
      rho_q[q] = density_at(h_q[q]);                                                        \
    }                                                                                       \
    double ub = pb + r * mu;                                                                \
    vec3 rho_end = density_at(max(float((pb * (pb + 2.0LF * r * mu) + (r - Rd) * (r + Rd)) / \
                                        (sqrt(ub * ub + rt2) + Rd)), 0.0));                 \
    float part_halff = float(part_half);                                                    \
    for (int q = 0; q <= n_gauss; ++q) {                                                    \
      int row = off_pw + q * n_points;                                                      \
      vec3 part_col = gl[row] * rho_start + gl[row + n_gauss + 1] * rho_end;                \
      for (int j = 0; j < n_gauss; ++j) part_col += gl[row + 1 + j] * rho_q[j];             \
      part_col = max(part_halff * part_col, vec3(0.0));                                     \
      if (q == n_gauss) {                                                                   \
        column += part_col;                                                                 \
        break;                                                                              \
      }                                                                                     \
      float mus = float(cos_zenith_along(r, mu_s, nu, s_q[q], r_q[q]));                     \
      vec4 to_sun = sun_lookup(h_q[q], mus);                                             \
      if (to_sun.w < 0.5) { /* else in the Earth's shadow */                                \
        vec3 x = column + part_col + to_sun.xyz;                                            \
        float wq = part_halff * gauss_w(q);                                                 \
        float sr = rho_q[q][0] * p_ray * wq, sm = rho_q[q][1] * p_mie * wq;                 \
        for (int i = 0; i < nwc; ++i)                                                       \
          acc[i] += scattering_term(exp(-column_optical_depth(spec[i], spec[nw + i],        \
                                                              spec[2 * nw + i], x[0], x[1], x[2])), \
                                    spec[3 * nw + i], spec[4 * nw + i], sr, sm);            \
      }                                                                                     \
    }                                                                                       \
    rho_start = rho_end;                                                                    \
  }
      ATMOSH_SKY_PIECE_PARTS(double, vc.s[k - 1], vc.s[k], parts, SKY_PART);
#undef SKY_PART
    }
    for (int i = 0; i < nwc; ++i) acc[i] *= spec[6 * nw + i] * irradiance_scale;
    if (ground && albedo > 0.0) {
      double sg_end = double(s_end);
      double ug = sg_end + r * mu;
      double rg = sqrt(ug * ug + rt2);
      float mus_g = float(cos_zenith_along(r, mu_s, nu, sg_end, rg));
      if (mus_g > 0.0) {
        vec4 to_sun = sun_lookup(0.0, mus_g);
        if (to_sun.w < 0.5) {
          vec3 xg = column + to_sun.xyz;
          for (int i = 0; i < nwc; ++i)
            acc[i] += spec[6 * nw + i] * irradiance_scale *
                      ground_term(albedo, mus_g, exp(-column_optical_depth(spec[i], spec[nw + i], spec[2 * nw + i],
                                                                           xg[0], xg[1], xg[2])));
        }
      }
    }
  }
  for (int i = 0; i < nw; ++i) radiance[out_base + i] = i < nwc ? acc[i] : 0.0;
}
