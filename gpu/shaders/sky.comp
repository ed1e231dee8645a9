// Single-scattering sky radiance, one invocation per pixel (see sky_lib.glsl,
// assembled before this file).
layout(local_size_x = 64) in;

float gauss_x(int q) { return gl[q]; }            // the rule on [-1, 1], for ATMOSH_SKY_PIECE_NODES
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
    vec4 total = lookup(true, h0, muf);
    for (int k = 1; k < nc; ++k) {
      float a0 = float(vc.s[k - 1]), b0 = float(vc.s[k]);
      if (!(b0 > a0)) continue;
      // Densest point of the piece (shared/scatter.glsl.hpp, double overload).
      float sd = float(piece_densest_point(r, mu, double(st), double(a0), double(b0)));
      double usd = double(sd) + r * mu;
      float hd = float((double(sd) * (double(sd) + 2.0LF * r * mu) + (r - Rd) * (r + Rd)) / (sqrt(usd * usd + rt2) + Rd));
      vec3 rho_d = density_at(hd);
      float tau_piece = (ext_max[0] * rho_d[0] + ext_max[1] * rho_d[1] + ext_max[2] * rho_d[2]) * (b0 - a0);
      int parts = piece_parts(tau_piece, max_piece_optical_depth);
      // One quadrature node (s, w) of the piece: the body of ATMOSH_SKY_PIECE_NODES
      // (shared/scatter.glsl.hpp), the same steps as SkyIntegrator::radiance's node.
#define SKY_NODE(s_arg, w_arg)                                                              \
  {                                                                                         \
    double s = (s_arg);                                                                     \
    float wq = float(w_arg);                                                                \
    double u = s + r * mu;                                                                  \
    double rs = sqrt(u * u + rt2);                                                          \
    float hs = float((s * (s + 2.0LF * r * mu) + (r - Rd) * (r + Rd)) / (rs + Rd));         \
    float mus = float(cos_zenith_along(r, mu_s, nu, s, rs));                                \
    vec4 to_sun = lookup(false, hs, mus);                                                   \
    if (to_sun.w < 0.5) { /* else in the Earth's shadow */                                  \
      float mu_p = float(clamp(u / rs, -1.0LF, 1.0LF));                                     \
      vec4 rest = lookup(true, hs, mu_p);                                                   \
      vec3 x = max(total.xyz - rest.xyz, vec3(0.0)) + to_sun.xyz;                           \
      vec3 rho = density_at(hs);                                                            \
      float sr = rho[0] * p_ray * wq, sm = rho[1] * p_mie * wq;                             \
      for (int i = 0; i < nwc; ++i)                                                         \
        acc[i] += scattering_term(exp(-column_optical_depth(spec[i], spec[nw + i],          \
                                                            spec[2 * nw + i], x[0], x[1], x[2])), \
                                  spec[3 * nw + i], spec[4 * nw + i], sr, sm);              \
    }                                                                                       \
  }
      ATMOSH_SKY_PIECE_NODES(double, double(a0), double(b0), parts, n_gauss, gauss_x, gauss_w, SKY_NODE);
#undef SKY_NODE
    }
    for (int i = 0; i < nwc; ++i) acc[i] *= spec[6 * nw + i] * irradiance_scale;
    if (ground && albedo > 0.0) {
      double sg_end = double(s_end);
      double ug = sg_end + r * mu;
      double rg = sqrt(ug * ug + rt2);
      float mus_g = float(cos_zenith_along(r, mu_s, nu, sg_end, rg));
      if (mus_g > 0.0) {
        vec4 to_sun = lookup(false, 0.0, mus_g);
        if (to_sun.w < 0.5) {
          vec3 xg = total.xyz + to_sun.xyz;
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
