// Single-scattering sky radiance, one invocation per pixel: SkyIntegrator::radiance
// (libatmo/src/sky.cpp) through the same shared code (shared/view_ray.glsl.hpp: the
// ray's set-up, its cuts, the walk along it; shared/scatter.glsl.hpp: the integrand),
// on the inputs of sky_lib.glsl. Assembled with ATMOSH_SKY_TRACE defined.
layout(local_size_x = 64) in;

// The pixel's state that sky_visit adds to (GLSL has no closures).
SkyViewRay g_ray;
float g_p_ray, g_p_mie;
float g_acc[kMaxWavelengths];

dvec3 sky_density(double h) { return dvec3(density_at(float(h))); }

// SkyIntegrator::shade's node: the sun column (none in the Earth's shadow) and the
// integrand at every wavelength.
void sky_visit(SkyViewNode nd) {
  int nw = params.nw;
  float mus = float(cos_zenith_along(g_ray.r, g_ray.mu_s, g_ray.nu, nd.s, nd.r));
  vec4 to_sun = sun_lookup(float(sky_altitude(nd.r, params.ground_radius_d)), mus);
  if (to_sun.w > 0.5) return;
  vec3 x = vec3(nd.column) + to_sun.xyz;
  float sr = float(nd.rho[0] * double(g_p_ray) * nd.w), sm = float(nd.rho[1] * double(g_p_mie) * nd.w);
  for (int i = 0; i < min(nw, kMaxWavelengths); ++i)
    g_acc[i] += scattering_term(exp(-column_optical_depth(spec[i], spec[nw + i], spec[2 * nw + i], x[0], x[1], x[2])),
                                spec[3 * nw + i], spec[4 * nw + i], sr, sm);
}

void main() {
  int pix = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x);
  if (pix >= params.n_items) return;
  int nw = params.nw, nwc = min(nw, kMaxWavelengths), n = params.n_gauss;
  double R = params.ground_radius_d;
  for (int i = 0; i < nwc; ++i) g_acc[i] = 0.0;
  dvec3 v = dvec3(dirs[pix].xyz), l = dvec3(params.sun_dir[0], params.sun_dir[1], params.sun_dir[2]);
  g_ray = sky_view_ray(params.observer_radius_d, v.z, l.z, clamp(dot(v, l), -1.0LF, 1.0LF), R, params.top_radius_d);
  if (dirs[pix].w > 0.0 && !g_ray.empty && g_ray.s_end > 0.0LF) {
    g_p_ray = params.has_ext[0] != 0 ? phase_value(0, float(g_ray.nu)) : 0.0;
    g_p_mie = params.has_ext[1] != 0 ? phase_value(1, float(g_ray.nu)) : 0.0;
    double cut_r[kMaxCutSpheres], gx[kMaxPartNodes], gw[kMaxPartNodes], pw[kMaxPartWeights];
    for (int k = 0; k < params.n_cuts; ++k) cut_r[k] = shell_d[params.off_cuts + k];
    for (int q = 0; q < n; ++q) {
      gx[q] = gl[q];
      gw[q] = gl[n + q];
    }
    for (int i = 0; i < (n + 1) * (n + 2); ++i) pw[i] = gl[2 * n + i];
    ViewRayCuts vc = view_ray_cuts(g_ray.r, g_ray.mu, g_ray.mu_s, g_ray.nu, R, g_ray.s_end,
                                   tangent_radius_sq(g_ray.r, g_ray.mu), cut_r, params.n_cuts);
    dvec3 ext_max = dvec3(params.ext_max[0], params.ext_max[1], params.ext_max[2]);
    dvec3 column = sky_trace(g_ray, vc.s, vc.n, R, ext_max, double(params.max_piece_optical_depth), gx, gw, n, pw);
    for (int i = 0; i < nwc; ++i) g_acc[i] *= spec[6 * nw + i] * params.irradiance_scale;
    float mus_g = float(sky_ground_sun_cosine(g_ray));
    vec4 to_sun = sun_lookup(0.0, mus_g);
    if (g_ray.ground && params.albedo > 0.0 && mus_g > 0.0 && to_sun.w < 0.5) {  // ground reflection
      vec3 xg = vec3(column) + to_sun.xyz;
      for (int i = 0; i < nwc; ++i)
        g_acc[i] += spec[6 * nw + i] * params.irradiance_scale *
                    ground_term(params.albedo, mus_g,
                                exp(-column_optical_depth(spec[i], spec[nw + i], spec[2 * nw + i], xg[0], xg[1], xg[2])));
    }
  }
  for (int i = 0; i < nw; ++i) radiance[pix * nw + i] = i < nwc ? g_acc[i] : 0.0;
}
