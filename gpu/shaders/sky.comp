// Single-scattering sky radiance, one invocation per pixel (see sky_lib.glsl,
// assembled before this file).
layout(local_size_x = 64) in;

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
      // Densest point of the piece: tangent point inside it, else the lower end.
      float sd;
      if (st > a0 && st < b0) sd = st;
      else {
        double ua = double(a0) + r * mu, ub = double(b0) + r * mu;
        sd = abs(ua) < abs(ub) ? a0 : b0;
      }
      double usd = double(sd) + r * mu;
      float hd = float((double(sd) * (double(sd) + 2.0LF * r * mu) + (r - Rd) * (r + Rd)) / (sqrt(usd * usd + rt2) + Rd));
      vec3 rho_d = density_at(hd);
      float tau_piece = (ext_max[0] * rho_d[0] + ext_max[1] * rho_d[1] + ext_max[2] * rho_d[2]) * (b0 - a0);
      int parts = max(int(min(64.0, ceil(tau_piece / max_piece_optical_depth))), 1);
      for (int part = 0; part < parts; ++part) {
        float a = a0 + (b0 - a0) * float(part) / float(parts);
        float b = a0 + (b0 - a0) * float(part + 1) / float(parts);
        float half_len = 0.5 * (b - a), mid = 0.5 * (a + b);
        for (int qn = 0; qn < n_gauss; ++qn) {
          double s = double(mid) + double(half_len) * double(gl[qn]);
          float wq = half_len * gl[n_gauss + qn];
          double u = s + r * mu;
          double rs = sqrt(u * u + rt2);
          // Altitude without cancellation: (s^2 + 2 s r mu + (r - R)(r + R)) / (rs + R).
          float hs = float((s * (s + 2.0LF * r * mu) + (r - Rd) * (r + Rd)) / (rs + Rd));
          float mus = float(cos_zenith_along(r, mu_s, nu, s, rs));
          vec4 to_sun = lookup(false, hs, mus);
          if (to_sun.w > 0.5) continue;  // Earth's shadow
          float mu_p = float(clamp(u / rs, -1.0LF, 1.0LF));
          vec4 rest = lookup(true, hs, mu_p);
          vec3 x = max(total.xyz - rest.xyz, vec3(0.0)) + to_sun.xyz;
          vec3 rho = density_at(hs);
          float sr = rho[0] * p_ray * wq, sm = rho[1] * p_mie * wq;
          for (int i = 0; i < nwc; ++i)
            acc[i] += exp(-(spec[i] * x[0] + spec[nw + i] * x[1] + spec[2 * nw + i] * x[2])) *
                      (spec[3 * nw + i] * sr + spec[4 * nw + i] * sm);
        }
      }
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
            acc[i] += albedo / 3.14159265358979 * spec[6 * nw + i] * irradiance_scale * mus_g *
                      exp(-(spec[i] * xg[0] + spec[nw + i] * xg[1] + spec[2 * nw + i] * xg[2]));
        }
      }
    }
  }
  for (int i = 0; i < nw; ++i) radiance[out_base + i] = i < nwc ? acc[i] : 0.0;
}
